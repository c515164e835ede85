//! The colour output checked in float64: every covered pixel's colour is the renderer's
//! shading model (Blinn-Phong, a head-light and a key light fixed to the camera; design §4.8)
//! evaluated at the pixel's read-back normal for its glyph's colour, and every empty pixel is
//! the background. The geometry (coverage, IDs, depth, normals) is checked against the
//! reference by [`compare`](mod@crate::compare); this isolates the shading arithmetic and the sRGB store,
//! so a colour can be held to one level whatever the driver.

use std::fmt;

use ellipsoid_splat::internals::BACKGROUND;
use ellipsoid_splat::{Camera, Error, Frame, Material, Result, Scene, NO_INSTANCE};
use glam::DVec3;

/// The key light's direction in view axes (right, up, towards the viewer).
const KEY: DVec3 = DVec3::new(-0.45, 0.65, 0.6);
/// Below this, the key light's cosine is too close to zero for float32 to decide whether
/// the key's highlight is on, and either answer is accepted: the shader's float32 dot product
/// of unit vectors errs by a few 2^-24 (about 2e-7), taken here with a margin of 50.
const KEY_EDGE: f64 = 1e-5;

/// How a frame's colours compare with the shading model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ColorStats {
    /// Covered pixels shaded and compared.
    pub shaded_pixels: usize,
    /// Empty pixels compared with the background.
    pub background_pixels: usize,
    /// Largest difference of a channel from the model, in 8-bit levels (alpha included).
    pub max_level_error: u8,
    /// Pixels off by more than one level in some channel.
    pub off_pixels: usize,
    /// The first such pixel, for the report: index, got, expected.
    pub first_off: Option<(usize, [u8; 4], [u8; 4])>,
}

impl ColorStats {
    /// Ok when every pixel is within one level of the model: float32 shading and the
    /// hardware's sRGB encoding may each round once.
    pub fn check(&self) -> Result<(), String> {
        match self.first_off {
            None => Ok(()),
            Some((k, got, want)) => Err(format!(
                "{} pixels' colours differ from the shading model by more than one level (up \
                 to {}); the first, pixel {k}: {got:?}, expected {want:?}",
                self.off_pixels, self.max_level_error
            )),
        }
    }
}

impl fmt::Display for ColorStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "colour: {} shaded + {} background pixels, max error {} levels, {} off by more \
             than one",
            self.shaded_pixels, self.background_pixels, self.max_level_error, self.off_pixels
        )
    }
}

/// Compares `frame`'s colours with `material`'s shading of `scene` seen by `camera`, the
/// frame's own normals and IDs deciding what each pixel shows. For frames of one sample per
/// pixel: a resolved multisampled pixel mixes its samples' colours.
pub fn compare_colors(
    frame: &Frame,
    scene: &Scene,
    camera: &Camera,
    material: &Material,
) -> Result<ColorStats> {
    let pixels = frame.len();
    if [frame.color.len(), frame.normal.len(), frame.id.len()] != [pixels; 3] {
        return Err(Error::invalid(
            "frame",
            "colour, normal and ID outputs must all be read back",
        ));
    }
    let background = encode([
        BACKGROUND[0] as f64,
        BACKGROUND[1] as f64,
        BACKGROUND[2] as f64,
    ]);
    let mut stats = ColorStats::default();
    for k in 0..pixels {
        let got = frame.color[k];
        let candidates = match frame.id[k] {
            NO_INSTANCE => {
                stats.background_pixels += 1;
                [background; 2]
            }
            id => {
                let glyph = scene.ellipsoids.get(id as usize).ok_or_else(|| {
                    Error::invalid(
                        "frame",
                        format!("pixel {k} shows glyph {id}, beyond the scene's last"),
                    )
                })?;
                stats.shaded_pixels += 1;
                let normal = DVec3::from(frame.normal[k].map(f64::from));
                shade(camera, material, glyph.color, normal).map(encode)
            }
        };
        let error = candidates
            .iter()
            .fold(u8::MAX, |best, want| best.min(level_error(got, *want)));
        stats.max_level_error = stats.max_level_error.max(error);
        if error > 1 {
            stats.off_pixels += 1;
            stats.first_off.get_or_insert((k, got, candidates[0]));
        }
    }
    Ok(stats)
}

fn level_error(a: [u8; 4], b: [u8; 4]) -> u8 {
    (0..4).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0)
}

/// The linear colour of a glyph of sRGB colour `color` (as the instance packs it: eight bits
/// a channel) with unit world normal `normal`: two answers, which differ only where float32
/// cannot decide whether the key's highlight is on.
fn shade(camera: &Camera, material: &Material, color: [f32; 3], normal: DVec3) -> [[f64; 3]; 2] {
    let base = color.map(|c| srgb_to_linear((c.clamp(0.0, 1.0) * 255.0).round() as f64 / 255.0));
    let b = camera.basis();
    let nv = DVec3::new(
        normal.dot(b.right),
        normal.dot(b.up),
        -normal.dot(b.forward),
    );
    let key = KEY.normalize();
    let half_key = (key + DVec3::Z).normalize();
    let shininess = material.shininess as f64;
    let (ka, kd, ks) = (
        material.ambient as f64,
        material.diffuse as f64,
        material.specular as f64,
    );
    let head = nv.z.max(0.0);
    let side = nv.dot(key).max(0.0);
    let spec_head = specular_lobe(head, shininess);
    let spec_key = specular_lobe(nv.dot(half_key).max(0.0), shininess);
    let with_key_highlight = |on: bool| {
        let spec_side = if on { spec_key } else { 0.0 };
        std::array::from_fn(|c| {
            let s = material.specular_color[c] as f64;
            ka * base[c]
                + 0.55 * (kd * head * base[c] + ks * spec_head * s)
                + 0.6 * (kd * side * base[c] + ks * spec_side * s)
        })
    };
    if nv.dot(key).abs() < KEY_EDGE {
        [with_key_highlight(true), with_key_highlight(false)]
    } else {
        [with_key_highlight(side > 0.0); 2]
    }
}

/// Schlick's rational stand-in for `x^n`, as the shaders have it.
fn specular_lobe(x: f64, n: f64) -> f64 {
    x / (n - n * x + x)
}

fn srgb_to_linear(c: f64) -> f64 {
    if c > 0.04045 {
        ((c + 0.055) / 1.055).powf(2.4)
    } else {
        c / 12.92
    }
}

fn linear_to_srgb(c: f64) -> f64 {
    if c > 0.003_130_8 {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    } else {
        12.92 * c
    }
}

/// What an sRGB RGBA8 target stores for a linear colour of alpha 1.
fn encode(linear: [f64; 3]) -> [u8; 4] {
    let level = |c: f64| (linear_to_srgb(c.clamp(0.0, 1.0)) * 255.0).round() as u8;
    [level(linear[0]), level(linear[1]), level(linear[2]), 255]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_and_meets_its_anchor_points() {
        for level in 0..=255u8 {
            let c = level as f64 / 255.0;
            assert!((linear_to_srgb(srgb_to_linear(c)) - c).abs() < 1e-12);
        }
        assert_eq!(encode([0.0, 1.0, 0.5]), [0, 255, 188, 255]);
    }

    #[test]
    fn a_normal_facing_the_viewer_takes_ambient_head_light_and_its_full_highlight() {
        let camera = Camera::look_at(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, 45.0, 0.1, 8, 8)
            .expect("camera");
        let material = Material::default();
        let shaded = shade(&camera, &material, [1.0, 0.0, 0.0], DVec3::Z);
        // nv = (0, 0, 1): head = 1 (lobe 1), side = 0.6 / |KEY| > 0.
        let side = 0.6 / KEY.length();
        let half = (KEY.normalize() + DVec3::Z).normalize();
        let lobe = specular_lobe(half.z, 40.0);
        let red = 0.15 + 0.55 * (0.75 + 0.4) + 0.6 * (0.75 * side + 0.4 * lobe);
        let green = 0.55 * 0.4 + 0.6 * 0.4 * lobe;
        // The material's weights are float32: equal to about 1e-8.
        assert_eq!(shaded[0], shaded[1], "the key light is decidable here");
        assert!((shaded[0][0] - red).abs() < 1e-6, "{shaded:?}");
        assert!((shaded[0][1] - green).abs() < 1e-6, "{shaded:?}");
    }
}
