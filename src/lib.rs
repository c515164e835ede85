//! `ellipsoid-splat`: very many ellipsoids drawn exactly as ray-cast impostors in one instanced
//! Vulkan draw.
//!
//! [`EllipsoidRenderer`] records into a host's command buffers: the host's device, enabled
//! features, allocator (through [`MemoryAllocator`]), render pass (or dynamic rendering), sample
//! count, projection and viewport, one or several views a frame. These crate docs and the types'
//! docs are the embedding contract; `docs/embedding.md` walks through the example hosts
//! (`examples/minimal.rs`, a complete host in 150 lines, and `examples/embed`). With the default
//! feature `offscreen`, `OffscreenRenderer` owns its Vulkan device and reads frames back (example
//! at the end). Why the contract is what it is, and the numerics of the exact hit, are in
//! `docs/design.md`.
//!
//! # Embedding
//!
//! A host that draws into its own frame depends on the library without its default features:
//! `ellipsoid-splat = { version = "0.1", default-features = false, features = ["gpu-allocator"] }`
//! (or `"vk-mem"`, or neither and its own [`MemoryAllocator`]). One frame, in the order a host
//! records it:
//!
//! ```no_run
//! use ash::vk;
//! use ellipsoid_splat::{Camera, EllipsoidRenderer, HostDevice, MemoryAllocator, RendererOptions};
//! use ellipsoid_splat::{Scene, Target};
//!
//! /// Makes the renderer on the host's device and records one frame into `cmd`: the upload and
//! /// the pre-pass outside the host's pass, the draw inside it, between the host's own draws.
//! ///
//! /// # Safety
//! /// The handles are valid and belong together, the device has `target.required_features()`
//! /// enabled, and `cmd` is recording outside any pass for `host.queue_family_index`.
//! unsafe fn first_frame(
//!     host: &HostDevice,
//!     allocator: &mut dyn MemoryAllocator,
//!     cmd: vk::CommandBuffer,
//!     scene: &Scene,
//!     camera: &Camera,
//!     begin_pass: impl Fn(vk::CommandBuffer),
//!     end_pass: impl Fn(vk::CommandBuffer),
//! ) -> ellipsoid_splat::Result<EllipsoidRenderer> {
//!     let target = Target::dynamic(vk::Format::R8G8B8A8_SRGB, vk::Format::D32_SFLOAT);
//!     let device = host.device;
//!     // SAFETY: the caller's contract; the target's attachments are the host's pass's.
//!     let mut renderer =
//!         unsafe { EllipsoidRenderer::new(host, allocator, RendererOptions::new(target))? };
//!     // SAFETY: slot 0 has no earlier work; `cmd` is outside any pass.
//!     unsafe {
//!         renderer.begin_frame(device, allocator, 0)?;
//!         renderer.upload(device, allocator, cmd, scene)?;
//!         renderer.record_prepass(device, allocator, cmd, camera)?;
//!     }
//!     begin_pass(cmd); // the host begins its pass and draws its meshes
//!     // SAFETY: inside the pass the target describes, with the camera of the pre-pass.
//!     unsafe { renderer.record(device, allocator, cmd, camera)? };
//!     end_pass(cmd); // the host rebinds its own state for what it draws next
//!     // The host submits `cmd`; once the GPU is done, `renderer.destroy(device, allocator)`.
//!     Ok(renderer)
//! }
//! ```
//!
//! What the host describes: [`HostDevice`] (its handles, borrowed, and the [`DeviceFeatures`] it
//! enabled), a [`Target`] (the pass, samples, auxiliary outputs), [`RendererOptions`] (frames in
//! flight, [`Settings`], pipeline cache) and its allocator. Cameras come from the host's own
//! matrices ([`Camera::from_view_projection_viewport`]) or from a [`Projection`].
//!
//! ## The order of calls
//!
//! 1. `new(&host, &mut allocator, options)` once.
//! 2. Per frame, for slot `s` in `0..frames_in_flight`, after the host waited for that slot's fence:
//!    - `begin_frame(device, allocator, s)` first;
//!    - outside any pass: `upload(.., cmd, &scene)` or `update(.., cmd, first, &ellipsoids)` when
//!      the data changed, then `record_prepass(.., cmd, &camera)` once per view;
//!    - inside the host's pass (or passes), before, between or after the host's draws:
//!      `record(.., cmd, &camera)` once per view. A draw that goes through the pre-pass without
//!      `record_prepass` having been called first with the same camera is an error, not a wrong
//!      picture.
//!    - The command buffer is submitted before the slot begins again. A host that skips a frame
//!      after `begin_frame` (say, its swapchain went out of date) may drop the command buffer
//!      only if the renderer recorded nothing into it: a dropped upload leaves the instances
//!      unwritten, a dropped pre-pass its timestamp queries unreset.
//! 3. `destroy(device, allocator)` once the GPU is done with everything recorded.
//!
//! **Several views a frame.** Two eyes, split screen, picture-in-picture, a shadow or probe view:
//! each view has its own pre-pass buffers, descriptor sets and history (`src/renderer/view.rs`,
//! up to `MAX_VIEWS` = 64 a frame; the instances and pipelines are shared). The first
//! `record_prepass` after `begin_frame` takes view 0, the next view 1, and so on; `record` draws
//! with the view whose pre-pass was recorded with an equal camera and has not drawn yet. So the
//! host records all pre-passes outside its passes, then each view's draw in whatever pass and
//! target holds it (each view draws into the target current at its pre-pass; the views may share
//! one attachment through their viewport origins, or go into different targets). A host that
//! records its views in the same order every frame finds each view's history (the still-camera
//! rule of the visible-first splat, design §5.7, the stamps of the glyphs it showed) where it left it. The buffers of a view
//! exist from the first frame that uses it and are kept, for the frames to come, until `destroy`
//! (a buffer grown for a larger image is retired like any replaced buffer, below). A jittered
//! camera differs from frame to frame, so under TAA a view is never still: its frames are a
//! moving camera's class, where the plan measures the visible-first splat too (design §5.7). A view drawn twice in a frame (a depth pre-pass, then the main
//! pass) is two views: two `record_prepass` calls with the same camera, the draws in the same
//! order.
//!
//! **Settings.** `settings()` returns the settings in force; `set_settings(settings)` replaces them
//! with the effects listed in [`Settings`]. `prepare_for(device, allocator, &camera)` builds the draw
//! pipeline a frame with `camera` needs (and, for the mesh baselines, mesh buffers) ahead of
//! recording; otherwise `record_prepass` and `record` build the draw pipeline, and
//! `record_prepass` the pre-pass pipelines, so a variant's pipelines are built on first use. With `research`, `set_draw_config` draws a benchmark baseline from the next frame on (the
//! shipped renderer is `DrawConfig::default()`), and `set_count_fragments` selects the counting
//! shader builds.
//!
//! Also available: `current_target()`, `gpu_memory_bytes()` (the scene's buffers), `count()` (the
//! instances uploaded) and `origin()` (the scene origin of design §4.1).
//!
//! ## Frames in flight
//!
//! Objects the renderer replaces while earlier frames may still read them -- instance, staging,
//! culling and record buffers, and descriptor pools (a descriptor set is never rewritten once
//! recorded; a replaced buffer means a new pool) -- are *retired*, not destroyed (`FrameSlots` in
//! `src/frame_slots.rs`). An object retired during frame `F` (counting `begin_frame` calls) can only
//! be used by work recorded up to then; once every slot has begun again after `F`, the host has
//! waited for all of that work, and `begin_frame` destroys it. `destroy` releases everything that
//! remains.
//!
//! ## Barriers, and what the renderer never does
//!
//! The renderer records only barriers between its own commands, each a single global memory
//! barrier defined as data in `src/barriers.rs` (which lists them, with where each is recorded;
//! `tests/barriers.rs` checks each against the hazards it exists for).
//!
//! It never submits, waits, or creates fences or semaphores; never destroys or modifies a host
//! object (device, allocator, render pass, pipeline cache, images); never touches the host's images
//! -- their layouts, attachment barriers, resolves and presentation are the host's, as for any
//! draw; records no queue-family ownership transfer and assumes one queue. Inside the pass it binds
//! its own pipeline, descriptor set and push constants and sets viewport and scissor to the
//! camera's image rectangle (its size at its `viewport_origin`); it leaves other dynamic state alone, and the host rebinds its own state
//! afterwards. It allocates only through the host's allocator, with named allocations. Outside
//! the pass it records only transfers, dispatches and barriers -- except the benchmark's
//! visibility-buffer draw (`research` only, design §5.6), whose `record_prepass` begins and ends a
//! rendering pass of its own with no attachments and binds graphics state there.
//!
//! ## Errors
//!
//! Every call returns [`Result`]: an [`Error`] names where and why, never a panic. Running out of
//! memory leaves the renderer usable; a lost device ends it ([`Error`] says what to do for each).
//!
//! # Public surface and stability
//!
//! The crate root is the host's vocabulary, and without features all of it: at most 30 free
//! items, no public module (counted by `tests/public_surface.rs`). Limits are associated
//! constants ([`Target::NORMAL_FORMAT`], [`Camera::MAX_PRINCIPAL_SHIFT`]); the plan's details a
//! host reads but never names (the draw's and the splat's paths, the reasons' payloads, the
//! footprint) are types it cannot name, and the first guess's thresholds are private. `research` adds the module
//! `research`; `offscreen` adds the standalone renderer, its `Frame`, its own Vulkan `Context` and
//! the module `supersample` (a frame drawn K times larger and box-filtered in linear light, shared
//! by the tool's `--supersample` and the Python package). Everything else is private, or in the
//! one `#[doc(hidden)] pub mod internals` that the workspace's other crates, the tests and the
//! benchmarks use (barriers as data, the validation messenger, eigen-solver and shape colours,
//! the packer, the offscreen background, the float64 reference's `Basis` and `Ray`); it may
//! change in any release. The option structs ([`RendererOptions`], [`Settings`], [`Material`], [`Culling`],
//! [`Target`], [`DeviceFeatures`], [`HostDevice`], and with `offscreen` `ContextOptions` and
//! `Outputs`) are `#[non_exhaustive]` with constructors (`new`, `default`, named constants), so a
//! new field is not a breaking change; so are the enums a later version may grow ([`Projection`],
//! [`Pass`], [`InstanceFormat`], [`PlanReason`], [`Error`]). `MemoryUse` stays exhaustive: every
//! allocator must place every use, so a new one would break them anyway.
//!
//! # Features
//!
//! - `gpu-allocator` (default): [`MemoryAllocator`] for `gpu_allocator::vulkan::Allocator` 0.28.
//! - `vk-mem`: [`MemoryAllocator`] for `vk_mem::Allocator` 0.5 (VMA). A host enables the one
//!   its engine uses, or neither and implements the trait.
//! - `offscreen` (default; implies `gpu-allocator`): the standalone path with its own Vulkan
//!   instance and device, images and read-back -- `OffscreenRenderer`, `Outputs`,
//!   `FrameTiming`, `Frame`, `NO_INSTANCE`, the context (`Context`, `ContextOptions`,
//!   `DeviceInfo`), the validation messenger, owned images and queries. It adds no
//!   dependency. Without it the crate is the embeddable renderer alone, and `build.rs` skips
//!   `glsl/offscreen/`.
//! - `research` (implies `offscreen`): the benchmark's baselines and measuring aids, all in the
//!   module `research` -- the textbook intersection, the box proxy, icosphere meshes, flat
//!   fill, fixed footprints (axis rectangle, Gumhold's world quad, and the fixed hexagon,
//!   octagon and rectangle), the fast normal, flat depth, the visibility-buffer draw, the
//!   splat's floors, the `Method` list and fragment counting. Without it `build.rs` skips
//!   `glsl/research/` and the `COUNT_FRAGMENTS` builds. Hosts never need it.
//!
//! The workspace's own crates depend on the library with default features off and ask for
//! what they need. The integration tests `methods` and `footprints` require `research`;
//! `tests/golden.rs` runs with or without it (its cases drawn with the benchmark's methods
//! only with it).
//!
//! Diagnostics go through the `log` crate. [`EllipsoidRenderer`] reads no environment
//! variable; the `offscreen` context reads `ELLIPSOID_SPLAT_DEVICE` (which device, when
//! `ContextOptions::device` is `None`) and, in `ContextOptions::validated`,
//! `ELLIPSOID_SPLAT_EXTRA_VALIDATION` (`gpu-assisted` or `best-practices`).
//!
//! # The standalone renderer
//!
//! ```
//! # #[cfg(feature = "offscreen")]
//! # fn main() -> ellipsoid_splat::Result<()> {
//! use ellipsoid_splat::{Camera, ContextOptions, Ellipsoid, OffscreenRenderer, Outputs, Scene};
//! use glam::{DQuat, DVec3};
//!
//! let glyph = Ellipsoid::new(
//!     DVec3::ZERO,
//!     DVec3::new(1.0, 0.5, 0.25),
//!     DQuat::IDENTITY,
//!     Some([0.8, 0.3, 0.2]),
//! )?;
//! let scene = Scene::new(vec![glyph]);
//! let (centre, radius) = scene.bounding_sphere().expect("one glyph");
//! let camera = Camera::framing(centre, radius, 640, 480)?;
//! let mut renderer = OffscreenRenderer::new(&ContextOptions::default())?;
//! let frame = renderer.render(&scene, &camera, Outputs::ALL)?;
//! assert_eq!(frame.len(), 640 * 480);
//! renderer.finish()?;
//! # Ok(())
//! # }
//! # #[cfg(not(feature = "offscreen"))]
//! # fn main() {}
//! ```

mod allocator;
mod barriers;
mod bounds;
mod camera;
mod culling;
mod depth;
mod ellipsoid;
mod error;
mod features;
mod footprint;
mod frame_slots;
mod gpu_layout;
mod host_camera;
mod instances;
mod path;
mod renderer;
mod scene;
mod settings;
#[cfg(test)]
mod spirv_mirror;
mod target;

#[cfg(feature = "offscreen")]
mod frame;
mod gpu;
#[cfg(feature = "offscreen")]
mod offscreen;
/// The benchmark's baselines and measuring aids: the drawing methods `bench` compares with
/// the shipped impostor. Hosts never need it.
#[cfg(feature = "research")]
pub mod research;
#[cfg(not(feature = "research"))]
#[path = "research/off.rs"]
mod research;
/// Supersampling: a frame drawn K times larger, box-filtered in linear light.
#[cfg(feature = "offscreen")]
pub mod supersample;

pub use allocator::{BufferMemory, MemoryAllocator, MemoryUse};
pub use bounds::ScreenBounds;
pub use camera::{Camera, Intrinsics, Projection};
pub use culling::Culling;
pub use depth::DepthConvention;
pub use ellipsoid::Ellipsoid;
pub use error::{Error, Result};
pub use features::DeviceFeatures;
pub use host_camera::HostViewport;
pub use instances::{InstanceFormat, Placement};
pub use path::{FramePath, HiddenLayers, PathKind, PlanMode};
pub use renderer::{EllipsoidRenderer, FramePlan, PlanReason};
pub use scene::Scene;
pub use settings::{Material, Settings};
pub use target::{HostDevice, Pass, RendererOptions, Target};

#[cfg(feature = "offscreen")]
pub use frame::{Frame, NO_INSTANCE};
#[cfg(feature = "offscreen")]
pub use gpu::{Context, ContextOptions, DeviceInfo, QueryResults};
#[cfg(feature = "offscreen")]
pub use offscreen::{FrameTiming, OffscreenRenderer, Outputs};

/// What the workspace's other crates (loaders, reference, tool), the tests and the
/// benchmarks use of the library's insides. Not part of the host API: anything here may
/// change in any release.
#[doc(hidden)]
pub mod internals {
    /// The renderer's barriers as data (`tests/barriers.rs` checks them).
    pub mod barriers {
        pub use crate::barriers::*;
    }
    /// The pixel-ray contract's frame and rays (`Camera::basis`, `Camera::ray`), for the
    /// float64 reference.
    pub use crate::camera::{Basis, Ray};
    pub use crate::ellipsoid::{shape_color, symmetric_eigen};
    #[cfg(feature = "offscreen")]
    pub use crate::gpu::validation;
    pub use crate::instances::pack_instances;
    /// The offscreen renderer's background (linear RGBA), for checks of its colour output.
    #[cfg(feature = "offscreen")]
    pub use crate::offscreen::BACKGROUND;
    /// Where the compute splat sets glyphs up once for its resolve.
    pub use crate::renderer::SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL;
}
