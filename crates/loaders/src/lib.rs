//! Scene files and generated scenes for `ellipsoid-splat`: each loader turns a file into a
//! [`Scene`](ellipsoid_splat::Scene) of ellipsoids and names the file, line, field and reason of
//! every bad record, never panicking on any input.
//!
//! Formats read:
//!
//! - [`csv`]: Ellipsoid CSV (`.csv`): centres with semi-axes and quaternions, or with tensors;
//!   optional colours;
//! - [`ply`]: 3D Gaussian Splatting PLY (`.ply`, binary either endian or ASCII);
//! - [`nifti`]: diffusion tensor volumes, NIfTI-1 (`.nii`, `.nii.gz`), as tensor glyphs;
//! - [`pdb`]: crystallographic thermal ellipsoids from PDB (`.pdb`, `.ent`) and mmCIF (`.cif`,
//!   `.mmcif`);
//! - [`lammps`]: LAMMPS `dump custom` text files (`.lammpstrj`, `.dump`, plain or gzipped):
//!   ellipsoids (ASPHERE) and spheres, one or more frames;
//! - [`xyz`]: extended XYZ (`.xyz`, `.extxyz`, plain or gzipped; ASE, OVITO, GPUMD), one or more
//!   frames;
//! - [`load()`]: any of them, by extension, else by the first bytes of the file;
//! - [`load_share`]: one process's share of a file read by several (each its own byte range
//!   or records), for drawing a scene split between processes.
//!
//! A file of several frames is read frame by frame through a [`Trajectory`] (`load` returns
//! frame 1 and says how many there are).
//!
//! Once loaded, glyphs can be recoloured by shape, principal direction or uniformly
//! ([`ColorMode`]; [`anisotropy`] gives the fractional anisotropy it weights by).
//!
//! Also [`generate`] (the tensor-field demo, random clouds, packed blocks and a liquid of rods
//! and spheres, for tests, benches and demos) and [`Progress`], the progress bar large files and long sweeps show on a terminal.
//!
//! # Diagnostics
//!
//! What the user should read about a load (parameters in effect, records filtered out or
//! skipped, parts of the file ignored) is returned in [`Loaded::notes`]; the caller decides how
//! to show it. Nothing is printed: the only other output is through the [`log`] crate, at debug
//! level (the format chosen, how long a load took), for hosts that install a logger. No
//! environment variable is read. The progress bar is drawn only when asked for
//! ([`LoadOptions::progress`]) and only on a terminal.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | format detection and loading by format | `src/load.rs` |
//! | the options every loader shares (`LoadOptions`) | `src/options.rs` |
//! | the report of a load and each glyph's origin (`Loaded`, `Origins`) | `src/loaded.rs` |
//! | gzip: whole particle files gunzipped in memory, the head of a stream for detection | `src/gzip.rs` |
//! | Ellipsoid CSV (`docs/formats.md`) | `src/csv.rs` |
//! | 3D Gaussian Splatting PLY (its own body reader: the measured reason in its module docs, `examples/ply_body_time.rs`) | `src/ply.rs` |
//! | diffusion tensor NIfTI-1 (why not the `nifti` crate's reader and affine: its module docs) | `src/nifti.rs` |
//! | thermal ellipsoids, PDB and mmCIF (why not pdbtbx's readers: its module docs and a test) | `src/pdb.rs` |
//! | LAMMPS dumps (`docs/formats.md`) | `src/lammps.rs` |
//! | extended XYZ (`docs/formats.md`) | `src/xyz.rs` |
//! | what the particle formats share: type palette, column mapping, atom values to an ellipsoid, a frame sorted by id | `src/particles.rs` |
//! | multi-frame particle files read frame by frame (`Trajectory`) | `src/trajectory.rs` |
//! | generated scenes (tensor field, random clouds, packed blocks) | `src/generate.rs` |
//! | colour modes (`--color`: file, shape, principal direction, principal times FA, uniform) | `src/color_mode.rs` |
//! | fractional anisotropy of three semi-axes | `src/anisotropy.rs` |
//! | progress bar | `src/progress.rs` |
//! | fuzz targets and corpus | `fuzz/` |
//! | files written whole or not at all (`docs/command-line.md`) | `src/atomic_file.rs` |
//! | one process's share of a scene file (`docs/mpi.md`): the plan by format, line-start byte ranges, each format's share, ids and species numbered across processes, the agreement, the `Exchange` it needs | `src/share/` (`mod.rs`, `line_ranges.rs`, `csv.rs`, `particles.rs`, `ply.rs`, `ids.rs`, `species.rs`, `collective.rs`, `exchange.rs`, `loaded_share.rs`) |

pub mod anisotropy;
pub mod atomic_file;
pub mod color_mode;
pub mod csv;
mod error;
pub mod generate;
mod gzip;
pub mod lammps;
pub mod load;
mod loaded;
pub mod nifti;
mod options;
mod particles;
pub mod pdb;
pub mod ply;
pub mod progress;
pub mod share;
pub mod trajectory;
pub mod xyz;

pub use self::anisotropy::fractional_anisotropy;
pub use self::atomic_file::write_atomically;
pub use self::color_mode::{principal_color, principal_direction, ColorMode, UNIFORM_GREY};
pub use self::csv::{csv_text, load_csv, parse_csv, save_csv};
pub use self::error::{Error, Result};
pub use self::generate::{lattice, md_liquid, packed_block, random_cloud, tensor_field};
pub use self::lammps::{load_lammps, parse_lammps};
pub use self::load::{load, Format, LoadOptions, Loaded, Origins, TensorOrder};
pub use self::nifti::{load_nifti, parse_nifti};
pub use self::particles::TYPE_PALETTE;
pub use self::pdb::{load_structure, parse_structure};
pub use self::ply::{load_ply, parse_ply};
pub use self::progress::Progress;
pub use self::share::{load_share, Exchange, LoadedShare, Split};
pub use self::trajectory::Trajectory;
pub use self::xyz::{load_xyz, parse_xyz};
