//! Drawing into a [`HostTarget`] with dynamic rendering (`vkCmdBeginRendering`): the layout
//! transitions a render pass would make are explicit barriers here.

use ash::vk;

use super::HostTarget;
use crate::image::subresource_range;

impl HostTarget {
    /// Transitions the images to attachment layouts, then begins rendering over `area`,
    /// clearing colour and depth to `[colour, depth]` and, under MSAA, resolving into the
    /// resolve image.
    pub(super) fn begin_rendering(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        area: vk::Rect2D,
        [clear_color, clear_depth]: [vk::ClearValue; 2],
    ) {
        let color_access =
            vk::AccessFlags2::COLOR_ATTACHMENT_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE;
        // Earlier uses (attachment writes, the copy out) complete before the transitions;
        // UNDEFINED discards the old contents, which are cleared anyway.
        let color_barrier = |image: vk::Image| {
            vk::ImageMemoryBarrier2::default()
                .src_stage_mask(
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT
                        | vk::PipelineStageFlags2::COPY,
                )
                .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
                .dst_access_mask(color_access)
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .image(image)
                .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR))
        };
        let tests = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let mut barriers = vec![
            color_barrier(self.color_image().image),
            vk::ImageMemoryBarrier2::default()
                .src_stage_mask(tests)
                .src_access_mask(vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE)
                .dst_stage_mask(tests)
                .dst_access_mask(
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                )
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .image(self.depth_image().image)
                .subresource_range(subresource_range(vk::ImageAspectFlags::DEPTH)),
        ];
        barriers.extend(self.resolve.as_ref().map(|r| color_barrier(r.image)));
        let dependency = vk::DependencyInfo::default().image_memory_barriers(&barriers);
        // SAFETY: `cmd` is recording outside a pass; the barriers name this target's images.
        unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };

        let mut color = vk::RenderingAttachmentInfo::default()
            .image_view(self.color_image().view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            // Multisampled: only the resolved image is kept.
            .store_op(if self.resolve.is_some() {
                vk::AttachmentStoreOp::DONT_CARE
            } else {
                vk::AttachmentStoreOp::STORE
            })
            .clear_value(clear_color);
        if let Some(resolve) = &self.resolve {
            color = color
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(resolve.view)
                .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
        }
        let colors = [color];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth_image().view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(clear_depth);
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&colors)
            .depth_attachment(&depth);
        // SAFETY: the images were just transitioned to the layouts named here.
        unsafe { device.cmd_begin_rendering(cmd, &info) };
    }

    /// Ends rendering and makes the copied image (the resolve image under MSAA) a
    /// TRANSFER_SRC_OPTIMAL transfer source.
    pub(super) fn end_rendering(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let barrier = vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
            .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)
            .old_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            .image(self.copied_image().image)
            .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR));
        let barriers = [barrier];
        let dependency = vk::DependencyInfo::default().image_memory_barriers(&barriers);
        // SAFETY: `cmd` is inside the rendering begun by `begin_rendering`; the barrier follows
        // it, outside any pass.
        unsafe {
            device.cmd_end_rendering(cmd);
            device.cmd_pipeline_barrier2(cmd, &dependency);
        }
    }
}
