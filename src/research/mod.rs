//! The benchmark's side of the library (feature `research`): the baselines `bench` compares
//! with the shipped impostor ([`DrawConfig`](crate::research::DrawConfig), [`Method`](crate::research::Method)), their shaders, icosphere meshes,
//! the compute splat's floors and the exact counts of shaded pixels and ray casts. Hosts never
//! need it. Without the feature, `off.rs` stands in: an empty `Baseline` the frame plan can
//! never hold, and a research state that changes nothing, so the renderer's own code carries
//! no feature gates.
//!
//! # Files
//!
//! | file | what it holds |
//! |---|---|
//! | `mod.rs` | the module's public items (`DrawConfig`, `Geometry`, `Footprint`, `Intersection`, `Shading`, `Method`, `icosphere`) and what the renderer asks of it |
//! | `baseline.rs` | the baselines' types and what differs when one is drawn: the pre-pass's proofs, set-up once, specialization constants, shaders, fixed-function state, a pass of its own |
//! | `method.rs` | `Method`: the methods `bench` compares, each a plan mode or a baseline |
//! | `measuring.rs` | `Research` (the renderer's research state) and `set_draw_config`, `set_splat_floor`, `set_tiled_splat`, `forget_shown`, `set_floor_pixels`, `set_count_fragments`, `fragment_count`, `compute_ray_count`, `record_counter_barrier` |
//! | `meshes.rs`, `icosphere.rs` | icosphere meshes and their buffers |
//! | `visibility_draw.rs` | the visibility-buffer draw (`impostor-visbuffer`, design §5.6): its attachment-less pass in the pre-pass |
//! | `traced.rs` | the traced path (`impostor-traced`, `set_traced`, `TracedBuild`; shaders `research/traced_boxes.comp`, `research/traced.comp`): a hierarchy of the glyphs' padded boxes walked per pixel with ray queries in place of the splat, on devices the offscreen renderer created with ray queries (Mesa 25's lavapipe); 9-117x the splat's time there, not a shipped path (`docs/deep-scenes.md`) |
//! | `shaders.rs` | the baselines' SPIR-V and every fragment shader's counting builds |
//! | `offscreen.rs` | the offscreen renderer's research switches and its counting frames |

mod baseline;
mod icosphere;
mod measuring;
mod meshes;
mod method;
mod offscreen;
mod shaders;
mod traced;
mod visibility_draw;

pub use baseline::{DrawConfig, Footprint, Geometry, Intersection, Shading};
pub use icosphere::{icosphere, Icosphere};
pub use method::Method;
pub use traced::TracedBuild;

pub(crate) use baseline::Baseline;
pub(crate) use measuring::Research;
pub(crate) use offscreen::{begin_counting, counts};
pub(crate) use shaders::{counted, TILED_BINS_COMP, TILED_SPLAT_COMP};
pub(crate) use traced::ray_query_supported;
// The traversal's group edge, for the test that reads it back from the compiled shader.
#[cfg(test)]
pub(crate) use traced::TRACE_GROUP_EDGE;
