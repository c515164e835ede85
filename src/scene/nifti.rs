//! Diffusion tensor NIfTI volumes (placeholder until the loader lands).

use std::path::Path;

use crate::error::{Error, Result};
use crate::scene::load::{LoadOptions, Loaded};

/// Loads a diffusion tensor volume.
pub fn load_nifti(path: &Path, _options: &LoadOptions) -> Result<Loaded> {
    Err(Error::invalid(
        "scene",
        format!("{}: NIfTI not supported yet", path.display()),
    ))
}
