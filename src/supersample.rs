//! Supersampling (`render --supersample K`, the Python package's `supersample=K`): the frame drawn K times larger in each direction, then every K x K
//! block of samples averaged into one pixel in linear light -- an exact box filter over a
//! regular K x K grid of sample positions, `(i + (s + 0.5) / K, j + (t + 0.5) / K)` for
//! `s, t` in `0..K`. Each sample is exact (the renderer's per-pixel contract), so a pixel's
//! colour is the exact coverage-weighted mean of what its K^2 samples show.
//!
//! Depth, normal and ID cannot be averaged: each output pixel holds the one sample at block
//! offset `(K / 2, K / 2)` (integer division), at `(K / 2 + 0.5) / K` of the pixel -- its
//! centre for odd K, half a sample right of and below it for even K.

use crate::camera::{Camera, Intrinsics, Projection};
use crate::error::{Error, Result};
use crate::frame::Frame;

/// The largest K: 64 samples per pixel.
pub const MAX_SUPERSAMPLE: u32 = 8;

/// The camera that draws `camera`'s view with K x K samples per pixel: the same view, K times
/// the pixels in each direction.
pub fn supersampled_camera(camera: &Camera, k: u32) -> Result<Camera> {
    let (width, height) = (camera.width.checked_mul(k), camera.height.checked_mul(k));
    let (Some(width), Some(height)) = (width, height) else {
        return Err(Error::invalid("supersample", "the image size overflows"));
    };
    // K times as many pixels per unit of the image plane: intrinsics, jitter and the
    // viewport's origin scale with the image.
    let k_f = k as f64;
    let scale = |i: Intrinsics| Intrinsics {
        fx: i.fx * k_f,
        fy: i.fy * k_f,
        cx: i.cx * k_f,
        cy: i.cy * k_f,
    };
    let projection = match camera.projection {
        Projection::PerspectiveIntrinsics(i) => Projection::PerspectiveIntrinsics(scale(i)),
        Projection::OrthographicIntrinsics(i) => Projection::OrthographicIntrinsics(scale(i)),
        centred => centred,
    };
    let camera = Camera {
        width,
        height,
        projection,
        jitter: camera.jitter * k_f,
        viewport_origin: camera.viewport_origin.map(|v| v * k),
        ..*camera
    };
    camera.validate()?;
    Ok(camera)
}

/// sRGB-encoded byte to linear light.
pub fn srgb_to_linear(byte: u8) -> f64 {
    let c = byte as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light in [0, 1] to the nearest sRGB-encoded byte.
pub fn linear_to_srgb(value: f64) -> u8 {
    let v = value.clamp(0.0, 1.0);
    let c = if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0).round() as u8
}

/// `frame`, drawn with K x K samples per pixel, filtered to its output size (see the module
/// documentation); outputs `frame` lacks stay empty.
pub fn box_filter(frame: &Frame, k: u32) -> Result<Frame> {
    if k == 0 || frame.width % k != 0 || frame.height % k != 0 {
        return Err(Error::invalid(
            "supersample",
            format!(
                "a {}x{} frame has no whole {k}x{k} blocks",
                frame.width, frame.height
            ),
        ));
    }
    let (width, height) = (frame.width / k, frame.height / k);
    let to_linear: Vec<f64> = (0..=255u8).map(srgb_to_linear).collect();
    let samples = (k * k) as f64;
    let pixels = width as usize * height as usize;
    let mut out = Frame {
        width,
        height,
        color: Vec::with_capacity(if frame.color.is_empty() { 0 } else { pixels }),
        depth: Vec::with_capacity(if frame.depth.is_empty() { 0 } else { pixels }),
        device_depth: Vec::with_capacity(if frame.device_depth.is_empty() {
            0
        } else {
            pixels
        }),
        normal: Vec::with_capacity(if frame.normal.is_empty() { 0 } else { pixels }),
        id: Vec::with_capacity(if frame.id.is_empty() { 0 } else { pixels }),
    };
    for j in 0..height {
        for i in 0..width {
            if !frame.color.is_empty() {
                let mut sum = [0.0f64; 4];
                for t in 0..k {
                    for s in 0..k {
                        let texel = frame.color[frame.index(i * k + s, j * k + t)];
                        for (c, total) in sum.iter_mut().enumerate().take(3) {
                            *total += to_linear[texel[c] as usize];
                        }
                        sum[3] += texel[3] as f64;
                    }
                }
                out.color.push([
                    linear_to_srgb(sum[0] / samples),
                    linear_to_srgb(sum[1] / samples),
                    linear_to_srgb(sum[2] / samples),
                    (sum[3] / samples).round() as u8,
                ]);
            }
            let held = frame.index(i * k + k / 2, j * k + k / 2);
            if !frame.depth.is_empty() {
                out.depth.push(frame.depth[held]);
            }
            if !frame.device_depth.is_empty() {
                out.device_depth.push(frame.device_depth[held]);
            }
            if !frame.normal.is_empty() {
                out.normal.push(frame.normal[held]);
            }
            if !frame.id.is_empty() {
                out.id.push(frame.id[held]);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_byte() {
        for byte in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(byte)), byte);
        }
    }

    /// One white sample of four over black is a quarter of the light: sRGB 0.537, byte 137
    /// (not 64, the mean of the encoded bytes); the held sample is block offset (1, 1).
    #[test]
    fn blocks_average_in_linear_light() {
        let frame = Frame {
            width: 2,
            height: 2,
            color: vec![
                [255, 255, 255, 255],
                [0, 0, 0, 255],
                [0, 0, 0, 255],
                [0, 0, 0, 255],
            ],
            depth: vec![1.0, 2.0, 3.0, 4.0],
            device_depth: vec![0.1, 0.2, 0.3, 0.4],
            normal: vec![[0.0; 3]; 4],
            id: vec![7, 8, 9, 10],
        };
        let out = box_filter(&frame, 2).unwrap();
        assert_eq!((out.width, out.height), (1, 1));
        assert_eq!(out.color, vec![[137, 137, 137, 255]]);
        assert_eq!((out.depth[0], out.id[0]), (4.0, 10));
        assert_eq!(out.device_depth, [0.4]);
        assert!(box_filter(&frame, 3).is_err());
    }
}
