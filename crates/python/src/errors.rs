//! The library's and the loaders' errors as Python exceptions.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

pyo3::create_exception!(
    _native,
    DeviceError,
    PyRuntimeError,
    "The Vulkan device failed or lacks what the renderer needs."
);

/// `ValueError` for invalid values, `DeviceError` for everything the device did.
pub fn renderer_error(error: ellipsoid_splat::Error) -> PyErr {
    match error {
        ellipsoid_splat::Error::Invalid { .. } => PyValueError::new_err(error.to_string()),
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
