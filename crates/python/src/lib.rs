//! The native half of the Python package `ellipsoid_splat` (`python/ellipsoid_splat/`): a thin
//! layer over the library's offscreen renderer and the loaders. The Python half normalises
//! and checks arguments (names, shapes, dtypes); this half builds the glyphs and cameras,
//! renders with the GIL released and returns NumPy arrays. Errors become Python exceptions:
//! `ValueError` for invalid values, `OSError` for files, `DeviceError` (a `RuntimeError`) for
//! the device; a panic becomes a `pyo3` `PanicException`, never an abort.

mod camera;
mod errors;
mod glyphs;
mod images;
mod load;
mod plan;
mod renderer;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<renderer::Renderer>()?;
    m.add_function(wrap_pyfunction!(load::load, m)?)?;
    m.add_function(wrap_pyfunction!(images::encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_exr, m)?)?;
    m.add("DeviceError", m.py().get_type::<errors::DeviceError>())?;
    Ok(())
}
