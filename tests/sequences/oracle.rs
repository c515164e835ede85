//! The oracle: the offscreen renderer (its own validated device) draws what a host's pass
//! should show -- the model's scene, uploaded with the placement, format and chunk limit of
//! the renderer's last upload, with the pass's settings, samples and cameras -- and each
//! pixel's coverage must agree with the host's picture exactly.
//!
//! Coverage is read from colour: the host clears to black, and the offscreen renderer to a
//! dark blue-grey whose red is about 60 of 255 in sRGB; every glyph's red is 0.9 or more
//! (`glyphs.rs`), so with ambient light alone at 0.15 a pixel with one covered sample of four
//! still shows red above 68 there and above 0 in the host's image.
//!
//! Single-sample passes are compared in colour too: the host's UNORM attachment stores the
//! shaded linear value, the offscreen renderer's sRGB one its encoding, so each covered
//! pixel's channels must decode to the same linear value within their rounding (one level of
//! the host's, one and a half of the sRGB store's). That checks which glyph shows and how it
//! is lit, not only that something does.

use ash::vk;
use ellipsoid_splat::{Camera, Ellipsoid, InstanceFormat, OffscreenRenderer, Outputs, Placement};
use ellipsoid_splat::{Scene, Settings};

/// Offscreen red above this is a covered pixel (the background's is about 60).
const BACKGROUND_RED_BELOW: u8 = 64;

/// What one host pass drew, as the model knows it.
pub struct Pass {
    pub scene: Vec<Ellipsoid>,
    pub placement: Placement,
    pub format: InstanceFormat,
    pub chunk_limit: u32,
    pub settings: Settings,
    pub samples: vk::SampleCountFlags,
    pub extent: (u32, u32),
    /// The cameras whose `record` drew.
    pub cameras: Vec<Camera>,
}

/// Pixels compared and covered.
pub struct Compared {
    pub pixels: u64,
    pub covered: u64,
}

/// Draws `pass` offscreen and compares coverage with the host's RGBA8 pixels.
pub fn compare(
    oracle: &mut OffscreenRenderer,
    pass: &Pass,
    host_rgba: &[u8],
) -> Result<Compared, String> {
    let (width, height) = pass.extent;
    let pixels = (width * height) as usize;
    let host: Vec<bool> = (0..pixels).map(|k| host_rgba[4 * k] > 0).collect();
    let mut offscreen_colors = None;
    let expected = if pass.cameras.is_empty() || pass.scene.is_empty() {
        vec![false; pixels]
    } else {
        let mut settings = pass.settings;
        settings.instance_format = pass.format;
        settings.max_chunk_instances = pass.chunk_limit;
        oracle.set_settings(settings);
        let fail =
            |what: &'static str| move |e: ellipsoid_splat::Error| format!("oracle {what}: {e}");
        oracle
            .set_samples(pass.samples)
            .map_err(fail("set_samples"))?;
        let scene = Scene::new(pass.scene.clone());
        oracle
            .upload_placed(&scene, pass.placement)
            .map_err(fail("upload_placed"))?;
        let mut outputs = Outputs::default();
        outputs.color = true;
        let (frame, _) = oracle
            .render_views(width, height, &pass.cameras, outputs)
            .map_err(fail("render_views"))?;
        let covered = frame
            .color
            .iter()
            .map(|c| c[0] > BACKGROUND_RED_BELOW)
            .collect();
        offscreen_colors = Some(frame.color);
        covered
    };
    let differ: Vec<usize> = (0..pixels).filter(|&k| host[k] != expected[k]).collect();
    if let Some(&first) = differ.first() {
        let (x, y) = (first as u32 % width, first as u32 / width);
        return Err(format!(
            "{} of {pixels} pixels differ in coverage from the offscreen renderer's; the first \
             at ({x}, {y}): host {} (rgba {:?}), offscreen {}",
            differ.len(),
            if host[first] { "covered" } else { "empty" },
            &host_rgba[4 * first..4 * first + 4],
            if expected[first] { "covered" } else { "empty" },
        ));
    }
    if let (Some(colors), vk::SampleCountFlags::TYPE_1) = (&offscreen_colors, pass.samples) {
        let differ: Vec<usize> = (0..pixels)
            .filter(|&k| host[k] && (0..3).any(|c| !same_light(host_rgba[4 * k + c], colors[k][c])))
            .collect();
        if let Some(&first) = differ.first() {
            let (x, y) = (first as u32 % width, first as u32 / width);
            return Err(format!(
                "{} covered pixels differ in colour from the offscreen renderer's; the first at \
                 ({x}, {y}): host (linear) {:?}, offscreen (sRGB) {:?}",
                differ.len(),
                &host_rgba[4 * first..4 * first + 3],
                &colors[first][..3],
            ));
        }
    }
    Ok(Compared {
        pixels: pixels as u64,
        covered: host.iter().filter(|&&c| c).count() as u64,
    })
}

/// Whether a linear 8-bit level and an sRGB 8-bit level can be one shaded value, each
/// rounded once (the sRGB store allowed half a level more).
fn same_light(linear: u8, srgb: u8) -> bool {
    let decode = |v: f64| {
        let v = v.clamp(0.0, 1.0);
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let (lo, hi) = ((linear as f64 - 0.5) / 255.0, (linear as f64 + 0.5) / 255.0);
    let (s_lo, s_hi) = (
        decode((srgb as f64 - 1.5) / 255.0),
        decode((srgb as f64 + 1.5) / 255.0),
    );
    lo <= s_hi + 1e-6 && s_lo <= hi + 1e-6
}
