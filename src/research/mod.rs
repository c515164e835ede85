//! The benchmark's side of the library (feature `research`): the baselines `bench` compares
//! with the shipped impostor ([`DrawConfig`](crate::research::DrawConfig), [`Method`](crate::research::Method)), their shaders, icosphere meshes,
//! the compute splat's floors and the exact counts of shaded pixels and ray casts. Hosts never
//! need it. Without the feature, `off.rs` stands in: an empty `Baseline` the frame plan can
//! never hold, and a research state that changes nothing, so the renderer's own code carries
//! no feature gates.

mod baseline;
mod icosphere;
mod measuring;
mod meshes;
mod method;
mod offscreen;
mod shaders;
mod visibility_draw;

pub use baseline::{DrawConfig, Footprint, Geometry, Intersection, Shading};
pub use icosphere::{icosphere, Icosphere};
pub use method::Method;

pub(crate) use baseline::Baseline;
pub(crate) use measuring::Research;
pub(crate) use offscreen::{begin_counting, counts};
pub(crate) use shaders::{counted, TILED_BINS_COMP, TILED_SPLAT_COMP};
