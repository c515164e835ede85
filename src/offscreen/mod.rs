//! The standalone path: owns a device, renders a scene into offscreen targets and reads back
//! colour, view depth, world normal and instance ID.
//!
//! The offscreen renderer (`src/offscreen/`, feature `offscreen`) owns its device and draws with
//! dynamic rendering into its own `R8G8B8A8_SRGB` colour and `D32_SFLOAT` depth targets, plus the
//! normal and ID targets, made and drawn into only when a frame's
//! `Outputs { color, depth, normal, id }` asks for either (`Outputs::ALL`, `Outputs::COLOR_DEPTH`;
//! the default asks for nothing).
//! `render(&scene, &camera, outputs)` uploads and renders; `render_uploaded(&camera, outputs)` renders
//! the uploaded scene and returns the `Frame` with its `FrameTiming`; `render_timed(&camera, outputs)`
//! draws without reading back (the frame a benchmark times). The targets are made for one image size
//! and one set of outputs and replaced when a frame needs another size or an output they lack
//! (`targets.rs`); only the outputs asked for are copied to the read-back buffer and filled in the
//! `Frame` (`src/frame.rs`; the others stay empty vectors): sRGB RGBA8 colour, view depth (depth-buffer
//! values mapped back through the camera's depth map in float64; +inf where the depth buffer still
//! holds its clear value), normal (0 where nothing is hit, `-f` on caps) and instance ID
//! (`NO_INSTANCE = u32::MAX` where nothing is hit). Row 0 is the top row everywhere.
//!
//! # Files
//!
//! | file | what it holds |
//! |---|---|
//! | `mod.rs` | `OffscreenRenderer` (`new`, `upload`, `render`, `render_views`, `render_uploaded`, `render_timed`, `settings`, `set_settings`, `set_samples`, `plan`, `last_plan`, `plan_wisdom`, `load_plan_wisdom`, `gpu_memory_bytes`, `context`, `finish`) and `FrameTiming`; the context, command buffer, fence and queries |
//! | `outputs.rs` | `Outputs { color, depth, normal, id }`, `ALL`, `COLOR_DEPTH` |
//! | `targets.rs` | `Targets`: colour and depth always, normal and ID only when asked for, and the read-back buffer holding only the outputs asked for (normal first, for its 16-byte texel alignment); multisampled, the attachments drawn into beside the single-sample ones they resolve to |
//! | `record.rs` | one frame: pre-pass, the dynamic-rendering pass (multisampled: resolving colour and normal by the mean), and the copies of the outputs asked for |
//! | `sample_zero.rs` | multisampled depth and ID read at sample 0 by a compute fetch (`glsl/offscreen/sample_zero_*.comp`) into the read-back buffer, not resolved: one driver's `SAMPLE_ZERO` resolve of `R32_UINT` takes another sample (`docs/conformance.md`) |
//! | `readback.rs` | the read-back buffer to a `Frame` (depth mapped back to view depth) |
//! | `submission.rs` | `Submission`: what the last submission left (idle, unfinished, device lost) and the submit-and-wait that decides it, so a submission that failed before reaching the GPU leaves the renderer usable (`Error`) |

use std::time::{Duration, Instant};

use ash::vk;

mod outputs;
mod readback;
mod record;
pub(crate) mod sample_zero;
mod submission;
mod targets;

use crate::camera::Camera;
use crate::ellipsoid::Ellipsoid;
use crate::error::{Error, Result, VkCall};
use crate::frame::Frame;
use crate::gpu::queries::{FrameQueries, QueryResults};
use crate::gpu::{Context, ContextOptions};
use crate::instances::Placement;
use crate::renderer::staged::StagedUpload;
use crate::renderer::{EllipsoidRenderer, FramePlan};
use crate::research;
use crate::scene::Scene;
use crate::settings::Settings;
use crate::target::{HostDevice, Pass, RendererOptions, Target};

pub use outputs::Outputs;
use sample_zero::SampleZero;
use submission::Submission;
use targets::Targets;

const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// Background colour (linear RGB).
pub const BACKGROUND: [f32; 4] = [0.045, 0.05, 0.065, 1.0];
/// How long to wait for one frame before calling the device hung.
const FRAME_TIMEOUT: Duration = Duration::from_secs(300);

/// A self-contained renderer: its own Vulkan device, targets and readback.
pub struct OffscreenRenderer {
    renderer: Option<EllipsoidRenderer>,
    targets: Option<Targets>,
    command_pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    queries: Option<FrameQueries>,
    /// Reads sample 0 of multisampled depth and ID (made by the first `set_samples` above 1).
    sample_zero: Option<SampleZero>,
    /// Samples per pixel of the attachments (`set_samples`).
    samples: vk::SampleCountFlags,
    /// What the last submission left: whether new work may be recorded.
    submission: Submission,
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
    /// Pixels shaded, counted exactly by the fragment shaders (read-back frames with the
    /// `research` feature and `set_count_fragments(true)`, on devices with
    /// `fragmentStoresAndAtomics`).
    pub shaded_fragments: Option<u64>,
    /// Ray casts the compute splat's passes made (counted alongside `shaded_fragments`; each
    /// shaded fragment of a ray-casting shader is one ray cast too).
    pub compute_ray_casts: Option<u64>,
    /// Copying the readback into a [`Frame`].
    pub readback: Duration,
}

impl OffscreenRenderer {
    /// Creates a context with `options` and the renderer (its pipelines are built on first
    /// use).
    pub fn new(options: &ContextOptions) -> Result<Self> {
        let context = Context::new(options)?;
        let mut this = Self {
            renderer: None,
            targets: None,
            command_pool: vk::CommandPool::null(),
            command_buffer: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            queries: None,
            sample_zero: None,
            samples: vk::SampleCountFlags::TYPE_1,
            submission: Submission::Idle,
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
        let host = HostDevice::new(
            &instance,
            self.context.physical_device(),
            &device,
            family,
            self.context.info().renderer_features,
        );
        let options = RendererOptions::new(target(true, vk::SampleCountFlags::TYPE_1));
        let (_, allocator) = self.context.device_and_allocator();
        // SAFETY: the context's handles belong together and have the required features (and
        // the compute splat's where `info` says so).
        let renderer = unsafe { EllipsoidRenderer::new(&host, allocator, options) };
        #[cfg_attr(not(feature = "research"), allow(unused_mut))]
        let mut renderer = renderer?;
        #[cfg(feature = "research")]
        if self.context.info().ray_query {
            renderer.connect_ray_query(&host);
        }
        self.renderer = Some(renderer);
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

    /// The settings in force (see [`EllipsoidRenderer::settings`]).
    pub fn settings(&self) -> &Settings {
        self.renderer().settings()
    }

    /// Changes the settings (see [`EllipsoidRenderer::set_settings`] for what each costs).
    pub fn set_settings(&mut self, settings: Settings) {
        self.renderer_mut().set_settings(settings);
    }

    /// The samples per pixel frames are drawn with ([`OffscreenRenderer::set_samples`]).
    pub fn samples(&self) -> vk::SampleCountFlags {
        self.samples
    }

    /// Draws later frames with `samples` samples per pixel (1, the default, or a count the
    /// device supports for colour and depth attachments and for sampling depth and integer
    /// images) and reads back the resolved frame: colour is the mean of the samples, the
    /// normal the mean of the samples' normals (not renormalised), depth and ID those of
    /// sample 0 (fetched by a compute pass, not resolved). Multisampled frames are shaded once
    /// per pixel with exact per-sample coverage, or per sample with
    /// [`Settings::per_sample_shading`].
    pub fn set_samples(&mut self, samples: vk::SampleCountFlags) -> Result<()> {
        let supported = self.context.info().sample_counts;
        if samples.as_raw().count_ones() != 1 || !supported.contains(samples) {
            return Err(crate::error::Error::invalid(
                "samples",
                format!("{samples:?} per pixel: the device supports {supported:?}"),
            ));
        }
        if samples != vk::SampleCountFlags::TYPE_1 && self.sample_zero.is_none() {
            self.sample_zero = Some(SampleZero::new(self.context.device())?);
        }
        self.samples = samples;
        // The plan of the next frame (`plan`) sees the new sample count at once.
        let renderer = self.renderer_mut();
        let aux = renderer.current_target().aux_outputs;
        // SAFETY: the offscreen targets are dynamic rendering: no render pass to outlive.
        unsafe { renderer.set_target(target(aux, samples)) }
    }

    /// What a frame of the uploaded scene with `camera` does (see
    /// [`EllipsoidRenderer::plan`]).
    pub fn plan(&self, camera: &Camera) -> Result<FramePlan> {
        self.renderer().plan(camera)
    }

    /// The plan of the last frame: the path it took and why (see
    /// [`EllipsoidRenderer::last_plan`]).
    pub fn last_plan(&self) -> Option<&FramePlan> {
        self.renderer().last_plan()
    }

    /// What the plan learned on this device, as bytes (see
    /// [`EllipsoidRenderer::plan_wisdom`]).
    pub fn plan_wisdom(&self) -> Vec<u8> {
        self.renderer().plan_wisdom()
    }

    /// Takes in what a renderer on the same device and driver build learned (see
    /// [`EllipsoidRenderer::load_plan_wisdom`]).
    pub fn load_plan_wisdom(&mut self, bytes: &[u8]) -> Result<()> {
        self.renderer_mut().load_plan_wisdom(bytes)
    }

    /// Bytes of GPU memory the uploaded scene's buffers take (see
    /// [`EllipsoidRenderer::gpu_memory_bytes`]).
    pub fn gpu_memory_bytes(&self) -> u64 {
        self.renderer().gpu_memory_bytes()
    }

    fn renderer(&self) -> &EllipsoidRenderer {
        self.renderer
            .as_ref()
            .expect("renderer exists after construction")
    }

    pub(crate) fn renderer_mut(&mut self) -> &mut EllipsoidRenderer {
        self.renderer
            .as_mut()
            .expect("renderer exists after construction")
    }

    /// The device, the allocator and the renderer, borrowed together.
    pub(crate) fn parts(
        &mut self,
    ) -> (
        &ash::Device,
        &mut gpu_allocator::vulkan::Allocator,
        &mut EllipsoidRenderer,
    ) {
        let (device, allocator) = self.context.device_and_allocator();
        let renderer = self
            .renderer
            .as_mut()
            .expect("renderer exists after construction");
        (device, allocator, renderer)
    }

    /// Uploads the scene's instances (replacing the previous scene), in a submission of its
    /// own.
    pub fn upload(&mut self, scene: &Scene) -> Result<()> {
        self.upload_placed(scene, Placement::of(scene))
    }

    /// [`OffscreenRenderer::upload`] with the glyphs stored as `placement` says (see
    /// [`EllipsoidRenderer::upload_placed`]): a process drawing its share of a scene split
    /// between processes uploads it with the whole scene's placement.
    pub fn upload_placed(&mut self, scene: &Scene, placement: Placement) -> Result<()> {
        let cmd = self.begin_commands()?;
        let (device, allocator, renderer) = self.parts();
        let staged = renderer.stage_scene(device, allocator, scene, placement)?;
        self.submit_staged(cmd, staged)
    }

    /// Replaces glyphs `first..first + ellipsoids.len()` of the uploaded scene (the rest keep
    /// theirs), in a submission of its own. Cheaper than [`OffscreenRenderer::upload`] for a
    /// part of a large scene; see [`EllipsoidRenderer::update`]: the glyphs are stored
    /// relative to the uploaded scene's origin and radius scale, so a scene updated within
    /// its uploaded bounds and largest radius draws exactly what uploading it whole draws.
    /// A range past the uploaded count is [`Error::Invalid`] and changes nothing.
    pub fn update(&mut self, first: u32, ellipsoids: &[Ellipsoid]) -> Result<()> {
        let cmd = self.begin_commands()?;
        let (device, allocator, renderer) = self.parts();
        let staged = renderer.stage_update(device, allocator, first, ellipsoids)?;
        self.submit_staged(cmd, staged)
    }

    /// Records `staged` into `cmd` (recording since `begin_commands`), submits it and waits:
    /// the renderer takes the new glyphs only once the copy has run, so an upload or update
    /// that fails anywhere (out of memory, say) leaves the scene drawn before.
    fn submit_staged(&mut self, cmd: vk::CommandBuffer, staged: StagedUpload) -> Result<()> {
        let (device, _, renderer) = self.parts();
        // SAFETY: `cmd` is recording outside a pass; the staged upload is committed or
        // discarded below.
        let recorded = unsafe { renderer.record_staged(device, cmd, &staged) }.and_then(|()| {
            // SAFETY: `cmd` is recording.
            unsafe { device.end_command_buffer(cmd) }.call("vkEndCommandBuffer")
        });
        let done = recorded.and_then(|()| self.submit_and_wait());
        let renderer = self.renderer_mut();
        match done {
            Ok(()) => {
                renderer.commit_staged(staged);
                Ok(())
            }
            Err(e) => {
                renderer.discard_staged(staged);
                Err(e)
            }
        }
    }

    /// Starts the renderer's frame (every earlier submission was waited for) and begins the
    /// one command buffer.
    fn begin_commands(&mut self) -> Result<vk::CommandBuffer> {
        self.submission.usable()?;
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

    /// Uploads `scene` and renders `outputs` of it with `camera`.
    pub fn render(&mut self, scene: &Scene, camera: &Camera, outputs: Outputs) -> Result<Frame> {
        self.upload(scene)?;
        Ok(self.render_uploaded(camera, outputs)?.0)
    }

    /// Renders the last uploaded scene and reads `outputs` back (the [`Frame`]'s other
    /// images are empty). Colour and depth targets always exist (the draw needs them); the
    /// normal and ID targets, which the fragment stage writes together, only when one of them
    /// is asked for. The frame is the attachments: the camera's image at its
    /// `viewport_origin`, the rest background.
    pub fn render_uploaded(
        &mut self,
        camera: &Camera,
        outputs: Outputs,
    ) -> Result<(Frame, FrameTiming)> {
        camera.validate()?; // Bounds the origin and size, so the sums below cannot overflow.
        let [x, y] = camera.viewport_origin;
        self.render_views(x + camera.width, y + camera.height, &[*camera], outputs)
    }

    /// Renders the last uploaded scene as several views of one frame -- a stereo pair side by
    /// side, a split screen, an inset -- into one `width x height` set of attachments, each
    /// view with its own pre-pass, all recorded into one command buffer (pre-passes first,
    /// then one pass drawing every view into its rectangle), and reads `outputs` back.
    /// The views' rectangles (each camera's size at its `viewport_origin`) lie inside the
    /// attachments and do not overlap, and their cameras share one depth convention (one
    /// depth clear); each pixel's depth is read back with the camera of the view holding it.
    pub fn render_views(
        &mut self,
        width: u32,
        height: u32,
        cameras: &[Camera],
        outputs: Outputs,
    ) -> Result<(Frame, FrameTiming)> {
        let extent = vk::Extent2D { width, height };
        let mut timing = self.draw(extent, cameras, outputs, true)?;
        let start = Instant::now();
        let frame = self.read_frame(cameras, outputs)?;
        timing.readback = start.elapsed();
        Ok((frame, timing))
    }

    /// Renders the last uploaded scene into the targets of `outputs` without reading them
    /// back: the frame a benchmark times.
    pub fn render_timed(&mut self, camera: &Camera, outputs: Outputs) -> Result<FrameTiming> {
        camera.validate()?; // Bounds the origin and size, so the sums below cannot overflow.
        let [x, y] = camera.viewport_origin;
        let extent = vk::Extent2D {
            width: x + camera.width,
            height: y + camera.height,
        };
        self.draw(extent, &[*camera], outputs, false)
    }

    /// Records, submits and waits for one frame of `cameras` in attachments of `extent`;
    /// copies the targets out with `readback`.
    fn draw(
        &mut self,
        extent: vk::Extent2D,
        cameras: &[Camera],
        outputs: Outputs,
        readback: bool,
    ) -> Result<FrameTiming> {
        check_views(extent, cameras)?;
        // Targets may be replaced only when no earlier frame may still be running.
        self.submission.usable()?;
        self.ensure_targets(extent, outputs)?;
        let supported = self.context.info().fragment_stores_and_atomics;
        let counting = {
            // Recording builds any pipeline the frame needs (the plan decides once, in
            // `record_prepass`); the timed part is submit to fence.
            let samples = self.samples;
            let renderer = self.renderer_mut();
            // SAFETY: the offscreen targets are dynamic rendering: no render pass to outlive.
            unsafe { renderer.set_target(target(outputs.aux(), samples))? };
            // The benchmark's read-back frames count shaded pixels (`research`; never else).
            research::begin_counting(renderer, readback, supported)?
        };
        self.record(cameras, extent, outputs, readback)?;
        let start = Instant::now();
        self.submit_and_wait()?;
        let gpu_wall = start.elapsed();
        let gpu = match &self.queries {
            Some(q) => match q.read(self.context.device()) {
                Ok(results) => results,
                Err(e) => return Err(self.noting_loss(e)),
            },
            None => QueryResults::default(),
        };
        let (shaded_fragments, compute_ray_casts) = if counting {
            research::counts(self.renderer())
        } else {
            (None, None)
        };
        Ok(FrameTiming {
            gpu_wall,
            gpu,
            shaded_fragments,
            compute_ray_casts,
            readback: Duration::ZERO,
        })
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
                what: "shutdown".into(),
                reason: format!(
                    "{live} allocation(s) still live after every resource was destroyed"
                ),
            });
        }
        Ok(())
    }

    /// Destroys everything but the context (idempotent).
    fn release(&mut self) {
        if let Err(e) = self.context.wait_idle() {
            log::error!("waiting for the device before tearing down: {e}");
        }
        let renderer = self.renderer.take();
        let targets = self.targets.take();
        if let Some(mut q) = self.queries.take() {
            // SAFETY: the device is idle (waited above).
            unsafe { q.destroy(self.context.device()) };
        }
        if let Some(mut fetch) = self.sample_zero.take() {
            // SAFETY: the device is idle (waited above).
            unsafe { fetch.destroy(self.context.device()) };
        }
        let (pool, fence) = (self.command_pool, self.fence);
        let (device, allocator) = self.context.device_and_allocator();
        if let Some(r) = renderer {
            // SAFETY: the device is idle (waited above).
            unsafe { r.destroy(device, allocator) };
        }
        if let Some(t) = targets {
            // SAFETY: the device is idle (waited above).
            unsafe { t.destroy(device, allocator) };
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

/// Checks that `cameras` can be the views of one offscreen frame in attachments of `extent`:
/// at least one, each valid and inside, none overlapping another, one depth convention.
fn check_views(extent: vk::Extent2D, cameras: &[Camera]) -> Result<()> {
    let invalid = |why: String| Err(Error::invalid("offscreen views", why));
    let Some(first) = cameras.first() else {
        return invalid("no camera to render".into());
    };
    if extent.width == 0 || extent.height == 0 || extent.width > 16384 || extent.height > 16384 {
        return invalid(format!(
            "attachments of {}x{} are outside 1..=16384",
            extent.width, extent.height
        ));
    }
    let rect = |c: &Camera| {
        let [x, y] = c.viewport_origin;
        (x, y, x + c.width, y + c.height)
    };
    for (k, camera) in cameras.iter().enumerate() {
        camera.validate()?;
        let (x0, y0, x1, y1) = rect(camera);
        if x1 > extent.width || y1 > extent.height {
            return invalid(format!(
                "view {k} ({}x{} at ({x0}, {y0})) reaches beyond the {}x{} attachments",
                camera.width, camera.height, extent.width, extent.height
            ));
        }
        if camera.depth.reversed != first.depth.reversed {
            return invalid(format!(
                "view {k} has {} Z but view 0 has {} Z: one depth buffer has one clear value",
                if camera.depth.reversed {
                    "reversed"
                } else {
                    "standard"
                },
                if first.depth.reversed {
                    "reversed"
                } else {
                    "standard"
                },
            ));
        }
        for (j, other) in cameras[..k].iter().enumerate() {
            let (a0, b0, a1, b1) = rect(other);
            if x0 < a1 && a0 < x1 && y0 < b1 && b0 < y1 {
                return invalid(format!("views {j} and {k} overlap"));
            }
        }
    }
    Ok(())
}

/// The offscreen pass: colour and depth, plus the normal and ID targets with `aux_outputs`,
/// with `samples` per pixel.
fn target(aux_outputs: bool, samples: vk::SampleCountFlags) -> Target {
    let color_formats = if aux_outputs {
        vec![COLOR_FORMAT, Target::NORMAL_FORMAT, Target::ID_FORMAT]
    } else {
        vec![COLOR_FORMAT]
    };
    Target {
        pass: Pass::Dynamic {
            color_formats,
            depth_format: DEPTH_FORMAT,
        },
        samples,
        aux_outputs,
    }
}
