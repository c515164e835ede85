//! `ellipsoid-splat`: very many ellipsoids drawn exactly as ray-cast impostors in one instanced
//! Vulkan draw.
//!
//! The quickest way in is [`OffscreenRenderer`], which owns its Vulkan device and reads frames
//! back; [`renderer::EllipsoidRenderer`] records into a command buffer it is given.
//!
//! ```
//! use ellipsoid_splat::gpu::ContextOptions;
//! use ellipsoid_splat::{Camera, Ellipsoid, OffscreenRenderer, Scene};
//! use glam::{DQuat, DVec3};
//!
//! # fn main() -> ellipsoid_splat::Result<()> {
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
//! let frame = renderer.render(&scene, &camera)?;
//! assert_eq!(frame.len(), 640 * 480);
//! renderer.finish()?;
//! # Ok(())
//! # }
//! ```

#![deny(missing_docs)]

pub mod barriers;
pub mod bounds;
pub mod camera;
pub mod culling;
pub mod depth;
pub mod draw;
pub mod ellipsoid;
pub mod error;
pub mod features;
pub mod frame;
mod frame_slots;
mod host_camera;
pub mod scene;

pub use camera::{Camera, Projection};
pub use depth::DepthConvention;
pub use ellipsoid::Ellipsoid;
pub use error::{Error, Result};
pub use frame::{Frame, NO_INSTANCE};
pub use scene::Scene;
pub mod gpu;
pub mod icosphere;
pub mod instances;
pub mod offscreen;
mod pipeline;
pub mod renderer;
pub mod target;

pub use offscreen::OffscreenRenderer;
pub use renderer::EllipsoidRenderer;
pub use target::{HostDevice, Pass, RendererOptions, Target};
