//! numpy <-> Rust conversions with argument checking.

use crate::errors::argument_error;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyAnyMethods, PyDict};

/// A float64 1-D argument of `expected` entries, all finite, copied out of Python.
///
/// Fast path for float64 arrays; anything else goes through `numpy.asarray(x)` and is accepted
/// when numpy converts it to float64 (`numpy.asarray(x, dtype=float64)`: booleans, integers,
/// floats, object arrays of real numbers). Complex values are refused (numpy would drop their
/// imaginary part), and so is anything numpy cannot convert (an object array holding a complex
/// number or a non-number).
pub fn vector_arg(
    value: &Bound<'_, PyAny>,
    name: &str,
    expected: usize,
    out: &mut Vec<f64>,
) -> PyResult<()> {
    let owned;
    let array = match value.cast::<PyArrayDyn<f64>>() {
        Ok(array) => array,
        Err(_) => {
            owned = as_float64_array(value, name)?;
            &owned
        }
    };
    let shape = array.shape();
    if shape.len() != 1 || shape[0] != expected {
        return Err(argument_error(
            name,
            &format!("shape ({expected},)"),
            format!("shape {shape:?}"),
        ));
    }
    let readonly = array.readonly();
    out.clear();
    match readonly.as_slice() {
        Ok(slice) => out.extend_from_slice(slice),
        Err(_) => out.extend(readonly.as_array().iter().copied()),
    }
    if let Some(i) = out.iter().position(|v| !v.is_finite()) {
        return Err(argument_error(
            &format!("{name}[{i}]"),
            "a finite number",
            out[i],
        ));
    }
    Ok(())
}

/// `value` as a float64 numpy array by numpy's rules (see [`vector_arg`]); complex dtypes and
/// values numpy cannot convert are refused, naming the argument `name`.
fn as_float64_array<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let numpy = value.py().import("numpy")?;
    let raw = numpy
        .call_method1("asarray", (value,))
        .map_err(|e| argument_error(name, "an array of floats", e))?;
    // numpy converts complex to float by dropping the imaginary part (a warning only).
    let dtype = raw.getattr("dtype")?;
    let (kind, dtype): (String, String) =
        (dtype.getattr("kind")?.extract()?, dtype.str()?.extract()?);
    if kind == "c" {
        return Err(argument_error(
            name,
            "an array of real numbers",
            format!("dtype {dtype}"),
        ));
    }
    let converted = numpy
        .call_method1("asarray", (&raw, "float64"))
        .map_err(|e| {
            argument_error(
                name,
                "an array of real numbers",
                format!("dtype {dtype} ({e})"),
            )
        })?;
    converted
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| argument_error(name, "an array of floats", value))
}

/// `names` as Python shows a list of str, `['l_sole', 'r_sole']` (for a `__repr__`).
pub fn python_list(names: &[String]) -> String {
    let quoted: Vec<String> = names
        .iter()
        .map(|n| format!("{n:?}").replace('"', "'"))
        .collect();
    format!("[{}]", quoted.join(", "))
}

/// A 1-D numpy array copied from a slice.
pub fn vector_out<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, values)
}

/// A C-ordered 2-D numpy array copied from a column-major matrix (any view).
pub fn matrix_out<'py, R, C, S>(
    py: Python<'py>,
    m: &nalgebra::Matrix<f64, R, C, S>,
) -> Bound<'py, PyArray2<f64>>
where
    R: nalgebra::Dim,
    C: nalgebra::Dim,
    S: nalgebra::RawStorage<f64, R, C>,
{
    Array2::from_shape_fn((m.nrows(), m.ncols()), |(i, j)| m[(i, j)]).into_pyarray(py)
}

/// A C-ordered (rows x columns) array from row-major data; `columns = 0` gives shape (rows, 0)
/// with rows taken as 0.
pub fn matrix_rows_out<'py>(
    py: Python<'py>,
    row_major: &[f64],
    columns: usize,
) -> Bound<'py, PyArray2<f64>> {
    let rows = row_major.len().checked_div(columns).unwrap_or(0);
    Array2::from_shape_vec((rows, columns), row_major.to_vec())
        .expect("row-major data matches its shape")
        .into_pyarray(py)
}

/// A C-ordered (rows x columns) array from row-major data that keeps its shape when a
/// dimension is empty (all joints rigid: motor arrays of shape (samples, 0)).
pub fn table_out<'py>(
    py: Python<'py>,
    row_major: &[f64],
    rows: usize,
    columns: usize,
) -> Bound<'py, PyArray2<f64>> {
    Array2::from_shape_vec((rows, columns), row_major.to_vec())
        .expect("row-major data matches its shape")
        .into_pyarray(py)
}

/// An instance of the dataclass `sea_momentum.results.<name>` built from `fields` (keyword
/// arguments): the typed results are defined once, in Python, and filled here with numbers and
/// arrays (no serialised text crosses the boundary).
pub fn result_object<'py>(
    py: Python<'py>,
    name: &str,
    fields: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    py.import("sea_momentum.results")?
        .getattr(name)?
        .call((), Some(fields))
}
