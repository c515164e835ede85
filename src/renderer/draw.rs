//! Recording the draw: one instanced (or indirect) draw per chunk, inside the host's pass.

use crate::allocator::MemoryAllocator;
use ash::vk;

use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::gpu_layout::resolve_tiles;

use super::buffers::Binding;
use super::chunks::SLICE_ALIGN;
use super::pipelines::keys::PipelineKey;
use super::pipelines::DRAW_PUSH_STAGES;
use super::plan::FramePlan;
use super::push::push_constants;
use super::viewport::viewport_and_scissor;
use super::EllipsoidRenderer;

impl EllipsoidRenderer {
    /// Creates what a frame with `plan` draws with (the pipelines, and a baseline's mesh),
    /// or finds it made; returns the draw's pipeline and, in a splatted frame, the
    /// resolve's.
    pub(crate) fn prepare(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        plan: &FramePlan,
    ) -> Result<(vk::Pipeline, Option<vk::Pipeline>)> {
        self.research.prepare(device, allocator, plan)?;
        let target = &self.targets[plan.target];
        let resolve = match PipelineKey::resolve(plan, &self.research) {
            Some(key) => Some(self.pipelines.draw(device, key, target)?),
            None => None,
        };
        // A baseline drawn in a pass of its own (the visibility-buffer draw) has a target of
        // its own.
        let own_target = plan.baseline.and_then(|b| b.own_pass_target());
        let target = own_target.as_ref().unwrap_or(target);
        let key = PipelineKey::draw(plan, &self.research);
        Ok((self.pipelines.draw(device, key, target)?, resolve))
    }

    /// Creates the pipeline of a frame with `camera` now, so the first `record` with it
    /// does not pay for building it.
    ///
    /// # Safety
    /// `device` is the renderer's device and `allocator` allocates from it.
    pub unsafe fn prepare_for(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        camera: &Camera,
    ) -> Result<()> {
        let plan = self.plan(camera)?;
        self.prepare(device, allocator, &plan).map(|_| ())
    }

    /// Records the draw into `cmd`, inside the host's pass. Sets viewport and scissor to the
    /// camera's image: its size at its `viewport_origin`. Records nothing if the scene is
    /// empty. It draws with the plan and target of the first view of the frame whose
    /// `record_prepass` had an equal camera and has not drawn yet (views with equal cameras
    /// draw in the order of their pre-passes); without one, with a new plan for the current
    /// target, which must need no pre-pass. A frame whose plan has a pre-pass needs
    /// `record_prepass` with the same camera first, before the pass, and with no upload or
    /// update in between (an error otherwise): one pre-pass serves one draw, so each view of
    /// a frame records its own pre-pass.
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` recording inside a pass compatible with the
    /// [`crate::Target`] that was current when this camera's `record_prepass` was recorded
    /// (the current one, in a frame without a pre-pass): same attachments, formats and sample
    /// count; for a render pass, its subpass; whose attachments hold the camera's rectangle (its size at its
    /// `viewport_origin`); it is submitted as
    /// [`EllipsoidRenderer::record_prepass`] requires.
    pub unsafe fn record(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        camera: &Camera,
    ) -> Result<()> {
        camera.validate()?;
        // The material is pushed now, whatever the pre-pass's plan saw.
        self.settings.material.validate()?;
        // The indirect draw needs this frame's pre-pass of this camera, recorded with the
        // same plan: the first view still waiting for its draw with it.
        let prepared = self
            .views
            .iter()
            .position(|v| v.prepared.as_ref().is_some_and(|(seen, _)| seen == camera));
        let prepared = prepared.and_then(|view| Some((view, self.views[view].prepared.take()?.1)));
        if self.scene.count == 0 {
            return Ok(());
        }
        // A view draws into the target that was current at its pre-pass (its plan's).
        let (view, plan, timed) = match prepared {
            Some((view, plan)) => (view, plan, Some(view)),
            None => {
                // A frame without a pre-pass reads no view's buffers: any view's sets do.
                let plan = self.plan_for_view(0, camera)?;
                if plan.prepass() {
                    return Err(Error::invalid(
                        "record",
                        "this frame has a pre-pass: call record_prepass with the same camera \
                         first (each pre-pass serves one draw)",
                    ));
                }
                (0, plan, None)
            }
        };
        // A plan without a pre-pass reads no view's buffers: view 0's sets do.
        let view = if plan.prepass() { view } else { 0 };
        let (pipeline, resolve) = self.prepare(device, allocator, &plan)?;
        let sets = self.descriptor_sets(device, view)?;
        let (viewport, scissor) = viewport_and_scissor(camera);
        let indirect = self.views[view].buffers.handle(Binding::IndirectDraw)?;
        let tiles = resolve_tiles(camera.width, camera.height);
        let layout = self.pipelines.draw_layout;
        // The visibility-buffer draw is done by now (`record_prepass`): only its resolve
        // remains.
        let draw = (!plan.visibility_draw()).then_some(pipeline);
        // SAFETY: `cmd` is recording inside a compatible rendering pass (caller contract); every
        // bound object is owned by `self` and outlives the command buffer's execution.
        unsafe {
            if let Some(timed) = timed {
                self.timer.draw_start(device, cmd, self.slot, timed);
            }
            if let Some(pipeline) = draw.or(resolve) {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            }
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[scissor]);
            // One draw per chunk, in instance order (so depth ties resolve as in one draw).
            let chunks: Vec<(u32, u32)> = self.chunking().chunks().collect();
            for (k, ((first, count), set)) in chunks.into_iter().zip(sets).enumerate() {
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    layout,
                    0,
                    &[set],
                    &[],
                );
                let push = push_constants(
                    camera,
                    &self.settings.material,
                    self.scene.origin,
                    self.scene.radius_unit,
                    first,
                );
                device.cmd_push_constants(
                    cmd,
                    layout,
                    DRAW_PUSH_STAGES,
                    0,
                    bytemuck::bytes_of(&push),
                );
                // The benchmark's floors measure the splat alone: nothing drawn.
                if plan.path.splat().is_some() && self.research.splat_floor() != 0 {
                    continue;
                }
                if let Some(resolve) = resolve {
                    // The resolve: a square per resolve tile shades the pixels whose nearest
                    // hit is one of this chunk's glyphs (the tiles no glyph marked are
                    // empty); then the glyphs the splat left to the draw, depth-tested
                    // against it.
                    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, resolve);
                    device.cmd_draw(cmd, 4, tiles, 0, 0);
                }
                let Some(pipeline) = draw else {
                    continue;
                };
                if resolve.is_some() {
                    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                }
                let indirect = plan
                    .indirect_draw()
                    .then_some((indirect, k as u64 * SLICE_ALIGN));
                match (plan.baseline, indirect) {
                    (Some(baseline), indirect) => self.research.record_draw(
                        device,
                        cmd,
                        baseline,
                        indirect,
                        count,
                        plan.footprint,
                    ),
                    (None, Some((buffer, offset))) => {
                        let stride = size_of::<vk::DrawIndirectCommand>() as u32;
                        device.cmd_draw_indirect(cmd, buffer, offset, 1, stride)
                    }
                    (None, None) => device.cmd_draw(cmd, plan.footprint.vertices(), count, 0, 0),
                }
            }
            if let Some(timed) = timed {
                self.timer.draw_end(device, cmd, self.slot, timed);
            }
        }
        Ok(())
    }
}
