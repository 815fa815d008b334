//! The one mapping from `sea_dyn::Error` to Python exceptions.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::PyErr;

create_exception!(
    sea_momentum,
    ModelError,
    PyValueError,
    "A robot description problem; the message names the URDF element and the condition."
);

/// Converts a core error into the matching Python exception.
pub fn to_py(error: sea_dyn::Error) -> PyErr {
    match error {
        sea_dyn::Error::Model(message) => ModelError::new_err(message),
        sea_dyn::Error::Input(message) => PyValueError::new_err(message),
        unknown @ sea_dyn::Error::UnknownFrame(_) => PyValueError::new_err(unknown.to_string()),
    }
}
