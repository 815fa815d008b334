//! `template_push_native`: pushes on a walk's template (`sea_study::analysis::template_walk`:
//! the controller's planner and momentum law on the linear inverted pendulum, the robot left
//! out) from Python, the GIL released. A template run takes milliseconds; nothing to stop.

use crate::errors::to_py;
use crate::numbers::count_arg;
use crate::numbers::Real;
use crate::overrides::override_pairs;
use crate::push::parse_directions;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sea_dyn::error::check_positive;
use sea_sim::analysis::push::{
    check_impulses, impulses_recovered_up_to, swing_push_start, SwingPhase,
};
use sea_sim::analysis::template_walk::{template_bisection, template_pushes};
use std::collections::HashMap;
use std::path::PathBuf;

/// Pushes of `duration_s` at fraction `phase` of the swing of step `step` (default 3) of the
/// walk of the scenario file `path`, on its template, along each of `directions`: bisected to
/// `tolerance_n_s`, or with `impulses` one run each. Returns a dict: `start_s` (the push's
/// start), `rows` (one dict per direction: `direction`, `recovered_impulse_n_s`, `pushes` (a
/// list of (impulse, recovered) in the order given; empty when bisected)).
#[pyfunction]
#[pyo3(
    text_signature = "(path, directions, phase, step=None, overrides=None, impulses=None, duration_s=0.1, tolerance_n_s=0.01)"
)]
#[pyo3(signature = (path, directions, phase, step=None, overrides=None, impulses=None, duration_s=Real(0.1), tolerance_n_s=Real(0.01)))]
#[allow(clippy::too_many_arguments)] // the Python signature, keyword arguments with defaults
pub fn template_push_native<'py>(
    py: Python<'py>,
    path: PathBuf,
    directions: Vec<String>,
    phase: Real,
    step: Option<&Bound<'py, PyAny>>,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    impulses: Option<Vec<Real>>,
    duration_s: Real,
    tolerance_n_s: Real,
) -> PyResult<Bound<'py, PyDict>> {
    let impulses = impulses.map(|list| list.into_iter().map(|Real(v)| v).collect::<Vec<f64>>());
    let (Real(phase), Real(duration_s), Real(tolerance_n_s)) = (phase, duration_s, tolerance_n_s);
    let pairs = override_pairs(overrides)?;
    let directions = parse_directions(&directions)?;
    let step = step.map(|step| count_arg("step", step, 0)).transpose()?;
    for (name, value) in [("duration_s", duration_s), ("tolerance_n_s", tolerance_n_s)] {
        check_positive(name, value).map_err(to_py)?;
    }
    if let Some(impulses) = &impulses {
        check_impulses(impulses).map_err(to_py)?;
    }
    let python_names = |e: sea_sim::Error| {
        let names = [
            ("--phase", "phase"),
            ("--step", "step"),
            ("window", "duration_s"),
        ];
        to_py(e.argument_named(&names))
    };
    let at = SwingPhase { step, phase };
    let (start_s, _) = swing_push_start(&path, &pairs, at).map_err(python_names)?;
    let window = (start_s, duration_s);
    let rows = PyList::empty(py);
    match impulses {
        Some(impulses) => {
            let table = py
                .detach(|| template_pushes(&path, &pairs, window, &directions, &impulses))
                .map_err(python_names)?;
            for (direction, recovered) in directions.iter().zip(table) {
                let pushes: Vec<(f64, bool)> = impulses
                    .iter()
                    .copied()
                    .zip(recovered.iter().copied())
                    .collect();
                let up_to = impulses_recovered_up_to(pushes.iter().map(|&(i, o)| (i, Some(o))));
                rows.append(row(py, direction.name(), up_to, pushes)?)?;
            }
        }
        None => {
            let found = py
                .detach(|| template_bisection(&path, &pairs, window, &directions, tolerance_n_s))
                .map_err(python_names)?;
            for (direction, impulse) in directions.iter().zip(found) {
                rows.append(row(py, direction.name(), Some(impulse), Vec::new())?)?;
            }
        }
    }
    let dict = PyDict::new(py);
    dict.set_item("start_s", start_s)?;
    dict.set_item("rows", rows)?;
    Ok(dict)
}

/// One direction's row.
fn row<'py>(
    py: Python<'py>,
    direction: &str,
    recovered: Option<f64>,
    pushes: Vec<(f64, bool)>,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("direction", direction)?;
    dict.set_item("recovered_impulse_n_s", recovered)?;
    dict.set_item("pushes", pushes)?;
    Ok(dict)
}
