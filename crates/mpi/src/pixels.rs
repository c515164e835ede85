//! A frame's pixels as the compositing sends and merges them: four 64-bit words a pixel -- the
//! key that decides which glyph a pixel shows, then colour and view depth, then the normal --
//! so one message carries a range of pixels whole.

use ellipsoid_splat::{Frame, Outputs, NO_INSTANCE};

/// Words a pixel takes.
pub const WORDS: usize = 4;

/// What a pixel shows, as one number that orders like the renderer's own depth test: the
/// depth attachment's value in the upper 32 bits (turned so that nearer is smaller in either
/// depth convention), the global glyph index below (so of equal depths the lower index wins,
/// as in one process). The background (the clear value, no glyph) is the largest key. The
/// value must lie in [0, 1] ([`encode`] checks it): there the bits order as the values do
/// (-0.0 is taken as 0.0, which the depth test holds equal).
pub fn key(device_depth: f32, reversed: bool, global_id: u32) -> u64 {
    let bits = (device_depth + 0.0).to_bits();
    let nearer_smaller = if reversed { u32::MAX - bits } else { bits };
    (u64::from(nearer_smaller) << 32) | u64::from(global_id)
}

/// `frame`'s pixels in compositing words, its glyph indices mapped through `global_ids`
/// (local index `i` is global glyph `global_ids[i]`). The frame must hold depth (with
/// `device_depth`) and ID; colour and normal are carried where present. The error names what
/// is missing or wrong.
pub fn encode(frame: &Frame, reversed: bool, global_ids: &[u32]) -> Result<Vec<u64>, String> {
    let n = frame.len();
    if frame.device_depth.len() != n || frame.depth.len() != n || frame.id.len() != n {
        return Err("the frame lacks depth or ID, which decide each pixel's glyph".into());
    }
    let mut words = Vec::with_capacity(n * WORDS);
    for i in 0..n {
        let local = frame.id[i];
        let global = if local == NO_INSTANCE {
            NO_INSTANCE
        } else {
            *global_ids.get(local as usize).ok_or_else(|| {
                format!(
                    "pixel {i} shows glyph {local}, but {} global indices were given",
                    global_ids.len()
                )
            })?
        };
        let z = frame.device_depth[i];
        if !(0.0..=1.0).contains(&z) {
            return Err(format!("pixel {i}'s depth {z} lies outside [0, 1]"));
        }
        let color = frame.color.get(i).map_or(0, |c| u32::from_le_bytes(*c));
        let normal = frame.normal.get(i).copied().unwrap_or([0.0; 3]);
        words.push(key(frame.device_depth[i], reversed, global));
        words.push(u64::from(color) | (u64::from(frame.depth[i].to_bits()) << 32));
        words.push(u64::from(normal[0].to_bits()) | (u64::from(normal[1].to_bits()) << 32));
        words.push(
            u64::from(normal[2].to_bits()) | (u64::from(frame.device_depth[i].to_bits()) << 32),
        );
    }
    Ok(words)
}

/// Keeps, pixel by pixel, whichever of `mine` and `theirs` has the smaller key.
pub fn merge(mine: &mut [u64], theirs: &[u64]) {
    for (a, b) in mine.chunks_exact_mut(WORDS).zip(theirs.chunks_exact(WORDS)) {
        if b[0] < a[0] {
            a.copy_from_slice(b);
        }
    }
}

/// The frame of `width x height` pixels in `words`: depth and ID always (IDs are the global
/// indices), colour and normal where `outputs` asks for them.
pub fn decode(words: &[u64], width: u32, height: u32, outputs: Outputs) -> Frame {
    let pixels = words.chunks_exact(WORDS);
    let mut frame = Frame {
        width,
        height,
        ..Frame::default()
    };
    frame.id = pixels.clone().map(|p| p[0] as u32).collect();
    frame.depth = pixels
        .clone()
        .map(|p| f32::from_bits((p[1] >> 32) as u32))
        .collect();
    frame.device_depth = pixels
        .clone()
        .map(|p| f32::from_bits((p[3] >> 32) as u32))
        .collect();
    if outputs.color {
        frame.color = pixels
            .clone()
            .map(|p| (p[1] as u32).to_le_bytes())
            .collect();
    }
    if outputs.normal {
        frame.normal = pixels
            .map(|p| {
                [
                    f32::from_bits(p[2] as u32),
                    f32::from_bits((p[2] >> 32) as u32),
                    f32::from_bits(p[3] as u32),
                ]
            })
            .collect();
    }
    frame
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_order_as_the_depth_test_does() {
        // Standard depth: smaller is nearer; reversed: larger is nearer.
        assert!(key(0.25, false, 9) < key(0.5, false, 1));
        assert!(key(0.5, true, 9) < key(0.25, true, 1));
        // Equal depths: the lower index.
        assert!(key(0.5, false, 3) < key(0.5, false, 4));
        // The background (clear value, no glyph) loses to every glyph.
        assert!(key(0.999_999_9, false, 5) < key(1.0, false, NO_INSTANCE));
        assert!(key(1e-30, true, 5) < key(0.0, true, NO_INSTANCE));
        // -0.0 is 0.0 to the depth test, so to the key.
        assert_eq!(key(-0.0, false, 3), key(0.0, false, 3));
    }

    #[test]
    fn a_frame_goes_through_the_words_unchanged_but_its_ids() {
        let frame = Frame {
            width: 2,
            height: 1,
            color: vec![[1, 2, 3, 4], [5, 6, 7, 8]],
            depth: vec![2.5, f32::INFINITY],
            device_depth: vec![0.5, 1.0],
            normal: vec![[0.0, 0.6, 0.8], [0.0; 3]],
            id: vec![1, NO_INSTANCE],
        };
        let words = encode(&frame, false, &[40, 41]).unwrap();
        let back = decode(&words, 2, 1, Outputs::ALL);
        assert_eq!(back.id, [41, NO_INSTANCE]);
        assert_eq!(
            Frame {
                id: frame.id.clone(),
                ..back
            },
            frame
        );
        assert!(encode(&frame, false, &[40])
            .unwrap_err()
            .contains("1 global"));
        let nan = Frame {
            device_depth: vec![f32::NAN, 1.0],
            ..frame.clone()
        };
        assert!(encode(&nan, false, &[40, 41])
            .unwrap_err()
            .contains("outside [0, 1]"));
    }

    #[test]
    fn merging_keeps_the_nearer_pixel() {
        let near = [key(0.2, false, 7), 1, 2, 3];
        let far = [key(0.3, false, 1), 4, 5, 6];
        let mut mine = far.to_vec();
        merge(&mut mine, &near);
        assert_eq!(mine, near);
        merge(&mut mine, &far);
        assert_eq!(mine, near);
    }
}
