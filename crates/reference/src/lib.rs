//! The float64 CPU reference renderer of `ellipsoid-splat` (the oracle of every accuracy test)
//! and the statistics of a GPU frame's error against it.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | float64 reference renderer (design §9.1) | `src/reference.rs` |
//! | GPU-against-reference statistics and bounds (design §9.2) | `src/compare.rs` |
//! | antialiased frames against the reference: covered samples per pixel at the GPU's positions, coverage error in samples | `src/coverage.rs` |
//! | the colour output against the shading model (`docs/testing.md`) | `src/shading.rs` |
//! | test support: validated renderers, teardown checks, GPU-against-reference assertions, the compact format's bounds (design §9.2, `docs/validation.md`) | `src/testing.rs` (`ellipsoid_splat_reference::testing`; the integration tests import it as `common`) |

pub mod compare;
pub mod coverage;
pub mod reference;
pub mod shading;
pub mod testing;

pub use compare::{compare, Bounds, ErrorStats};
pub use coverage::{compare_coverage, reference_coverage, CoverageStats, SamplePattern};
pub use reference::{render_reference, ReferenceFrame};
pub use shading::{compare_colors, ColorStats};
