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

use pyo3::exceptions::{PyOverflowError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyComplex};

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
/// expected.
fn not_bool_nor_complex(value: &Bound<'_, PyAny>, what: &str) -> PyResult<()> {
    // numpy's bool (`numpy.bool` in numpy 2, `numpy.bool_` before) is no Python bool, and its
    // complex scalars convert to float by dropping the imaginary part (a warning only).
    let type_name = value.get_type().name()?.to_string();
    let kind = if value.is_instance_of::<PyBool>() || type_name == "bool" || type_name == "bool_" {
        "the bool"
    } else if value.is_instance_of::<PyComplex>() || type_name.starts_with("complex") {
        "the complex number"
    } else {
        return Ok(());
    };
    let shown = value.repr()?;
    Err(PyTypeError::new_err(format!(
        "expected {what}, got {kind} {shown}"
    )))
}

/// The `TypeError` naming the range of `what` for an `int` beyond it (`error`, the conversion's
/// `OverflowError`, is its cause); the int is shown by its size (its digits could be more than
/// Python converts to text).
fn beyond_range(value: &Bound<'_, PyAny>, what: &str, error: PyErr) -> PyResult<PyErr> {
    let bits: u64 = value.call_method0("bit_length")?.extract()?;
    let sign = if value.lt(0)? { "a negative" } else { "an" };
    let message = format!("expected {what}, got {sign} int of {bits} bits, beyond its range");
    let type_error = PyTypeError::new_err(message);
    type_error.set_cause(value.py(), Some(error));
    Ok(type_error)
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
