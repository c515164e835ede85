//! Vulkan plumbing: owned buffers and shader modules; with the `offscreen` feature also the
//! own-device context, owned images, queries and the validation messenger.

pub(crate) mod buffer;
#[cfg(feature = "offscreen")]
pub mod context;
#[cfg(feature = "offscreen")]
pub(crate) mod image;
#[cfg(feature = "offscreen")]
pub mod queries;
pub(crate) mod shaders;
#[cfg(feature = "offscreen")]
pub mod validation;

pub(crate) use buffer::GpuBuffer;
#[cfg(feature = "offscreen")]
pub use context::{Context, ContextOptions, DeviceInfo};
#[cfg(feature = "offscreen")]
pub(crate) use image::GpuImage;
#[cfg(feature = "offscreen")]
pub use queries::QueryResults;
