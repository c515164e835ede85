//! `ellipsoid-splat`: very many ellipsoids drawn exactly as ray-cast impostors in one instanced
//! Vulkan draw.

pub mod bench;
pub mod camera;
pub mod cli;
pub mod compare;
pub mod culling;
pub mod draw;
pub mod ellipsoid;
pub mod error;
pub mod frame;
pub mod reference;
pub mod report;
pub mod scene;
pub mod skip;
pub mod stress;

pub use camera::{Camera, Projection};
pub use ellipsoid::Ellipsoid;
pub use error::{Error, Result};
pub use frame::{Frame, NO_INSTANCE};
pub use scene::Scene;
pub mod gpu;
pub mod icosphere;
pub mod instances;
pub mod offscreen;
pub mod output;
mod pipeline;
pub mod renderer;

pub use offscreen::OffscreenRenderer;
pub use renderer::EllipsoidRenderer;
