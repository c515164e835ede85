//! `ellipsoid-splat`: very many ellipsoids drawn exactly as ray-cast impostors in one instanced
//! Vulkan draw.

pub mod camera;
pub mod ellipsoid;
pub mod error;

pub use camera::{Camera, Projection};
pub use ellipsoid::Ellipsoid;
pub use error::{Error, Result};
