//! The renderer's research state and the benchmark's measuring aids: which baseline it
//! draws, the compute splat's floors, and the exact counts of shaded pixels and ray casts.
//!
//! The benchmark's roofline (`research`: `EllipsoidRenderer::set_splat_floor`, methods
//! `floor-memory` and `floor-arithmetic`) replaces the splat by a pass that only reads every
//! instance, or by the splat's ray casts without their atomics, and skips the resolve: the two
//! floors of what the machine allows for such frames. The floors still clear the keep bits and
//! run the compaction, but draw no glyph left to the draw: where glyphs overflow, a floor omits
//! that part of the frame (none do on the 2 px clouds the roofline is measured on).
//!
//! **What the benchmark counts** (`research`). `COUNT_RAY_CASTS` (spec constant 22) makes the
//! splat add its ray casts to the second word of the fragment counter (binding 1), beside the
//! shaded fragments: a frame's ray casts are those plus, for ray-casting fragment shaders, every
//! shaded pixel. The visible-pixel floor (`SPLAT_FLOOR` 3, method `floor-visible`) reads every
//! instance, sets each glyph up once and ray casts only the pixels the float64 reference shows it
//! at, each once, from lists the host gives (`set_floor_pixels`, binding 9 `FloorPixels`:
//! the glyph count, `count + 1` offsets, then the pixels as `x | y << 16`); nothing is kept.

use ash::vk;

use crate::allocator::MemoryAllocator;
use crate::barriers;
use crate::error::{Error, Result};
use crate::footprint::Footprint as ShippedFootprint;
use crate::renderer::{Binding, EllipsoidRenderer, FramePlan};

use super::baseline::{Baseline, DrawConfig, Geometry};
use super::meshes::Meshes;
use super::traced::Traced;

/// What a renderer holds for the benchmark.
#[derive(Default)]
pub(crate) struct Research {
    /// How the glyphs are drawn: the shipped impostor unless a baseline was chosen.
    config: DrawConfig,
    /// Fragment shaders count shaded pixels (and the splat its ray casts).
    count_fragments: bool,
    /// The compute splat's floor the frames measure (0: the splat itself).
    splat_floor: u32,
    /// Splatted frames run the tiled splat instead of the compute splat.
    tiled_splat: bool,
    /// The icosphere baselines' buffers.
    meshes: Meshes,
    /// The glyph count the visible-pixel floor's lists were made for.
    floor_pixels_for: Option<u32>,
    /// The offscreen renderer's read-back frames count (`set_count_fragments` there).
    pub count_read_back: bool,
    /// The traced path (`impostor-traced`).
    pub traced: Traced,
}

impl Research {
    /// The baseline drawn, if any.
    pub fn baseline(&self) -> Option<Baseline> {
        self.config.baseline()
    }

    /// Whether frames count shaded pixels and ray casts.
    pub fn count_fragments(&self) -> bool {
        self.count_fragments
    }

    /// The compute splat's floor (0: the splat itself).
    pub fn splat_floor(&self) -> u32 {
        self.splat_floor
    }

    /// Whether splatted frames run the tiled splat.
    pub fn tiled_splat(&self) -> bool {
        self.tiled_splat
    }

    /// Whether splatted frames run a variant of the splat that stores no set-up records for
    /// the resolve (the tiled splat, the traced path).
    pub fn splat_variant(&self) -> bool {
        self.tiled_splat || self.traced.build != super::traced::TracedBuild::Off
    }

    /// A new scene was uploaded: the floor's lists are for the old one.
    pub fn forget_upload(&mut self) {
        self.floor_pixels_for = None;
        self.traced.forget_upload();
    }

    /// Instances were replaced: the traced path's boxes are stale.
    pub fn forget_instances(&mut self) {
        self.traced.forget_upload();
    }

    /// Makes what `plan`'s baseline draws with (an icosphere's buffers).
    pub fn prepare(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        plan: &FramePlan,
    ) -> Result<()> {
        match plan.baseline.map(|b| b.geometry) {
            Some(Geometry::Mesh(level)) => self.meshes.ensure(device, allocator, level),
            _ => Ok(()),
        }
    }

    /// Records the draw of `count` instances of `baseline` (`indirect`: the pre-pass's
    /// command at this offset; `footprint`: the polygon the plan chose).
    ///
    /// # Safety
    /// `cmd` records inside the pass with the baseline's pipeline, descriptor set and push
    /// constants bound; the buffers outlive its execution.
    pub unsafe fn record_draw(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        baseline: Baseline,
        indirect: Option<(vk::Buffer, u64)>,
        count: u32,
        footprint: ShippedFootprint,
    ) {
        let stride = size_of::<vk::DrawIndirectCommand>() as u32;
        // SAFETY: caller contract.
        unsafe {
            match (baseline.geometry, indirect) {
                (Geometry::Impostor, Some((buffer, offset))) => {
                    device.cmd_draw_indirect(cmd, buffer, offset, 1, stride)
                }
                (Geometry::Impostor, None) => {
                    device.cmd_draw(cmd, baseline.vertices(footprint), count, 0, 0)
                }
                (Geometry::BoxProxy, _) => device.cmd_draw(cmd, 36, count, 0, 0),
                (Geometry::Mesh(level), _) => {
                    self.meshes.bind(device, cmd, level);
                    device.cmd_draw_indexed(cmd, self.meshes.index_count(level), count, 0, 0, 0)
                }
            }
        }
    }

    /// Destroys the meshes.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        // SAFETY: caller contract.
        unsafe {
            self.meshes.destroy(device, allocator);
            self.traced.destroy(device, allocator);
        }
    }
}

impl EllipsoidRenderer {
    /// Draws with `config` from the next frame on (a baseline of the benchmark; the shipped
    /// renderer is `DrawConfig::default()`). Builds that configuration's pipelines on first
    /// use.
    pub fn set_draw_config(&mut self, config: DrawConfig) {
        self.research.config = config;
    }

    /// The configuration frames are drawn with.
    pub fn draw_config(&self) -> DrawConfig {
        self.research.config
    }

    /// Replaces the compute splat by one of its floors, for the benchmark's roofline: 1 reads
    /// every instance and nothing else, 2 ray casts every pixel centre without the atomics, 3
    /// ray casts only the pixels each glyph shows (given by `set_floor_pixels` for the
    /// uploaded scene; a frame without them is an error), and none resolves; 0 is the splat
    /// itself. Frames that do not splat are unchanged.
    pub fn set_splat_floor(&mut self, floor: u32) {
        self.research.splat_floor = floor.min(3);
    }

    /// With `true`, frames that splat every glyph run the tiled splat
    /// (`research/tiled_splat.comp`) instead of the compute splat: the same picture, each
    /// screen tile's keys kept by one workgroup and written once.
    pub fn set_tiled_splat(&mut self, on: bool) {
        self.research.tiled_splat = on;
    }

    /// Forgets which glyphs the last frame showed, so that the next frame is drawn as a first
    /// frame of its scene would be (no visible-first splat; it stamps what it shows again):
    /// what the benchmark's `impostor-first-frame` measures.
    pub fn forget_shown(&mut self) {
        for view in &mut self.views {
            view.shown_stamped = None;
        }
    }

    /// Gives the visible-pixel floor (`set_splat_floor(3)`) the pixels each glyph shows:
    /// `ids` holds, row-major in rows of `width`, the scene index of the glyph each pixel
    /// shows (`u32::MAX` or any index beyond the scene: none), e.g. the float64 reference's.
    /// The floor's pass then reads every instance once and ray casts exactly these pixels,
    /// each once, keeping nothing. Writes a new host-visible buffer of 4 bytes per glyph and
    /// per visible pixel (the old one is retired).
    ///
    /// # Safety
    /// `device` is the renderer's device and `allocator` allocates from it.
    pub unsafe fn set_floor_pixels(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        ids: &[u32],
        width: u32,
    ) -> Result<()> {
        let lists = floor_pixel_lists(self.scene.count, ids, width)?;
        let buffer = self.buffers.replace(
            device,
            allocator,
            &mut self.slots,
            Binding::FloorPixels,
            4 * lists.len().max(2) as u64,
        )?;
        buffer.write(bytemuck::cast_slice(&lists))?;
        self.research.floor_pixels_for = Some(self.scene.count);
        Ok(())
    }

    /// Checks that a frame with `plan` can draw the visible-pixel floor: its lists were made
    /// for the uploaded scene.
    pub(crate) fn check_floor_pixels(&self, plan: &FramePlan) -> Result<()> {
        if self.research.splat_floor == 3
            && plan.path.splat().is_some()
            && self.research.floor_pixels_for != Some(self.scene.count)
        {
            return Err(Error::invalid(
                "visible-pixel floor",
                "set_floor_pixels has not given the pixels of the uploaded scene",
            ));
        }
        Ok(())
    }

    /// Counts shaded pixels with an atomic in separate builds of the fragment shaders (needs
    /// `fragmentStoresAndAtomics`); their arithmetic may round differently from the shipped
    /// ones.
    pub fn set_count_fragments(&mut self, on: bool) {
        self.research.count_fragments = on;
    }

    /// Zeroes the fragment and ray-cast counters; call before submitting a counting frame.
    pub fn reset_fragment_counter(&mut self) -> Result<()> {
        match self.buffers.get_mut(Binding::FragmentCounter) {
            Some(c) => c.write(&[0; 8]),
            None => Ok(()),
        }
    }

    /// Pixels shaded by the last counting frame (after its fence, and after the barrier of
    /// [`EllipsoidRenderer::record_counter_barrier`]).
    pub fn fragment_count(&self) -> Option<u32> {
        let bytes = self.buffers.get(Binding::FragmentCounter)?.mapped()?;
        Some(u32::from_ne_bytes(bytes.get(..4)?.try_into().ok()?))
    }

    /// Ray casts the compute splat's passes made in the last counting frame (each evaluation
    /// of the exact hit at a pixel centre; the fragment stages' own are their shaded pixels).
    pub fn compute_ray_count(&self) -> Option<u32> {
        let bytes = self.buffers.get(Binding::FragmentCounter)?.mapped()?;
        Some(u32::from_ne_bytes(bytes.get(4..8)?.try_into().ok()?))
    }

    /// Makes the counter's atomic writes visible to the host; record after the pass.
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` recording outside a pass.
    pub unsafe fn record_counter_barrier(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: caller contract.
        unsafe { barriers::COUNTER_TO_HOST.record(device, cmd) };
    }
}

/// The visible-pixel floor's lists (GLSL `floor_pixels` in `splat.comp`): `count`, then
/// `count + 1` offsets, then per glyph its pixels as `x | y << 16`, in scene order.
fn floor_pixel_lists(count: u32, ids: &[u32], width: u32) -> Result<Vec<u32>> {
    if width == 0 || width > 1 << 16 || ids.len() % width as usize != 0 {
        return Err(Error::invalid(
            "floor pixels",
            format!("{} ids are no whole rows of {width} pixels", ids.len()),
        ));
    }
    // Pixels are packed as x | y << 16.
    if ids.len() / width as usize > 1 << 16 {
        return Err(Error::invalid(
            "floor pixels",
            format!("{} rows, more than 65536", ids.len() / width as usize),
        ));
    }
    let n = count as usize;
    let mut offsets = vec![0u32; n + 1];
    for &id in ids {
        if (id as usize) < n {
            offsets[id as usize + 1] += 1;
        }
    }
    for k in 0..n {
        offsets[k + 1] += offsets[k];
    }
    let mut pixels = vec![0u32; offsets[n] as usize];
    let mut next: Vec<u32> = offsets[..n].to_vec();
    for (at, &id) in ids.iter().enumerate() {
        if (id as usize) < n {
            let (x, y) = (at as u32 % width, at as u32 / width);
            pixels[next[id as usize] as usize] = x | y << 16;
            next[id as usize] += 1;
        }
    }
    Ok([&[count][..], &offsets, &pixels].concat())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_lists_group_each_glyphs_pixels_in_order() {
        // 3 x 2 pixels: glyph 1 shows at (0,0) and (2,1), glyph 0 at (1,0); the rest nothing
        // or a glyph beyond the scene.
        let none = u32::MAX;
        let ids = [1, 0, none, 7, none, 1];
        let lists = floor_pixel_lists(3, &ids, 3).unwrap();
        assert_eq!(lists[0], 3);
        assert_eq!(
            &lists[1..5],
            &[0, 1, 3, 3],
            "offsets: glyph 0 one pixel, 1 two, 2 none"
        );
        assert_eq!(&lists[5..], &[1, 0, 2 | 1 << 16]);
        assert!(floor_pixel_lists(3, &ids, 4).is_err());
        assert!(floor_pixel_lists(3, &vec![0; (1 << 16) + 1], 1).is_err());
        assert!(floor_pixel_lists(3, &ids, 0).is_err());
    }
}
