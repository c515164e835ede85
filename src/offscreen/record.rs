//! Recording one offscreen frame: pre-pass, pass, and the copies to the readback buffer.

use ash::vk;

use crate::camera::Camera;
use crate::error::{Result, VkCall};
use crate::frame::NO_INSTANCE;
use crate::gpu::image::full_range;
use crate::gpu::GpuImage;

use super::sample_zero::{Attachment, Copy, SampleZero};
use super::targets::{Attachments, Targets};
use super::{OffscreenRenderer, Outputs, BACKGROUND};

impl OffscreenRenderer {
    /// Records one frame of `cameras` into the command buffer: each view's pre-pass, the
    /// pass drawing every view into the attachments of `outputs`, and with `readback` the
    /// copies of `outputs` to the readback buffer.
    pub(super) fn record(
        &mut self,
        cameras: &[Camera],
        extent: vk::Extent2D,
        outputs: Outputs,
        readback: bool,
    ) -> Result<()> {
        let cmd = self.begin_commands()?;
        let (device, allocator) = self.context.device_and_allocator();
        let queries = self.queries.as_ref();
        let sample_zero = self.sample_zero.as_ref();
        let targets = self
            .targets
            .as_ref()
            .expect("targets exist after ensure_targets");
        let renderer = self
            .renderer
            .as_mut()
            .expect("renderer exists after construction");
        // Colour always; normal and ID when asked for. Multisampled, the pass draws into the
        // multisampled attachments and resolves into these.
        let colors = targets.read.colors(outputs);
        let (drawn_colors, drawn_depth): (Vec<&GpuImage>, Option<&GpuImage>) =
            match &targets.multisampled {
                Some((_, drawn)) => (drawn.colors(outputs), Some(&drawn.depth)),
                None => (Vec::new(), None),
            };
        // SAFETY: `cmd` is recording (begin_commands) outside a pass; all recorded handles are
        // owned by `self` and live until the submission, which is waited for, completes.
        unsafe {
            if let Some(q) = queries {
                q.begin(device, cmd);
            }
            // The views' pre-passes run outside the rendering pass, all before it.
            for camera in cameras {
                renderer.record_prepass(device, allocator, cmd, camera)?;
            }

            // Attachments to render layouts.
            let mut barriers: Vec<vk::ImageMemoryBarrier> = colors
                .iter()
                .chain(&drawn_colors)
                .map(|t| {
                    vk::ImageMemoryBarrier::default()
                        .src_access_mask(vk::AccessFlags::empty())
                        .dst_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
                        .old_layout(vk::ImageLayout::UNDEFINED)
                        .new_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                        .image(t.handle())
                        .subresource_range(full_range(vk::ImageAspectFlags::COLOR))
                })
                .collect();
            for depth in std::iter::once(&targets.read.depth).chain(drawn_depth) {
                barriers.push(
                    vk::ImageMemoryBarrier::default()
                        .src_access_mask(vk::AccessFlags::empty())
                        // A resolve into the single-sample image writes it as a colour
                        // attachment write, whatever the aspect.
                        .dst_access_mask(
                            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                                | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE
                                | vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                        )
                        .old_layout(vk::ImageLayout::UNDEFINED)
                        .new_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                        .image(depth.handle())
                        .subresource_range(full_range(vk::ImageAspectFlags::DEPTH)),
                );
            }
            // The previous frame's copies and fetches of sample 0 read them: wait for both.
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                    | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
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
            // Multisampled: draw into the multisampled image; colour and normal are resolved
            // into the read one by the mean of the samples, ID and depth are kept and their
            // sample 0 fetched after the pass (`sample_zero.rs`: a `SAMPLE_ZERO` resolve of
            // integers takes another sample on some drivers).
            let attachment = |read: &GpuImage, drawn: Option<&GpuImage>, layout, mean: bool| {
                let info = vk::RenderingAttachmentInfo::default()
                    .image_layout(layout)
                    .load_op(vk::AttachmentLoadOp::CLEAR);
                match drawn {
                    None => info
                        .image_view(read.view())
                        .store_op(vk::AttachmentStoreOp::STORE),
                    Some(drawn) if mean => info
                        .image_view(drawn.view())
                        .store_op(vk::AttachmentStoreOp::DONT_CARE)
                        .resolve_image_view(read.view())
                        .resolve_image_layout(layout)
                        .resolve_mode(vk::ResolveModeFlags::AVERAGE),
                    Some(drawn) => info
                        .image_view(drawn.view())
                        .store_op(vk::AttachmentStoreOp::STORE),
                }
            };
            // Colour and normal are float formats, resolved by the mean; the ID is kept.
            let by_mean = [true, true, false];
            let color_attachments: Vec<vk::RenderingAttachmentInfo> = colors
                .iter()
                .zip(clears)
                .zip(by_mean)
                .enumerate()
                .map(|(k, ((t, clear), mean))| {
                    attachment(
                        t,
                        drawn_colors.get(k).copied(),
                        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                        mean,
                    )
                    .clear_value(vk::ClearValue { color: clear })
                })
                .collect();
            let depth_attachment = attachment(
                &targets.read.depth,
                drawn_depth,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                false,
            )
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: cameras[0].depth.clear_value(),
                    stencil: 0,
                },
            });
            let rendering = vk::RenderingInfo::default()
                .render_area(vk::Rect2D {
                    offset: vk::Offset2D { x: 0, y: 0 },
                    extent,
                })
                .layer_count(1)
                .color_attachments(&color_attachments)
                .depth_attachment(&depth_attachment);
            device.cmd_begin_rendering(cmd, &rendering);
            if let Some(q) = queries {
                q.begin_statistics(device, cmd);
            }
            for camera in cameras {
                renderer.record(device, allocator, cmd, camera)?;
            }
            if let Some(q) = queries {
                q.end_statistics(device, cmd);
            }
            device.cmd_end_rendering(cmd);
            if let Some(q) = queries {
                q.end(device, cmd);
            }

            if readback {
                // Attachments to transfer source, then copy into the readback buffer.
                let to_transfer = |image: vk::Image, aspect, old, src_access| {
                    vk::ImageMemoryBarrier::default()
                        .src_access_mask(src_access)
                        .dst_access_mask(vk::AccessFlags::TRANSFER_READ)
                        .old_layout(old)
                        .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                        .image(image)
                        .subresource_range(full_range(aspect))
                };
                let mut barriers: Vec<vk::ImageMemoryBarrier> = colors
                    .iter()
                    .map(|t| {
                        to_transfer(
                            t.handle(),
                            vk::ImageAspectFlags::COLOR,
                            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                            vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                        )
                    })
                    .collect();
                // A resolve writes its image as a colour attachment write, whatever the aspect.
                barriers.push(to_transfer(
                    targets.read.depth.handle(),
                    vk::ImageAspectFlags::DEPTH,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE
                        | vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                ));
                device.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                        | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
                        | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
                    vk::PipelineStageFlags::TRANSFER,
                    vk::DependencyFlags::empty(),
                    &[],
                    &[],
                    &barriers,
                );
                let (offsets, _) = Targets::layout(extent, targets.outputs);
                let (normal, id) = match &targets.read.aux {
                    Some((normal, id)) => (Some(normal), Some(id)),
                    None => (None, None),
                };
                // Multisampled, depth and ID come from the fetch of sample 0 below.
                let single = targets.multisampled.is_none();
                let images = [
                    (
                        Some(&targets.read.color),
                        vk::ImageAspectFlags::COLOR,
                        offsets[0],
                    ),
                    (
                        Some(&targets.read.depth).filter(|_| single),
                        vk::ImageAspectFlags::DEPTH,
                        offsets[1],
                    ),
                    (normal, vk::ImageAspectFlags::COLOR, offsets[2]),
                    (
                        id.filter(|_| single),
                        vk::ImageAspectFlags::COLOR,
                        offsets[3],
                    ),
                ];
                let wanted = [outputs.color, outputs.depth, outputs.normal, outputs.id];
                for ((image, aspect, offset), wanted) in images.into_iter().zip(wanted) {
                    let (Some(image), Some(offset), true) = (image, offset, wanted) else {
                        continue;
                    };
                    let region = vk::BufferImageCopy::default()
                        .buffer_offset(offset)
                        .image_subresource(vk::ImageSubresourceLayers {
                            aspect_mask: aspect,
                            mip_level: 0,
                            base_array_layer: 0,
                            layer_count: 1,
                        })
                        .image_extent(vk::Extent3D {
                            width: extent.width,
                            height: extent.height,
                            depth: 1,
                        });
                    device.cmd_copy_image_to_buffer(
                        cmd,
                        image.handle(),
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        targets.readback.handle(),
                        &[region],
                    );
                }
                if let (Some((_, drawn)), Some(fetch)) = (&targets.multisampled, sample_zero) {
                    record_sample_zero(device, cmd, fetch, targets, drawn, outputs, offsets);
                }
                renderer.record_counter_barrier(device, cmd);
                // Make the copies and fetches visible to the host read after the fence.
                let to_host = vk::BufferMemoryBarrier::default()
                    .src_access_mask(
                        vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE,
                    )
                    .dst_access_mask(vk::AccessFlags::HOST_READ)
                    .buffer(targets.readback.handle())
                    .offset(0)
                    .size(vk::WHOLE_SIZE);
                device.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
                    vk::PipelineStageFlags::HOST,
                    vk::DependencyFlags::empty(),
                    &[],
                    &[to_host],
                    &[],
                );
            }
            device.end_command_buffer(cmd).call("vkEndCommandBuffer")?;
        }
        Ok(())
    }
}

/// Records the fetch of sample 0 of the multisampled depth and ID attachments (`drawn`) into
/// their regions of the read-back buffer, for the outputs asked for: the attachments' writes
/// before the reads, with their layouts changed for sampling.
///
/// # Safety
/// `cmd` is recording outside a pass, after the pass that drew into `drawn`; nothing pending
/// uses `fetch`'s sets; every handle outlives the submission.
unsafe fn record_sample_zero(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    fetch: &SampleZero,
    targets: &Targets,
    drawn: &Attachments,
    outputs: Outputs,
    offsets: [Option<u64>; 4],
) {
    let to_sampled = |image: &GpuImage, aspect, old, src_access| {
        vk::ImageMemoryBarrier::default()
            .src_access_mask(src_access)
            .dst_access_mask(vk::AccessFlags::SHADER_READ)
            .old_layout(old)
            .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
            .image(image.handle())
            .subresource_range(full_range(aspect))
    };
    let mut barriers = Vec::new();
    let mut copies = Vec::new();
    if let (true, Some(offset)) = (outputs.depth, offsets[1]) {
        barriers.push(to_sampled(
            &drawn.depth,
            vk::ImageAspectFlags::DEPTH,
            vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
        ));
        copies.push(Copy {
            attachment: Attachment::Depth,
            view: drawn.depth.view(),
            offset,
        });
    }
    if let (true, Some(offset), Some((_, id))) = (outputs.id, offsets[3], &drawn.aux) {
        barriers.push(to_sampled(
            id,
            vk::ImageAspectFlags::COLOR,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
        ));
        copies.push(Copy {
            attachment: Attachment::Id,
            view: id.view(),
            offset,
        });
    }
    if copies.is_empty() {
        return;
    }
    // SAFETY: caller contract.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
                | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
            vk::PipelineStageFlags::COMPUTE_SHADER,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &barriers,
        );
        fetch.record(
            device,
            cmd,
            targets.readback.handle(),
            targets.read.color.extent(),
            &copies,
        );
    }
}
