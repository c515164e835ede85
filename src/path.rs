//! The exact paths a frame can take. Each draws the same picture (bit for bit on lavapipe;
//! within the float64 reference's bounds on any driver, docs/design.md §9.5) and costs
//! differently: which is fastest depends on the device and the scene, so the frame plan
//! measures them (`src/renderer/learning.rs`).

use std::fmt;

use crate::culling::Culling;

/// The exact path of one frame, carrying only what that path needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FramePath {
    /// Every glyph rasterized as an impostor, after the pre-pass when it culls or sets glyphs
    /// up once (the path's `culling` and `setup_once`, also [`crate::FramePlan::culling`] and
    /// [`crate::FramePlan::setup_once`]).
    Draw(DrawPath),
    /// The glyphs ray cast by a compute pass into a visibility buffer and shaded once per
    /// pixel by a resolve inside the host's pass; those too large for it are drawn in the
    /// same frame (docs/design.md §5.6). The path's `hidden` says what it does about hidden
    /// glyphs ([`HiddenLayers`]), its `max_box_pixels` the most pixel centres a glyph's box
    /// may hold for the splat to walk it.
    Splat(SplatPath),
}

/// What the draw does besides rasterizing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DrawPath {
    /// The exact culling of the pre-pass (docs/design.md §5.3).
    pub culling: Culling,
    /// The pre-pass computes each small glyph's set-up once for the draw's stages.
    pub setup_once: bool,
}

impl DrawPath {
    /// Whether the draw runs a pre-pass first (and then reads its list indirectly).
    pub fn prepass(&self) -> bool {
        self.culling.any() || self.setup_once
    }
}

/// What the compute splat does about hidden glyphs, and what it leaves to the draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplatPath {
    /// How the hidden layers are treated (docs/design.md §5.7).
    pub hidden: HiddenLayers,
    /// The most pixel centres a glyph's box may hold for the splat to walk it; larger glyphs
    /// (and those reaching the eye plane) are drawn in the same frame.
    pub max_box_pixels: u32,
    /// The splat stores each glyph's shading set-up once, and the resolve reads it instead of
    /// setting up the glyph of each pixel again (docs/design.md §5.6).
    pub setup_once: bool,
}

/// How a splatted frame treats the glyphs hidden behind others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HiddenLayers {
    /// Every glyph is splatted, hidden ones too.
    SplatAll,
    /// Every glyph is splatted, and the glyphs the frame shows are stamped so that the next
    /// frame with the same camera can splat them first.
    StampShown,
    /// The glyphs the last stamping frame with this camera showed are splatted first, then of
    /// the rest only those their hits do not hide; the frame stamps what it shows.
    VisibleFirst {
        /// The culling the second pass lists the rest with (its occlusion test is the first
        /// pass's hits, not the pre-pass's tiles).
        rest: Culling,
    },
}

/// The candidates a frame plan chooses among: which path, as the plan measures and a host
/// fixes it ([`crate::Settings::plan`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PathKind {
    /// [`FramePath::Draw`].
    Draw,
    /// [`FramePath::Splat`] with every glyph splatted.
    Splat,
    /// [`FramePath::Splat`] with the visible-first splat: the glyphs the last frame showed
    /// first, the camera still or moving (the first frame after an upload only stamps what
    /// it shows).
    VisibleFirst,
}

impl PathKind {
    /// Every kind, in the order of their indices.
    pub const ALL: [PathKind; 3] = [PathKind::Draw, PathKind::Splat, PathKind::VisibleFirst];

    /// A short name: `draw`, `splat`, `visible-first`.
    pub fn name(self) -> &'static str {
        match self {
            PathKind::Draw => "draw",
            PathKind::Splat => "splat",
            PathKind::VisibleFirst => "visible-first",
        }
    }

    /// The kind named by [`PathKind::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Index into per-kind tables.
    pub(crate) fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for PathKind {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FramePath {
    /// The kind of path the frame takes as it is timed: a splat that only stamps what it
    /// shows is `None` (a frame on the way to the visible-first splat, timed as neither).
    pub fn timed_kind(&self) -> Option<PathKind> {
        match self {
            FramePath::Draw(_) => Some(PathKind::Draw),
            FramePath::Splat(s) => match s.hidden {
                HiddenLayers::SplatAll => Some(PathKind::Splat),
                HiddenLayers::StampShown => None,
                HiddenLayers::VisibleFirst { .. } => Some(PathKind::VisibleFirst),
            },
        }
    }

    /// The splat's path, if the frame splats.
    pub fn splat(&self) -> Option<&SplatPath> {
        match self {
            FramePath::Splat(s) => Some(s),
            FramePath::Draw(_) => None,
        }
    }

    /// The draw's path, if the frame draws every glyph.
    pub fn draw(&self) -> Option<&DrawPath> {
        match self {
            FramePath::Draw(d) => Some(d),
            FramePath::Splat(_) => None,
        }
    }
}

/// How a host lets the frame plan choose ([`crate::Settings::plan`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PlanMode {
    /// The first guess from the scene's size on screen, then the candidates timed on frames
    /// the renderer draws anyway, a few frames each, spread out; the fastest is kept per
    /// device and scene class (the default). Needs timestamps on the queue family; without
    /// them it is [`PlanMode::Estimate`].
    #[default]
    Measure,
    /// The first guess alone: no exploring, the same path for the same scene and camera
    /// every time (conformance runs, reproducible benchmarks).
    Estimate,
    /// This kind wherever it can serve the frame; otherwise the path that can.
    Fixed(PathKind),
}
