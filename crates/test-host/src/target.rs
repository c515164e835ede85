//! [`HostTarget`]: the engine's offscreen render target. Colour and depth images (multisampled
//! or not), a single-sample resolve image under MSAA, and a host-visible buffer the final
//! colour is copied into. It is drawn into through a `VkRenderPass` (`target/render_pass.rs`)
//! or dynamic rendering (`target/dynamic_rendering.rs`).

mod dynamic_rendering;
mod render_pass;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::buffer::OwnedBuffer;
use crate::image::{color_layers, OwnedImage};
use crate::{Host, HostResult};

/// How a [`HostTarget`] is rendered to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetKind {
    /// `vkCmdBeginRendering` (Vulkan 1.3 dynamic rendering) with explicit layout barriers.
    Dynamic,
    /// A classic `VkRenderPass` + `VkFramebuffer` with one subpass.
    RenderPass,
}

/// The depth convention of a [`HostTarget`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthKind {
    /// Reversed-Z, infinite far plane: cleared to 0, compare GREATER.
    ReversedInfinite,
    /// Standard Z in [0, 1] between near and far: cleared to 1, compare LESS.
    StandardFinite,
}

/// An offscreen render target of the host engine: colour, depth, optional MSAA resolve image,
/// and a host-visible buffer the final colour is copied into. Each part is `None` only while
/// (or after a failure) being created.
pub struct HostTarget {
    kind: TargetKind,
    depth_kind: DepthKind,
    samples: vk::SampleCountFlags,
    extent: vk::Extent2D,
    color: Option<OwnedImage>,
    depth: Option<OwnedImage>,
    /// Single-sample image the MSAA colour is resolved into (only when samples > 1).
    resolve: Option<OwnedImage>,
    readback: Option<OwnedBuffer>,
    /// Null for [`TargetKind::Dynamic`].
    render_pass: vk::RenderPass,
    /// Null for [`TargetKind::Dynamic`].
    framebuffer: vk::Framebuffer,
}

impl HostTarget {
    /// Format of the colour (and resolve) image.
    pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
    /// Format of the depth image.
    pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

    /// Creates the images, the readback buffer and, for [`TargetKind::RenderPass`], the render
    /// pass and framebuffer.
    pub fn new(
        host: &mut Host,
        kind: TargetKind,
        depth: DepthKind,
        samples: vk::SampleCountFlags,
        width: u32,
        height: u32,
    ) -> HostResult<HostTarget> {
        if samples.as_raw().count_ones() != 1 {
            return Err(format!("sample count {samples:?} is not a single count"));
        }
        if width == 0 || height == 0 {
            return Err(format!("empty target {width}x{height}"));
        }
        // SAFETY: the physical device comes from the host's instance.
        let limits = unsafe {
            host.instance()
                .get_physical_device_properties(host.physical_device())
        }
        .limits;
        let supported =
            limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
        if !supported.contains(samples) {
            return Err(format!(
                "{samples:?} not supported for colour+depth (device supports {supported:?})"
            ));
        }
        let mut target = HostTarget {
            kind,
            depth_kind: depth,
            samples,
            extent: vk::Extent2D { width, height },
            color: None,
            depth: None,
            resolve: None,
            readback: None,
            render_pass: vk::RenderPass::null(),
            framebuffer: vk::Framebuffer::null(),
        };
        match target.create_resources(host) {
            Ok(()) => Ok(target),
            Err(e) => {
                target.destroy(host);
                Err(e)
            }
        }
    }

    fn create_resources(&mut self, host: &mut Host) -> HostResult<()> {
        let msaa = self.samples != vk::SampleCountFlags::TYPE_1;
        let (extent, samples) = (self.extent, self.samples);
        let color = vk::ImageAspectFlags::COLOR;
        let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        let copied = attachment | vk::ImageUsageFlags::TRANSFER_SRC;
        let mut image = |name, format, usage, samples, aspect| {
            OwnedImage::new(host, name, format, usage, samples, extent, aspect).map(Some)
        };
        // Multisampled: the colour is resolved into a single-sample image, which is copied.
        let color_usage = if msaa { attachment } else { copied };
        self.color = image(
            "host colour",
            Self::COLOR_FORMAT,
            color_usage,
            samples,
            color,
        )?;
        self.depth = image(
            "host depth",
            Self::DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            samples,
            vk::ImageAspectFlags::DEPTH,
        )?;
        if msaa {
            let single = vk::SampleCountFlags::TYPE_1;
            self.resolve = image("host resolve", Self::COLOR_FORMAT, copied, single, color)?;
        }
        let bytes = u64::from(extent.width) * u64::from(extent.height) * 4;
        self.readback = Some(OwnedBuffer::new(
            host,
            "host readback",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?);
        if self.kind == TargetKind::RenderPass {
            self.create_render_pass(host.device())?;
        }
        Ok(())
    }

    fn color_image(&self) -> &OwnedImage {
        self.color.as_ref().expect("created in HostTarget::new")
    }

    fn depth_image(&self) -> &OwnedImage {
        self.depth.as_ref().expect("created in HostTarget::new")
    }

    /// The single-sample image read back: the resolve image under MSAA, else the colour image.
    fn copied_image(&self) -> &OwnedImage {
        self.resolve.as_ref().unwrap_or_else(|| self.color_image())
    }

    /// The depth compare op for this target's convention (GREATER reversed, LESS standard).
    pub fn depth_compare(&self) -> vk::CompareOp {
        match self.depth_kind {
            DepthKind::ReversedInfinite => vk::CompareOp::GREATER,
            DepthKind::StandardFinite => vk::CompareOp::LESS,
        }
    }

    /// The value depth is cleared to (the far plane): 0 reversed, 1 standard.
    pub fn depth_clear(&self) -> f32 {
        match self.depth_kind {
            DepthKind::ReversedInfinite => 0.0,
            DepthKind::StandardFinite => 1.0,
        }
    }

    /// Render pass or dynamic rendering.
    pub fn kind(&self) -> TargetKind {
        self.kind
    }

    /// The depth convention.
    pub fn depth_kind(&self) -> DepthKind {
        self.depth_kind
    }

    /// Samples per pixel of the colour and depth images.
    pub fn samples(&self) -> vk::SampleCountFlags {
        self.samples
    }

    /// Width and height in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The render pass (null for [`TargetKind::Dynamic`]); pipelines drawing into the target
    /// use its subpass 0.
    pub fn render_pass(&self) -> vk::RenderPass {
        self.render_pass
    }

    /// Starts drawing into the target: the render pass, or layout transitions and
    /// `vkCmdBeginRendering`, clearing colour to opaque black and depth to
    /// [`Self::depth_clear`]; then a full viewport and scissor.
    pub fn begin_pass(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: self.extent,
        };
        let clears = [
            vk::ClearValue {
                color: vk::ClearColorValue {
                    float32: [0.0, 0.0, 0.0, 1.0],
                },
            },
            vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: self.depth_clear(),
                    stencil: 0,
                },
            },
        ];
        match self.kind {
            TargetKind::RenderPass => self.begin_render_pass(device, cmd, area, clears),
            TargetKind::Dynamic => self.begin_rendering(device, cmd, area, clears),
        }
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: self.extent.width as f32,
            height: self.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: `cmd` is recording; dynamic state is valid to set at any time.
        unsafe {
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
        }
    }

    /// Ends the pass, leaving the final single-sample colour (the resolve image under MSAA) a
    /// TRANSFER_SRC_OPTIMAL transfer source, and copies it into the readback buffer, made
    /// visible to the host. Read it with [`Self::read_rgba`] after [`Host::submit_and_wait`].
    pub fn end_pass(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        match self.kind {
            TargetKind::RenderPass => Self::end_render_pass(device, cmd),
            TargetKind::Dynamic => self.end_rendering(device, cmd),
        }
        let readback = self.readback.as_ref().expect("created in HostTarget::new");
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: color_layers(),
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: self.extent.width,
                height: self.extent.height,
                depth: 1,
            },
        };
        // To the host's read, and to the next pass's copy into the same buffer (a command
        // buffer may hold several passes).
        let to_host = [vk::BufferMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST | vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::HOST_READ | vk::AccessFlags2::TRANSFER_WRITE)
            .buffer(readback.buffer)
            .offset(0)
            .size(vk::WHOLE_SIZE)];
        let dependency = vk::DependencyInfo::default().buffer_memory_barriers(&to_host);
        // SAFETY: `cmd` is recording outside a pass; the image is in TRANSFER_SRC_OPTIMAL and
        // the buffer holds exactly width * height * 4 bytes.
        unsafe {
            device.cmd_copy_image_to_buffer(
                cmd,
                self.copied_image().image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.buffer,
                &[region],
            );
            device.cmd_pipeline_barrier2(cmd, &dependency);
        }
    }

    /// The pixels copied by [`Self::end_pass`]: tightly packed RGBA8 rows, row 0 at the top.
    /// Call after [`Host::submit_and_wait`].
    pub fn read_rgba(&self) -> HostResult<Vec<u8>> {
        let bytes = self.extent.width as usize * self.extent.height as usize * 4;
        let readback = self.readback.as_ref().expect("created in HostTarget::new");
        Ok(readback.mapped()?[..bytes].to_vec())
    }

    /// Destroys everything the target created. The GPU must be done with it (call after
    /// [`Host::submit_and_wait`]).
    pub fn destroy(mut self, host: &mut Host) {
        let (device, allocator) = host.device_and_allocator();
        // SAFETY: the caller guarantees no pending work uses the target; framebuffer before
        // render pass and views, null handles are ignored by Vulkan.
        unsafe {
            device.destroy_framebuffer(self.framebuffer, None);
            device.destroy_render_pass(self.render_pass, None);
        }
        for image in [self.resolve.take(), self.depth.take(), self.color.take()]
            .into_iter()
            .flatten()
        {
            image.destroy(device, allocator);
        }
        if let Some(readback) = self.readback.take() {
            readback.destroy(device, allocator);
        }
    }
}
