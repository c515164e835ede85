//! Writing a target's readback as a PNG.

use std::path::Path;

use crate::HostResult;

/// Writes tightly packed RGBA8 pixels (row 0 at the top) as a PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> HostResult<()> {
    let image = ::image::RgbaImage::from_raw(width, height, rgba.to_vec())
        .ok_or_else(|| format!("{} bytes is not a {width}x{height} RGBA8 image", rgba.len()))?;
    image
        .save(path)
        .map_err(|e| format!("writing {}: {e}", path.display()))
}
