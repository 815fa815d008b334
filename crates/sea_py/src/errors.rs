//! The one mapping from Rust errors to Python exceptions, and the exception classes.
//!
//! Classes (defined here, registered in `sea_momentum._native`, re-exported by `sea_momentum`):
//!
//! | class                                  | raised for                                        |
//! |----------------------------------------|---------------------------------------------------|
//! | `SeaError(Exception)`                  | base of all below; also MCAP logging failures     |
//! | `ModelError(SeaError, ValueError)`     | unusable URDF (element, file), unparsable URDF    |
//! |                                        | (file), unknown frame name                        |
//! | `ScenarioError(SeaError, ValueError)`  | scenario key or controller setting (key, rule,    |
//! |                                        | value), malformed TOML (file, line)               |
//! | `SolverError(SeaError, RuntimeError)`  | numerical failure (operation): mass matrix not    |
//! |                                        | positive definite, degenerate contacts, ...       |
//! | `SeaIOError(SeaError, OSError)`        | reading or writing a file: `errno`, `strerror`,   |
//! |                                        | `filename` set as by `OSError(errno, strerror,    |
//! |                                        | filename)`                                        |
//! | `ValueError`                           | a bad argument (name, expected, actual)           |
//!
//! Instances carry the Rust fields as attributes: `ModelError.element` (and `filename`, `None`
//! when the description was not read from a file), `ScenarioError.key`,
//! `SolverError.operation`, `ValueError.argument` (when the Rust error has them). Every error of
//! the bindings goes through [`ToPyErr`] (Rust errors) or [`argument_error`] (checks done in the
//! bindings themselves), so a class or a message format changes in this file only.

use pyo3::exceptions::{PyException, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

/// The exception classes, created once per interpreter.
struct Classes {
    sea: Py<PyType>,
    model: Py<PyType>,
    scenario: Py<PyType>,
    solver: Py<PyType>,
    io: Py<PyType>,
}

static CLASSES: PyOnceLock<Classes> = PyOnceLock::new();

/// `class name(*bases): __doc__ = doc` in module `sea_momentum` (classes with two bases, such
/// as `ModelError(SeaError, ValueError)`, cannot be declared with `create_exception!`).
fn new_class(
    py: Python<'_>,
    name: &str,
    bases: &[Bound<'_, PyType>],
    doc: &str,
) -> PyResult<Py<PyType>> {
    let namespace = PyDict::new(py);
    namespace.set_item("__doc__", doc)?;
    namespace.set_item("__module__", "sea_momentum")?;
    let class = py
        .get_type::<PyType>()
        .call1((name, PyTuple::new(py, bases)?, namespace))?;
    Ok(class.cast_into::<PyType>()?.unbind())
}

fn create_classes(py: Python<'_>) -> PyResult<Classes> {
    let sea = new_class(
        py,
        "SeaError",
        &[py.get_type::<PyException>()],
        "Base of every sea_momentum error.",
    )?;
    let base = sea.bind(py).clone();
    let model = new_class(
        py,
        "ModelError",
        &[base.clone(), py.get_type::<PyValueError>()],
        "The robot description is unusable: names the URDF element (attribute `element`) and \
         its file (attribute `filename`), or the file and line of a parse failure.",
    )?;
    let scenario = new_class(
        py,
        "ScenarioError",
        &[base.clone(), py.get_type::<PyValueError>()],
        "A scenario value or controller setting breaks a rule: names the dotted key \
         (attribute `key`), the rule and the value, after the file and the key's line when \
         they are known; or a scenario file is malformed TOML (file and line).",
    )?;
    let solver = new_class(
        py,
        "SolverError",
        &[base.clone(), py.get_type::<PyRuntimeError>()],
        "A numerical failure on well-formed input (attribute `operation`), e.g. a mass matrix \
         that is not positive definite or degenerate contact constraints.",
    )?;
    let io = new_class(
        py,
        "SeaIOError",
        &[base, py.get_type::<PyOSError>()],
        "Reading or writing a file failed; `errno`, `strerror` and `filename` are set.",
    )?;
    Ok(Classes {
        sea,
        model,
        scenario,
        solver,
        io,
    })
}

fn classes(py: Python<'_>) -> &Classes {
    CLASSES.get_or_init(py, || {
        create_classes(py).expect("creating the sea_momentum exception classes")
    })
}

/// Adds the exception classes to the module.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    let c = classes(py);
    for (name, class) in [
        ("SeaError", &c.sea),
        ("ModelError", &c.model),
        ("ScenarioError", &c.scenario),
        ("SolverError", &c.solver),
        ("SeaIOError", &c.io),
    ] {
        module.add(name, class.bind(py))?;
    }
    Ok(())
}

/// Which class an error maps to.
#[derive(Clone, Copy)]
enum Kind {
    Sea,
    Model,
    Scenario,
    Solver,
    Value,
}

/// An exception of `kind` with `message` and the attribute `name = value` (if any).
fn raise(kind: Kind, message: String, attributes: &[(&str, Option<&str>)]) -> PyErr {
    Python::attach(|py| {
        let c = classes(py);
        let class = match kind {
            Kind::Sea => c.sea.bind(py).clone(),
            Kind::Model => c.model.bind(py).clone(),
            Kind::Scenario => c.scenario.bind(py).clone(),
            Kind::Solver => c.solver.bind(py).clone(),
            Kind::Value => py.get_type::<PyValueError>(),
        };
        let made = class.call1((message.clone(),)).and_then(|instance| {
            for &(name, value) in attributes {
                instance.setattr(name, value)?;
            }
            Ok(PyErr::from_value(instance))
        });
        made.unwrap_or_else(|e| e)
    })
}

/// The errno of `source`: the operating system's code, or for an error found by our own checks
/// (`is a folder`) the code of its kind, as Python's `errno` module gives it on this platform;
/// None for a kind without one.
fn errno_of(py: Python<'_>, source: &std::io::Error) -> Option<i32> {
    use std::io::ErrorKind as K;
    if let Some(code) = source.raw_os_error() {
        return Some(code);
    }
    let name = match source.kind() {
        K::NotFound => "ENOENT",
        K::PermissionDenied => "EACCES",
        K::AlreadyExists => "EEXIST",
        K::IsADirectory => "EISDIR",
        K::NotADirectory => "ENOTDIR",
        K::InvalidInput => "EINVAL",
        _ => return None,
    };
    let module = py.import("errno").ok()?;
    module.getattr(name).ok()?.extract().ok()
}

/// `SeaIOError(errno, strerror, filename)`: errno is None for an error without one.
fn io_error(path: &str, source: &std::io::Error) -> PyErr {
    let strerror = sea_dyn::error::io_message(source);
    Python::attach(|py| {
        let class = classes(py).io.bind(py).clone();
        match class.call1((errno_of(py, source), strerror, path)) {
            Ok(instance) => PyErr::from_value(instance),
            Err(e) => e,
        }
    })
}

/// A Rust error as its Python exception (one implementation per error type).
pub trait ToPyErr {
    /// The exception.
    fn to_py_err(self) -> PyErr;
}

impl ToPyErr for sea_dyn::Error {
    fn to_py_err(self) -> PyErr {
        use sea_dyn::Error as E;
        let message = self.to_string();
        match &self {
            E::Model { element, file, .. } => {
                let file = file.as_ref().map(|f| f.display().to_string());
                let attributes = [
                    ("element", Some(element.as_str())),
                    ("filename", file.as_deref()),
                ];
                raise(Kind::Model, message, &attributes)
            }
            E::Parse { .. } => raise(Kind::Model, message, &[]),
            E::UnknownFrame { name } => raise(Kind::Model, message, &[("element", Some(name))]),
            E::InvalidArgument { argument, .. } => {
                raise(Kind::Value, message, &[("argument", Some(argument))])
            }
            E::Io { path, source } => io_error(&path.display().to_string(), source),
            E::Numerical { operation, .. } => {
                raise(Kind::Solver, message, &[("operation", Some(operation))])
            }
            _ => raise(Kind::Sea, message, &[]),
        }
    }
}

impl ToPyErr for sea_ctrl::Error {
    fn to_py_err(self) -> PyErr {
        match self {
            sea_ctrl::Error::Dynamics(e) => e.to_py_err(),
            sea_ctrl::Error::Setting { ref key, .. } => {
                raise(Kind::Scenario, self.to_string(), &[("key", Some(key))])
            }
            other => raise(Kind::Sea, other.to_string(), &[]),
        }
    }
}

impl ToPyErr for sea_sim::Error {
    fn to_py_err(self) -> PyErr {
        use sea_sim::Error as E;
        match self {
            E::Dynamics(e) => e.to_py_err(),
            E::Control(e) => e.to_py_err(),
            E::Scenario { ref key, .. } => {
                raise(Kind::Scenario, self.to_string(), &[("key", Some(key))])
            }
            E::Parse { .. } => raise(Kind::Scenario, self.to_string(), &[]),
            E::Io { path, source } => io_error(&path, &source),
            other => raise(Kind::Sea, other.to_string(), &[]),
        }
    }
}

/// For `.map_err(to_py)`: any Rust error of the workspace as its Python exception.
pub fn to_py(error: impl ToPyErr) -> PyErr {
    error.to_py_err()
}

/// A bad argument found by the bindings themselves: `ValueError` with the message
/// `argument: expected ..., got ...` (the same as the Rust core's `InvalidArgument`).
pub fn argument_error(argument: &str, expected: &str, actual: impl ToString) -> PyErr {
    sea_dyn::Error::invalid(argument, expected, actual).to_py_err()
}

/// Issues `message` as a Python `UserWarning` (a NUL inside it is replaced).
pub fn warn_user(py: Python<'_>, message: &str) -> PyResult<()> {
    let message = std::ffi::CString::new(message.replace('\0', " "))
        .unwrap_or_else(|_| c"sea_momentum: a warning could not be written".to_owned());
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    PyErr::warn(py, &category, &message, 1)
}
