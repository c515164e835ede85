//! Scene files and generated scenes for `ellipsoid-splat`: each loader turns a file into a
//! [`Scene`](ellipsoid_splat::Scene) and names the file, line, field and reason of every bad
//! record.
//!
//! - [`csv`]: ellipsoid CSV (centres, semi-axes and rotations, or tensors; optional colours);
//! - [`ply`]: 3D Gaussian Splatting PLY;
//! - [`nifti`]: diffusion tensor volumes (NIfTI-1, optionally gzipped);
//! - [`pdb`]: thermal ellipsoids from PDB and mmCIF;
//! - [`load()`]: any of them, by extension or content;
//! - [`generate`]: the tensor-field demo, random clouds and packed blocks.

pub mod csv;
pub mod generate;
pub mod load;
pub mod nifti;
pub mod pdb;
pub mod ply;
pub mod progress;

pub use self::csv::{load_csv, parse_csv};
pub use self::generate::{packed_block, random_cloud, tensor_field};
pub use self::load::{load, LoadOptions, Loaded, TensorOrder};
pub use self::nifti::{load_nifti, parse_nifti};
pub use self::pdb::{load_structure, parse_structure};
pub use self::ply::{load_ply, parse_ply};
pub use self::progress::Progress;
