//! `run_scenario`: a closed-loop scenario run natively (GIL released), results as numpy arrays.

use crate::arrays::{matrix_rows_out, vector_out};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;
use std::path::PathBuf;

/// Maps a `sea_ctrl` error to Python: configuration and model problems are `ValueError`
/// (`ModelError` for the URDF), file problems `OSError`.
fn to_py(error: sea_sim::Error) -> PyErr {
    match error {
        sea_sim::Error::Dynamics(e) => crate::errors::to_py(e),
        sea_sim::Error::Control(sea_ctrl::Error::Dynamics(e)) => crate::errors::to_py(e),
        sea_sim::Error::Io { .. } => PyOSError::new_err(error.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// A Python value as a TOML literal: str, bool, int, float (numpy scalars too), lists of those.
fn toml_literal(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if let Ok(text) = value.extract::<String>() {
        return Ok(toml::Value::String(text).to_string());
    }
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Ok(value.extract::<bool>()?.to_string());
    }
    if value.is_instance_of::<pyo3::types::PyInt>() {
        return Ok(value.extract::<i64>()?.to_string());
    }
    if let Ok(number) = value.extract::<f64>() {
        return Ok(toml::Value::Float(number).to_string());
    }
    if let Ok(items) = value.try_iter() {
        let parts = items
            .map(|item| toml_literal(&item?))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(format!("[{}]", parts.join(", ")));
    }
    Err(PyValueError::new_err(format!(
        "cannot use {} as a scenario value",
        value.repr()?
    )))
}

/// Runs the scenario file `path` with `overrides` ({"controller.kind": "rigid", ...}; values
/// are TOML literals or bare strings), optionally writing an MCAP log. Returns a dict of arrays
/// (time, x, thetadot_desired, com, com_reference, momentum, contact_wrenches, motor_torques,
/// joint_error_norm, qp_solved), the layout (nq, nv, ne), names, and the summary as JSON text.
#[pyfunction]
#[pyo3(signature = (path, overrides=None, mcap=None, progress=false))]
pub fn run_scenario_native<'py>(
    py: Python<'py>,
    path: PathBuf,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    mcap: Option<PathBuf>,
    progress: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let mut pairs = Vec::new();
    for (key, value) in overrides.unwrap_or_default() {
        let text = toml_literal(&value)
            .map_err(|e| PyValueError::new_err(format!("override '{key}': {e}")))?;
        pairs.push((key, text));
    }
    let scenario = sea_sim::scenario::Scenario::from_file(&path, &pairs).map_err(to_py)?;
    let (record, summary) = py
        .detach(|| {
            sea_sim::closed_loop::run(&scenario, mcap.as_deref(), |t, total| {
                if progress {
                    eprintln!("  {}: t = {t:5.2} / {total:.2} s", scenario.name);
                }
            })
        })
        .map_err(to_py)?;
    let (nq, nv, ne) = record.layout;
    let nx = nq + nv + 2 * ne;
    let dict = PyDict::new(py);
    let rows = record.time.len();
    let n_contacts = scenario.robot.contacts.len();
    dict.set_item("time", vector_out(py, &record.time))?;
    dict.set_item("x", matrix_rows_out(py, &record.state, nx))?;
    dict.set_item(
        "thetadot_desired",
        matrix_rows_out(py, &record.thetadot_desired, ne),
    )?;
    dict.set_item("com", matrix_rows_out(py, &record.com, 3))?;
    dict.set_item(
        "com_reference",
        matrix_rows_out(py, &record.com_reference, 3),
    )?;
    dict.set_item("momentum", matrix_rows_out(py, &record.momentum, 6))?;
    let wrenches = matrix_rows_out(py, &record.contact_wrenches, 6 * n_contacts);
    dict.set_item(
        "contact_wrenches",
        wrenches.call_method1("reshape", ((rows, n_contacts, 6),))?,
    )?;
    dict.set_item(
        "motor_torques",
        matrix_rows_out(py, &record.motor_torques, ne),
    )?;
    dict.set_item("joint_error_norm", vector_out(py, &record.joint_error_norm))?;
    dict.set_item("qp_solved", vector_out(py, &record.qp_solved))?;
    dict.set_item("nq", nq)?;
    dict.set_item("nv", nv)?;
    dict.set_item("ne", ne)?;
    dict.set_item("joint_names", record.joint_names.clone())?;
    dict.set_item("elastic_joints", record.elastic_joints.clone())?;
    dict.set_item("contacts", scenario.robot.contacts.clone())?;
    dict.set_item("summary_json", summary.to_json().to_string())?;
    Ok(dict)
}
