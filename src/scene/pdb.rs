//! Thermal ellipsoids from PDB and mmCIF files (placeholder until the loader lands).

use std::path::Path;

use crate::error::{Error, Result};
use crate::scene::load::{LoadOptions, Loaded};

/// Loads the anisotropic displacement ellipsoids of a structure.
pub fn load_structure(path: &Path, _options: &LoadOptions) -> Result<Loaded> {
    Err(Error::invalid(
        "scene",
        format!("{}: PDB not supported yet", path.display()),
    ))
}
