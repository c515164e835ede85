//! `EllipsoidRenderer`: the pipelines, the scene's buffers and the recorded draw, embeddable
//! in a host's frame. It records into command buffers it is given; it never submits, never
//! waits, and never destroys what the host owns.
//!
//! # Barriers and layouts
//!
//! Everything is recorded for one queue (the `HostDevice::queue_family_index`), in the order
//! the host records the calls:
//! - [`EllipsoidRenderer::upload`] and [`EllipsoidRenderer::update`] (outside a pass): a barrier
//!   from earlier vertex, fragment (the compute splat's resolve) and compute reads of the
//!   instance buffer to the transfer write, the copy from a staging buffer, and a barrier from
//!   the transfer write to vertex, fragment and compute shader reads.
//! - [`EllipsoidRenderer::record_prepass`] (outside a pass): a barrier from the previous draw's
//!   indirect, vertex, fragment and compute reads to its transfer and compute writes, its
//!   dispatches (the culling steps; or, where the plan splats, the compute splat after
//!   clearing its visibility buffer and keep bits, then the steps that compact the glyphs it
//!   leaves to the draw; or the visible-first splat's steps, two passes dispatched indirectly
//!   after `PREPASS_STEP_TO_DISPATCH`) with compute-to-compute barriers between them, and a
//!   barrier from its compute writes to indirect-command, vertex and fragment shader reads.
//!   (The benchmark's visibility-buffer draw, `research` only, records instead the same first
//!   barrier, the visibility buffer's clear, a barrier to fragment-shader atomics, its own
//!   attachment-less pass, and a barrier from those atomics to the resolve's vertex and
//!   fragment reads.)
//! - [`EllipsoidRenderer::record`] (inside the host's pass): binds its pipeline, descriptor set
//!   and push constants, sets viewport and scissor to the camera's image, and draws (in a
//!   splatted frame, per chunk, the resolve and then the glyphs left to the draw). It
//!   records no barrier and leaves the host's dynamic state other than viewport and scissor
//!   as it was; the host rebinds its own pipeline afterwards.
//!
//! The renderer never touches the host's images: their layouts and the barriers around the
//! pass (attachment writes before sampling, resolve, present) are the host's, as for any draw.
//! It reads depth with the camera's compare op and writes depth and the colour attachments of
//! its [`Target`] with no blending. Every barrier is listed as data in [`crate::barriers`].
//!
//! The parts, one file each: [`FramePlan`] (what a frame does, decided once), the scene's
//! buffers (one table), chunking, descriptor sets, pipelines, upload, pre-pass and draw.
//!
//! # Files
//!
//! | file | what it holds |
//! |---|---|
//! | `mod.rs` | `EllipsoidRenderer`: `new`, `plan`, `last_plan`, `plan_wisdom`, `load_plan_wisdom`, `can_measure`, `settings`, `set_settings`, `set_target`, `current_target`, `begin_frame` (which hands the slot's frame times to the plan's learning), `gpu_memory_bytes`, `count`, `origin`, `destroy`; sizing the scene's buffers; the per-chunk descriptor sets; the barrier contract in its module documentation |
//! | `plan.rs` | `FramePlan`, every per-frame decision made once (the crate docs): which paths can serve the frame, the one it takes, its footprint, variants and sampling; `SETUP_ONCE_MAX_AREA_PX`, `MAX_SETUP_ONCE_INSTANCES`, `SPLAT_MAX_BOX_PIXELS`, `SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL`, `MAX_SPLAT_CHUNKS` |
//! | `plan_reason.rs` | `PlanReason` (why a frame takes its path), `DrawReason` (what rules the splat out), `Guess`, `Measured` |
//! | `estimate.rs` | the first guess from the scene's size on screen, and its lavapipe thresholds (design §5.8) |
//! | `learning.rs` | `PlanLearning`, `SceneClass`: the candidates' times per scene class, the exploring schedule, the settled choices (design §5.8) |
//! | `frame_timer.rs` | `FrameTimer`: timestamps around each view's pre-pass and draw in the host's command buffers, read when the slot begins again (design §5.8) |
//! | `wisdom.rs` | what the plan learned as bytes, keyed by the device and driver build (design §5.8) |
//! | `buffers.rs` | `SceneBuffers` and `Binding`: one buffer per descriptor binding as one table (name, descriptor type, stages, usage, memory), each grown by the same rule (a buffer too small is replaced and the old one retired, `src/frame_slots.rs`) |
//! | `chunks.rs` | `Chunking`, `SLICE_ALIGN`: how a scene is split across bindings (design §5.4) |
//! | `descriptors.rs` | the descriptor-set layout and one set per chunk, in a pool of its own, with the texel views they point at (`TEXEL_VIEWS`) |
//! | `pipelines/mod.rs` | `Pipelines`: the two pipeline layouts (graphics push range `DRAW_PUSH_STAGES`, compute-only for the pre-pass) and every pipeline, built on first use and kept per key |
//! | `pipelines/keys.rs` | `PipelineKey`, `SplatKey`, `CullKey`: each derived from the frame plan in one place, with its specialization constants (`SpecConstants`) |
//! | `pipelines/create.rs` | creating the graphics and compute pipelines the keys describe |
//! | `pipelines/raster.rs` | `Raster`: the fixed-function state that differs between the impostor and a baseline |
//! | `push.rs` | `push_constants`: the `PushConstants` of a frame and chunk (`PushConstants`) |
//! | `upload.rs` | `upload`, `update`: staged, recorded and taken in at once |
//! | `staged.rs` | `StagedUpload`: an upload or update whose memory is made and bytes staged before anything of the renderer changes, its copy between barriers, then taken in or dropped (`Error`) |
//! | `uploaded.rs` | `UploadedScene`: what the CPU keeps of the uploaded scene (count, origin, format, compact unit, all spheres, box, size sample) and the decisions made from it (`projected_sample`, `screen_share`, `beyond_near_plane`) |
//! | `prepass/mod.rs` | `record_prepass`: one pre-pass per chunk, sharing the occlusion tiles; the dispatches of each path (design §5.3, §5.6, §5.7) |
//! | `prepass/steps.rs` | `CullStep`, `CullSelect`, the workgroup sizes and the sizes of the buffers the steps fill; the benchmark's tiled splat's `TiledStep` and list sizes |
//! | `prepass/record.rs` | `Prepass`: one chunk's clears, dispatches and barriers, recorded |
//! | `draw.rs` | `prepare_for` (pipelines ahead of recording) and `record`: one draw per chunk, with the view whose pre-pass had the same camera |
//! | `viewport.rs` | the viewport and scissor of a camera's image |
//! | `view.rs` | `View`, `MAX_VIEWS`: one view of a frame -- its pre-pass buffers, descriptor sets, prepared plan and history (the crate docs) |

mod buffers;
mod chunks;
mod descriptors;
mod draw;
mod estimate;
mod frame_timer;
mod learning;
pub(crate) mod pipelines;
mod plan;
mod plan_reason;
pub(crate) mod prepass;
pub(crate) mod push;
pub(crate) mod staged;
mod upload;
mod uploaded;
mod view;
pub(crate) mod viewport;
mod wisdom;

use crate::allocator::MemoryAllocator;
use ash::vk;
use glam::DVec3;

use crate::camera::Camera;
use crate::error::Result;
use crate::features::DeviceFeatures;
use crate::frame_slots::{FrameSlots, Retired};
use crate::research::Research;
use crate::settings::Settings;
use crate::target::DeviceCaps;
use crate::target::{HostDevice, RendererOptions, Target};

pub(crate) use buffers::Binding;
use buffers::SceneBuffers;
use chunks::Chunking;
#[cfg(test)]
pub(crate) use descriptors::{
    TexelView, OCCLUSION_TILE_WORDS, SHADING_RECORD_STORES, SHADING_RECORD_TEXELS, TEXEL_VIEWS,
    VISIBILITY_KEYS,
};
use frame_timer::FrameTimer;
use learning::PlanLearning;
use pipelines::Pipelines;
pub use plan::FramePlan;
use plan::PlanInputs;
#[doc(hidden)]
pub use plan::SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL;
pub use plan_reason::PlanReason;
use uploaded::UploadedScene;
use view::{View, MAX_VIEWS};

/// Pipeline, descriptor and instance data for drawing one scene into a host's frame.
///
/// One frame, recorded into the host's command buffer (`examples/minimal.rs` and
/// `examples/embed` are whole programs):
///
/// ```no_run
/// use ash::vk;
/// use ellipsoid_splat::{Camera, EllipsoidRenderer, Scene};
/// use glam::DMat4;
///
/// /// # Safety
/// /// `cmd` is recording outside a pass; `slot`'s previous work has completed.
/// unsafe fn frame(
///     renderer: &mut EllipsoidRenderer,
///     device: &ash::Device,
///     allocator: &mut gpu_allocator::vulkan::Allocator,
///     cmd: vk::CommandBuffer,
///     slot: u32,
///     scene: Option<&Scene>,
///     (view, projection): (DMat4, DMat4),
/// ) -> ellipsoid_splat::Result<()> {
///     // The host's matrices (Vulkan clip space) and image size give the camera.
///     let camera = Camera::from_view_projection(view, projection, 1920, 1080)?;
///     unsafe {
///         renderer.begin_frame(device, allocator, slot)?;
///         if let Some(scene) = scene {
///             renderer.upload(device, allocator, cmd, scene)?; // outside the pass
///         }
///         renderer.record_prepass(device, allocator, cmd, &camera)?; // outside the pass
///         // ... the host begins its render pass (or dynamic rendering) and draws its meshes ...
///         renderer.record(device, allocator, cmd, &camera)?; // inside the pass
///         // ... the host ends its pass, submits, and waits for this slot before reusing it.
///     }
///     Ok(())
/// }
/// ```
pub struct EllipsoidRenderer {
    caps: DeviceCaps,
    pub(crate) settings: Settings,
    /// The host enabled the compute splat's device features.
    compute_splat_features: bool,
    /// Every target drawn into so far; `target` indexes the current one.
    targets: Vec<Target>,
    target: usize,
    pub(crate) slots: FrameSlots<Retired>,
    pub(crate) pipelines: Pipelines,
    /// The buffers every view shares (`Binding::per_view` is false).
    pub(crate) buffers: SceneBuffers,
    /// The views drawn so far: each frame's `record_prepass` calls take them in order.
    pub(crate) views: Vec<View>,
    /// The view the next `record_prepass` of this frame takes.
    next_view: usize,
    /// The views the last finished frame recorded (0 until a frame has been followed by a
    /// `begin_frame`): after that many, the next pre-pass is the next frame's first view.
    views_per_frame: usize,
    pub(crate) scene: UploadedScene,
    /// The stamp of the last recorded pre-pass (never 0; see `gpu_layout::IndirectDraw`).
    frame_stamp: u32,
    /// The frame slot `begin_frame` started last.
    slot: u32,
    /// What the plan measured: the candidate paths' times per scene class.
    learning: PlanLearning,
    /// Timestamps around each view's pre-pass and draw, for `learning`.
    timer: FrameTimer,
    /// The plan of the last `record_prepass`.
    last_plan: Option<FramePlan>,
    /// The benchmark's baselines and measuring aids (nothing without `research`).
    pub(crate) research: Research,
    /// `destroy` ran (a renderer dropped without it leaks its Vulkan objects, and says so).
    destroyed: bool,
}

impl Drop for EllipsoidRenderer {
    fn drop(&mut self) {
        if !self.destroyed {
            log::error!("EllipsoidRenderer dropped without destroy(): its Vulkan objects leaked");
        }
    }
}

impl EllipsoidRenderer {
    /// A renderer for the host's device, drawing into `options.target`. Creates the
    /// descriptor-set and pipeline layouts and a few small buffers through `allocator`;
    /// pipelines are built on first use of each variant, so a scene pays only for what it
    /// draws. Errors name what the host's device or target lacks.
    ///
    /// `EllipsoidRenderer::new` checks the queue family, features, depth format, colour attachment
    /// count and formats, and sample count, and names what is missing.
    ///
    /// # Safety
    /// `host`'s handles are valid and belong together (the device was created from
    /// `physical_device`, which comes from `instance`), the device has the features
    /// `host.enabled_features` names enabled (the renderer trusts it), `allocator`
    /// allocates from that device and is the one every later call passes, and
    /// `options.target`'s render pass (if any) and `options.pipeline_cache` outlive the
    /// renderer.
    pub unsafe fn new(
        host: &HostDevice,
        allocator: &mut dyn MemoryAllocator,
        options: RendererOptions,
    ) -> Result<Self> {
        let caps = host.caps()?;
        options.target.validate(&caps)?;
        options.settings.material.validate()?;
        let device = host.device;
        let mut renderer = Self {
            caps,
            settings: options.settings,
            compute_splat_features: caps.enabled.contains(DeviceFeatures::COMPUTE_SPLAT),
            targets: vec![options.target],
            target: 0,
            slots: FrameSlots::new(options.frames_in_flight)?,
            pipelines: Pipelines::new(options.pipeline_cache),
            buffers: SceneBuffers::default(),
            views: vec![View::default()],
            next_view: 0,
            views_per_frame: 0,
            scene: UploadedScene {
                chunk_limit: options.settings.max_chunk_instances,
                ..UploadedScene::default()
            },
            frame_stamp: 1,
            slot: 0,
            learning: PlanLearning::default(),
            timer: FrameTimer::new(
                device,
                options.frames_in_flight,
                caps.limits.timestamp_period,
                caps.timestamp_valid_bits,
            )?,
            last_plan: None,
            research: Research::default(),
            destroyed: false,
        };
        // On failure, `destroy` releases whatever was created (null handles are skipped).
        match renderer.pipelines.create_layouts(device).and_then(|_| {
            let empty = Chunking {
                count: 0,
                ..renderer.chunking()
            };
            renderer.size_buffers(device, allocator, 0, empty, (1, 1), false, false)
        }) {
            Ok(()) => Ok(renderer),
            Err(e) => {
                // SAFETY: nothing was recorded with the renderer's objects yet.
                unsafe { renderer.destroy(device, allocator) };
                Err(e)
            }
        }
    }

    /// What the next frame with `camera` does: footprint, culling, set-up once, shader
    /// variants, the compute splat. `record_prepass` makes this plan and `record` draws with
    /// it; the visible-first splat depends on the frames recorded before (what the last
    /// showed), so after `record_prepass` the plan of the same camera may differ. The plan
    /// is that of the view whose last pre-pass had this camera (a host recording its views in
    /// the same order every frame draws it there), else of the view the next
    /// `record_prepass` takes (after the frame's last view, the next frame's first).
    pub fn plan(&self, camera: &Camera) -> Result<FramePlan> {
        // Before a frame has finished, the views made so far stand for the frame's.
        let views = match self.views_per_frame {
            0 => self.views.len(),
            views => views,
        };
        let next = self.next_view.checked_rem(views).unwrap_or(0);
        let view = self
            .views
            .iter()
            .position(|v| v.last_camera == Some(*camera))
            .unwrap_or(next);
        self.plan_for_view(view, camera)
    }

    /// The plan of `camera` drawn as view `view` (whose history a new view lacks).
    fn plan_for_view(&self, view: usize, camera: &Camera) -> Result<FramePlan> {
        camera.validate()?;
        self.settings.material.validate()?;
        let (last_camera, shown_stamped) = self
            .views
            .get(view)
            .map_or((None, None), |v| (v.last_camera, v.shown_stamped));
        FramePlan::new(PlanInputs {
            compute_splat_features: self.compute_splat_features,
            max_visibility_bytes: Chunking::max_binding_bytes(&self.caps.limits, 8),
            standard_sample_locations: self.caps.limits.standard_sample_locations == vk::TRUE,
            sample_rate_shading: self.caps.enabled.sample_rate_shading,
            timed: self.timer.available(),
            chunks: self.chunking().len(),
            shading_records_fit: self.chunking().shading_records_fit(&self.caps.limits),
            still: last_camera == Some(*camera),
            shown_stamped: shown_stamped.is_some(),
            scene: &self.scene,
            settings: &self.settings,
            learning: &self.learning,
            baseline: self.research.baseline(),
            splat_floor: self.research.splat_floor() != 0,
            splat_variant: self.research.splat_variant(),
            target: (self.target, &self.targets[self.target]),
            camera,
        })
    }

    /// The plan of the last `record_prepass`: the path the frame took and why (with
    /// [`crate::PlanMode::Measure`], "measured: X ms against Y ms" once its class is learned).
    pub fn last_plan(&self) -> Option<&FramePlan> {
        self.last_plan.as_ref()
    }

    /// What the plan learned on this device, as bytes to save and give to
    /// [`EllipsoidRenderer::load_plan_wisdom`] of a later renderer on the same device and
    /// driver build (keyed by their IDs, driver version and pipeline-cache UUID, as
    /// `VkPipelineCache` data is): each settled scene class, the path chosen and the
    /// candidates' median frame times.
    pub fn plan_wisdom(&self) -> Vec<u8> {
        wisdom::export(&self.learning, &self.caps.identity)
    }

    /// Takes in what a renderer on the same device and driver build learned
    /// ([`EllipsoidRenderer::plan_wisdom`]): its scene classes are then planned as learned,
    /// without exploring. Bytes from another device, driver build or format, or damaged, are
    /// refused with an error that says which, and change nothing.
    pub fn load_plan_wisdom(&mut self, bytes: &[u8]) -> Result<()> {
        for (class, best, medians) in wisdom::import(bytes, &self.caps.identity)? {
            self.learning.insert_settled(class, best, medians);
        }
        Ok(())
    }

    /// Whether the plan can measure on this device (its queue family has timestamps); where
    /// it cannot, [`crate::PlanMode::Measure`] plans as [`crate::PlanMode::Estimate`] does.
    pub fn can_measure(&self) -> bool {
        self.timer.available()
    }

    /// The settings in force.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Changes the settings. The material costs nothing (push constants). Culling, set-up
    /// once and the sphere and cap-free paths take effect at the next frame and build the
    /// pipelines of the new variant on first use (milliseconds each on a GPU driver, up to
    /// a few hundred on lavapipe). The instance format and the chunk size take effect at
    /// the next `upload`. A material shading cannot use is refused by the next plan
    /// (`plan`, `record_prepass`, `record`), naming the field, until settings replace it.
    pub fn set_settings(&mut self, settings: Settings) {
        self.settings = settings;
    }

    /// Draws into `target` from the next frame on, that is from the next `record_prepass`
    /// (or `record`, for a frame without a pre-pass); pipelines for earlier targets are kept,
    /// so switching back costs nothing. Errors say what the device or the description lacks.
    /// Targets are told apart by their handles and formats: a host that recreates its render
    /// pass (say, on resize) passes the new handle, and the renderer builds pipelines for it.
    ///
    /// # Safety
    /// `target`'s render pass (if any) outlives the renderer, as for
    /// [`EllipsoidRenderer::new`].
    pub unsafe fn set_target(&mut self, target: Target) -> Result<()> {
        if let Some(k) = self.targets.iter().position(|t| *t == target) {
            self.target = k;
            return Ok(());
        }
        target.validate(&self.caps)?;
        self.targets.push(target);
        self.target = self.targets.len() - 1;
        Ok(())
    }

    /// The target `set_target` made current: the next `record_prepass` (or a `record` without
    /// one) plans for it.
    pub fn current_target(&self) -> &Target {
        &self.targets[self.target]
    }

    /// Starts frame slot `slot` (in `0..frames_in_flight`): destroys the buffers and
    /// descriptor sets replaced while frames that might still read them were recorded, and
    /// makes the frame's first `record_prepass` take view 0 again. Call it once per frame,
    /// before recording anything else of the frame.
    ///
    /// # Safety
    /// Every command buffer recorded with this renderer since `slot` last began has finished
    /// executing (the host waited for that slot's fence).
    pub unsafe fn begin_frame(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        slot: u32,
    ) -> Result<()> {
        for object in self.slots.begin(slot)? {
            // SAFETY: the frame-slot rule and the caller's contract prove no pending work
            // uses it.
            unsafe { object.destroy(device, allocator) };
        }
        // The slot's last frames are done (caller contract): their times are there.
        for (token, ms) in self.timer.begin_slot(device, slot) {
            match ms {
                Some(ms) => self.learning.record(token, ms),
                None => self.learning.lost(token),
            }
        }
        self.slot = slot;
        if self.next_view > 0 {
            self.views_per_frame = self.next_view;
        }
        self.next_view = 0;
        for view in &mut self.views {
            view.prepared = None;
        }
        Ok(())
    }

    /// Bytes of memory the host's allocator gave the renderer's buffers (instances, and every
    /// view's culling and set-up buffers and occlusion tiles): what the scene costs the
    /// host's memory budget.
    pub fn gpu_memory_bytes(&self) -> u64 {
        self.buffers.memory_bytes()
            + self
                .views
                .iter()
                .map(|v| v.buffers.memory_bytes())
                .sum::<u64>()
    }

    /// Number of instances uploaded.
    pub fn count(&self) -> u32 {
        self.scene.count
    }

    /// The scene origin that instance positions are stored relative to.
    pub fn origin(&self) -> DVec3 {
        self.scene.origin
    }

    /// How the uploaded instances are split across descriptor sets.
    pub(crate) fn chunking(&self) -> Chunking {
        Chunking::new(
            self.scene.count,
            self.scene.format.bytes(),
            Chunking::max_binding_bytes(&self.caps.limits, 16),
            self.scene.chunk_limit,
        )
    }

    /// Makes every buffer but the instances' hold a scene cut as `chunking` says in an image
    /// of `extent` pixels (the occlusion tiles; with `visibility`, the compute splat's
    /// visibility buffer), those of each view for view `view` (made if new).
    #[allow(clippy::too_many_arguments)]
    fn size_buffers(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        view: usize,
        chunking: Chunking,
        extent: (u32, u32),
        visibility: bool,
        stamps: bool,
    ) -> Result<()> {
        let count = chunking.count;
        // Set-up records only for scenes that can use them.
        let records = if chunking.has_records() {
            count.max(1) as u64
        } else {
            1
        };
        let sizes = [
            (Binding::FragmentCounter, 8),
            (
                Binding::TileLists,
                if visibility && self.research.tiled_splat() {
                    prepass::steps::tiled_lists_bytes(extent.0, extent.1, count)
                } else {
                    8
                },
            ),
            (Binding::FloorPixels, 8),
            (
                Binding::GlyphStamps,
                if stamps {
                    crate::gpu_layout::glyph_stamps_bytes(count.max(1))
                } else {
                    8
                },
            ),
            (Binding::Visible, 4 * count.max(1) as u64),
            (
                Binding::IndirectDraw,
                chunking.len() as u64 * chunks::SLICE_ALIGN,
            ),
            (
                Binding::CullGroups,
                chunking.len() as u64 * chunking.groups_slice(),
            ),
            (
                Binding::OcclusionTiles,
                prepass::steps::tiles_bytes(extent.0, extent.1),
            ),
            (
                Binding::Visibility,
                if visibility {
                    crate::gpu_layout::visibility_bytes(extent.0, extent.1)
                } else {
                    8
                },
            ),
            (
                Binding::ShadingRecords,
                records * size_of::<crate::gpu_layout::ShadingRecord>() as u64,
            ),
            (
                Binding::FootprintRecords,
                records * size_of::<crate::gpu_layout::FootprintRecord>() as u64,
            ),
        ];
        if self.views.len() <= view {
            self.views.resize_with(view + 1, View::default);
        }
        for (binding, bytes) in sizes {
            let buffers = if binding.per_view() {
                &mut self.views[view].buffers
            } else {
                &mut self.buffers
            };
            buffers.ensure(device, allocator, &mut self.slots, binding, bytes)?;
        }
        if self.buffers.replaced {
            self.shared_buffers_replaced();
        }
        Ok(())
    }

    /// Every view's descriptor sets name a shared buffer that was replaced (or chunks that
    /// changed): each view writes new ones before its next use.
    fn shared_buffers_replaced(&mut self) {
        for view in &mut self.views {
            view.buffers.replaced = true;
        }
        self.buffers.replaced = false;
    }

    /// Takes the view the next `record_prepass` of this frame uses.
    fn take_next_view(&mut self) -> Result<usize> {
        let view = self.next_view;
        if view >= MAX_VIEWS {
            return Err(crate::error::Error::invalid(
                "record_prepass",
                format!(
                    "more than {MAX_VIEWS} views in one frame: call begin_frame once per frame"
                ),
            ));
        }
        self.next_view += 1;
        if self.views.len() <= view {
            self.views.resize_with(view + 1, View::default);
        }
        Ok(view)
    }

    /// View `view`'s descriptor sets, one per chunk: new ones (in a pool of their own) when
    /// a buffer was replaced or the scene changed since the last were written; the old pool
    /// is retired, since command buffers recorded earlier may still use it.
    pub(crate) fn descriptor_sets(
        &mut self,
        device: &ash::Device,
        view: usize,
    ) -> Result<Vec<vk::DescriptorSet>> {
        if self.buffers.replaced {
            self.shared_buffers_replaced();
        }
        let chunking = self.chunking();
        let v = &mut self.views[view];
        if !v.buffers.replaced && !v.descriptors.sets.is_empty() {
            return Ok(v.descriptors.sets.clone());
        }
        let sets = descriptors::create_chunk_sets(
            device,
            self.pipelines.set_layout(),
            (&self.buffers, &v.buffers),
            &chunking,
            (
                self.scene.format.bytes() as u64,
                self.caps.limits.max_texel_buffer_elements,
            ),
        )?;
        let old = std::mem::replace(&mut v.descriptors, sets);
        if old.pool != vk::DescriptorPool::null() {
            self.slots.retire(Retired::DescriptorPool(old.pool));
        }
        for view in old.views {
            self.slots.retire(Retired::BufferView(view));
        }
        v.buffers.replaced = false;
        Ok(v.descriptors.sets.clone())
    }

    /// Destroys everything the renderer created (nothing of the host's).
    ///
    /// # Safety
    /// No command buffer recorded with the renderer is pending or will be submitted again.
    pub unsafe fn destroy(mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        self.destroyed = true;
        for object in self.slots.drain() {
            // SAFETY: the caller guarantees no pending work uses it.
            unsafe { object.destroy(device, allocator) };
        }
        // SAFETY: all objects were created by `self` from `device` (null handles are ignored);
        // the caller guarantees no pending work uses them.
        unsafe {
            self.buffers.destroy(device, allocator);
            for view in &mut self.views {
                view.destroy(device, allocator);
            }
            self.research.destroy(device, allocator);
            self.timer.destroy(device);
            self.pipelines.destroy(device);
        }
    }
}
