//! What a draw does: which geometry stands in for each ellipsoid, which screen polygon bounds
//! an impostor, how the ray is intersected and what the fragment stage computes. The shipped
//! renderer is `DrawConfig::default()` with the footprint chosen per frame; the other
//! settings are the measured alternatives of `ellipsoid-splat bench` (`Method`), drawable only
//! with the `research` feature (its shaders are compiled only then).

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
    /// Chosen per draw from the glyphs' mean projected area (the shipped default): the
    /// oriented rectangle for small glyphs (or, opted into, the triangle), where vertex work
    /// dominates; the hexagon and then the octagon as glyphs grow and fragments dominate. See
    /// [`Footprint::for_area`]. Multisampled targets take the fewest primitives instead
    /// ([`Footprint::for_area_multisampled`]).
    #[default]
    Auto,
    /// A triangle around the projected ellipse (area ratio 1.65; 3 vertices, one primitive).
    Triangle,
    /// The oriented rectangle around the projected ellipse: 4/pi of its area for any shape
    /// and orientation.
    OrientedRect,
    /// A hexagon around the projected ellipse (area ratio 1.10; 6 vertices).
    Hexagon,
    /// An octagon around the projected ellipse (area ratio 1.05; 8 vertices).
    Octagon,
    /// The axis-aligned bounding rectangle of the projected ellipse (loose for thin glyphs at
    /// 45 degrees).
    AxisRect,
    /// Gumhold's square around the silhouette circle in the silhouette plane, projected.
    WorldQuad,
}

impl Footprint {
    /// Mean projected glyph area (square pixels) above which the hexagon's 13 % fewer
    /// fragments pay for its 2 extra vertices, and above which the octagon's pay for 2 more.
    /// From lavapipe's costs on this project's machine: about 0.18 us per vertex (its
    /// front end is single-threaded) and 6 ns per impostor fragment.
    pub const HEXAGON_AREA: f64 = 360.0;
    /// See [`Footprint::HEXAGON_AREA`].
    pub const OCTAGON_AREA: f64 = 1200.0;
    /// Mean projected area below which the triangle's one primitive and three vertices cost
    /// less than the rectangle's two and four, its larger area notwithstanding (measured like
    /// the others, README "Skipping what a scene doesn't need").
    pub const TRIANGLE_AREA: f64 = 250.0;

    /// The footprint `Auto` resolves to for glyphs of this mean projected area.
    pub fn for_area(mean_area_px: f64) -> Footprint {
        if mean_area_px >= Self::OCTAGON_AREA {
            Footprint::Octagon
        } else if mean_area_px >= Self::HEXAGON_AREA {
            Footprint::Hexagon
        } else if mean_area_px >= Self::TRIANGLE_AREA {
            Footprint::OrientedRect
        } else {
            Footprint::Triangle
        }
    }

    /// The footprint `Auto` resolves to on multisampled targets. There lavapipe finds each
    /// primitive's coverage at every sample of every 4 x 4 block it touches, which costs more
    /// than the fragments a tighter polygon saves: the triangle below
    /// [`Footprint::TRIANGLE_AREA`], the oriented rectangle above. Measured with 4x MSAA in
    /// `examples/embed --bench` with the footprint forced in a patched build (2026-11-25,
    /// lavapipe on 2 CPU cores, variants interleaved): glyphs of 559 px^2, rectangle 196.7 ms
    /// against hexagon 234.0; of 29 px^2, triangle 173.4 ms against rectangle 209.1. The
    /// 250 px^2 crossover is the single-sample one; offscreen at 1920x1080 (same patch) the
    /// triangle matched the rectangle at 80 px^2 and beat it at about 200 px^2. Glyphs beyond
    /// 1,200 px^2, where the octagon might pay again, were not measured.
    pub fn for_area_multisampled(mean_area_px: f64) -> Footprint {
        if mean_area_px >= Self::TRIANGLE_AREA {
            Footprint::OrientedRect
        } else {
            Footprint::Triangle
        }
    }

    /// Vertices per instance (a triangle strip over the polygon).
    pub fn vertices(self) -> u32 {
        match self {
            Footprint::Hexagon => 6,
            Footprint::Octagon => 8,
            Footprint::Triangle => 3,
            _ => 4,
        }
    }

    /// The `BOUNDS` specialization constant (`glsl/include/instance_setup.glsl`).
    pub(crate) fn bounds_mode(self) -> u32 {
        match self {
            Footprint::Auto
            | Footprint::Triangle
            | Footprint::OrientedRect
            | Footprint::Hexagon
            | Footprint::Octagon => 0,
            Footprint::AxisRect => 1,
            Footprint::WorldQuad => 2,
        }
    }
}

/// What the impostor's fragment stage computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Shading {
    /// Exact hit, unit normal and per-fragment depth.
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
    /// A screen-space polygon, ray-cast per pixel (the shipped renderer).
    #[default]
    Impostor,
    /// The oriented bounding box as 12 triangles, ray-cast inside (textbook intersection).
    BoxProxy,
    /// An icosphere of subdivision level 0..=4 (20 ... 5120 triangles); perspective only.
    Mesh(u32),
}

/// One complete way of drawing the ellipsoids.
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

/// The drawing methods compared by `ellipsoid-splat bench`; their names are the `method`
/// column of `results.csv`.
#[cfg(feature = "research")]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// The renderer as shipped.
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
    /// The shipped impostor with the compute splat wherever it can run, however few the
    /// glyphs (`Settings::compute_splat_min_glyphs` 0): small and medium glyphs are splatted
    /// by a compute pass and shaded by a resolve over the tiles they touch.
    ImpostorCompute,
    /// The shipped impostor always drawn through the rasterizer (`Settings::compute_splat`
    /// off).
    ImpostorDraw,
    /// The shipped impostor with every frame drawn as the first frame of its scene with its
    /// camera: no visible-first splat (the benchmark forgets what the frames before showed),
    /// but the frame stamps what it shows, as the first still frame after a move does.
    ImpostorFirstFrame,
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
    /// Oriented bounding box, ray-cast inside.
    BoxProxy,
    /// Instanced icosphere of the given level.
    Mesh(u32),
    /// Tight quads with a trivial fragment shader.
    FlatFill,
}

#[cfg(feature = "research")]
impl Method {
    /// Every method, in the order of the tables.
    pub const ALL: [Method; 24] = [
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
        Method::ImpostorCompute,
        Method::ImpostorDraw,
        Method::ImpostorFirstFrame,
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

    /// The compute splat's floor the method measures (see `set_splat_floor`; 0: none).
    pub fn splat_floor(self) -> u32 {
        match self {
            Method::FloorMemory => 1,
            Method::FloorArithmetic => 2,
            Method::FloorVisible => 3,
            _ => 0,
        }
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
            Method::ImpostorCompute => "impostor-compute".into(),
            Method::ImpostorDraw => "impostor-draw".into(),
            Method::ImpostorFirstFrame => "impostor-first-frame".into(),
            Method::ImpostorVisbuffer => "impostor-visbuffer".into(),
            Method::FloorMemory => "floor-memory".into(),
            Method::FloorArithmetic => "floor-arithmetic".into(),
            Method::FloorVisible => "floor-visible".into(),
            Method::BoxProxy => "box-proxy".into(),
            Method::Mesh(level) => format!("mesh-L{level}"),
            Method::FlatFill => "flat-fill".into(),
        }
    }

    /// The renderer settings of the method: the shipped ones, with compact instances or the
    /// compute splat for the methods that measure them.
    pub fn settings(self) -> crate::Settings {
        let shipped = crate::Settings::default();
        match self {
            Method::ImpostorCompact => crate::Settings {
                instance_format: crate::instances::InstanceFormat::Compact,
                ..shipped
            },
            Method::ImpostorCompute
            | Method::FloorMemory
            | Method::FloorArithmetic
            | Method::FloorVisible => crate::Settings {
                compute_splat: true,
                compute_splat_min_glyphs: 0,
                ..shipped
            },
            Method::ImpostorDraw => crate::Settings {
                compute_splat: false,
                ..shipped
            },
            _ => shipped,
        }
    }

    /// The draw configuration that implements the method.
    pub fn config(self) -> DrawConfig {
        let base = DrawConfig::default();
        match self {
            Method::Impostor
            | Method::ImpostorCompact
            | Method::ImpostorCompute
            | Method::ImpostorDraw
            | Method::ImpostorFirstFrame
            | Method::FloorMemory
            | Method::FloorArithmetic
            | Method::FloorVisible => base,
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
