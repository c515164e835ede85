//! Scene files to arrays, through the loaders the command-line tool uses (CSV, PLY, NIfTI,
//! PDB/mmCIF, LAMMPS dumps, extended XYZ), with their notes and colour modes; a trajectory's
//! frames one at a time.

use std::path::PathBuf;

use ellipsoid_splat_loaders::{
    load as load_file, ColorMode, LoadOptions, Loaded, TensorOrder, Trajectory,
};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{loader_error, no_panic};

/// The options `load` and `load_frames` take, by name.
const OPTIONS: [&str; 11] = [
    "skip_invalid",
    "sigma",
    "min_opacity",
    "tensor_order",
    "min_fa",
    "mask",
    "glyph_scale",
    "color",
    "columns",
    "type_colors",
    "progress",
];

/// The loader options and colour mode of `options` (a dict of the names in [`OPTIONS`]);
/// `ValueError` naming an unknown option or a bad value.
fn parse_options(options: Option<&Bound<'_, PyDict>>) -> PyResult<(LoadOptions, ColorMode)> {
    let mut load = LoadOptions::default();
    let mut mode = ColorMode::File;
    let Some(options) = options else {
        return Ok((load, mode));
    };
    for (key, value) in options.iter() {
        let key: String = key.extract()?;
        let bad = |e: PyErr| PyValueError::new_err(format!("{key}: {e}"));
        match key.as_str() {
            "skip_invalid" => load.skip_invalid = value.extract().map_err(bad)?,
            "sigma" => load.sigma = value.extract().map_err(bad)?,
            "min_opacity" => load.min_opacity = value.extract().map_err(bad)?,
            "min_fa" => load.min_fa = value.extract().map_err(bad)?,
            "glyph_scale" => load.glyph_scale = value.extract().map_err(bad)?,
            "mask" => load.mask = value.extract::<Option<PathBuf>>().map_err(bad)?,
            "progress" => load.progress = value.extract().map_err(bad)?,
            "tensor_order" => {
                load.tensor_order = match value.extract::<String>().map_err(bad)?.as_str() {
                    "fsl" => TensorOrder::Fsl,
                    "nifti" => TensorOrder::Nifti,
                    other => {
                        return Err(PyValueError::new_err(format!(
                            "tensor_order must be 'fsl' or 'nifti', got {other:?}"
                        )))
                    }
                }
            }
            "color" => {
                let name: String = value.extract().map_err(bad)?;
                mode = ColorMode::ALL
                    .into_iter()
                    .find(|m| m.name() == name)
                    .ok_or_else(|| {
                        let names: Vec<&str> = ColorMode::ALL.iter().map(|m| m.name()).collect();
                        PyValueError::new_err(format!(
                            "color must be one of {names:?}, got {name:?}"
                        ))
                    })?;
            }
            "columns" => {
                // {standard name: the file's column}, as the tool's --columns.
                let map: std::collections::BTreeMap<String, String> =
                    value.extract().map_err(bad)?;
                load.columns = map.into_iter().collect();
            }
            // Checked (components in [0, 1]) by the loaders, as for the tool's flag.
            "type_colors" => load.type_colors = value.extract().map_err(bad)?,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown option {key:?}; the options are {}",
                    OPTIONS.join(", ")
                )))
            }
        }
    }
    Ok((load, mode))
}

/// The glyphs of `loaded`, coloured in `mode`, as a dict of `centers` (N, 3), `radii` (N, 3),
/// `rotations` (N, 4: w, x, y, z), `colors` (N, 3) float64 arrays, `notes` and `skipped`.
fn scene_dict<'py>(
    py: Python<'py>,
    loaded: Loaded,
    mode: ColorMode,
) -> PyResult<Bound<'py, PyDict>> {
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

/// Loads `path` (its first frame, for a trajectory) with the tool's loading options; see
/// [`scene_dict`] for what it returns.
#[pyfunction]
#[pyo3(signature = (path, options=None))]
pub fn load<'py>(
    py: Python<'py>,
    path: PathBuf,
    options: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (options, mode) = parse_options(options)?;
    let loaded =
        py.allow_threads(|| no_panic(|| load_file(&path, &options).map_err(loader_error)))?;
    scene_dict(py, loaded, mode)
}

/// A scene file's frames (one for most formats; every frame of a LAMMPS dump or extended
/// XYZ file), each parsed when asked for.
#[pyclass(frozen, module = "ellipsoid_splat._native")]
pub struct Frames {
    trajectory: Trajectory,
    mode: ColorMode,
}

#[pymethods]
impl Frames {
    fn __len__(&self) -> usize {
        self.trajectory.len()
    }

    /// Frame `index` (0-based) as `load` returns a scene, with its `timestep` (None where
    /// the file gives none).
    fn frame<'py>(&self, py: Python<'py>, index: usize) -> PyResult<Bound<'py, PyDict>> {
        if index >= self.trajectory.len() {
            return Err(PyIndexError::new_err(format!(
                "frame index {index} is out of range: the file has {} frames",
                self.trajectory.len()
            )));
        }
        let loaded =
            py.allow_threads(|| no_panic(|| self.trajectory.frame(index).map_err(loader_error)))?;
        let dict = scene_dict(py, loaded, self.mode)?;
        dict.set_item("timestep", self.trajectory.timestep(index))?;
        Ok(dict)
    }
}

/// Opens `path` for its frames, read once and parsed frame by frame.
#[pyfunction]
#[pyo3(signature = (path, options=None))]
pub fn load_frames(
    py: Python<'_>,
    path: PathBuf,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Frames> {
    let (options, mode) = parse_options(options)?;
    let trajectory =
        py.allow_threads(|| no_panic(|| Trajectory::open(&path, &options).map_err(loader_error)))?;
    Ok(Frames { trajectory, mode })
}
