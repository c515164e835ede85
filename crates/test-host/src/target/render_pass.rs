//! Drawing into a [`HostTarget`] through a `VkRenderPass` with one subpass and a framebuffer.

use ash::vk;

use super::HostTarget;
use crate::{fail, HostResult};

/// An attachment with no stencil that starts UNDEFINED (its old contents are not kept).
fn attachment(
    format: vk::Format,
    samples: vk::SampleCountFlags,
    load_op: vk::AttachmentLoadOp,
    store_op: vk::AttachmentStoreOp,
    final_layout: vk::ImageLayout,
) -> vk::AttachmentDescription {
    vk::AttachmentDescription::default()
        .format(format)
        .samples(samples)
        .load_op(load_op)
        .store_op(store_op)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(final_layout)
}

impl HostTarget {
    /// One subpass: colour 0, depth 1 and, under MSAA, resolve 2; and the framebuffer of the
    /// target's views. The image copied out afterwards (colour, or resolve under MSAA) ends in
    /// TRANSFER_SRC_OPTIMAL.
    pub(super) fn create_render_pass(&mut self, device: &ash::Device) -> HostResult<()> {
        use vk::{AttachmentLoadOp as Load, AttachmentStoreOp as Store, ImageLayout as Layout};
        let msaa = self.resolve.is_some();
        let samples = self.samples;
        // Multisampled: only the resolved image is kept.
        let (color_store, color_final) = if msaa {
            (Store::DONT_CARE, Layout::COLOR_ATTACHMENT_OPTIMAL)
        } else {
            (Store::STORE, Layout::TRANSFER_SRC_OPTIMAL)
        };
        let mut attachments = vec![
            attachment(
                Self::COLOR_FORMAT,
                samples,
                Load::CLEAR,
                color_store,
                color_final,
            ),
            attachment(
                Self::DEPTH_FORMAT,
                samples,
                Load::CLEAR,
                Store::DONT_CARE,
                Layout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            ),
        ];
        if msaa {
            attachments.push(attachment(
                Self::COLOR_FORMAT,
                vk::SampleCountFlags::TYPE_1,
                Load::DONT_CARE,
                Store::STORE,
                Layout::TRANSFER_SRC_OPTIMAL,
            ));
        }
        let color_refs = [vk::AttachmentReference {
            attachment: 0,
            layout: Layout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let depth_ref = vk::AttachmentReference {
            attachment: 1,
            layout: Layout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        };
        let resolve_refs = [vk::AttachmentReference {
            attachment: 2,
            layout: Layout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let mut subpass = vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&color_refs)
            .depth_stencil_attachment(&depth_ref);
        if msaa {
            subpass = subpass.resolve_attachments(&resolve_refs);
        }
        let attachment_stages = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
            | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
        let dependencies = [
            // Earlier work on these images (last frame's attachment writes and the copy out)
            // before this pass's layout transitions, clears and writes.
            vk::SubpassDependency {
                src_subpass: vk::SUBPASS_EXTERNAL,
                dst_subpass: 0,
                src_stage_mask: attachment_stages | vk::PipelineStageFlags::TRANSFER,
                dst_stage_mask: attachment_stages,
                src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
                dst_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_READ
                    | vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
                dependency_flags: vk::DependencyFlags::empty(),
            },
            // Colour writes and the resolve before the copy out of the pass.
            vk::SubpassDependency {
                src_subpass: 0,
                dst_subpass: vk::SUBPASS_EXTERNAL,
                src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                dst_stage_mask: vk::PipelineStageFlags::TRANSFER,
                src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                dst_access_mask: vk::AccessFlags::TRANSFER_READ,
                dependency_flags: vk::DependencyFlags::empty(),
            },
        ];
        let subpasses = [subpass];
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachments)
            .subpasses(&subpasses)
            .dependencies(&dependencies);
        // SAFETY: every pointer in `info` refers to locals alive during the call.
        self.render_pass = unsafe { device.create_render_pass(&info, None) }
            .map_err(fail("vkCreateRenderPass"))?;

        let mut views = vec![self.color_image().view, self.depth_image().view];
        views.extend(self.resolve.as_ref().map(|resolve| resolve.view));
        let framebuffer_info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&views)
            .width(self.extent.width)
            .height(self.extent.height)
            .layers(1);
        // SAFETY: the views match the render pass's attachments in format and samples.
        self.framebuffer = unsafe { device.create_framebuffer(&framebuffer_info, None) }
            .map_err(fail("vkCreateFramebuffer"))?;
        Ok(())
    }

    /// Begins the render pass over `area`, clearing colour and depth to `[colour, depth]`.
    pub(super) fn begin_render_pass(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        area: vk::Rect2D,
        [clear_color, clear_depth]: [vk::ClearValue; 2],
    ) {
        // One value per attachment: colour, depth and (ignored, DONT_CARE) resolve.
        let clears = [clear_color, clear_depth, clear_color];
        let count = if self.resolve.is_some() { 3 } else { 2 };
        let info = vk::RenderPassBeginInfo::default()
            .render_pass(self.render_pass)
            .framebuffer(self.framebuffer)
            .render_area(area)
            .clear_values(&clears[..count]);
        // SAFETY: `cmd` is recording outside a pass; the framebuffer matches the pass.
        unsafe { device.cmd_begin_render_pass(cmd, &info, vk::SubpassContents::INLINE) };
    }

    /// Ends the render pass. Its final layouts and its 0 -> EXTERNAL dependency already made
    /// the copied image a TRANSFER_SRC_OPTIMAL transfer source.
    pub(super) fn end_render_pass(device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is inside the pass begun by `begin_render_pass`.
        unsafe { device.cmd_end_render_pass(cmd) };
    }
}
