//! `ellipsoid-splat`: very many ellipsoids drawn exactly as ray-cast impostors in one instanced
//! Vulkan draw.
//!
//! [`EllipsoidRenderer`] records into a host's command buffers: the host's device, allocator,
//! render pass (or dynamic rendering), sample count and projection (see `examples/minimal.rs`
//! and the README's "Embedding" section). With the default feature `offscreen`,
//! `OffscreenRenderer` owns its Vulkan device and reads frames back.
//!
//! Features:
//! - `offscreen` (default): `OffscreenRenderer`, `Frame`, `Outputs` and the `gpu` context; no
//!   extra dependency.
//! - `research`: the benchmark's baselines (`draw::Method`: textbook intersection, box proxy,
//!   icosphere meshes, flat fill, fixed footprints) and fragment counting. Hosts never need it.
//!
//! Diagnostics go through the `log` crate. [`EllipsoidRenderer`] reads no environment
//! variable; the `offscreen` context reads `ELLIPSOID_SPLAT_DEVICE` (which device, when
//! `gpu::ContextOptions::device` is `None`) and, in `gpu::ContextOptions::validated`,
//! `ELLIPSOID_SPLAT_EXTRA_VALIDATION` (`gpu-assisted` or `best-practices`).
//!
//! The design, the numerics of the exact hit and every contract are in `docs/design.md`.
//!
//! ```
//! # #[cfg(feature = "offscreen")]
//! # fn main() -> ellipsoid_splat::Result<()> {
//! use ellipsoid_splat::gpu::ContextOptions;
//! use ellipsoid_splat::{Camera, Ellipsoid, OffscreenRenderer, Outputs, Scene};
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

pub mod allocator;
pub mod barriers;
pub mod bounds;
pub mod camera;
mod culling;
pub mod depth;
pub mod draw;
pub mod ellipsoid;
pub mod error;
pub mod features;
mod frame_slots;
mod gpu_layout;
mod host_camera;
// The packing is public for the benchmark's CPU timings only.
#[cfg(feature = "research")]
pub mod instances;
#[cfg(not(feature = "research"))]
mod instances;
mod pipeline;
pub mod renderer;
pub mod scene;
pub mod settings;
mod target;

#[cfg(feature = "offscreen")]
pub mod frame;
#[cfg(feature = "offscreen")]
pub mod gpu;
#[cfg(not(feature = "offscreen"))]
mod gpu;
#[cfg(feature = "research")]
pub mod icosphere;
#[cfg(feature = "offscreen")]
pub mod offscreen;

pub use allocator::MemoryAllocator;
pub use camera::{Camera, Intrinsics, Projection};
pub use culling::Culling;
pub use depth::DepthConvention;
pub use ellipsoid::Ellipsoid;
pub use error::{Error, Result};
pub use features::DeviceFeatures;
pub use host_camera::HostViewport;
pub use instances::InstanceFormat;
pub use renderer::{DrawReason, EllipsoidRenderer, FramePlan};
pub use scene::Scene;
pub use settings::{Material, Settings};
pub use target::{HostDevice, Pass, RendererOptions, Target, ID_FORMAT, NORMAL_FORMAT};

#[cfg(feature = "offscreen")]
pub use frame::{Frame, NO_INSTANCE};
#[cfg(feature = "offscreen")]
pub use offscreen::{OffscreenRenderer, Outputs};
