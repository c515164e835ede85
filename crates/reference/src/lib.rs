//! The float64 CPU reference renderer of `ellipsoid-splat` (the oracle of every accuracy test)
//! and the statistics of a GPU frame's error against it.

pub mod compare;
pub mod coverage;
pub mod reference;
pub mod shading;
pub mod testing;

pub use compare::{compare, Bounds, ErrorStats};
pub use coverage::{compare_coverage, reference_coverage, CoverageStats, SamplePattern};
pub use reference::{render_reference, ReferenceFrame};
pub use shading::{compare_colors, ColorStats};
