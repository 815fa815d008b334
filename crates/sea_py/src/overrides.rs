//! Python values as scenario overrides: `{key: value}` dicts and values as the `key=value`
//! pairs of TOML literals that a scenario file's `--set` takes, checked by the scenario schema.

use crate::errors::argument_error;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFrozenSet, PySet};
use std::collections::HashMap;

/// `overrides` ({key: value}) as `key=value` pairs of TOML literals.
pub(crate) fn override_pairs(
    overrides: Option<HashMap<String, Bound<'_, PyAny>>>,
) -> PyResult<Vec<(String, String)>> {
    let mut pairs = Vec::new();
    for (key, value) in overrides.unwrap_or_default() {
        let text = toml_literal(&value, &key)?;
        pairs.push((key, text));
    }
    pairs.sort();
    Ok(pairs)
}

/// A Python value as a TOML literal: str, bool, int, float (numpy scalars too: `numpy.bool_`
/// is a bool, numpy integers are integers), lists, tuples and numpy arrays of those; `key`
/// names the override in
/// errors, including an integer outside the 64-bit range.
pub(crate) fn toml_literal(value: &Bound<'_, PyAny>, key: &str) -> PyResult<String> {
    // A numpy array is its list, and a 0-d array (or a numpy scalar) its Python number: numpy
    // gives a 0-d float array an `__index__` that refuses it, so it must not reach the
    // integers' test below as itself.
    // Only numpy's own types: another type's `tolist` could return itself again and again.
    let module = value.get_type().getattr("__module__")?;
    if module.extract::<String>().is_ok_and(|m| m == "numpy") && value.hasattr("tolist")? {
        return toml_literal(&value.call_method0("tolist")?, key);
    }
    if let Ok(text) = value.extract::<String>() {
        return Ok(toml::Value::String(text).to_string());
    }
    // Python bools and numpy.bool_ (before the integers: bool is an int subclass).
    if let Ok(flag) = value.extract::<bool>() {
        return Ok(flag.to_string());
    }
    // Python ints and anything with __index__ (numpy integers), before the floats.
    if value.is_instance_of::<pyo3::types::PyInt>() || value.hasattr("__index__")? {
        let index = value
            .py()
            .import("operator")?
            .call_method1("index", (value,));
        return match index.and_then(|i| i.extract::<i64>()) {
            Ok(integer) => Ok(integer.to_string()),
            Err(_) => Err(argument_error(
                &format!("overrides['{key}']"),
                "an integer within the 64-bit range",
                value.repr()?,
            )),
        };
    }
    if let Ok(number) = value.extract::<f64>() {
        return Ok(toml::Value::Float(number).to_string());
    }
    // A dict is an inline table (e.g. one `[[disturbances]]` entry).
    if let Ok(table) = value.cast::<PyDict>() {
        let parts = table
            .iter()
            .map(|(name, item)| {
                let name = toml::Value::String(name.str()?.to_string()).to_string();
                Ok(format!("{name} = {}", toml_literal(&item, key)?))
            })
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(format!("{{{}}}", parts.join(", ")));
    }
    // A set has no order, and an array's order matters (`robot.contacts`: left, right).
    if value.is_instance_of::<PySet>() || value.is_instance_of::<PyFrozenSet>() {
        return Err(argument_error(
            &format!("overrides['{key}']"),
            "a list or tuple (a set has no order)",
            value.repr()?,
        ));
    }
    if let Ok(items) = value.try_iter() {
        let parts = items
            .map(|item| toml_literal(&item?, key))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(format!("[{}]", parts.join(", ")));
    }
    Err(argument_error(
        &format!("overrides['{key}']"),
        "str, bool, int, float or a list of those",
        value.repr()?,
    ))
}
