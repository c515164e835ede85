//! 3D Gaussian Splatting PLY scenes (placeholder until the loader lands).

use std::path::Path;

use crate::error::{Error, Result};
use crate::scene::load::{LoadOptions, Loaded};

/// Loads a 3D Gaussian Splatting PLY file.
pub fn load_ply(path: &Path, _options: &LoadOptions) -> Result<Loaded> {
    Err(Error::invalid(
        "scene",
        format!("{}: PLY not supported yet", path.display()),
    ))
}
