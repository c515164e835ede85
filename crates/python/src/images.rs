//! Pictures as files and bytes, written as the command-line tool writes them: sRGB colour
//! PNG, float32 EXR channels (lossless), 32-bit IDs as EXR or packed into PNG.

use std::path::{Path, PathBuf};

use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
    WritableImage,
};
use numpy::ndarray::Axis;
use numpy::{PyReadonlyArray2, PyReadonlyArray3, PyReadonlyArrayDyn};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::errors::no_panic;

/// PNG bytes of an (H, W, 4) uint8 RGBA image.
#[pyfunction]
pub fn encode_png<'py>(
    py: Python<'py>,
    rgba: PyReadonlyArray3<'py, u8>,
) -> PyResult<Bound<'py, PyBytes>> {
    let png = no_panic(|| {
        let view = rgba.as_array();
        let shape = view.shape();
        if shape[2] != 4 || shape[0] == 0 || shape[1] == 0 {
            return Err(PyValueError::new_err(format!(
                "the image has shape {shape:?}, expected (H, W, 4), H and W at least 1"
            )));
        }
        let (h, w) = (shape[0], shape[1]);
        let (Ok(h), Ok(w)) = (u32::try_from(h), u32::try_from(w)) else {
            return Err(PyValueError::new_err(format!("the image is too large: {shape:?}")));
        };
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
        Ok(png)
    })?;
    Ok(PyBytes::new(py, &png))
}

/// Writes a float32 image as EXR channels `names`: `array` is (H, W) with one name or
/// (H, W, C) with C names (R, G, B for normals), read straight from NumPy; the file is
/// written with the GIL released.
#[pyfunction]
pub fn write_exr_f32(
    py: Python<'_>,
    path: PathBuf,
    names: Vec<String>,
    array: PyReadonlyArrayDyn<'_, f32>,
) -> PyResult<()> {
    let view = array.as_array();
    let (height, width, channels) = match *view.shape() {
        [h, w] => (h, w, 1),
        [h, w, c] => (h, w, c),
        ref other => {
            return Err(PyValueError::new_err(format!(
                "the image has shape {other:?}, expected (H, W) or (H, W, C)"
            )))
        }
    };
    check(&names, channels)?;
    let samples: Vec<Vec<f32>> = if view.ndim() == 2 {
        vec![view.iter().copied().collect()]
    } else {
        (0..channels)
            .map(|c| view.index_axis(Axis(2), c).iter().copied().collect())
            .collect()
    };
    let channels = names
        .iter()
        .zip(samples)
        .map(|(name, samples)| AnyChannel::new(name.as_str(), FlatSamples::F32(samples)))
        .collect();
    py.allow_threads(|| no_panic(|| write_exr(&path, width, height, channels)))
}

/// Writes a uint32 (H, W) image as the EXR channel `name`, read straight from NumPy.
#[pyfunction]
pub fn write_exr_u32(
    py: Python<'_>,
    path: PathBuf,
    name: String,
    array: PyReadonlyArray2<'_, u32>,
) -> PyResult<()> {
    let view = array.as_array();
    let (height, width) = view.dim();
    let samples = FlatSamples::U32(view.iter().copied().collect());
    let channels = vec![AnyChannel::new(name.as_str(), samples)];
    py.allow_threads(|| no_panic(|| write_exr(&path, width, height, channels)))
}

/// Writes `channels` of a `width x height` image, lossless, as the command-line tool does.
fn write_exr(
    path: &Path,
    width: usize,
    height: usize,
    channels: Vec<AnyChannel<FlatSamples>>,
) -> PyResult<()> {
    if width == 0 || height == 0 {
        return Err(PyValueError::new_err(format!(
            "the image is {width} x {height}: nothing to write"
        )));
    }
    let layer = Layer::new(
        (width, height),
        LayerAttributes::named("ellipsoid-splat"),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(SmallVec::from_vec(channels)),
    );
    Image::from_layer(layer)
        .write()
        .to_file(path)
        .map_err(|e| PyOSError::new_err(format!("{}: {e}", path.display())))
}

fn check(names: &[String], channels: usize) -> PyResult<()> {
    if names.len() == channels {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "{} channel names for an image of {channels} channels",
            names.len()
        )))
    }
}
