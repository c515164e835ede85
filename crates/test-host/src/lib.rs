//! A small host engine that embeds `ellipsoid-splat` the way a real engine would: the renderer
//! gets this engine's device, allocator, command buffer, render pass (or dynamic rendering),
//! sample count and projection matrices, and draws into its frame next to its own meshes.
//! `examples/embed` and the embedding tests (`tests/embedding.rs`) are built on it.
//!
//! It is written against `ash`, `gpu-allocator` and `glam` alone, nothing from
//! `ellipsoid_splat`, so it cannot lean on the library's own Vulkan code. One concept a file:
//!
//! - [`Host`] (`host.rs`): device, queue, allocator, one command buffer and fence;
//!   `instance.rs`: the instance and its debug messenger; `validation.rs`: the validation
//!   layer's checks and the callback collecting its messages.
//! - [`HostTarget`] (`target.rs`): colour and depth images, optional MSAA resolve, readback;
//!   drawn into through a `VkRenderPass` (`render_pass.rs`) or dynamic rendering
//!   (`dynamic_rendering.rs`). `image.rs`, `buffer.rs`: images and buffers with their memory.
//! - [`MeshPipeline`] (`mesh.rs`): flat-coloured triangle lists; `geometry.rs`: a tilted plane
//!   and a cube to draw with it.
//! - `projection.rs`: Vulkan projection matrices in both depth conventions; `png.rs`: writing
//!   a readback as a PNG.
//!
//! Every Vulkan object has one owner (the [`Host`], a [`HostTarget`] or a [`MeshPipeline`]),
//! which destroys it; owners made from a [`Host`] are destroyed before it.

mod buffer;
mod geometry;
mod host;
mod image;
mod instance;
mod mesh;
mod png;
mod projection;
mod target;
mod validation;

pub use geometry::{cube, tilted_plane, CUBE_FACE_GREYS, CUBE_GREY};
pub use host::{Host, HostHandles};
pub use mesh::{MeshPipeline, MeshVertex};
pub use png::write_png;
pub use projection::{reversed_infinite_perspective, standard_finite_perspective};
pub use target::{DepthKind, HostTarget, TargetKind};

/// Result of every host operation; the error names the Vulkan call that failed.
pub type HostResult<T> = Result<T, String>;

/// Turns a Vulkan (or allocator) error into a message naming the failing call.
fn fail<E: std::fmt::Debug>(call: &'static str) -> impl FnOnce(E) -> String {
    move |e| format!("{call} failed: {e:?}")
}
