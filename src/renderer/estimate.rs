//! The frame plan's first guess: which path pays, from the scene's size on screen, by
//! thresholds measured on lavapipe (`docs/compute-splat.md`,
//! `docs/hidden-layers.md`). On other devices the plan measures the
//! candidates and keeps the fastest (`learning.rs`); this is where it starts, and all of
//! [`crate::PlanMode::Estimate`].

use crate::path::PathKind;

use super::plan_reason::Guess;

/// The largest mean projected glyph area (square pixels) for which the first guess splats.
/// Measured on lavapipe at 50,000 glyphs of growing size (the figures: `docs/compute-splat.md`);
/// beyond it most glyphs overflow to the draw.
pub const SPLAT_MAX_MEAN_AREA_PX: f64 = 1024.0;

/// The fewest glyphs for which the first guess splats: the splat's fixed cost (clearing the
/// visibility buffer, resolving the tiles its glyphs touch) met the draw's per-glyph cost on
/// lavapipe (the figures: `docs/compute-splat.md`).
pub const SPLAT_MIN_GLYPHS: u32 = 50_000;

/// The least area per glyph (square pixels) a scene must be expected to hide
/// ([`crate::FramePlan::hidden_area_px`]) for the first guess of a still camera to be the
/// visible-first splat: between the tensor-field sizes it lost and won on lavapipe (the
/// figures: `docs/hidden-layers.md`). A moving camera's first guess is the plain splat; the
/// plan that measures times the visible-first splat there too.
pub const VISIBLE_FIRST_MIN_HIDDEN_PX: f64 = 45.0;

/// What the first guess looks at.
pub(crate) struct Sizes {
    /// Glyphs uploaded.
    pub glyphs: u32,
    /// Mean projected area of the sampled glyphs on screen.
    pub mean_area_px: f64,
    /// Area per glyph the scene is expected to hide.
    pub hidden_area_px: f64,
    /// The camera is the view's last pre-pass's (the threshold below was measured so).
    pub still: bool,
}

/// The first guess among `candidates` (the draw is always one), and why.
pub(crate) fn first_guess(sizes: &Sizes, candidates: &[PathKind]) -> (PathKind, Guess) {
    let can = |kind| candidates.contains(&kind);
    if !can(PathKind::Splat) || sizes.mean_area_px > SPLAT_MAX_MEAN_AREA_PX {
        (PathKind::Draw, Guess::LargeGlyphs)
    } else if sizes.glyphs < SPLAT_MIN_GLYPHS {
        (PathKind::Draw, Guess::FewGlyphs)
    } else if can(PathKind::VisibleFirst)
        && sizes.still
        && sizes.hidden_area_px >= VISIBLE_FIRST_MIN_HIDDEN_PX
    {
        (PathKind::VisibleFirst, Guess::HiddenLayers)
    } else {
        (PathKind::Splat, Guess::SmallGlyphs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_guess_follows_the_thresholds() {
        let all = PathKind::ALL;
        let moving = [PathKind::Draw, PathKind::Splat];
        let sizes = |glyphs, mean_area_px, hidden_area_px| Sizes {
            glyphs,
            mean_area_px,
            hidden_area_px,
            still: true,
        };
        let guess = |s: Sizes, c: &[PathKind]| first_guess(&s, c).0;
        assert_eq!(guess(sizes(60_000, 2.0, 0.0), &all), PathKind::Splat);
        assert_eq!(guess(sizes(60_000, 2000.0, 0.0), &all), PathKind::Draw);
        assert_eq!(guess(sizes(40_000, 2.0, 0.0), &all), PathKind::Draw);
        assert_eq!(
            guess(sizes(60_000, 100.0, 60.0), &all),
            PathKind::VisibleFirst
        );
        assert_eq!(guess(sizes(60_000, 100.0, 60.0), &moving), PathKind::Splat);
        assert_eq!(
            guess(sizes(60_000, 2.0, 0.0), &[PathKind::Draw]),
            PathKind::Draw
        );
    }
}
