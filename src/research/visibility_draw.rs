//! The benchmark's visibility-buffer draw (feature `research`, method `impostor-visbuffer`):
//! every glyph is rasterized and ray cast as the shipped impostor is, but each fragment only
//! keeps its pixel's nearest hit in the compute splat's visibility buffer; the resolve in the
//! host's pass then shades each visible pixel once. It measures what shading once per
//! visible pixel buys a rasterizer with no early depth test for depth-exporting shaders.
//!
//! The fragment stage's atomics must be visible to the resolve's reads in the host's pass, so
//! the draw runs before it, in a dynamic-rendering pass of its own with no attachments.
//!
//! The benchmark's visibility-buffer draw (`research`: `Shading::VisibilityBuffer`, method
//! `impostor-visbuffer`, `FramePlan::visibility_draw`) measures shading once per visible pixel
//! through the rasterizer: `record_prepass` clears the visibility buffer and draws every glyph,
//! in a dynamic-rendering pass of its own with no attachments, with the shipped vertex stage and
//! `research/ellipsoid_visibility.frag`, which runs the same hit and keeps the key with the same
//! atomics (and marks the tile) instead of shading and exporting depth; the host's pass then
//! only resolves. Its own pass is what makes it correct: the resolve reads, in the host's pass,
//! what the draw's fragment stage wrote, and only a barrier between two passes orders that
//! (inside one pass it would need a self-dependency of the host's render pass, or
//! `VK_KHR_dynamic_rendering_local_read`). It is bit-identical to the draw
//! (`tests/compute_splat.rs`) and slower on lavapipe ([`compute-splat.md`](compute-splat.md)).

use ash::vk;

use crate::barriers;
use crate::camera::Camera;
use crate::error::Result;
use crate::gpu_layout::visibility_bytes;
use crate::renderer::pipelines::DRAW_PUSH_STAGES;
use crate::renderer::push::push_constants;
use crate::renderer::viewport::viewport_and_scissor;
use crate::renderer::{Binding, EllipsoidRenderer, FramePlan};

impl EllipsoidRenderer {
    /// Records the visibility-buffer draw of a frame with `camera` and `plan` into `cmd`,
    /// with `pipeline` (built for the baseline's own pass, which has no attachments): the
    /// buffer's clear, the draw of every chunk, and the barriers before the clear and after
    /// the draw.
    ///
    /// # Safety
    /// As [`EllipsoidRenderer::record_prepass`]: `cmd` records outside any pass; the
    /// visibility buffer is sized for `camera`.
    pub(crate) unsafe fn record_visibility_draw(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        view: usize,
        camera: &Camera,
        plan: &FramePlan,
        pipeline: vk::Pipeline,
    ) -> Result<()> {
        let visibility = self.views[view].buffers.handle(Binding::Visibility)?;
        let sets = self.descriptor_sets(device, view)?;
        let empty = if plan.reversed_z { 0 } else { u32::MAX };
        // The pass has no attachments: its area is the camera's rectangle.
        let (viewport, area) = viewport_and_scissor(camera);
        let rendering = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1);
        let layout = self.pipelines.draw_layout;
        let vertices = plan.footprint.vertices();
        // SAFETY: `cmd` records outside any pass (caller contract); every handle is owned by
        // `self` and outlives the submission; the fill covers the buffer's image part.
        unsafe {
            barriers::PREPASS_AFTER_PREVIOUS_FRAME.record(device, cmd);
            device.cmd_fill_buffer(
                cmd,
                visibility,
                0,
                visibility_bytes(camera.width, camera.height),
                empty,
            );
            barriers::VISIBILITY_CLEARED_TO_DRAW.record(device, cmd);
            device.cmd_begin_rendering(cmd, &rendering);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            let chunks: Vec<(u32, u32)> = self.chunking().chunks().collect();
            for ((first, count), set) in chunks.into_iter().zip(sets) {
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
                device.cmd_draw(cmd, vertices, count, 0, 0);
            }
            device.cmd_end_rendering(cmd);
            barriers::VISIBILITY_DRAW_TO_RESOLVE.record(device, cmd);
        }
        Ok(())
    }
}
