//! The standalone path: owns a device, renders a scene into offscreen targets and reads back
//! colour, view depth, world normal and instance ID.

use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::camera::Camera;
use crate::draw::{DrawConfig, Footprint, Intersection};
use crate::error::{Error, Result, VkCall};
use crate::frame::Frame;
use crate::gpu::image::full_range;
use crate::gpu::queries::{FrameQueries, QueryResults};
use crate::gpu::{Context, ContextOptions, GpuBuffer, GpuImage};
use crate::renderer::{
    Culling, EllipsoidRenderer, HostDevice, Material, Pass, RendererOptions, Target, ID_FORMAT,
    NORMAL_FORMAT,
};
use crate::scene::Scene;

const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// Background colour (linear RGB).
const BACKGROUND: [f32; 4] = [0.045, 0.05, 0.065, 1.0];
/// How long to wait for one frame before calling the device hung.
const FRAME_TIMEOUT: Duration = Duration::from_secs(300);

/// Offscreen attachments of one size and the host buffer they are copied into.
struct Targets {
    color: GpuImage,
    depth: GpuImage,
    normal: GpuImage,
    id: GpuImage,
    readback: GpuBuffer,
}

impl Targets {
    /// Byte offsets of colour, depth, normal and ID inside the readback buffer. The normal
    /// comes first: a copy's buffer offset must be a multiple of its 16-byte texel.
    fn offsets(extent: vk::Extent2D) -> [u64; 4] {
        let pixels = extent.width as u64 * extent.height as u64;
        [16 * pixels, 20 * pixels, 0, 24 * pixels]
    }

    fn readback_bytes(extent: vk::Extent2D) -> u64 {
        28 * extent.width as u64 * extent.height as u64
    }
}

/// A self-contained renderer: its own Vulkan device, targets and readback.
pub struct OffscreenRenderer {
    renderer: Option<EllipsoidRenderer>,
    targets: Option<Targets>,
    command_pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    queries: Option<FrameQueries>,
    /// Read-back frames count shaded pixels (bench only: the counting shaders are separate
    /// SPIR-V, and their arithmetic may round differently from the shipped ones).
    count_fragments: bool,
    /// Timed frames also write the normal and ID targets (to measure what skipping them saves).
    timed_aux: bool,
    /// A submission failed or was not waited for to completion: its command buffer may still
    /// be pending, so nothing may be recorded again.
    unfinished: bool,
    // Declared last: dropped after the fields above have been destroyed by `Drop`.
    context: Context,
}

/// Wall time of the parts of one frame, and what the GPU queries measured.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameTiming {
    /// Submit to fence signalled.
    pub gpu_wall: Duration,
    /// Timestamps around the rendering pass, and fragment shader invocations in it.
    pub gpu: QueryResults,
    /// Pixels shaded, counted exactly by the fragment shaders (read-back frames on devices
    /// with `fragmentStoresAndAtomics`).
    pub shaded_fragments: Option<u64>,
    /// Copying the readback into a [`Frame`].
    pub readback: Duration,
}

impl OffscreenRenderer {
    /// Creates a context with `options` and the renderer's pipelines.
    pub fn new(options: &ContextOptions) -> Result<Self> {
        let context = Context::new(options)?;
        let mut this = Self {
            renderer: None,
            targets: None,
            command_pool: vk::CommandPool::null(),
            command_buffer: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            queries: None,
            count_fragments: false,
            timed_aux: false,
            unfinished: false,
            context,
        };
        this.create_objects()?; // on error, Drop releases what exists
        Ok(this)
    }

    fn create_objects(&mut self) -> Result<()> {
        let (_, family) = self.context.queue();
        let device = self.context.device();
        let info = vk::CommandPoolCreateInfo::default().queue_family_index(family);
        // SAFETY: valid create info; owned by `self`, destroyed in `Drop`.
        self.command_pool =
            unsafe { device.create_command_pool(&info, None) }.call("vkCreateCommandPool")?;
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: allocated from our pool; freed with it.
        self.command_buffer =
            unsafe { device.allocate_command_buffers(&info) }.call("vkAllocateCommandBuffers")?[0];
        // SAFETY: valid create info; owned by `self`.
        self.fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .call("vkCreateFence")?;
        // ash's instance and device are tables of function pointers: cheap to clone.
        let (instance, device) = (
            self.context.instance().clone(),
            self.context.device().clone(),
        );
        let host = HostDevice {
            instance: &instance,
            physical_device: self.context.physical_device(),
            device: &device,
            queue_family_index: family,
        };
        let (_, allocator) = self.context.device_and_allocator();
        // SAFETY: the context's handles belong together and have the required features.
        let renderer =
            unsafe { EllipsoidRenderer::new(&host, allocator, RendererOptions::new(target(true))) };
        self.renderer = Some(renderer?);
        let info = self.context.info();
        let (statistics, period) = (info.pipeline_statistics, info.timestamp_period);
        self.queries = Some(FrameQueries::new(
            self.context.device(),
            statistics,
            period,
        )?);
        Ok(())
    }

    /// The Vulkan context (device info, validation messages).
    pub fn context(&self) -> &Context {
        &self.context
    }

    /// Shading parameters.
    pub fn material_mut(&mut self) -> &mut Material {
        &mut self.renderer_mut().material
    }

    /// Chooses the intersection formulation for the following frames.
    pub fn set_intersection(&mut self, intersection: Intersection) {
        self.renderer_mut().config.intersection = intersection;
    }

    /// Chooses the screen polygon drawn per instance for the following frames.
    pub fn set_footprint(&mut self, footprint: Footprint) {
        self.renderer_mut().config.footprint = footprint;
    }

    /// With `true`, read-back frames run the counting shader builds and report
    /// `FrameTiming::shaded_fragments` (needs `fragmentStoresAndAtomics`).
    pub fn set_count_fragments(&mut self, on: bool) {
        self.count_fragments = on;
    }

    /// With `true`, timed frames write the normal and ID targets too, as if a host had asked
    /// for them; by default they draw colour and depth only.
    pub fn set_timed_aux_outputs(&mut self, on: bool) {
        self.timed_aux = on;
    }

    /// Chooses the exact culling of the pre-pass for the following frames.
    pub fn set_culling(&mut self, culling: Culling) {
        self.renderer_mut().culling = culling;
    }

    /// Whether the pre-pass computes each impostor's set-up once (on by default).
    pub fn set_setup_in_prepass(&mut self, on: bool) {
        self.renderer_mut().setup_in_prepass = on;
    }

    /// Whether `Footprint::Auto` may draw glyphs of a few pixels as one triangle (off by
    /// default).
    pub fn set_small_glyph_triangles(&mut self, on: bool) {
        self.renderer_mut().small_glyph_triangles = on;
    }

    /// Whether the shaders take the sphere path for all-sphere scenes (on by default).
    pub fn set_sphere_path(&mut self, on: bool) {
        self.renderer_mut().sphere_path = on;
    }

    /// Whether the cap code is left out when nothing reaches the near plane (on by default).
    pub fn set_cap_free_path(&mut self, on: bool) {
        self.renderer_mut().cap_free_path = on;
    }

    /// Bytes of GPU memory the uploaded scene's buffers take (see
    /// [`EllipsoidRenderer::gpu_memory_bytes`]).
    pub fn gpu_memory_bytes(&self) -> u64 {
        self.renderer
            .as_ref()
            .map_or(0, EllipsoidRenderer::gpu_memory_bytes)
    }

    /// How the next `upload` stores instances (full float32 by default).
    pub fn set_instance_format(&mut self, format: crate::instances::InstanceFormat) {
        self.renderer_mut().instance_format = format;
    }

    /// At most this many instances per chunk (the device's storage-buffer range caps it
    /// anyway); takes effect at the next `upload`.
    pub fn set_max_chunk_instances(&mut self, count: u32) {
        self.renderer_mut().max_chunk_instances = count;
    }

    /// The scene-chosen shader variants a draw with `camera` uses: (sphere path, cap-free).
    pub fn shader_variants(&self, camera: &Camera) -> (bool, bool) {
        self.renderer
            .as_ref()
            .map_or((false, false), |r| r.shader_variants(camera))
    }

    /// Whether a draw of the uploaded scene with `camera` takes its set-up from the pre-pass.
    pub fn sets_up_in_prepass(&self, camera: &Camera) -> bool {
        self.renderer
            .as_ref()
            .is_some_and(|r| r.sets_up_in_prepass(camera))
    }

    /// Chooses the whole draw configuration (a `bench` method) for the following frames.
    pub fn set_config(&mut self, config: DrawConfig) {
        self.renderer_mut().config = config;
    }

    fn renderer_mut(&mut self) -> &mut EllipsoidRenderer {
        self.renderer
            .as_mut()
            .expect("renderer exists after construction")
    }

    /// Uploads the scene's instances (replacing the previous scene), in a submission of its
    /// own.
    pub fn upload(&mut self, scene: &Scene) -> Result<()> {
        let cmd = self.begin_commands()?;
        let renderer = self
            .renderer
            .as_mut()
            .expect("renderer exists after construction");
        let (device, allocator) = self.context.device_and_allocator();
        // SAFETY: `cmd` is recording outside a pass; it is submitted and waited for below.
        let recorded = unsafe { renderer.upload(device, allocator, cmd, scene) };
        // SAFETY: `cmd` is recording.
        unsafe { device.end_command_buffer(cmd) }.call("vkEndCommandBuffer")?;
        recorded?;
        self.submit_and_wait()
    }

    /// Starts the renderer's frame (every earlier submission was waited for) and begins the
    /// one command buffer.
    fn begin_commands(&mut self) -> Result<vk::CommandBuffer> {
        if self.unfinished {
            return Err(Error::invalid(
                "offscreen renderer",
                "an earlier frame did not finish (it timed out or the device was lost): create a new renderer",
            ));
        }
        let cmd = self.command_buffer;
        let renderer = self
            .renderer
            .as_mut()
            .expect("renderer exists after construction");
        let (device, allocator) = self.context.device_and_allocator();
        // SAFETY: every submit is waited for, so nothing recorded earlier is pending: the
        // renderer's one frame slot may begin and the pool may be reset (best practice over
        // resetting the buffer).
        unsafe {
            renderer.begin_frame(device, allocator, 0)?;
            device
                .reset_command_pool(self.command_pool, vk::CommandPoolResetFlags::empty())
                .call("vkResetCommandPool")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(cmd, &begin)
                .call("vkBeginCommandBuffer")?;
        }
        Ok(cmd)
    }

    /// Uploads `scene` and renders it with `camera`.
    pub fn render(&mut self, scene: &Scene, camera: &Camera) -> Result<Frame> {
        self.upload(scene)?;
        Ok(self.render_uploaded(camera)?.0)
    }

    /// Renders the last uploaded scene and reads the frame back.
    pub fn render_uploaded(&mut self, camera: &Camera) -> Result<(Frame, FrameTiming)> {
        let mut timing = self.draw(camera, true)?;
        let start = Instant::now();
        let frame = self.read_frame(camera)?;
        timing.readback = start.elapsed();
        Ok((frame, timing))
    }

    /// Renders the last uploaded scene without reading it back: the frame a benchmark times.
    pub fn render_timed(&mut self, camera: &Camera) -> Result<FrameTiming> {
        self.draw(camera, false)
    }

    /// Records, submits and waits for one frame; copies the targets out with `readback`.
    fn draw(&mut self, camera: &Camera, readback: bool) -> Result<FrameTiming> {
        camera.validate()?;
        let extent = vk::Extent2D {
            width: camera.width,
            height: camera.height,
        };
        self.ensure_targets(extent)?;
        let counting = self.count_fragments && self.context.info().fragment_stores_and_atomics;
        {
            // Pipelines and meshes are made before recording, never inside a timed frame.
            let renderer = self
                .renderer
                .as_mut()
                .expect("renderer exists after construction");
            let (device, allocator) = self.context.device_and_allocator();
            renderer.set_target(target(readback || self.timed_aux))?;
            renderer.count_fragments = readback && counting;
            renderer.reset_fragment_counter()?;
            renderer.prepare(device, allocator, camera)?;
        }
        self.record(camera, extent, readback)?;
        let start = Instant::now();
        self.submit_and_wait()?;
        let gpu_wall = start.elapsed();
        let gpu = match &self.queries {
            Some(q) => q.read(self.context.device())?,
            None => QueryResults::default(),
        };
        let renderer = self
            .renderer
            .as_ref()
            .expect("renderer exists after construction");
        let shaded_fragments = if renderer.count_fragments {
            renderer.fragment_count().map(u64::from)
        } else {
            None
        };
        Ok(FrameTiming {
            gpu_wall,
            gpu,
            shaded_fragments,
            readback: Duration::ZERO,
        })
    }

    fn ensure_targets(&mut self, extent: vk::Extent2D) -> Result<()> {
        if self
            .targets
            .as_ref()
            .is_some_and(|t| t.color.extent() == extent)
        {
            return Ok(());
        }
        let (device, allocator) = self.context.device_and_allocator();
        if let Some(old) = self.targets.take() {
            // SAFETY: every submission is waited for before returning, so nothing uses them.
            for image in [old.color, old.depth, old.normal, old.id] {
                image.destroy(device, allocator);
            }
            old.readback.destroy(device, allocator);
        }
        let attach = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color_aspect = vk::ImageAspectFlags::COLOR;
        // Build one at a time so a failure frees the ones already made.
        let mut made: Vec<GpuImage> = Vec::new();
        let specs = [
            ("colour target", COLOR_FORMAT, attach, color_aspect),
            (
                "depth target",
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                vk::ImageAspectFlags::DEPTH,
            ),
            ("normal target", NORMAL_FORMAT, attach, color_aspect),
            ("id target", ID_FORMAT, attach, color_aspect),
        ];
        for (name, format, usage, aspect) in specs {
            match GpuImage::new(device, allocator, name, format, extent, usage, aspect) {
                Ok(image) => made.push(image),
                Err(e) => {
                    made.into_iter().for_each(|i| i.destroy(device, allocator));
                    return Err(e);
                }
            }
        }
        let readback = match GpuBuffer::new(
            device,
            allocator,
            "readback",
            Targets::readback_bytes(extent),
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        ) {
            Ok(b) => b,
            Err(e) => {
                made.into_iter().for_each(|i| i.destroy(device, allocator));
                return Err(e);
            }
        };
        let mut it = made.into_iter();
        let (Some(color), Some(depth), Some(normal), Some(id)) =
            (it.next(), it.next(), it.next(), it.next())
        else {
            unreachable!("four targets were made");
        };
        self.targets = Some(Targets {
            color,
            depth,
            normal,
            id,
            readback,
        });
        Ok(())
    }

    fn record(&mut self, camera: &Camera, extent: vk::Extent2D, readback: bool) -> Result<()> {
        let cmd = self.begin_commands()?;
        let (device, allocator) = self.context.device_and_allocator();
        let queries = self.queries.as_ref();
        let targets = self
            .targets
            .as_ref()
            .expect("targets exist after ensure_targets");
        let renderer = self
            .renderer
            .as_mut()
            .expect("renderer exists after construction");
        // Timed frames draw colour and depth only, as a host would; read-back frames add the
        // normal and ID targets.
        let colors: Vec<&GpuImage> = if readback || self.timed_aux {
            vec![&targets.color, &targets.normal, &targets.id]
        } else {
            vec![&targets.color]
        };
        // SAFETY: `cmd` is recording (begin_commands) outside a pass; all recorded handles are
        // owned by `self` and live until the submission, which is waited for, completes.
        unsafe {
            if let Some(q) = queries {
                q.begin(device, cmd);
            }
            // The culling pre-pass runs outside the rendering pass.
            renderer.record_prepass(device, allocator, cmd, camera)?;

            // Attachments to render layouts. The previous frame's copy read them: wait for it.
            let mut barriers: Vec<vk::ImageMemoryBarrier> = colors
                .iter()
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
            barriers.push(
                vk::ImageMemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::empty())
                    .dst_access_mask(
                        vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                            | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
                    )
                    .old_layout(vk::ImageLayout::UNDEFINED)
                    .new_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                    .image(targets.depth.handle())
                    .subresource_range(full_range(vk::ImageAspectFlags::DEPTH)),
            );
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
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
                    uint32: [crate::frame::NO_INSTANCE, 0, 0, 0],
                },
            ];
            let color_attachments: Vec<vk::RenderingAttachmentInfo> = colors
                .iter()
                .zip(clears)
                .map(|(t, clear)| {
                    vk::RenderingAttachmentInfo::default()
                        .image_view(t.view())
                        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                        .load_op(vk::AttachmentLoadOp::CLEAR)
                        .store_op(vk::AttachmentStoreOp::STORE)
                        .clear_value(vk::ClearValue { color: clear })
                })
                .collect();
            let depth_attachment = vk::RenderingAttachmentInfo::default()
                .image_view(targets.depth.view())
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
            renderer.record(device, allocator, cmd, camera)?;
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
                barriers.push(to_transfer(
                    targets.depth.handle(),
                    vk::ImageAspectFlags::DEPTH,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
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
                let offsets = Targets::offsets(extent);
                let images = [
                    (&targets.color, vk::ImageAspectFlags::COLOR, offsets[0]),
                    (&targets.depth, vk::ImageAspectFlags::DEPTH, offsets[1]),
                    (&targets.normal, vk::ImageAspectFlags::COLOR, offsets[2]),
                    (&targets.id, vk::ImageAspectFlags::COLOR, offsets[3]),
                ];
                for (image, aspect, offset) in images {
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
                renderer.record_counter_barrier(device, cmd);
                // Make the copies visible to the host read after the fence.
                let to_host = vk::BufferMemoryBarrier::default()
                    .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                    .dst_access_mask(vk::AccessFlags::HOST_READ)
                    .buffer(targets.readback.handle())
                    .offset(0)
                    .size(vk::WHOLE_SIZE);
                device.cmd_pipeline_barrier(
                    cmd,
                    vk::PipelineStageFlags::TRANSFER,
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

    fn submit_and_wait(&mut self) -> Result<()> {
        // Cleared only once the fence has signalled and been reset.
        self.unfinished = true;
        let device = self.context.device();
        let (queue, _) = self.context.queue();
        let buffers = [self.command_buffer];
        let submit = vk::SubmitInfo::default().command_buffers(&buffers);
        // SAFETY: the command buffer is fully recorded; the fence is unsignalled (reset after
        // every wait) and owned by `self`.
        unsafe {
            device
                .queue_submit(queue, &[submit], self.fence)
                .call("vkQueueSubmit")?;
            let waited =
                device.wait_for_fences(&[self.fence], true, FRAME_TIMEOUT.as_nanos() as u64);
            if waited == Err(vk::Result::TIMEOUT) {
                return Err(Error::vulkan(
                    "vkWaitForFences (frame took longer than 300 s)",
                    vk::Result::TIMEOUT,
                ));
            }
            waited.call("vkWaitForFences")?;
            device.reset_fences(&[self.fence]).call("vkResetFences")?;
        }
        self.unfinished = false;
        Ok(())
    }

    fn read_frame(&self, camera: &Camera) -> Result<Frame> {
        let targets = self
            .targets
            .as_ref()
            .expect("targets exist after ensure_targets");
        let bytes = targets.readback.mapped().ok_or_else(|| Error::Allocation {
            what: "readback",
            reason: "not host-visible".into(),
        })?;
        let extent = targets.color.extent();
        let offsets = Targets::offsets(extent);
        let pixels = extent.width as usize * extent.height as usize;
        let word = |base: u64, i: usize| {
            let at = base as usize + 4 * i;
            [bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]
        };
        let map = camera.depth_map();
        let far_value = camera.depth.clear_value();
        let mut frame = Frame {
            width: extent.width,
            height: extent.height,
            color: Vec::with_capacity(pixels),
            depth: Vec::with_capacity(pixels),
            normal: Vec::with_capacity(pixels),
            id: Vec::with_capacity(pixels),
        };
        for i in 0..pixels {
            frame.color.push(word(offsets[0], i));
            // The clear value is "nothing here": infinitely far.
            let z = f32::from_ne_bytes(word(offsets[1], i));
            frame.depth.push(if z != far_value {
                map.view_depth(z as f64) as f32
            } else {
                f32::INFINITY
            });
            let n = |k: usize| f32::from_ne_bytes(word(offsets[2], 4 * i + k));
            frame.normal.push([n(0), n(1), n(2)]);
            frame.id.push(u32::from_ne_bytes(word(offsets[3], i)));
        }
        Ok(frame)
    }
}

impl OffscreenRenderer {
    /// Tears everything down and reports what a clean shutdown must not have: allocations the
    /// allocator still tracks, and validation messages (including those raised while the
    /// device and instance are destroyed).
    pub fn finish(mut self) -> Result<()> {
        self.release();
        let live = self.context.live_allocations();
        let log = self.context.message_log();
        drop(self);
        let failures = crate::gpu::validation::failures(&log);
        if let Some(first) = failures.first() {
            return Err(Error::Validation {
                count: failures.len(),
                first: first.to_string(),
            });
        }
        if live != 0 {
            return Err(Error::Allocation {
                what: "shutdown",
                reason: format!(
                    "{live} allocation(s) still live after every resource was destroyed"
                ),
            });
        }
        Ok(())
    }

    /// Destroys everything but the context (idempotent).
    fn release(&mut self) {
        let _ = self.context.wait_idle();
        let renderer = self.renderer.take();
        let targets = self.targets.take();
        if let Some(mut q) = self.queries.take() {
            q.destroy(self.context.device());
        }
        let (pool, fence) = (self.command_pool, self.fence);
        let (device, allocator) = self.context.device_and_allocator();
        if let Some(r) = renderer {
            // SAFETY: the device is idle (waited above).
            unsafe { r.destroy(device, allocator) };
        }
        if let Some(t) = targets {
            for image in [t.color, t.depth, t.normal, t.id] {
                image.destroy(device, allocator);
            }
            t.readback.destroy(device, allocator);
        }
        // SAFETY: the device is idle; pool (with its command buffer) and fence are owned here
        // (null after the first release, which Vulkan ignores).
        unsafe {
            device.destroy_fence(fence, None);
            device.destroy_command_pool(pool, None);
        }
        self.fence = vk::Fence::null();
        self.command_pool = vk::CommandPool::null();
    }
}

impl Drop for OffscreenRenderer {
    fn drop(&mut self) {
        self.release();
    }
}

/// The offscreen pass: colour and depth, plus the normal and ID targets with `aux_outputs`.
fn target(aux_outputs: bool) -> Target {
    let color_formats = if aux_outputs {
        vec![COLOR_FORMAT, NORMAL_FORMAT, ID_FORMAT]
    } else {
        vec![COLOR_FORMAT]
    };
    Target {
        pass: Pass::Dynamic {
            color_formats,
            depth_format: DEPTH_FORMAT,
        },
        samples: vk::SampleCountFlags::TYPE_1,
        aux_outputs,
    }
}
