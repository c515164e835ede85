//! The offscreen renderer's research switches: a baseline, a floor, counting read-back frames.

#[cfg(feature = "offscreen")]
use crate::error::Result;
use crate::renderer::EllipsoidRenderer;

use super::baseline::DrawConfig;

#[cfg(feature = "offscreen")]
impl crate::OffscreenRenderer {
    /// Draws with a benchmark baseline's `config` from the next frame on.
    pub fn set_draw_config(&mut self, config: DrawConfig) {
        self.renderer_mut().set_draw_config(config);
    }

    /// Replaces the compute splat by one of its floors (see
    /// [`EllipsoidRenderer::set_splat_floor`]).
    pub fn set_splat_floor(&mut self, floor: u32) {
        self.renderer_mut().set_splat_floor(floor);
    }

    /// Traces the splat's frames (see [`EllipsoidRenderer::set_traced`]).
    pub fn set_traced(&mut self, build: super::TracedBuild) {
        self.renderer_mut().set_traced(build);
    }

    /// Runs the tiled splat in splatted frames (see
    /// [`EllipsoidRenderer::set_tiled_splat`]).
    pub fn set_tiled_splat(&mut self, on: bool) {
        self.renderer_mut().set_tiled_splat(on);
    }

    /// Forgets which glyphs the last frame showed (see
    /// [`EllipsoidRenderer::forget_shown`]).
    pub fn forget_shown(&mut self) {
        self.renderer_mut().forget_shown();
    }

    /// Gives the visible-pixel floor the pixels each glyph shows (see
    /// [`EllipsoidRenderer::set_floor_pixels`]).
    pub fn set_floor_pixels(&mut self, ids: &[u32], width: u32) -> Result<()> {
        let (device, allocator, renderer) = self.parts();
        // SAFETY: the renderer was made on this context's device and allocator.
        unsafe { renderer.set_floor_pixels(device, allocator, ids, width) }
    }

    /// With `true`, read-back frames run the counting shader builds and report
    /// `FrameTiming::shaded_fragments` (needs `fragmentStoresAndAtomics`).
    pub fn set_count_fragments(&mut self, on: bool) {
        self.renderer_mut().research.count_read_back = on;
    }
}

/// Before a frame: whether it counts (a read-back frame, asked for, on a device that can),
/// with the counters zeroed if so.
pub(crate) fn begin_counting(
    renderer: &mut EllipsoidRenderer,
    readback: bool,
    supported: bool,
) -> crate::error::Result<bool> {
    let counting = readback && renderer.research.count_read_back && supported;
    renderer.set_count_fragments(counting);
    renderer.reset_fragment_counter()?;
    Ok(counting)
}

/// After a counting frame: the shaded pixels and the compute splat's ray casts.
pub(crate) fn counts(renderer: &EllipsoidRenderer) -> (Option<u64>, Option<u64>) {
    (
        renderer.fragment_count().map(u64::from),
        renderer.compute_ray_count().map(u64::from),
    )
}
