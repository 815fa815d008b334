//! Python numbers as the bindings' scalar arguments: [`Real`] for a float argument and
//! [`Integer`] for an integer argument.
//!
//! PyO3's own `f64` and `i64` extractions take `True` for 1 (`bool` is an `int` subclass in
//! Python), take numpy's complex scalars by dropping their imaginary part, and raise an
//! `OverflowError` that names no argument for an `int` beyond their range. These raise a
//! `TypeError` for all three, which PyO3 prefixes with `argument 'name': `.
//!
//! A default such as `Real(0.1)` is no literal to PyO3, which then shows it as `...`: the
//! functions with one write their `text_signature` out (`test_stub.py` compares it with the
//! stub).

use crate::errors::argument_error;
use pyo3::exceptions::{PyOverflowError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyComplex, PyFloat, PyInt};

/// A real-number argument: a Python `float` or `int`, a numpy floating or integer scalar, a
/// 0-d array or anything with `__float__`; not a bool (Python's or numpy's) nor a complex
/// number, nor an `int` beyond the float range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Real(pub f64);

/// An integer argument: a Python `int` or anything with `__index__` (numpy integers), not a
/// bool nor an `int` beyond the 64-bit range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Integer(pub i64);

/// The `TypeError` for a bool or a complex number given where `what` ("a real number") is
/// expected: Python's, numpy's scalars (numpy's complex scalars convert to float by dropping
/// the imaginary part, with a warning only) and 0-d arrays of those (by their dtype's kind).
fn not_bool_nor_complex(value: &Bound<'_, PyAny>, what: &str) -> PyResult<()> {
    // The common case at once (a tick's `t` in a Python loop): a float or an int, not a bool.
    if value.is_exact_instance_of::<PyFloat>() || value.is_exact_instance_of::<PyInt>() {
        return Ok(());
    }
    // numpy's dtype kind; another library's dtype (torch's) has none, and is left to `__float__`.
    let dtype_kind = value
        .getattr("dtype")
        .and_then(|dtype| dtype.getattr("kind"))
        .and_then(|kind| kind.extract::<String>())
        .unwrap_or_default();
    let kind = if value.is_instance_of::<PyBool>() || dtype_kind == "b" {
        "the bool"
    } else if value.is_instance_of::<PyComplex>() || dtype_kind == "c" {
        "the complex number"
    } else {
        return Ok(());
    };
    let shown = value.repr()?;
    Err(PyTypeError::new_err(format!(
        "expected {what}, got {kind} {shown}"
    )))
}

/// The `TypeError` naming the range of `what` for an integer beyond it (`error`, the
/// conversion's `OverflowError`, is its cause); the integer is shown by its size (its digits
/// could be more than Python converts to text), when it has one (`operator.index`).
fn beyond_range(value: &Bound<'_, PyAny>, what: &str, error: PyErr) -> PyResult<PyErr> {
    let py = value.py();
    let index = py.import("operator")?.call_method1("index", (value,));
    let size = index.and_then(|integer| {
        let bits: u64 = integer.call_method0("bit_length")?.extract()?;
        let sign = if integer.lt(0)? { "a negative" } else { "an" };
        Ok(format!("{sign} int of {bits} bits"))
    });
    let given = match size {
        Ok(size) => size,
        Err(_) => format!("a {}", value.get_type().name()?),
    };
    let message = format!("expected {what}, got {given}, beyond its range");
    let type_error = PyTypeError::new_err(message);
    type_error.set_cause(py, Some(error));
    Ok(type_error)
}

/// A whole-number argument `value` from `min` to `usize::MAX`, named `argument` in the
/// `ValueError` when it is an integer out of that range (of any size) and in the `TypeError`
/// when it is no integer (a bool, a float).
pub(crate) fn count_arg(argument: &str, value: &Bound<'_, PyAny>, min: usize) -> PyResult<usize> {
    let py = value.py();
    let named = |error: PyErr| {
        let message = format!("argument '{argument}': {}", error.value(py));
        PyTypeError::new_err(message)
    };
    let out_of_range = || {
        let expected = format!("an integer from {min} to {}", usize::MAX);
        argument_error(argument, &expected, value)
    };
    not_bool_nor_complex(value, "an integer").map_err(named)?;
    match value.extract::<usize>() {
        Ok(count) if count >= min => Ok(count),
        Ok(_) => Err(out_of_range()),
        Err(error) if error.is_instance_of::<PyOverflowError>(py) => Err(out_of_range()),
        Err(error) if error.is_instance_of::<PyTypeError>(py) => Err(named(error)),
        Err(error) => Err(error),
    }
}

/// `value` as a `T` (`f64` or `i64`), `what` it must be ("a real number"), refused as the
/// module doc says; `range` names `T`'s range in the error of an `int` beyond it.
fn number<'py, T>(value: Borrowed<'_, 'py, PyAny>, what: &str, range: &str) -> PyResult<T>
where
    T: for<'a> FromPyObject<'a, 'py, Error = PyErr>,
{
    let value = value.to_owned();
    not_bool_nor_complex(&value, what)?;
    match value.extract::<T>() {
        Err(error) if error.is_instance_of::<PyOverflowError>(value.py()) => {
            Err(beyond_range(&value, &format!("{what} ({range})"), error)?)
        }
        extracted => extracted,
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Real {
    type Error = PyErr;

    fn extract(value: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        number(value, "a real number", "a float").map(Real)
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for Integer {
    type Error = PyErr;

    fn extract(value: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        number(value, "an integer", "64 bits").map(Integer)
    }
}

/// `Option<Real>` as `Option<f64>`.
pub fn real_or_none(value: Option<Real>) -> Option<f64> {
    value.map(|Real(number)| number)
}
