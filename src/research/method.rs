//! The drawing methods `ellipsoid-splat bench` compares: the shipped renderer under each
//! plan mode, and the baselines. Their names are the `method` column of `results.csv`.

use crate::path::{PathKind, PlanMode};

use super::baseline::{DrawConfig, Footprint, Geometry, Intersection, Shading};
use super::traced::TracedBuild;

/// The drawing methods compared by `ellipsoid-splat bench`; their names are the `method`
/// column of `results.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// The renderer as shipped: the plan measures the paths that can serve the frame and
    /// keeps the fastest (`PlanMode::Measure`).
    Impostor,
    /// Gumhold's world-space quad in the silhouette plane.
    ImpostorWorldQuad,
    /// Always the oriented rectangle (the shipped renderer picks by glyph size).
    ImpostorOrientedRect,
    /// The axis-aligned screen rectangle of the projected ellipse.
    ImpostorAxisRect,
    /// A hexagon around the projected ellipse.
    ImpostorHexagon,
    /// An octagon around the projected ellipse.
    ImpostorOctagon,
    /// The textbook intersection.
    ImpostorTextbook,
    /// Modulus-normalised gradient instead of a unit normal.
    ImpostorFastNormal,
    /// No per-fragment depth correction.
    ImpostorFlatDepth,
    /// The shipped impostor reading 32-byte compact instances (float16 semi-axes, snorm16
    /// rotation) instead of 48-byte float32 ones.
    ImpostorCompact,
    /// The shipped impostor with the plan's first guess only (`PlanMode::Estimate`): what the
    /// plan takes before it has measured anything.
    ImpostorEstimate,
    /// The shipped impostor splatted wherever the splat can run, every glyph
    /// (`PlanMode::Fixed(PathKind::Splat)`): small and medium glyphs are ray cast by a
    /// compute pass and shaded by a resolve over the tiles they touch.
    ImpostorCompute,
    /// The shipped impostor with the visible-first splat wherever it can run
    /// (`PlanMode::Fixed(PathKind::VisibleFirst)`).
    ImpostorVisibleFirst,
    /// The shipped impostor always drawn through the rasterizer
    /// (`PlanMode::Fixed(PathKind::Draw)`).
    ImpostorDraw,
    /// The shipped impostor with every frame drawn as the first frame of its scene with its
    /// camera: no visible-first splat (the benchmark forgets what the frames before showed),
    /// but the frame stamps what it shows, as the first frame after an upload does.
    ImpostorFirstFrame,
    /// The tiled splat wherever the splat can run: each screen tile's glyphs walked by one
    /// workgroup that keeps the tile's keys in registers and writes them once, instead of an
    /// atomic per covered pixel (`research/tiled_splat.comp`).
    ImpostorTiled,
    /// Visibility-buffer shading of the draw: every glyph is drawn without shading into the
    /// visibility buffer, and the resolve shades each visible pixel once.
    ImpostorVisbuffer,
    /// The roofline's memory floor: a compute pass that only reads every instance (frames
    /// that would splat; nothing is drawn).
    FloorMemory,
    /// The roofline's arithmetic floor: the compute splat's ray casts of every pixel centre
    /// without its atomics (frames that would splat; nothing is drawn).
    FloorArithmetic,
    /// The visible-pixel floor: every instance read and set up once, and only the pixels each
    /// glyph shows ray cast, each once (given by the reference's IDs; frames that would
    /// splat; nothing is drawn or kept).
    FloorVisible,
    /// The traced path (research): the compute splat's frames ray cast per pixel along a
    /// bounding-volume hierarchy of the glyphs' boxes with ray queries, the hierarchy built
    /// once per upload (needs `DeviceFeatures::ray_query`).
    ImpostorTraced,
    /// The traced path with its hierarchy built again every frame: against
    /// `impostor-traced`, the build's cost.
    ImpostorTracedRebuild,
    /// Oriented bounding box, ray-cast inside.
    BoxProxy,
    /// Instanced icosphere of the given level.
    Mesh(u32),
    /// Tight quads with a trivial fragment shader.
    FlatFill,
}

impl Method {
    /// Every method, in the order of the tables.
    pub const ALL: [Method; 27] = [
        Method::Impostor,
        Method::ImpostorOrientedRect,
        Method::ImpostorWorldQuad,
        Method::ImpostorAxisRect,
        Method::ImpostorHexagon,
        Method::ImpostorOctagon,
        Method::ImpostorTextbook,
        Method::ImpostorFastNormal,
        Method::ImpostorFlatDepth,
        Method::ImpostorCompact,
        Method::ImpostorEstimate,
        Method::ImpostorCompute,
        Method::ImpostorVisibleFirst,
        Method::ImpostorDraw,
        Method::ImpostorFirstFrame,
        Method::ImpostorTiled,
        Method::ImpostorVisbuffer,
        Method::FloorMemory,
        Method::FloorArithmetic,
        Method::FloorVisible,
        Method::BoxProxy,
        Method::Mesh(0),
        Method::Mesh(1),
        Method::Mesh(2),
        Method::Mesh(3),
        Method::Mesh(4),
        Method::FlatFill,
    ];

    /// The traced path's methods, not in [`Method::ALL`] (they need ray queries, which the
    /// tests' first driver lacks): `bench --methods` names them.
    pub const TRACED: [Method; 2] = [Method::ImpostorTraced, Method::ImpostorTracedRebuild];

    /// When the method builds the traced path's hierarchy (`Off`: it does not trace).
    pub fn traced(self) -> TracedBuild {
        match self {
            Method::ImpostorTraced => TracedBuild::PerUpload,
            Method::ImpostorTracedRebuild => TracedBuild::EveryFrame,
            _ => TracedBuild::Off,
        }
    }

    /// The compute splat's floor the method measures (see `set_splat_floor`; 0: none).
    pub fn splat_floor(self) -> u32 {
        match self {
            Method::FloorMemory => 1,
            Method::FloorArithmetic => 2,
            Method::FloorVisible => 3,
            _ => 0,
        }
    }

    /// Whether the method runs the tiled splat (see `set_tiled_splat`) in place of the
    /// compute splat.
    pub fn tiled_splat(self) -> bool {
        self == Method::ImpostorTiled
    }

    /// The name in `results.csv`.
    pub fn name(self) -> String {
        match self {
            Method::Impostor => "impostor".into(),
            Method::ImpostorWorldQuad => "impostor-world-quad".into(),
            Method::ImpostorOrientedRect => "impostor-oriented-rect".into(),
            Method::ImpostorAxisRect => "impostor-axis-rect".into(),
            Method::ImpostorHexagon => "impostor-hexagon".into(),
            Method::ImpostorOctagon => "impostor-octagon".into(),
            Method::ImpostorTextbook => "impostor-textbook".into(),
            Method::ImpostorFastNormal => "impostor-fast-normal".into(),
            Method::ImpostorFlatDepth => "impostor-flat-depth".into(),
            Method::ImpostorCompact => "impostor-compact".into(),
            Method::ImpostorEstimate => "impostor-estimate".into(),
            Method::ImpostorCompute => "impostor-compute".into(),
            Method::ImpostorVisibleFirst => "impostor-visible-first".into(),
            Method::ImpostorDraw => "impostor-draw".into(),
            Method::ImpostorFirstFrame => "impostor-first-frame".into(),
            Method::ImpostorVisbuffer => "impostor-visbuffer".into(),
            Method::ImpostorTiled => "impostor-tiled".into(),
            Method::FloorMemory => "floor-memory".into(),
            Method::FloorArithmetic => "floor-arithmetic".into(),
            Method::FloorVisible => "floor-visible".into(),
            Method::ImpostorTraced => "impostor-traced".into(),
            Method::ImpostorTracedRebuild => "impostor-traced-rebuild".into(),
            Method::BoxProxy => "box-proxy".into(),
            Method::Mesh(level) => format!("mesh-L{level}"),
            Method::FlatFill => "flat-fill".into(),
        }
    }

    /// The renderer settings of the method: the shipped ones, with compact instances or a
    /// plan mode for the methods that measure them.
    pub fn settings(self) -> crate::Settings {
        let plan = match self {
            Method::ImpostorEstimate => PlanMode::Estimate,
            Method::ImpostorCompute
            | Method::ImpostorTiled
            | Method::FloorMemory
            | Method::FloorArithmetic
            | Method::FloorVisible
            | Method::ImpostorTraced
            | Method::ImpostorTracedRebuild => PlanMode::Fixed(PathKind::Splat),
            Method::ImpostorVisibleFirst => PlanMode::Fixed(PathKind::VisibleFirst),
            Method::ImpostorDraw => PlanMode::Fixed(PathKind::Draw),
            _ => PlanMode::Measure,
        };
        let instance_format = if self == Method::ImpostorCompact {
            crate::InstanceFormat::Compact
        } else {
            crate::InstanceFormat::Full
        };
        crate::Settings {
            plan,
            instance_format,
            ..crate::Settings::default()
        }
    }

    /// The path kind the method fixes, if it fixes one (the candidates `bench` measures the
    /// plan's regret against).
    pub fn fixed_path(self) -> Option<PathKind> {
        match self.settings().plan {
            PlanMode::Fixed(kind)
                if self.splat_floor() == 0
                    && self.traced() == TracedBuild::Off
                    && !self.tiled_splat() =>
            {
                Some(kind)
            }
            _ => None,
        }
    }

    /// The draw configuration that implements the method.
    pub fn config(self) -> DrawConfig {
        let base = DrawConfig::default();
        match self {
            Method::Impostor
            | Method::ImpostorCompact
            | Method::ImpostorEstimate
            | Method::ImpostorCompute
            | Method::ImpostorVisibleFirst
            | Method::ImpostorDraw
            | Method::ImpostorFirstFrame
            | Method::ImpostorTiled
            | Method::FloorMemory
            | Method::FloorArithmetic
            | Method::FloorVisible
            | Method::ImpostorTraced
            | Method::ImpostorTracedRebuild => base,
            Method::ImpostorWorldQuad => DrawConfig {
                footprint: Footprint::WorldQuad,
                ..base
            },
            Method::ImpostorOrientedRect => DrawConfig {
                footprint: Footprint::OrientedRect,
                ..base
            },
            Method::ImpostorAxisRect => DrawConfig {
                footprint: Footprint::AxisRect,
                ..base
            },
            Method::ImpostorHexagon => DrawConfig {
                footprint: Footprint::Hexagon,
                ..base
            },
            Method::ImpostorOctagon => DrawConfig {
                footprint: Footprint::Octagon,
                ..base
            },
            Method::ImpostorTextbook => DrawConfig {
                intersection: Intersection::Textbook,
                ..base
            },
            Method::ImpostorFastNormal => DrawConfig {
                shading: Shading::FastNormal,
                ..base
            },
            Method::ImpostorFlatDepth => DrawConfig {
                shading: Shading::FlatDepth,
                ..base
            },
            Method::ImpostorVisbuffer => DrawConfig {
                shading: Shading::VisibilityBuffer,
                ..base
            },
            Method::BoxProxy => DrawConfig {
                geometry: Geometry::BoxProxy,
                intersection: Intersection::Textbook,
                ..base
            },
            Method::Mesh(level) => DrawConfig {
                geometry: Geometry::Mesh(level),
                ..base
            },
            Method::FlatFill => DrawConfig {
                shading: Shading::FlatFill,
                ..base
            },
        }
    }
}
