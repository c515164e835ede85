//! `ellipsoid-splat`: very many ellipsoids drawn exactly as ray-cast impostors in one instanced
//! Vulkan draw.
//!
//! [`EllipsoidRenderer`] records into a host's command buffers: the host's device, allocator
//! (through [`MemoryAllocator`]), render pass (or dynamic rendering), sample count, projection
//! and viewport, one or several views a frame (see `examples/minimal.rs` and
//! `docs/embedding.md`). With the default feature `offscreen`, `OffscreenRenderer` owns its
//! Vulkan device and reads frames back.
//!
//! Features:
//! - `gpu-allocator` (default): [`MemoryAllocator`] for `gpu_allocator::vulkan::Allocator`.
//! - `vk-mem`: [`MemoryAllocator`] for `vk_mem::Allocator` (VMA), for hosts on VMA.
//! - `offscreen` (default): `OffscreenRenderer`, `Frame`, `Outputs` and its own Vulkan
//!   `Context`; implies `gpu-allocator`.
//! - `research`: the benchmark's baselines (`research::Method`: textbook intersection, box
//!   proxy, icosphere meshes, flat fill, fixed footprints) and fragment counting. Hosts never
//!   need it.
//!
//! Diagnostics go through the `log` crate. [`EllipsoidRenderer`] reads no environment
//! variable; the `offscreen` context reads `ELLIPSOID_SPLAT_DEVICE` (which device, when
//! `ContextOptions::device` is `None`) and, in `ContextOptions::validated`,
//! `ELLIPSOID_SPLAT_EXTRA_VALIDATION` (`gpu-assisted` or `best-practices`).
//!
//! The design, the numerics of the exact hit and every contract are in `docs/design.md`.
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
}
