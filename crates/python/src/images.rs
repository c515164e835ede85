//! Pictures as files and bytes, written as the command-line tool writes them: sRGB colour
//! PNG, float32 EXR channels (lossless), 32-bit IDs as EXR or packed into PNG.

use std::path::PathBuf;

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
    WritableImage,
};
use numpy::PyReadonlyArray3;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// PNG bytes of an (H, W, 4) uint8 RGBA image.
#[pyfunction]
pub fn encode_png<'py>(
    py: Python<'py>,
    rgba: PyReadonlyArray3<'py, u8>,
) -> PyResult<Bound<'py, PyBytes>> {
    let view = rgba.as_array();
    let shape = view.shape();
    if shape[2] != 4 {
        return Err(PyValueError::new_err(format!(
            "the image has shape {shape:?}, expected (H, W, 4)"
        )));
    }
    let (h, w) = (shape[0] as u32, shape[1] as u32);
    let bytes: Vec<u8> = view.iter().copied().collect();
    let mut png = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut png),
        &bytes,
        w,
        h,
        image::ExtendedColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .map_err(|e| PyValueError::new_err(format!("PNG encoding: {e}")))?;
    Ok(PyBytes::new(py, &png))
}

/// Writes float32 (or uint32, for `ID`) channels of a `width x height` image to an EXR file.
#[pyfunction]
pub fn write_exr(
    path: PathBuf,
    width: usize,
    height: usize,
    float_channels: Vec<(String, Vec<f32>)>,
    uint_channels: Vec<(String, Vec<u32>)>,
) -> PyResult<()> {
    let mut channels = Vec::new();
    for (name, samples) in float_channels {
        check(&name, samples.len(), width * height)?;
        channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(samples)));
    }
    for (name, samples) in uint_channels {
        check(&name, samples.len(), width * height)?;
        channels.push(AnyChannel::new(name.as_str(), FlatSamples::U32(samples)));
    }
    let layer = Layer::new(
        (width, height),
        LayerAttributes::named("ellipsoid-splat"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    Image::from_layer(layer)
        .write()
        .to_file(&path)
        .map_err(|e| PyOSError::new_err(format!("{}: {e}", path.display())))
}

fn check(name: &str, len: usize, want: usize) -> PyResult<()> {
    if len == want {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "channel {name} has {len} samples, {want} expected"
        )))
    }
}
