//! Pictures as files and bytes, written as the command-line tool writes them: sRGB colour
//! PNG, float32 EXR channels (lossless), 32-bit IDs as EXR or packed into PNG.

use std::path::{Path, PathBuf};

use exr::block::chunk::Chunk;
use exr::block::writer::ChunksWriter;
use exr::block::{BlockIndex, UncompressedBlock};
use exr::meta::attribute::{ChannelDescription, SampleType};
use exr::meta::header::Header;
use exr::prelude::SmallVec;
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
            return Err(PyValueError::new_err(format!(
                "the image is too large: {shape:?}"
            )));
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
/// (H, W, C) with C names (R, G, B for normals), copied straight out of NumPy's buffer; the
/// file is compressed and written with the GIL released.
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
    // Row-major (H, W, C); one copy, a memcpy for a C-contiguous array.
    let values: Vec<f32> = match view.as_slice() {
        Some(slice) => slice.to_vec(),
        None => view.iter().copied().collect(),
    };
    let image = Samples {
        width,
        height,
        names,
        sample_type: SampleType::F32,
        values,
    };
    py.allow_threads(|| no_panic(|| image.write(&path)))
}

/// Writes a uint32 (H, W) image as the EXR channel `name`, copied straight out of NumPy.
#[pyfunction]
pub fn write_exr_u32(
    py: Python<'_>,
    path: PathBuf,
    name: String,
    array: PyReadonlyArray2<'_, u32>,
) -> PyResult<()> {
    let view = array.as_array();
    let (height, width) = view.dim();
    let values: Vec<u32> = match view.as_slice() {
        Some(slice) => slice.to_vec(),
        None => view.iter().copied().collect(),
    };
    let image = Samples {
        width,
        height,
        names: vec![name],
        sample_type: SampleType::U32,
        values,
    };
    py.allow_threads(|| no_panic(|| image.write(&path)))
}

/// A row-major (height, width, channels) image of 32-bit samples.
struct Samples<T> {
    width: usize,
    height: usize,
    /// One per channel, in the samples' order.
    names: Vec<String>,
    sample_type: SampleType,
    /// The samples, `names.len()` per pixel.
    values: Vec<T>,
}

/// A 32-bit sample (float32 or uint32) as the file stores it.
trait Sample: Copy + Sync {
    fn ne_bytes(self) -> [u8; 4];
}

impl Sample for f32 {
    fn ne_bytes(self) -> [u8; 4] {
        self.to_ne_bytes()
    }
}

impl Sample for u32 {
    fn ne_bytes(self) -> [u8; 4] {
        self.to_ne_bytes()
    }
}

impl<T: Sample> Samples<T> {
    /// Writes the image as an EXR file with the `exr` crate's block writer, encoded as the
    /// command-line tool encodes it (lossless: RLE in 64 x 64 tiles; `Header::new`'s
    /// encoding, the crate's `Encoding::FAST_LOSSLESS`). Each tile's bytes are gathered
    /// from the samples directly, not sample by sample through the crate's image model, and
    /// compressed by the crate, a share of the tiles on each core; the chunks are then
    /// written in order.
    fn write(&self, path: &Path) -> PyResult<()> {
        let (width, height, count) = (self.width, self.height, self.names.len());
        if width == 0 || height == 0 {
            return Err(PyValueError::new_err(format!(
                "the image is {width} x {height}: nothing to write"
            )));
        }
        if self.values.len() != width * height * count {
            return Err(PyValueError::new_err(format!(
                "{} samples for a {width} x {height} image of {count} channels",
                self.values.len()
            )));
        }
        // EXR lists channels by name, and stores each line's samples channel by channel in
        // that order.
        let mut order: Vec<usize> = (0..count).collect();
        order.sort_by(|&a, &b| self.names[a].cmp(&self.names[b]));
        let channels = order
            .iter()
            .map(|&c| ChannelDescription::named(self.names[c].as_str(), self.sample_type))
            .collect();
        let header = Header::new("ellipsoid-splat".into(), (width, height), channels);
        let headers: exr::meta::Headers = SmallVec::from_vec(vec![header]);
        let blocks: Vec<(usize, BlockIndex)> =
            exr::block::enumerate_ordered_header_block_indices(&headers).collect();
        // One tile's chunk: its lines, each channel's samples in turn, compressed by the crate.
        let chunk = |&(_, block): &(usize, BlockIndex)| {
            let (x0, y0) = (block.pixel_position.x(), block.pixel_position.y());
            let (w, h) = (block.pixel_size.x(), block.pixel_size.y());
            let mut data = vec![0u8; w * h * count * 4];
            let mut out = data.chunks_exact_mut(4);
            for y in y0..y0 + h {
                let row = &self.values[(y * width + x0) * count..(y * width + x0 + w) * count];
                for &c in &order {
                    // The row's samples first: `zip` takes from its first iterator first.
                    for (v, bytes) in row.iter().skip(c).step_by(count).zip(&mut out) {
                        bytes.copy_from_slice(&v.ne_bytes());
                    }
                }
            }
            UncompressedBlock { index: block, data }.compress_to_chunk(&headers)
        };
        // A share of the tiles for each core, in threads of their own (no queue per tile).
        let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
        let share = blocks.len().div_ceil(workers).max(1);
        let chunks: Vec<exr::error::Result<Chunk>> = std::thread::scope(|scope| {
            let parts: Vec<_> = blocks
                .chunks(share)
                .map(|part| scope.spawn(move || part.iter().map(chunk).collect::<Vec<_>>()))
                .collect();
            parts
                .into_iter()
                .flat_map(|part| part.join().unwrap_or_default())
                .collect()
        });
        if chunks.len() != blocks.len() {
            return Err(PyOSError::new_err(format!(
                "{}: a thread compressing the tiles failed",
                path.display()
            )));
        }
        // Whole or not at all: a failed write never leaves a broken file where a good one was.
        ellipsoid_splat_loaders::write_atomically(path, |file| {
            exr::block::write(file, headers.clone(), true, |_, writer| {
                for ((index, _), chunk) in blocks.iter().zip(chunks) {
                    writer.write_chunk(*index, chunk?)?;
                }
                Ok(())
            })
            .map_err(std::io::Error::other)
        })
        .map_err(|e| PyOSError::new_err(format!("{}: {e}", path.display())))
    }
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
