//! Scene files to arrays, through the loaders the command-line tool uses (CSV, PLY, NIfTI,
//! PDB/mmCIF), with their notes and colour modes.

use std::path::PathBuf;

use ellipsoid_splat_loaders::{load as load_file, ColorMode, LoadOptions, TensorOrder};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{loader_error, no_panic};

/// Loads `path` with the tool's loading options; returns a dict of `centers` (N, 3),
/// `radii` (N, 3), `rotations` (N, 4: w, x, y, z), `colors` (N, 3) float64 arrays, `notes`
/// (the loader's sentences) and `skipped` (records left out).
#[pyfunction]
#[pyo3(signature = (path, skip_invalid=false, sigma=2.0, min_opacity=0.0, tensor_order="fsl", min_fa=0.0, mask=None, glyph_scale=0.5, color="file"))]
#[allow(clippy::too_many_arguments)]
pub fn load<'py>(
    py: Python<'py>,
    path: PathBuf,
    skip_invalid: bool,
    sigma: f64,
    min_opacity: f64,
    tensor_order: &str,
    min_fa: f64,
    mask: Option<PathBuf>,
    glyph_scale: f64,
    color: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let tensor_order = match tensor_order {
        "fsl" => TensorOrder::Fsl,
        "nifti" => TensorOrder::Nifti,
        other => {
            return Err(PyValueError::new_err(format!(
                "tensor_order must be 'fsl' or 'nifti', got {other:?}"
            )))
        }
    };
    let options = LoadOptions {
        skip_invalid,
        sigma,
        min_opacity,
        tensor_order,
        min_fa,
        mask,
        glyph_scale,
        ..LoadOptions::default()
    };
    let mode = ColorMode::ALL
        .into_iter()
        .find(|m| m.name() == color)
        .ok_or_else(|| {
            let names: Vec<&str> = ColorMode::ALL.iter().map(|m| m.name()).collect();
            PyValueError::new_err(format!("color must be one of {names:?}, got {color:?}"))
        })?;
    let loaded =
        py.allow_threads(|| no_panic(|| load_file(&path, &options).map_err(loader_error)))?;
    let mut scene = loaded.scene;
    mode.apply(&mut scene.ellipsoids);
    let n = scene.len();
    let column = |f: &dyn Fn(&ellipsoid_splat::Ellipsoid) -> Vec<f64>, cols: usize| {
        let flat: Vec<f64> = scene.ellipsoids.iter().flat_map(f).collect();
        Array2::from_shape_vec((n, cols), flat).map_err(|e| PyValueError::new_err(e.to_string()))
    };
    let dict = PyDict::new(py);
    dict.set_item(
        "centers",
        column(&|e| e.center.to_array().to_vec(), 3)?.into_pyarray(py),
    )?;
    dict.set_item(
        "radii",
        column(&|e| e.radii.to_array().to_vec(), 3)?.into_pyarray(py),
    )?;
    dict.set_item(
        "rotations",
        column(
            &|e| vec![e.rotation.w, e.rotation.x, e.rotation.y, e.rotation.z],
            4,
        )?
        .into_pyarray(py),
    )?;
    dict.set_item(
        "colors",
        column(&|e| e.color.iter().map(|&c| c as f64).collect(), 3)?.into_pyarray(py),
    )?;
    dict.set_item("notes", loaded.notes)?;
    dict.set_item("skipped", loaded.skipped)?;
    Ok(dict)
}
