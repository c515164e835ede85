//! How the tool lets the frame plan choose its path (`--plan`), and how it reports what the
//! plan chose: the path's name and the reason, as `render`, `view` and `bench` print them.

use ash::vk;

use crate::error::Result;
use ellipsoid_splat::{Camera, FramePlan, OffscreenRenderer, Outputs};
use ellipsoid_splat::{FramePath, HiddenLayers, PathKind, PlanMode, PlanReason};

/// The most frames `render --plan measure` draws with its camera before the frame it writes,
/// waiting for the plan to have timed every candidate (about 10 to 20 frames do).
pub const RENDER_LEARNING_FRAMES: usize = 40;

/// The most frames `render --plan estimate|visible-first` draws before the frame it writes:
/// the first frame's camera is not yet still (a class of its own for the first guess), and the
/// visible-first splat's first frame only stamps what it shows.
pub const RENDER_STILL_FRAMES: usize = 2;

/// The most frames `bench` draws of a method whose plan measures, after its warm-up, before
/// its timed rounds.
pub const BENCH_LEARNING_FRAMES: usize = 60;

/// How the frame plan chooses the path (`--plan`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum PlanArg {
    /// Time the paths that can serve the frame on frames of the same camera, and keep the
    /// fastest (`render` draws those frames before the one it writes).
    #[default]
    Measure,
    /// The first guess from the scene's size on screen, no timing: the same path every run.
    Estimate,
    /// Every glyph rasterized.
    Draw,
    /// The compute splat, every glyph (the draw where the splat cannot run).
    Splat,
    /// The splat of the glyphs the last frame of the same camera showed first, then of the
    /// rest only those they do not hide (the plain splat where the camera moves).
    VisibleFirst,
}

impl PlanArg {
    /// The most frames `render` draws with its camera before the frame it writes: the frames
    /// the plan needs to settle on a path (none where the path is fixed whatever the camera
    /// does).
    pub fn warm_up_frames(self) -> usize {
        match self {
            PlanArg::Measure => RENDER_LEARNING_FRAMES,
            PlanArg::Estimate | PlanArg::VisibleFirst => RENDER_STILL_FRAMES,
            PlanArg::Draw | PlanArg::Splat => 0,
        }
    }

    /// The plan mode it asks for.
    pub fn mode(self) -> PlanMode {
        match self {
            PlanArg::Measure => PlanMode::Measure,
            PlanArg::Estimate => PlanMode::Estimate,
            PlanArg::Draw => PlanMode::Fixed(PathKind::Draw),
            PlanArg::Splat => PlanMode::Fixed(PathKind::Splat),
            PlanArg::VisibleFirst => PlanMode::Fixed(PathKind::VisibleFirst),
        }
    }
}

/// The path's name as the tool prints it: `draw`, `splat`, `visible-first`, or `splat
/// (stamping)` for the first splat on the way to the visible-first one.
pub fn path_name(path: &FramePath) -> &'static str {
    match path {
        FramePath::Draw(_) => PathKind::Draw.name(),
        FramePath::Splat(s) => match s.hidden {
            HiddenLayers::SplatAll => PathKind::Splat.name(),
            HiddenLayers::StampShown => "splat (stamping)",
            HiddenLayers::VisibleFirst { .. } => PathKind::VisibleFirst.name(),
        },
    }
}

/// `splat (measured: 34.200 ms against draw 61.000 ms)`: the path and why.
pub fn describe(plan: &FramePlan) -> String {
    format!("{} ({})", path_name(&plan.path), plan.reason)
}

/// Whether the plan of `renderer`'s last frame had settled: timed every candidate of the
/// scene class and kept the fastest (its reason is then `Measured`; `Exploring` until then),
/// or had nothing to choose (the draw the only path, or one candidate).
pub fn settled(renderer: &OffscreenRenderer) -> bool {
    renderer.last_plan().is_some_and(|plan| {
        matches!(plan.reason, PlanReason::Only(_) | PlanReason::Measured(_))
            || plan.candidates().len() < 2
    })
}

/// What the frames before the one `render` writes did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WarmUp {
    /// Frames drawn.
    pub frames: usize,
    /// Whether the plan had settled by then (see [`warm_up`]); only a plan that measures may
    /// not have.
    pub settled: bool,
}

/// Draws frames of `camera` into attachments of `extent` without reading them back, as many as
/// the plan `plan` needs to settle and at most `plan.warm_up_frames()` (none where the draw is
/// the only path): with `measure`, until it has timed its candidates ([`settled`]);
/// otherwise until the next frame's path would be the last one's. The next frame then takes
/// the path the plan settled on.
pub fn warm_up(
    renderer: &mut OffscreenRenderer,
    camera: &Camera,
    extent: vk::Extent2D,
    outputs: Outputs,
    plan: PlanArg,
) -> Result<WarmUp> {
    // Nothing to settle where the draw is the only path.
    let most = match renderer.plan(camera)?.reason {
        PlanReason::Only(_) => 0,
        _ => plan.warm_up_frames(),
    };
    let [x, y] = camera.viewport_origin;
    // A frame timed without read-back has the camera's own extent; where the output is larger
    // the frames are read back too, so that the targets stay those of the frame written.
    let own_extent = x + camera.width == extent.width && y + camera.height == extent.height;
    let mut frames = 0;
    while frames < most {
        if own_extent {
            renderer.render_timed(camera, outputs)?;
        } else {
            renderer.render_views(extent.width, extent.height, &[*camera], outputs)?;
        }
        frames += 1;
        let settled = match renderer.last_plan() {
            None => true,
            Some(_) if plan == PlanArg::Measure => settled(renderer),
            Some(last) => renderer.plan(camera)?.path == last.path,
        };
        if settled {
            return Ok(WarmUp {
                frames,
                settled: true,
            });
        }
    }
    // Only learning can run out of frames: the other plans' paths are set by then.
    Ok(WarmUp {
        frames,
        settled: plan != PlanArg::Measure || most == 0,
    })
}
