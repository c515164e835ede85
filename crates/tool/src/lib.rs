//! The `ellipsoid-splat` command line as a library: argument parsing, the numerical-stability
//! sweep, the time-against-error benchmark, the skip benchmark, reports, image outputs and the
//! interactive viewer (`view`); and which `render` flags `ellipsoid-splat-mpi` (feature `mpi`)
//! honours.
//! `main.rs` dispatches to these; tests call them directly.

pub mod antialias_bench;
pub mod antialias_stress;
pub mod bench;
pub mod camera_setup;
pub mod cli;
pub mod conformance;
pub mod error;
pub mod frame_range;
pub mod host_memory;
pub mod movie;
pub mod mpi_flags;
pub mod output;
pub mod plan;
pub mod render_device;
pub mod report;
pub mod scene_io;
pub mod sequence;
pub mod skip;
pub mod stress;
pub mod view;
