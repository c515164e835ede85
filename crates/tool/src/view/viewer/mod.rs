//! The viewer's GPU side, a host of the renderer like any engine: it owns the device, the
//! swapchain, the renderer's output images and the frame slots, and draws a frame with the
//! library's embedding API only (`EllipsoidRenderer`, `Target`, `Pass`, `Camera`): upload
//! or update and pre-pass outside the pass, the draw inside a dynamic-rendering pass with
//! colour, normal, ID and depth, then the colour copied to the swapchain image.

mod readback;
mod record;

use std::path::Path;
use std::time::Duration;

use ash::vk;
use winit::window::Window;

use ellipsoid_splat::{
    Camera, Ellipsoid, EllipsoidRenderer, FramePlan, Pass, RendererOptions, Scene, Settings, Target,
};

use super::device::Gpu;
use super::frames::{Frames, FRAMES_IN_FLIGHT};
use super::subset::Sample;
use super::swapchain::{self, Swapchain};
use super::targets::{ReadbackBuffer, Targets, DEPTH_FORMAT};
use super::VkCall;
use crate::error::{Error, Result};

/// The background, the same linear colour `render` clears to, so pictures compare.
const BACKGROUND: [f32; 4] = [0.045, 0.05, 0.065, 1.0];
/// The ID of pixels no glyph covers.
const NO_INSTANCE: u32 = u32::MAX;

/// A renderer with the glyphs it was given.
struct Drawn {
    renderer: EllipsoidRenderer,
    /// For the moving frames' sample: the full scene's index of each of its glyphs.
    sample: Option<Sample>,
}

/// What a frame did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Presented.
    Presented,
    /// Nothing drawn: the swapchain was out of date at the acquire (made again next turn).
    Skipped,
}

/// What the pixel under the cursor held in the last frame drawn.
#[derive(Clone, Copy, Debug)]
pub struct Probe {
    /// The full scene's glyph index, if a glyph covers the pixel.
    pub glyph: Option<u32>,
    /// Its view depth in the last frame's camera (`None` over the background).
    pub depth: Option<f64>,
}

/// What a frame changes in the scene before it draws.
#[derive(Clone, Copy)]
pub enum SceneChange<'a> {
    /// These glyphs (index in the full scene, new glyph) are replaced, the scene's origin
    /// kept.
    Glyphs(&'a [(u32, Ellipsoid)]),
    /// The whole scene is uploaded again, with its own origin (a trajectory's next frame,
    /// with the same glyph count, so that it draws exactly what `render` draws of it).
    Whole(&'a Scene),
}

/// The viewer's GPU objects. Fields are destroyed in [`Viewer::destroy`], children first.
pub struct Viewer {
    full: Option<Drawn>,
    moving: Option<Drawn>,
    frames: Option<Frames>,
    targets: Option<Targets>,
    swapchain: Option<Swapchain>,
    probe_buffer: Option<ReadbackBuffer>,
    format: vk::SurfaceFormatKHR,
    vsync: bool,
    /// The swapchain must be made again before the next frame (resize, out of date,
    /// suboptimal).
    pub stale: bool,
    frame: u64,
    /// The camera of the last frame drawn, and whether it drew the moving sample.
    last: Option<(Camera, bool)>,
    /// GPU times of finished frames, with whether each moved, not yet collected.
    finished: Vec<(Duration, bool)>,
    moved_in_slot: [bool; FRAMES_IN_FLIGHT as usize],
    // Last: dropped after everything above was destroyed.
    gpu: Gpu,
}

impl Viewer {
    /// The device and renderers for `window`, with `scene` uploaded (and its moving sample
    /// of about `moving_glyphs`, if the scene is larger).
    pub fn new(
        window: &Window,
        device: Option<&str>,
        validation: bool,
        vsync: bool,
        settings: Settings,
        scene: &Scene,
        moving_glyphs: usize,
    ) -> Result<Self> {
        let gpu = Gpu::new(window, device, validation)?;
        let format = swapchain::choose_format(&gpu)?;
        let mut this = Self {
            full: None,
            moving: None,
            frames: None,
            targets: None,
            swapchain: None,
            probe_buffer: None,
            format,
            vsync,
            stale: true,
            frame: 0,
            last: None,
            finished: Vec::new(),
            moved_in_slot: [false; FRAMES_IN_FLIGHT as usize],
            gpu,
        };
        // On failure, `destroy` frees what `create` made so far.
        match this.create(settings, scene, moving_glyphs) {
            Ok(()) => Ok(this),
            Err(e) => {
                this.destroy();
                Err(e)
            }
        }
    }

    fn create(&mut self, settings: Settings, scene: &Scene, moving_glyphs: usize) -> Result<()> {
        // SAFETY: a query of the `Gpu`'s own physical device.
        let (props, families) = unsafe {
            (
                self.gpu
                    .instance
                    .get_physical_device_properties(self.gpu.physical_device),
                self.gpu
                    .instance
                    .get_physical_device_queue_family_properties(self.gpu.physical_device),
            )
        };
        let timestamps = families[self.gpu.queue_family as usize].timestamp_valid_bits > 0;
        self.frames = Some(Frames::new(
            &self.gpu.device,
            self.gpu.queue_family,
            timestamps,
            props.limits.timestamp_period,
        )?);
        let (device, allocator) = self.gpu.device_and_allocator();
        self.probe_buffer = Some(ReadbackBuffer::new(device, allocator, 8)?);
        self.full = Some(self.drawn(settings, scene, None)?);
        if let Some(sample) = Sample::of(scene, moving_glyphs) {
            let sampled = sample.scene.clone();
            self.moving = Some(self.drawn(settings, &sampled, Some(sample))?);
        }
        Ok(())
    }

    /// The renderer's target: dynamic rendering into colour (the swapchain's format),
    /// normal and ID, and depth.
    fn target(&self) -> Target {
        {
            let mut target = Target::new(Pass::Dynamic {
                color_formats: vec![self.format.format, Target::NORMAL_FORMAT, Target::ID_FORMAT],
                depth_format: DEPTH_FORMAT,
            });
            target.samples = vk::SampleCountFlags::TYPE_1;
            target.aux_outputs = true;
            target
        }
    }

    /// A renderer with `scene` uploaded (one submission, waited for).
    fn drawn(
        &mut self,
        settings: Settings,
        scene: &Scene,
        sample: Option<Sample>,
    ) -> Result<Drawn> {
        let mut options = RendererOptions::new(self.target());
        options.frames_in_flight = FRAMES_IN_FLIGHT;
        options.settings = settings;
        let host = self.gpu.host();
        let (instance, physical, family) = (
            host.instance.clone(),
            host.physical_device,
            host.queue_family_index,
        );
        let device = self.gpu.device.clone();
        let host = ellipsoid_splat::HostDevice::new(
            &instance,
            physical,
            &device,
            family,
            self.gpu.features,
        );
        // SAFETY: the `Gpu`'s handles belong together, its device enables the required
        // features (and the compute splat's when `compute_splat` says so), and the renderer is
        // destroyed before the device (`destroy`). No pipeline cache, no render pass.
        let mut renderer = unsafe { EllipsoidRenderer::new(&host, self.gpu.allocator(), options) }?;
        let uploaded = self.submit_and_wait(|device, allocator, cmd| {
            // SAFETY: `cmd` is recording outside a pass; the submission is waited for.
            unsafe {
                renderer.begin_frame(device, allocator, 0)?;
                Ok(renderer.upload(device, allocator, cmd, scene)?)
            }
        });
        if let Err(e) = uploaded {
            let (device, allocator) = self.gpu.device_and_allocator();
            // SAFETY: the submission was waited for (or never made).
            unsafe { renderer.destroy(device, allocator) };
            return Err(e);
        }
        Ok(Drawn { renderer, sample })
    }

    /// Records `work` into the read command buffer, submits it and waits.
    fn submit_and_wait(
        &mut self,
        work: impl FnOnce(
            &ash::Device,
            &mut gpu_allocator::vulkan::Allocator,
            vk::CommandBuffer,
        ) -> Result<()>,
    ) -> Result<()> {
        let frames = self.frames.as_ref().expect("frames exist after create");
        let (cmd, fence) = (frames.read_cmd, frames.read_fence);
        let queue = self.gpu.queue;
        let (device, allocator) = self.gpu.device_and_allocator();
        // SAFETY: the read command buffer is not pending (every use waits for its fence),
        // it records outside any pass, and the submission is waited for before returning.
        unsafe {
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .call("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(cmd, &begin)
                .call("vkBeginCommandBuffer")?;
            let recorded = work(device, allocator, cmd);
            device.end_command_buffer(cmd).call("vkEndCommandBuffer")?;
            recorded?;
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            device
                .queue_submit(queue, &[submit], fence)
                .call("vkQueueSubmit")?;
            device
                .wait_for_fences(&[fence], true, u64::MAX)
                .call("vkWaitForFences")?;
            device.reset_fences(&[fence]).call("vkResetFences")?;
        }
        Ok(())
    }

    /// Glyphs in the full scene (and in the moving sample, if there is one).
    pub fn glyph_counts(&self) -> (u32, Option<u32>) {
        let count = |d: &Option<Drawn>| d.as_ref().map(|d| d.renderer.count());
        (count(&self.full).unwrap_or(0), count(&self.moving))
    }

    /// GPU memory of the scene's buffers (both renderers) and everything the allocator holds.
    pub fn gpu_memory(&self) -> (u64, u64) {
        let scene = [&self.full, &self.moving]
            .iter()
            .filter_map(|d| d.as_ref())
            .map(|d| d.renderer.gpu_memory_bytes())
            .sum();
        (scene, self.gpu.allocated_bytes())
    }

    /// The device's name.
    pub fn device_name(&self) -> &str {
        &self.gpu.name
    }

    /// The size of the images the next frame draws, once a swapchain exists.
    pub fn extent(&self) -> Option<vk::Extent2D> {
        self.swapchain.as_ref().map(|s| s.extent)
    }

    /// GPU times of the frames finished since the last call, with whether each moved.
    pub fn take_finished(&mut self) -> Vec<(Duration, bool)> {
        std::mem::take(&mut self.finished)
    }

    /// Makes the swapchain (and the targets) for the window's size `window`, if stale.
    /// Returns false when the window has no area.
    pub fn ensure_swapchain(&mut self, window: vk::Extent2D) -> Result<bool> {
        if !self.stale && self.swapchain.is_some() {
            return Ok(true);
        }
        // SAFETY: waits for all submitted work, so the old swapchain, its semaphores and the
        // old targets are unused.
        unsafe { self.gpu.device.device_wait_idle() }.call("vkDeviceWaitIdle")?;
        let old = self.swapchain.take();
        let old_handle = old.as_ref().map_or(vk::SwapchainKHR::null(), |s| s.handle);
        let made = Swapchain::new(&self.gpu, self.format, window, self.vsync, old_handle);
        if let Some(old) = old {
            // SAFETY: the device is idle; the old swapchain was retired by the new one.
            unsafe { old.destroy(&self.gpu) };
        }
        let Some(swapchain) = made? else {
            return Ok(false);
        };
        let extent = swapchain.extent;
        println!(
            "swapchain: {}x{} {:?} {:?}, {} images",
            extent.width,
            extent.height,
            swapchain.format.format,
            swapchain.present_mode,
            swapchain.images.len()
        );
        self.swapchain = Some(swapchain);
        if self.targets.as_ref().map(|t| t.extent) != Some(extent) {
            let (device, allocator) = self.gpu.device_and_allocator();
            if let Some(old) = self.targets.take() {
                // SAFETY: the device is idle.
                unsafe { old.destroy(device, allocator) };
            }
            self.targets = Some(Targets::new(device, allocator, self.format.format, extent)?);
            // New images hold nothing to probe until a frame is drawn.
            self.last = None;
        }
        self.stale = false;
        Ok(true)
    }

    /// Draws and presents one frame with `camera` (whose size must be the swapchain's):
    /// `change` goes into the scene first; a `moving` frame draws the sample, if any; with
    /// `screenshot`, the swapchain image as presented is written to that PNG.
    pub fn draw(
        &mut self,
        camera: &Camera,
        moving: bool,
        change: SceneChange,
        screenshot: Option<&Path>,
    ) -> Result<Outcome> {
        let slot = (self.frame % u64::from(FRAMES_IN_FLIGHT)) as usize;
        let frames = self.frames.as_mut().expect("frames exist after create");
        let (fence, cmd, acquired) = {
            let s = &frames.slots[slot];
            (s.fence, s.cmd, s.acquired)
        };
        let device = self.gpu.device.clone();
        // SAFETY: the fence belongs to the device.
        unsafe { device.wait_for_fences(&[fence], true, u64::MAX) }.call("vkWaitForFences")?;
        if let Some(time) = frames.gpu_time(&device, slot) {
            self.finished.push((time, self.moved_in_slot[slot]));
        }
        // The screenshot's buffer is made before the acquire, so failing to make it leaves no
        // image acquired and never presented.
        let extent = self
            .swapchain
            .as_ref()
            .expect("ensure_swapchain made it")
            .extent;
        let shot = match screenshot {
            Some(_) => {
                let (device, allocator) = self.gpu.device_and_allocator();
                let bytes = 4 * u64::from(extent.width) * u64::from(extent.height);
                Some(ReadbackBuffer::new(device, allocator, bytes)?)
            }
            None => None,
        };
        let drop_shot = |viewer: &mut Self, shot: Option<ReadbackBuffer>| {
            if let Some(shot) = shot {
                let (device, allocator) = viewer.gpu.device_and_allocator();
                // SAFETY: waited idle first, so no submission uses the buffer.
                unsafe {
                    let _ = device.device_wait_idle();
                    shot.destroy(device, allocator);
                }
            }
        };
        let swapchain = self.swapchain.as_ref().expect("ensure_swapchain made it");
        // SAFETY: the semaphore is unsignalled: its last acquire was waited on by the slot's
        // last submission, whose fence just passed.
        let acquire = unsafe {
            self.gpu.swapchain_loader.acquire_next_image(
                swapchain.handle,
                u64::MAX,
                acquired,
                vk::Fence::null(),
            )
        };
        let image_index = match acquire {
            Ok((index, suboptimal)) => {
                // Draw this frame; make the swapchain again before the next.
                self.stale |= suboptimal;
                index
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.stale = true;
                drop_shot(self, shot);
                return Ok(Outcome::Skipped);
            }
            Err(e) => {
                drop_shot(self, shot);
                return Err(Error::vulkan("vkAcquireNextImageKHR", e));
            }
        };
        let image = swapchain.images[image_index as usize];
        let copied = swapchain.copied[image_index as usize];
        let readable = swapchain.readable;
        let use_sample = moving && self.moving.is_some();
        let recorded = self.record_frame(
            slot,
            (cmd, image, readable),
            camera,
            use_sample,
            change,
            shot.as_ref(),
        );
        let frames = self.frames.as_ref().expect("frames exist");
        let fence = frames.slots[slot].fence;
        let submitted = recorded.and_then(|()| {
            let cmds = [cmd];
            let waits = [acquired];
            let stages = [vk::PipelineStageFlags::TRANSFER];
            let signals = [copied];
            let submit = vk::SubmitInfo::default()
                .wait_semaphores(&waits)
                .wait_dst_stage_mask(&stages)
                .command_buffers(&cmds)
                .signal_semaphores(&signals);
            // SAFETY: the command buffer was recorded by `record_frame`; the fence was waited
            // for above and is reset only now that a submission will signal it.
            unsafe {
                device.reset_fences(&[fence]).call("vkResetFences")?;
                device
                    .queue_submit(self.gpu.queue, &[submit], fence)
                    .call("vkQueueSubmit")
            }
        });
        if let Err(e) = submitted {
            drop_shot(self, shot);
            return Err(e);
        }
        self.moved_in_slot[slot] = moving;
        self.frame += 1;
        self.last = Some((*camera, use_sample));
        let swapchains = [self.swapchain.as_ref().expect("exists").handle];
        let indices = [image_index];
        let waits = [copied];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and its copy is signalled by `copied`.
        match unsafe {
            self.gpu
                .swapchain_loader
                .queue_present(self.gpu.queue, &present)
        } {
            Ok(suboptimal) => self.stale |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(e) => {
                drop_shot(self, shot);
                return Err(Error::vulkan("vkQueuePresentKHR", e));
            }
        }
        if let (Some(shot), Some(path)) = (shot, screenshot) {
            let written = self.write_screenshot(&shot, slot, extent, path);
            let (device, allocator) = self.gpu.device_and_allocator();
            // SAFETY: `write_screenshot` waited for the frame's fence (or the device).
            unsafe {
                let _ = device.device_wait_idle();
                shot.destroy(device, allocator);
            }
            written?;
        }
        Ok(Outcome::Presented)
    }

    /// The store of validation messages (it outlives the viewer, to hold those of teardown).
    pub fn message_log(&self) -> ellipsoid_splat::internals::validation::MessageLog {
        self.gpu.message_log()
    }

    /// The plan of the last frame drawn (the moving sample's renderer's, if it drew that).
    pub fn last_plan(&self) -> Option<FramePlan> {
        let (_, sample) = self.last?;
        let drawn = if sample { &self.moving } else { &self.full };
        drawn.as_ref()?.renderer.last_plan().copied()
    }

    /// The camera of the last frame drawn.
    pub fn last_camera(&self) -> Option<Camera> {
        self.last.map(|(camera, _)| camera)
    }

    /// Destroys everything, children first (waits for the device to be idle).
    pub fn destroy(&mut self) {
        let device = self.gpu.device.clone();
        // SAFETY: waiting makes every object below unused.
        let _ = unsafe { device.device_wait_idle() };
        let swapchain = self.swapchain.take();
        let (device, allocator) = self.gpu.device_and_allocator();
        // SAFETY: the device is idle; each object goes once.
        unsafe {
            for drawn in [self.full.take(), self.moving.take()].into_iter().flatten() {
                drawn.renderer.destroy(device, allocator);
            }
            if let Some(targets) = self.targets.take() {
                targets.destroy(device, allocator);
            }
            if let Some(buffer) = self.probe_buffer.take() {
                buffer.destroy(device, allocator);
            }
            if let Some(frames) = self.frames.take() {
                frames.destroy(device);
            }
            if let Some(swapchain) = swapchain {
                swapchain.destroy(&self.gpu);
            }
        }
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        self.destroy();
    }
}

/// Makes transfer writes visible to the host once the submission's fence passed.
///
/// # Safety
/// `cmd` is recording outside a pass.
unsafe fn to_host(device: &ash::Device, cmd: vk::CommandBuffer) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    // SAFETY: caller contract.
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[barrier],
            &[],
            &[],
        )
    };
}
