//! Vulkan plumbing: context, owned buffers and images, shaders, validation messages.

pub mod buffer;
pub mod context;
pub mod image;
pub mod queries;
pub mod shaders;
pub mod validation;

pub use buffer::GpuBuffer;
pub use context::{Context, ContextOptions, DeviceInfo};
pub use image::GpuImage;
