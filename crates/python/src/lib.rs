//! The native half of the Python package `ellipsoid_splat` (`python/ellipsoid_splat/`): a thin
//! layer over the library's offscreen renderer and the loaders. The Python half normalises
//! and checks arguments (names, shapes, dtypes); this half builds the glyphs and cameras,
//! renders with the GIL released and returns NumPy arrays. Errors become Python exceptions:
//! `ValueError` for invalid values, `OSError` for files, `DeviceError` (a `RuntimeError`) for
//! the device (`DeviceLostError` and `OutOfMemoryError`, two of those, for a lost device and
//! memory running out; `PoisonedError` for a renderer an earlier call left broken),
//! `OtherRankError` (a `RuntimeError`) for another MPI process's failure (feature `mpi`). No
//! Rust panic reaches Python: each entry point catches them as `DeviceError`.
//!
//! # Files
//!
//! | what | where |
//! |---|---|
//! | the Python package (`docs/python.md`): argument checks, `Frame`, `Renderer` | `python/ellipsoid_splat/`; the native module `src/` (in situ over MPI: `composited.rs`, feature `mpi`); pytest in `tests/`; `examples/rust_frame.rs` (the Rust API's frame the tests compare with), `insitu_mpi.py` (in situ, mpi4py); `bench_overhead.py` |

mod camera;
#[cfg(feature = "mpi")]
mod composited;
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
    m.add_function(wrap_pyfunction!(load::load_frames, m)?)?;
    m.add_class::<load::Frames>()?;
    m.add(
        "TYPE_PALETTE",
        ellipsoid_splat_loaders::TYPE_PALETTE
            .map(|c| c.map(f64::from))
            .to_vec(),
    )?;
    m.add_function(wrap_pyfunction!(images::encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_exr_f32, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_exr_u32, m)?)?;
    m.add("DeviceError", m.py().get_type::<errors::DeviceError>())?;
    m.add("PoisonedError", m.py().get_type::<errors::PoisonedError>())?;
    m.add(
        "DeviceLostError",
        m.py().get_type::<errors::DeviceLostError>(),
    )?;
    m.add(
        "OutOfMemoryError",
        m.py().get_type::<errors::OutOfMemoryError>(),
    )?;
    m.add(
        "OtherRankError",
        m.py().get_type::<errors::OtherRankError>(),
    )?;
    #[cfg(feature = "mpi")]
    {
        m.add_function(wrap_pyfunction!(composited::render_composited, m)?)?;
        m.add_function(wrap_pyfunction!(composited::composite_failed, m)?)?;
    }
    Ok(())
}
