//! Recording one frame of the viewer: the scene updates and the pre-pass outside the pass,
//! the renderer's draw inside a dynamic-rendering pass into colour, normal, ID and depth, and
//! the colour copied into the acquired swapchain image (and from there to a screenshot buffer).

use ash::vk;

use crate::error::Result;
use ellipsoid_splat::{Camera, Ellipsoid, Scene};

use super::{to_host, SceneChange, Viewer, BACKGROUND, NO_INSTANCE};
use crate::view::targets::ReadbackBuffer;
use crate::view::VkCall;

impl Viewer {
    /// Records frame `slot`: scene updates, the pre-pass, the pass, and the copy of the colour
    /// into the swapchain image (and from there into `shot`, if given).
    pub(super) fn record_frame(
        &mut self,
        slot: usize,
        (cmd, image, readable): (vk::CommandBuffer, vk::Image, bool),
        camera: &Camera,
        use_sample: bool,
        change: SceneChange,
        shot: Option<&ReadbackBuffer>,
    ) -> Result<()> {
        let device = self.gpu.device.clone();
        let targets = self.targets.as_ref().expect("ensure_swapchain made them");
        let (color, normal, id, depth) = (
            targets.color.image,
            targets.normal.image,
            targets.id.image,
            targets.depth.image,
        );
        let views = [targets.color.view, targets.normal.view, targets.id.view];
        let depth_view = targets.depth.view;
        let extent = targets.extent;
        let allocator = self.gpu.allocator();
        let frames = self.frames.as_mut().expect("frames exist");
        // SAFETY: the slot's fence passed, so its command buffer is not pending; everything
        // recorded is owned by the viewer and outlives the submission (destroy waits idle).
        unsafe {
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .call("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(cmd, &begin)
                .call("vkBeginCommandBuffer")?;
            frames.start_timer(&device, slot);
            // Both renderers begin every frame, so each retires what it replaced on time.
            for drawn in [&mut self.full, &mut self.moving].into_iter().flatten() {
                drawn
                    .renderer
                    .begin_frame(&device, allocator, slot as u32)?;
                let updates = match change {
                    SceneChange::Glyphs(updates) => updates,
                    SceneChange::Whole(scene) => {
                        match &mut drawn.sample {
                            None => drawn.renderer.upload(&device, allocator, cmd, scene)?,
                            Some(sample) => {
                                // The same glyph indices (the caller keeps the count).
                                sample.scene = Scene::new(
                                    sample
                                        .indices
                                        .iter()
                                        .map(|&i| scene.ellipsoids[i as usize])
                                        .collect(),
                                );
                                drawn
                                    .renderer
                                    .upload(&device, allocator, cmd, &sample.scene)?
                            }
                        }
                        continue;
                    }
                };
                // Glyphs at consecutive positions go in one update (a colour mode changes
                // them all: one copy, not a copy and two barriers per glyph).
                let mut run: Vec<Ellipsoid> = Vec::new();
                let mut run_start = 0;
                let positions = updates.iter().filter_map(|&(index, glyph)| {
                    let at = match &drawn.sample {
                        None => Some(index),
                        Some(sample) => sample.position(index),
                    };
                    at.map(|at| (at, glyph))
                });
                for (at, glyph) in positions {
                    if !run.is_empty() && at != run_start + run.len() as u32 {
                        drawn
                            .renderer
                            .update(&device, allocator, cmd, run_start, &run)?;
                        run.clear();
                    }
                    if run.is_empty() {
                        run_start = at;
                    }
                    run.push(glyph);
                }
                if !run.is_empty() {
                    drawn
                        .renderer
                        .update(&device, allocator, cmd, run_start, &run)?;
                }
            }
            let drawn = if use_sample {
                self.moving.as_mut()
            } else {
                self.full.as_mut()
            }
            .expect("the full renderer exists");
            drawn
                .renderer
                .record_prepass(&device, allocator, cmd, camera)?;

            // The outputs become attachments; the last frame's copies and any read since
            // (transfer) must be done first. Their old contents are cleared anyway.
            let color_range = range(vk::ImageAspectFlags::COLOR);
            let to_attachment = |image, aspect, layout, access| {
                vk::ImageMemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::empty())
                    .dst_access_mask(access)
                    .old_layout(vk::ImageLayout::UNDEFINED)
                    .new_layout(layout)
                    .image(image)
                    .subresource_range(range(aspect))
            };
            let color_out = (
                vk::ImageAspectFlags::COLOR,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            );
            let mut barriers: Vec<_> = [color, normal, id]
                .into_iter()
                .map(|i| to_attachment(i, color_out.0, color_out.1, color_out.2))
                .collect();
            barriers.push(to_attachment(
                depth,
                vk::ImageAspectFlags::DEPTH,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ));
            let fragment_tests = vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
            let attachment_stages =
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT | fragment_tests;
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                attachment_stages,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &barriers,
            );
            let clears = [
                vk::ClearColorValue {
                    float32: BACKGROUND,
                },
                vk::ClearColorValue { float32: [0.0; 4] },
                vk::ClearColorValue {
                    uint32: [NO_INSTANCE, 0, 0, 0],
                },
            ];
            let attachments: Vec<_> = views
                .iter()
                .zip(clears)
                .map(|(&view, clear)| {
                    vk::RenderingAttachmentInfo::default()
                        .image_view(view)
                        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                        .load_op(vk::AttachmentLoadOp::CLEAR)
                        .store_op(vk::AttachmentStoreOp::STORE)
                        .clear_value(vk::ClearValue { color: clear })
                })
                .collect();
            let depth_attachment = vk::RenderingAttachmentInfo::default()
                .image_view(depth_view)
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue {
                        depth: camera.depth.clear_value(),
                        stencil: 0,
                    },
                });
            let rendering = vk::RenderingInfo::default()
                .render_area(extent.into())
                .layer_count(1)
                .color_attachments(&attachments)
                .depth_attachment(&depth_attachment);
            device.cmd_begin_rendering(cmd, &rendering);
            drawn.renderer.record(&device, allocator, cmd, camera)?;
            device.cmd_end_rendering(cmd);

            // The outputs become copy sources (colour now, ID and depth for probes later);
            // the swapchain image becomes the copy's destination.
            let to_source = |image, aspect, access| {
                vk::ImageMemoryBarrier::default()
                    .src_access_mask(access)
                    .dst_access_mask(vk::AccessFlags::TRANSFER_READ)
                    .old_layout(if aspect == vk::ImageAspectFlags::DEPTH {
                        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL
                    } else {
                        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
                    })
                    .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                    .image(image)
                    .subresource_range(range(aspect))
            };
            let mut barriers: Vec<_> = [color, normal, id]
                .into_iter()
                .map(|i| {
                    to_source(
                        i,
                        vk::ImageAspectFlags::COLOR,
                        vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                    )
                })
                .collect();
            barriers.push(to_source(
                depth,
                vk::ImageAspectFlags::DEPTH,
                vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ));
            // The acquire semaphore's wait (at the transfer stage) orders this after the
            // presentation engine's read of the image.
            barriers.push(
                vk::ImageMemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::empty())
                    .dst_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                    .old_layout(vk::ImageLayout::UNDEFINED)
                    .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                    .image(image)
                    .subresource_range(color_range),
            );
            device.cmd_pipeline_barrier(
                cmd,
                attachment_stages | vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &barriers,
            );
            let whole = vk::ImageSubresourceLayers::default()
                .aspect_mask(vk::ImageAspectFlags::COLOR)
                .layer_count(1);
            let region = vk::ImageCopy::default()
                .src_subresource(whole)
                .dst_subresource(whole)
                .extent(extent.into());
            device.cmd_copy_image(
                cmd,
                color,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            );
            let mut layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            if let Some(shot) = shot {
                // Exactly what is shown: the swapchain image itself where it can be read,
                // else the colour output it is a copy of.
                let source = if readable {
                    let barrier = vk::ImageMemoryBarrier::default()
                        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                        .dst_access_mask(vk::AccessFlags::TRANSFER_READ)
                        .old_layout(layout)
                        .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                        .image(image)
                        .subresource_range(color_range);
                    device.cmd_pipeline_barrier(
                        cmd,
                        vk::PipelineStageFlags::TRANSFER,
                        vk::PipelineStageFlags::TRANSFER,
                        vk::DependencyFlags::empty(),
                        &[],
                        &[],
                        &[barrier],
                    );
                    layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                    image
                } else {
                    color
                };
                let copy = vk::BufferImageCopy::default()
                    .image_subresource(whole)
                    .image_extent(extent.into());
                device.cmd_copy_image_to_buffer(
                    cmd,
                    source,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    shot.buffer,
                    &[copy],
                );
                to_host(&device, cmd);
            }
            let present = vk::ImageMemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::empty())
                .old_layout(layout)
                .new_layout(vk::ImageLayout::PRESENT_SRC_KHR)
                .image(image)
                .subresource_range(color_range);
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::BOTTOM_OF_PIPE,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &[present],
            );
            frames.stop_timer(&device, slot);
            device.end_command_buffer(cmd).call("vkEndCommandBuffer")?;
        }
        Ok(())
    }
}

/// The whole of a single-level, single-layer image.
fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(1)
        .layer_count(1)
}
