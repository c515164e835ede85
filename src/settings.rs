//! What a host may tune: the material, the exact work-skipping the renderer does, and how
//! instances are stored. Each setting is safe to leave at its default; the work-skipping
//! changes no pixel, the material and the compact instance format do.

use crate::culling::Culling;
use crate::error::{Error, Result};
use crate::instances::InstanceFormat;
use crate::path::PlanMode;

/// Blinn-Phong material after Gumhold 2003: ambient, diffuse, specular, shininess, specular
/// colour.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Material {
    /// Ambient weight.
    pub ambient: f32,
    /// Diffuse weight.
    pub diffuse: f32,
    /// Specular weight.
    pub specular: f32,
    /// Phong exponent.
    pub shininess: f32,
    /// Colour of highlights.
    pub specular_color: [f32; 3],
}

impl Default for Material {
    fn default() -> Self {
        Self {
            ambient: 0.15,
            diffuse: 0.75,
            specular: 0.4,
            shininess: 40.0,
            specular_color: [1.0, 1.0, 1.0],
        }
    }
}

impl Material {
    /// Checks that shading can use every field: weights finite and at least 0, shininess
    /// finite and above 0, a highlight colour finite and at least 0. The fields are public,
    /// so a host may have written anything; the renderer refuses a frame (and a new
    /// renderer) with such a material rather than push NaN into every pixel.
    pub(crate) fn validate(&self) -> Result<()> {
        let weight = |v: f32| v.is_finite() && v >= 0.0;
        let why = |what: &str, value: String| {
            Err(Error::invalid(
                format!("material {what}"),
                format!("{value}: weights must be finite and >= 0, shininess finite and > 0"),
            ))
        };
        for (what, value) in [
            ("ambient", self.ambient),
            ("diffuse", self.diffuse),
            ("specular", self.specular),
        ] {
            if !weight(value) {
                return why(what, value.to_string());
            }
        }
        if !(self.shininess.is_finite() && self.shininess > 0.0) {
            return why("shininess", self.shininess.to_string());
        }
        if !self.specular_color.iter().all(|&c| weight(c)) {
            return why("specular colour", format!("{:?}", self.specular_color));
        }
        Ok(())
    }

    /// Unlit: every pixel shows its glyph's colour as it is (ambient 1, no diffuse or specular
    /// light). With white glyphs, a resolved multisampled pixel is the covered fraction of its
    /// samples over the background: what the coverage checks measure.
    pub fn unlit() -> Self {
        Self {
            ambient: 1.0,
            diffuse: 0.0,
            specular: 0.0,
            ..Self::default()
        }
    }
}

/// How the renderer draws: the material and which exact shortcuts it may take. Given at
/// creation ([`crate::RendererOptions::settings`]) or later through
/// [`crate::EllipsoidRenderer::set_settings`], which says what each change costs. A material
/// shading cannot use (a weight not finite or below 0, shininess not above 0) is refused by
/// name: by `EllipsoidRenderer::new`, and by every plan made while it is in force.
///
/// `Settings` (`src/settings.rs`), given in `RendererOptions::settings` or later through
/// `set_settings`. Every field has a safe default; none but `material` and
/// `instance_format` changes a pixel:
///
/// | field | default | what it does | a change takes effect |
/// |---|---|---|---|
/// | `material` | `Material::default()`: ambient 0.15, diffuse 0.75, specular 0.4, shininess 40, white highlights | the shading (design §4.8); a weight not finite or below 0, or shininess not above 0, is refused by `new` and by every plan while in force (`Error::Invalid`, "material ambient" ...) | at the next `record`; push constants, free |
/// | `culling` | `Culling::ON` (`frustum`, `pixel_centres`, `occlusion`) | which exact culling the pre-pass does (design §5.3) | at the next frame |
/// | `setup_once` | on | the pre-pass sets small glyphs up once for the draw (design §5.3), and the compute splat each glyph with a hit for its resolve where the scene's glyphs are few enough for the image (design §5.6) | at the next frame |
/// | `cap_free_path` | on | the `NO_CAPS` variant when nothing reaches the near plane (design §4.6) | at the next frame |
/// | `small_glyph_triangles` | off | the triangle footprint for glyphs of a few pixels (design §5.1) | at the next frame |
/// | `instance_format` | `InstanceFormat::Full` | 48-byte float32 or 32-byte compact instances ([`crate::InstanceFormat`]) | at the next `upload` |
/// | `plan` | `PlanMode::Measure` | how the plan chooses among the exact paths that can serve a frame -- the draw, the compute splat (design §5.6), the visible-first splat (design §5.7): by timing them on this device, by the first guess alone, or fixed (design §5.8) | at the next frame |
/// | `per_sample_shading` | off | on multisampled targets, shade every sample (exact depth per sample) instead of once per pixel with exact per-sample coverage and one depth, the nearest covered sample's ([`crate::Target`]) | builds pipelines on first use |
/// | `max_chunk_instances` | `u32::MAX` | the most instances per descriptor set (design §5.4) | set it before an `upload` |
///
/// A change that takes effect at the next frame may select a pipeline variant not built yet;
/// it is built on first use (the draw's ahead of recording by `prepare_for`), and kept.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Settings {
    /// Shading parameters.
    pub material: Material,
    /// Culling done by the pre-pass (all kinds by default; each is exact).
    pub culling: Culling,
    /// For glyphs of a few pixels, compute each impostor's set-up once in the pre-pass
    /// instead of in each of its vertices; in a splatted frame, store each glyph's set-up
    /// for the resolve instead of setting up each pixel's glyph again (on by default).
    pub setup_once: bool,
    /// Leave out the near-plane cap code when no ellipsoid reaches in front of the near
    /// plane (on by default).
    pub cap_free_path: bool,
    /// Draw glyphs of a few pixels as one triangle instead of the oriented rectangle on
    /// single-sample targets. Off by default: fewer vertices and primitives, but 1.65 shaded
    /// fragments per covered pixel instead of 1.27. On multisampled targets `Auto` takes the
    /// triangle below the same size whatever this says (`Footprint::for_area_multisampled`
    /// in `src/footprint.rs`).
    pub small_glyph_triangles: bool,
    /// How `upload` stores instances: full float32 (default) or the compact 32-byte records,
    /// a third less memory at a measured accuracy cost.
    pub instance_format: InstanceFormat,
    /// How the frame plan chooses among the exact paths that can serve a frame -- the
    /// draw, the compute splat, the visible-first splat ([`crate::FramePath`]): by
    /// measuring them on this device (the default), by its first guess alone, or as fixed.
    /// Every path draws the same picture (bit for bit on lavapipe; within the float64
    /// reference's bounds on any driver), so the choice costs time, never a pixel.
    pub plan: PlanMode,
    /// The most instances drawn with one descriptor set; the device's
    /// `maxStorageBufferRange` and `maxTexelBufferElements` cap it anyway. Larger scenes are drawn in chunks, each with
    /// its own pre-pass and draw. Rounded down to a multiple of 256 (at least 256). Takes
    /// effect at the next `upload`.
    pub max_chunk_instances: u32,
    /// On multisampled targets, run the fragment stage at every sample (sample-rate
    /// shading): each sample gets its own hit and depth, so host meshes intersect the glyphs
    /// exactly per sample, at about the sample count times the cost of one sample. Off by
    /// default: the fragment stage runs once per pixel, decides exactly which sample
    /// positions the glyph covers (by the silhouette's quadratic form, or the full hit where
    /// a cap or far plane may cut the glyph or the view is orthographic) and writes them in
    /// `gl_SampleMask`, and writes
    /// one depth per pixel, the nearest of the covered samples' (a glyph in front of host
    /// geometry at every sample it covers shows at all of them); it shades at that sample.
    /// Silhouettes are exact per sample;
    /// where a glyph and a host mesh cross, a pixel's samples may fall on the wrong side.
    /// Devices without the standard sample locations, and sample counts other than 2 and 4,
    /// always shade per sample.
    pub per_sample_shading: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            material: Material::default(),
            culling: Culling::default(),
            setup_once: true,
            cap_free_path: true,
            small_glyph_triangles: false,
            plan: PlanMode::Measure,
            instance_format: InstanceFormat::Full,
            max_chunk_instances: u32::MAX,
            per_sample_shading: false,
        }
    }
}
