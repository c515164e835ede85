//! Why a frame takes its path: what rules the compute splat out, the first guess from the
//! scene's size on screen, or what the candidates measured.

use std::fmt;

use crate::path::PathKind;

/// Why the compute splat cannot serve a frame, which the draw then takes: the payload of
/// [`PlanReason::Only`], whose documentation lists the cases for hosts (this type is not
/// exported).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum DrawReason {
    /// A benchmark baseline is drawn (`research`): the splat is the shipped impostor's.
    Baseline,
    /// The host did not enable the splat's device features (`shaderInt64`,
    /// `shaderBufferInt64Atomics`).
    MissingFeatures,
    /// The target is multisampled.
    Multisampled,
    /// The depth attachment is not float32.
    DepthFormat,
    /// The image's visibility buffer would not fit one storage-buffer binding.
    ImageTooLarge,
    /// The scene needs more chunks than the splat resolves.
    TooManyChunks,
    /// No sampled glyph is on screen.
    NothingOnScreen,
}

impl fmt::Display for DrawReason {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            DrawReason::Baseline => {
                "a benchmark baseline is drawn (the splat is the shipped impostor's)"
            }
            DrawReason::MissingFeatures => {
                "the device lacks the splat's 64-bit buffer atomics, or the host did not enable them"
            }
            DrawReason::Multisampled => {
                "the target is multisampled: the splat keeps one hit per pixel, and a pixel's \
                 samples may show different glyphs, which would take a 64-bit key and an atomic \
                 per sample and a resolve shading every sample whose glyph differs; the draw \
                 decides each sample exactly (at the standard positions of 2 and 4 samples, \
                 shading once per pixel unless per-sample shading is asked for)"
            }
            DrawReason::DepthFormat => {
                "the depth attachment is not float32 (the splat's keys order float32 depths)"
            }
            DrawReason::ImageTooLarge => {
                "the image's visibility buffer would exceed one storage-buffer binding or \
                 texel view"
            }
            DrawReason::TooManyChunks => "the scene needs more chunks than the splat resolves",
            DrawReason::NothingOnScreen => "no sampled glyph is on screen",
        })
    }
}

/// The first guess of the frame plan, from the scene's size on screen (the thresholds of
/// `src/renderer/estimate.rs`, measured on lavapipe): the payload of
/// [`PlanReason::Estimated`], whose documentation lists the cases for hosts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Guess {
    /// Too few glyphs to pay for the splat's fixed cost: the draw.
    FewGlyphs,
    /// Glyphs too large on average for the splat: the draw.
    LargeGlyphs,
    /// Many glyphs, small enough: the splat.
    SmallGlyphs,
    /// Splatted, many glyphs deep, and the camera still: the visible-first splat (a moving
    /// camera's first guess is the plain splat).
    HiddenLayers,
}

impl fmt::Display for Guess {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            Guess::FewGlyphs => "too few glyphs to pay for the splat's fixed cost",
            Guess::LargeGlyphs => "the glyphs are too large on average for the splat",
            Guess::SmallGlyphs => "many glyphs small enough for the splat",
            Guess::HiddenLayers => "many glyphs deep with the camera still: visible first",
        })
    }
}

/// What the candidates measured for a scene class: the payload of [`PlanReason::Measured`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// Median GPU time of the chosen path's frames, milliseconds.
    pub ms: f64,
    /// The next fastest candidate and its median; `None` if the others were not timed (all
    /// rejected after their first frame counts as timed).
    pub runner_up: Option<(PathKind, f64)>,
}

/// Why a frame takes its path ([`crate::FramePlan::reason`]).
///
/// The payloads of `Only` and `Estimated` are not exported: a host reads them through
/// `Display` (on the payload, or on the whole reason, which prints e.g. "the only path: the
/// target is multisampled: ...") or `Debug`, and matches on the variant.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum PlanReason {
    /// The draw is the only path that can serve the frame; the payload prints why, one of:
    /// a benchmark baseline is drawn (`research`); the device lacks the splat's 64-bit buffer
    /// atomics or the host did not enable them (enable `shaderInt64` and
    /// `shaderBufferInt64Atomics`: [`crate::DeviceFeatures::COMPUTE_SPLAT`]); the target is
    /// multisampled; the depth attachment is not float32; the image's visibility buffer would
    /// exceed one storage-buffer binding; the scene needs more chunks than the splat resolves;
    /// no sampled glyph is on screen.
    Only(DrawReason),
    /// The host fixed the path ([`crate::PlanMode::Fixed`]).
    Fixed,
    /// The first guess, from the scene's size on screen (before measuring, or with
    /// [`crate::PlanMode::Estimate`]); the payload prints which threshold decided: too few
    /// glyphs to pay for the splat's fixed cost or glyphs too large on average (the draw),
    /// many glyphs small enough (the splat), or many glyphs deep with the camera still (the
    /// visible-first splat; a moving camera's first guess is the plain splat).
    Estimated(Guess),
    /// The plan is still timing the candidates for this scene class (the frame runs one of
    /// them, or the fastest so far between two trials).
    Exploring,
    /// The fastest candidate measured for this scene class on this device: the payload's
    /// `ms`, the median GPU time of the path's frames, and `runner_up`, the next fastest
    /// kind and its median where another was timed.
    Measured(Measured),
}

impl fmt::Display for PlanReason {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            PlanReason::Only(why) => write!(f, "the only path: {why}"),
            PlanReason::Fixed => f.write_str("fixed by the host"),
            PlanReason::Estimated(guess) => write!(f, "first guess: {guess}"),
            PlanReason::Exploring => f.write_str("exploring: timing the candidates"),
            PlanReason::Measured(m) => match m.runner_up {
                Some((kind, ms)) => write!(f, "measured: {:.3} ms against {kind} {ms:.3} ms", m.ms),
                None => write!(f, "measured: {:.3} ms, the other candidates slower", m.ms),
            },
        }
    }
}
