//! Writing a [`Frame`] to files: colour PNG, float32 EXR view depth and world normal, and a
//! lossless 32-bit instance-ID image. All are `width x height`, row 0 at the top.

use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
    WritableImage,
};

use ellipsoid_splat::error::{Error, Result};
use ellipsoid_splat::frame::Frame;

fn encode_error(path: &Path, reason: impl ToString) -> Error {
    Error::Encode {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    }
}

fn write_rgba8_png(frame: &Frame, path: &Path, bytes: &[u8]) -> Result<()> {
    image::save_buffer(
        path,
        bytes,
        frame.width,
        frame.height,
        image::ExtendedColorType::Rgba8,
    )
    .map_err(|e| encode_error(path, e))
}

/// sRGB colour as an 8-bit RGBA PNG.
pub fn write_color_png(frame: &Frame, path: &Path) -> Result<()> {
    let bytes: Vec<u8> = frame.color.iter().flatten().copied().collect();
    write_rgba8_png(frame, path, &bytes)
}

fn write_exr(path: &Path, frame: &Frame, channels: Vec<AnyChannel<FlatSamples>>) -> Result<()> {
    let size = (frame.width as usize, frame.height as usize);
    let layer = Layer::new(
        size,
        LayerAttributes::named("ellipsoid-splat"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| encode_error(path, e))
}

/// View depth `dot(p - eye, f)` as a float32 EXR channel `Z`; background is +inf.
pub fn write_depth_exr(frame: &Frame, path: &Path) -> Result<()> {
    let z = AnyChannel::new("Z", FlatSamples::F32(frame.depth.clone()));
    write_exr(path, frame, vec![z])
}

/// World-space unit normal as float32 EXR channels `R, G, B`; background is 0.
pub fn write_normal_exr(frame: &Frame, path: &Path) -> Result<()> {
    let channel = |name: &str, k: usize| {
        AnyChannel::new(
            name,
            FlatSamples::F32(frame.normal.iter().map(|n| n[k]).collect()),
        )
    };
    write_exr(
        path,
        frame,
        vec![channel("R", 0), channel("G", 1), channel("B", 2)],
    )
}

/// Instance IDs, lossless: `.exr` writes a 32-bit unsigned channel `ID`; `.png` packs each ID
/// little-endian into RGBA8 (R = lowest byte). Background is `u32::MAX` (0xFFFFFFFF).
pub fn write_id_image(frame: &Frame, path: &Path) -> Result<()> {
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if is_png {
        let bytes: Vec<u8> = frame.id.iter().flat_map(|id| id.to_le_bytes()).collect();
        write_rgba8_png(frame, path, &bytes)
    } else {
        let id = AnyChannel::new("ID", FlatSamples::U32(frame.id.clone()));
        write_exr(path, frame, vec![id])
    }
}
