//! The library's and the loaders' errors as Python exceptions, and panics caught before they
//! reach Python.

use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::{PyErr, PyResult};

pyo3::create_exception!(
    _native,
    DeviceError,
    PyRuntimeError,
    "The Vulkan device failed or lacks what the renderer needs."
);

pyo3::create_exception!(
    _native,
    DeviceLostError,
    DeviceError,
    "The Vulkan device was lost (a GPU fault, reset or driver crash): every later call that \
     needs the GPU raises this too; make a new Renderer (docs/python.md, \"The rules of the package\")."
);

pyo3::create_exception!(
    _native,
    OutOfMemoryError,
    DeviceError,
    "GPU or host memory ran out while the renderer made what the message names. The call \
     changed nothing (a failed upload keeps the glyphs uploaded before): the renderer stays \
     usable (docs/python.md, \"The rules of the package\")."
);

pyo3::create_exception!(
    _native,
    PoisonedError,
    DeviceError,
    "An earlier call on this renderer failed inside the library part-way (it raised \
     DeviceError saying so): the renderer's state is unknown, so every later call raises this. \
     Create a new renderer."
);

pyo3::create_exception!(
    _native,
    OtherRankError,
    PyRuntimeError,
    "Another process of the communicator failed in Renderer.render_composited (its own error \
     is raised there; the message names its rank): nothing was composited."
);

/// `ValueError` for invalid values, `DeviceError` for everything the device did (a lost
/// device and memory running out as the subclasses naming them).
pub fn renderer_error(error: ellipsoid_splat::Error) -> PyErr {
    match error {
        ellipsoid_splat::Error::Invalid { .. } => PyValueError::new_err(error.to_string()),
        ellipsoid_splat::Error::DeviceLost { .. } => DeviceLostError::new_err(error.to_string()),
        ellipsoid_splat::Error::OutOfMemory { .. } => OutOfMemoryError::new_err(error.to_string()),
        other => DeviceError::new_err(other.to_string()),
    }
}

/// `OSError` for files that cannot be read, `ValueError` for their contents.
pub fn loader_error(error: ellipsoid_splat_loaders::Error) -> PyErr {
    match error {
        ellipsoid_splat_loaders::Error::Io { .. } => PyOSError::new_err(error.to_string()),
        ellipsoid_splat_loaders::Error::Renderer(inner) => renderer_error(inner),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// The error a later call on a renderer gets after a call panicked with its state locked.
pub fn poisoned() -> PyErr {
    PoisonedError::new_err(
        "an earlier call on this renderer failed inside the library: create a new renderer",
    )
}

/// Runs `work`; a panic in it becomes `DeviceError` with the panic's message (a bug of the
/// library or of this package, never a Python `PanicException`). Runs with or without the GIL.
pub fn no_panic<T>(work: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|panic| Err(panicked(panic.as_ref())))
}

fn panicked(panic: &(dyn Any + Send)) -> PyErr {
    let message = panic
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| panic.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("no message");
    DeviceError::new_err(format!(
        "the library failed unexpectedly (a bug; please report it): {message}"
    ))
}
