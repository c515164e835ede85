//! The `ellipsoid-splat` command line as a library: argument parsing, the numerical-stability
//! sweep, the time-against-error benchmark, the skip benchmark, reports, image outputs and the
//! interactive viewer (`view`); and which `render` flags `ellipsoid-splat-mpi` (feature `mpi`)
//! honours.
//! `main.rs` dispatches to these; tests call them directly.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | command-line arguments (`docs/command-line.md`), one file per command or shared flag group, each checked into typed options | `src/cli/` |
//! | what the arguments drive: the scene read and saved, the camera, the host memory check | `src/scene_io.rs`, `src/camera_setup.rs`, `src/host_memory.rs` |
//! | subcommand dispatch and exit statuses (`docs/command-line.md`) | `src/main.rs` |
//! | PNG and EXR writers, numbered file names (`docs/command-line.md`) | `src/output.rs` |
//! | the renderer a `render` asks for, made ready (scene uploaded, plan warmed up) | `src/render_device.rs` |
//! | `render --frames`: the frames a range names, the trajectory drawn in three overlapping threads, the movie through ffmpeg | `src/frame_range.rs`, `sequence.rs`, `movie.rs` |
//! | the viewer stepping and playing a trajectory | `src/view/playback.rs` |
//! | `render` under mpirun (`docs/mpi.md`): the flags refused, the run, the agreement, the `Exchange` over MPI | `src/mpi_flags.rs`, `src/bin/ellipsoid-splat-mpi/` (`main.rs`, `render.rs`, `agree.rs`, `exchange.rs`, `error.rs`) |
//! | the driver check (`conformance`) | `src/conformance.rs` |
//! | numerical-stability sweep (`stress`) | `src/stress.rs` |
//! | run time against error (`bench`) and its targets | `src/bench.rs` |
//! | each skippable piece of work on and off (`bench --skip`) | `src/skip.rs` |
//! | the antialiased points of `stress` (`stress_aa.csv`) | `src/antialias_stress.rs` |
//! | what antialiasing costs (`bench --antialias`) | `src/antialias_bench.rs` |
//! | the interactive viewer (`view`): window, swapchain, input, picking, the moving sample | `src/view/` (`docs/viewer.md`) |
//! | charts (on plotters' linear and log coordinates) and tables | `src/report/` (`plot.rs`, `table.rs`) |

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
