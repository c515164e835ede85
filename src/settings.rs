//! What a host may tune: the material, the exact work-skipping the renderer does, and how
//! instances are stored. Each setting is safe to leave at its default; the work-skipping
//! changes no pixel, the material and the compact instance format do.

use crate::culling::Culling;
use crate::instances::InstanceFormat;

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
/// [`crate::EllipsoidRenderer::set_settings`], which says what each change costs.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Settings {
    /// Shading parameters.
    pub material: Material,
    /// Culling done by the pre-pass (all kinds by default; each is exact).
    pub culling: Culling,
    /// For glyphs of a few pixels, compute each impostor's set-up once in the pre-pass
    /// instead of in each of its vertices (on by default).
    pub setup_once: bool,
    /// Take the sphere path when every instance uploaded is a sphere (on by default).
    pub sphere_path: bool,
    /// Leave out the near-plane cap code when no ellipsoid reaches in front of the near
    /// plane (on by default).
    pub cap_free_path: bool,
    /// Draw glyphs of a few pixels as one triangle instead of the oriented rectangle on
    /// single-sample targets. Off by default: fewer vertices and primitives, but 1.65 shaded
    /// fragments per covered pixel instead of 1.27. On multisampled targets `Auto` takes the
    /// triangle below the same size whatever this says
    /// ([`crate::draw::Footprint::for_area_multisampled`]).
    pub small_glyph_triangles: bool,
    /// How `upload` stores instances: full float32 (default) or the compact 32-byte records,
    /// a third less memory at a measured accuracy cost.
    pub instance_format: InstanceFormat,
    /// Draw frames of many small and medium glyphs without the rasterizer: a compute pass ray
    /// casts each glyph's pixel centres and keeps the nearest hit per pixel with a 64-bit
    /// atomic, and a pass inside the host's pass shades each covered pixel once; glyphs too
    /// large for it (a box of more than 4,096 pixel centres, or reaching the eye plane) are
    /// drawn in the same frame. The same pixels, depths and IDs as the draw (bit for bit where
    /// the driver compiles the shared set-up and hit alike in every stage, as lavapipe does;
    /// only where a splatted and a drawn glyph lie at exactly the same depth does the
    /// splatted one show rather than the lower instance). On by default for the shipped
    /// impostor with the automatic footprint, but it runs only where the host enabled
    /// [`crate::DeviceFeatures::COMPUTE_SPLAT`] (and says so in
    /// [`crate::HostDevice::enabled_features`]), on single-sample targets with
    /// float32 depth, for glyphs of at most `SPLAT_MAX_MEAN_AREA_PX` on average (in the size
    /// sample), for at most `MAX_SPLAT_CHUNKS` chunks and for at least
    /// `compute_splat_min_glyphs` glyphs.
    pub compute_splat: bool,
    /// In frames the compute splat takes (one chunk, occlusion culling on) of a camera held
    /// still, splat first the glyphs an earlier frame with that camera showed (a frame whose
    /// camera is the frame before's stamps them), then only those of the others whose every
    /// pixel is not already held by a nearer hit of the first pass (tested per tile of 4 x 4
    /// pixels, each glyph as a whole, before any ray cast). On by default; the same pixels bit
    /// for bit; it pays where many glyphs lie hidden (README, "Skipping the hidden layers"),
    /// and is taken only where each glyph is expected to hide at least
    /// `visible_first_min_hidden_px`.
    pub visible_first: bool,
    /// The least area per glyph, in square pixels, that the scene is expected to hide for the
    /// visible-first splat to run ([`crate::FramePlan::hidden_area_px`]: the mean projected
    /// area times `1 - 1 / layers`): it saves the hidden glyphs' ray casts, and its own steps
    /// (three compactions, the tiles, the stamps) cost about the same per glyph whatever its
    /// size. 45 by default: on lavapipe the tensor field at 1280x720 (31 px^2 hidden per
    /// glyph) is 16 % slower with it, at 1600x900 (49 px^2) 6 % faster (README).
    pub visible_first_min_hidden_px: f64,
    /// The fewest glyphs for which the compute splat pays: it has a fixed cost (clearing the
    /// visibility buffer and resolving the tiles its glyphs touch, about 30 ms when they
    /// spread over a whole 1920x1080 image on lavapipe) and saves about 0.45 us per glyph;
    /// measured with `bench`, the two meet between 10,000 and 100,000.
    pub compute_splat_min_glyphs: u32,
    /// The most instances drawn with one descriptor set; the device's
    /// `maxStorageBufferRange` caps it anyway. Larger scenes are drawn in chunks, each with
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
            sphere_path: true,
            cap_free_path: true,
            small_glyph_triangles: false,
            compute_splat: true,
            visible_first: true,
            visible_first_min_hidden_px: 45.0,
            compute_splat_min_glyphs: 50_000,
            instance_format: InstanceFormat::Full,
            max_chunk_instances: u32::MAX,
            per_sample_shading: false,
        }
    }
}
