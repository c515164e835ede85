//! Why a frame keeps the draw instead of the compute splat: the first condition of the splat
//! (§5.6) that the frame's scene, settings, target, device or camera does not meet.

use std::fmt;

/// Why a frame's glyphs are drawn through the rasterizer rather than splatted
/// ([`crate::FramePlan::drawn_because`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum DrawReason {
    /// `Settings::compute_splat` is off.
    SplatOff,
    /// A benchmark baseline or a fixed footprint is drawn: the splat is the shipped impostor's.
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
    /// The glyphs are too large on average.
    GlyphsTooLarge,
    /// Too few glyphs to pay for the splat's fixed cost.
    TooFewGlyphs,
}

impl fmt::Display for DrawReason {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(match self {
            DrawReason::SplatOff => "the compute splat is off in the settings",
            DrawReason::Baseline => {
                "a benchmark baseline or a fixed footprint is drawn (the splat is the shipped \
                 impostor's, with the footprint chosen by size)"
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
                "the image's visibility buffer would exceed one storage-buffer binding"
            }
            DrawReason::TooManyChunks => "the scene needs more chunks than the splat resolves",
            DrawReason::NothingOnScreen => "no sampled glyph is on screen",
            DrawReason::GlyphsTooLarge => "the glyphs are too large on average for the splat",
            DrawReason::TooFewGlyphs => "too few glyphs to pay for the splat's fixed cost",
        })
    }
}
