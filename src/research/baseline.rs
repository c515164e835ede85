//! The benchmark's baselines: other geometry, footprints, intersections and fragment work
//! than the shipped impostor's, drawable for comparison. A [`DrawConfig`] other than the
//! default is a baseline: the frame plan then draws it (`DrawReason::Baseline`), and the
//! pipelines, pre-pass and draw ask it what differs.

use ash::vk;

use crate::error::{Error, Result};
use crate::footprint::Footprint as ShippedFootprint;
use crate::gpu::shaders::{self, FragmentShader};
use crate::gpu_layout::SpecConstants;
use crate::renderer::pipelines::raster::Raster;
use crate::target::{Pass, Target};

use super::shaders as research_shaders;

/// How the fragment shader intersects the pixel's ray with the ellipsoid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Intersection {
    /// Gumhold's closed form in the silhouette frame: no cancellation at any distance.
    #[default]
    Stable,
    /// The textbook quadratic `b^2 - ac` in parameter space, in float32: the baseline that
    /// shows what the stable form buys (it loses hits and normals at large distance/radius).
    Textbook,
}

/// The screen-space polygon each impostor is drawn as.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Footprint {
    /// Chosen per frame from the glyphs' mean projected area, as shipped.
    #[default]
    Auto,
    /// Always the triangle.
    Triangle,
    /// Always the oriented rectangle.
    OrientedRect,
    /// Always the hexagon.
    Hexagon,
    /// Always the octagon.
    Octagon,
    /// The axis-aligned bounding rectangle of the projected ellipse (loose for thin glyphs at
    /// 45 degrees).
    AxisRect,
    /// Gumhold's square around the silhouette circle in the silhouette plane, projected.
    WorldQuad,
}

impl Footprint {
    /// The polygon drawn where the plan chose `chosen`.
    fn polygon(self, chosen: ShippedFootprint) -> Option<ShippedFootprint> {
        match self {
            Footprint::Auto => Some(chosen),
            Footprint::Triangle => Some(ShippedFootprint::Triangle),
            Footprint::OrientedRect => Some(ShippedFootprint::OrientedRect),
            Footprint::Hexagon => Some(ShippedFootprint::Hexagon),
            Footprint::Octagon => Some(ShippedFootprint::Octagon),
            Footprint::AxisRect | Footprint::WorldQuad => None,
        }
    }

    /// The `BOUNDS` specialization constant (`glsl/include/instance_setup.glsl`).
    fn bounds_mode(self) -> u32 {
        match self {
            Footprint::AxisRect => 1,
            Footprint::WorldQuad => 2,
            _ => 0,
        }
    }
}

/// What the impostor's fragment stage computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Shading {
    /// Exact hit, unit normal and per-fragment depth (shipped).
    #[default]
    Exact,
    /// Herbison-Evans' modulus-normalised gradient instead of a unit normal (no square root).
    FastNormal,
    /// No per-fragment depth: the quad's nearest-point depth stands.
    FlatDepth,
    /// No ray cast, no discard, no depth: the rasterizer's limit for the footprint.
    FlatFill,
    /// The exact hit, kept per pixel in the compute splat's visibility buffer instead of
    /// shaded (no colour, no depth export), in a pass of its own before the host's; the
    /// splat's resolve then shades each visible pixel once.
    VisibilityBuffer,
}

/// What stands in for each ellipsoid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Geometry {
    /// A screen-space polygon, ray-cast per pixel (shipped).
    #[default]
    Impostor,
    /// The oriented bounding box as 12 triangles, ray-cast inside (textbook intersection).
    BoxProxy,
    /// An icosphere of subdivision level 0..=4 (20 ... 5120 triangles); perspective only.
    Mesh(u32),
}

/// One complete way of drawing the ellipsoids; the default is the shipped impostor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DrawConfig {
    /// Stand-in geometry.
    pub geometry: Geometry,
    /// Screen polygon of an impostor.
    pub footprint: Footprint,
    /// Ray/ellipsoid intersection of an impostor.
    pub intersection: Intersection,
    /// Fragment work of an impostor.
    pub shading: Shading,
}

/// A baseline: a `DrawConfig` other than the default.
pub(crate) type Baseline = DrawConfig;

impl DrawConfig {
    /// The baseline this configuration draws, `None` for the shipped impostor.
    pub(crate) fn baseline(self) -> Option<Baseline> {
        (self != DrawConfig::default()).then_some(self)
    }

    /// An error if the camera's projection is one the baseline cannot draw.
    pub(crate) fn check_camera(self, orthographic: bool) -> Result<()> {
        if orthographic && self.geometry != Geometry::Impostor {
            return Err(Error::invalid(
                "draw configuration",
                format!("{:?} supports perspective cameras only", self.geometry),
            ));
        }
        Ok(())
    }

    /// Whether the pre-pass's culling proofs hold for it (they assume the exact hit's
    /// coverage and depth; flat fill covers whole polygons).
    pub(crate) fn through_prepass(self) -> bool {
        self.geometry == Geometry::Impostor
            && self.intersection == Intersection::Stable
            && self.shading != Shading::FlatFill
    }

    /// Whether its stages can read a set-up computed once (the exact fragment stage, an
    /// n-gon or axis-rectangle footprint).
    pub(crate) fn setup_once_allowed(self) -> bool {
        self.through_prepass()
            && matches!(self.shading, Shading::Exact | Shading::FastNormal)
            && self.footprint != Footprint::WorldQuad
    }

    /// The visibility-buffer draw: a pass of its own in the pre-pass, then the resolve.
    pub(crate) fn visibility_draw(self) -> bool {
        self.geometry == Geometry::Impostor && self.shading == Shading::VisibilityBuffer
    }

    /// Vertices per instance of an impostor drawn where the plan chose `chosen`.
    pub(crate) fn vertices(self, chosen: ShippedFootprint) -> u32 {
        self.footprint
            .polygon(chosen)
            .map_or(4, ShippedFootprint::vertices)
    }

    /// Sets the specialization constants it changes (intersection, footprint, normal).
    pub(crate) fn specialize(self, chosen: ShippedFootprint, constants: &mut SpecConstants) {
        constants.textbook = (self.intersection == Intersection::Textbook) as u32;
        constants.bounds = self.footprint.bounds_mode();
        constants.corners = self.vertices(chosen);
        constants.fast_normal = (self.shading == Shading::FastNormal) as u32;
    }

    /// The SPIR-V of its vertex stage and its fragment shader's builds.
    pub(crate) fn stages(self, setup_once: bool) -> Result<(&'static [u8], FragmentShader)> {
        Ok(match (self.geometry, self.shading) {
            (Geometry::Impostor, Shading::Exact | Shading::FastNormal) if setup_once => (
                shaders::ELLIPSOID_SETUP_ONCE_VERT,
                shaders::ELLIPSOID_SETUP_ONCE_FRAG,
            ),
            (Geometry::Impostor, Shading::Exact | Shading::FastNormal) => {
                (shaders::ELLIPSOID_VERT, shaders::ELLIPSOID_FRAG)
            }
            (Geometry::Impostor, Shading::FlatDepth) => (
                shaders::ELLIPSOID_VERT,
                research_shaders::ELLIPSOID_FLAT_DEPTH_FRAG,
            ),
            (Geometry::Impostor, Shading::VisibilityBuffer) => (
                shaders::ELLIPSOID_VERT,
                research_shaders::ELLIPSOID_VISIBILITY_FRAG,
            ),
            (Geometry::Impostor, Shading::FlatFill) => {
                (shaders::ELLIPSOID_VERT, research_shaders::FLAT_FILL_FRAG)
            }
            (Geometry::Mesh(_), _) => (research_shaders::MESH_VERT, research_shaders::MESH_FRAG),
            (Geometry::BoxProxy, _) => (research_shaders::BOX_VERT, shaders::ELLIPSOID_FRAG),
        })
    }

    /// What it rasterizes: closed meshes and boxes show only their front faces (their
    /// triangles wind counter-clockwise seen from outside in a y-up view; the y flip into
    /// Vulkan's framebuffer makes that clockwise there); flat fill tests no depth, and the
    /// visibility-buffer draw has no depth attachment (its atomics keep the nearest hit).
    pub(crate) fn raster(self) -> Raster {
        match self.geometry {
            Geometry::Impostor => Raster {
                depth: !matches!(self.shading, Shading::FlatFill | Shading::VisibilityBuffer),
                ..Raster::IMPOSTOR
            },
            Geometry::BoxProxy | Geometry::Mesh(_) => Raster {
                mesh_vertices: matches!(self.geometry, Geometry::Mesh(_)),
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                cull_mode: vk::CullModeFlags::BACK,
                depth: true,
            },
        }
    }

    /// The target its pipeline is built for when it draws in a pass of its own (the
    /// visibility-buffer draw: no attachments at all).
    pub(crate) fn own_pass_target(self) -> Option<Target> {
        self.visibility_draw().then(|| Target {
            pass: Pass::Dynamic {
                color_formats: Vec::new(),
                depth_format: vk::Format::UNDEFINED,
            },
            samples: vk::SampleCountFlags::TYPE_1,
            aux_outputs: false,
        })
    }
}
