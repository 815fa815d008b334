//! `linearize` and `stability_margin`: the closed loop's linearisation and stability margins
//! (GIL released), results as dicts of numbers and numpy arrays for `sea_momentum.analysis`.

use crate::arrays::{matrix_out, vector_out};
use crate::errors::{argument_error, to_py};
use crate::interrupt::run_interruptible;
use crate::numbers::{real_or_none, Integer, Real};
use crate::overrides::override_pairs;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sea_sim::analysis::margin::MAX_SCAN_POINTS;
use sea_sim::analysis::{
    linearize_with, stability_margin_report, ControlTiming, Linearization, LinearizeOptions,
    MarginMethod, MarginOptions, MarginWatch,
};
use sea_sim::scenario::{Sampling, Setting};
use std::collections::HashMap;
use std::path::PathBuf;

/// `sampling` (None: the scenario's; "continuous"; "zero_order_hold" at `controller.rate_hz`).
fn sampling_arg(
    sampling: Option<&str>,
    scenario: &sea_sim::scenario::Scenario,
) -> PyResult<Option<ControlTiming>> {
    let Some(name) = sampling else {
        return Ok(None);
    };
    let sampling = Sampling::from_name(name).ok_or_else(|| {
        argument_error(
            "sampling",
            &format!("None or one of {}", Sampling::allowed()),
            format!("'{name}'"),
        )
    })?;
    Ok(Some(ControlTiming::of(sampling, &scenario.controller)))
}

/// The fields of a linearisation (see `sea_momentum.analysis.Linearization`).
fn linearization_fields<'py>(py: Python<'py>, lin: &Linearization) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let re = |values: &[nalgebra::Complex<f64>]| values.iter().map(|c| c.re).collect::<Vec<_>>();
    let im = |values: &[nalgebra::Complex<f64>]| values.iter().map(|c| c.im).collect::<Vec<_>>();
    d.set_item("matrix", matrix_out(py, &lin.matrix))?;
    d.set_item("eigenvalues_re", vector_out(py, &re(&lin.eigenvalues)))?;
    d.set_item("eigenvalues_im", vector_out(py, &im(&lin.eigenvalues)))?;
    d.set_item("growth_rates", vector_out(py, &lin.growth_rates))?;
    d.set_item("growth_rate", lin.growth_rate)?;
    d.set_item("stable", lin.stable)?;
    d.set_item(
        "least_stable_rate",
        (lin.least_stable_rate.re, lin.least_stable_rate.im),
    )?;
    d.set_item("state_names", lin.state_names.clone())?;
    let mode = lin.least_stable_mode.as_slice();
    d.set_item("mode_re", vector_out(py, &re(mode)))?;
    d.set_item("mode_im", vector_out(py, &im(mode)))?;
    d.set_item("dominant_states", lin.dominant_states.clone())?;
    d.set_item("equilibrium", vector_out(py, &lin.equilibrium.state))?;
    d.set_item("converged", lin.equilibrium.converged)?;
    d.set_item("residual", lin.equilibrium.residual)?;
    d.set_item("newton_iterations", lin.equilibrium.iterations)?;
    d.set_item("map_residual", lin.map_residual)?;
    let (name, period) = (lin.sampling.sampling().name(), lin.sampling.period());
    d.set_item("sampling", name)?;
    d.set_item("control_period", period)?;
    d.set_item("time", lin.time)?;
    d.set_item("step", lin.step)?;
    let check = lin.step_check;
    d.set_item("check_step", check.map(|c| c.step))?;
    d.set_item("eigenvalue_change", check.map(|c| c.eigenvalue_change))?;
    d.set_item("least_stable_change", check.map(|c| c.least_stable_change))?;
    d.set_item("growth_rate_change", check.map(|c| c.growth_rate_change))?;
    Ok(d)
}

/// Linearises the closed loop of the scenario file `path` (with `overrides`) about its
/// equilibrium with the references frozen at `t` (default 0). Returns the fields of
/// `sea_momentum.analysis.Linearization` as a dict.
#[pyfunction]
#[pyo3(signature = (path, t=None, overrides=None, sampling=None))]
pub fn linearize_native<'py>(
    py: Python<'py>,
    path: PathBuf,
    t: Option<Real>,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    sampling: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let pairs = override_pairs(overrides)?;
    let time = real_or_none(t).unwrap_or(0.0);
    sea_dyn::error::check_non_negative("t", time).map_err(to_py)?;
    let scenario = sea_sim::scenario::Scenario::from_file(&path, &pairs).map_err(to_py)?;
    let options = LinearizeOptions {
        time,
        sampling: sampling_arg(sampling, &scenario)?,
        ..Default::default()
    };
    let lin = py
        .detach(|| linearize_with(&scenario, &options))
        .map_err(to_py)?;
    linearization_fields(py, &lin)
}

/// The values of `parameter` in `[lower, upper]` where the closed loop's stability changes.
/// Returns a dict: `parameter`, `boundaries` (ascending; for a key that takes whole numbers,
/// `integer` true, each halfway between two of them), `conclusion` ("boundaries",
/// "stable_over_range" or "unstable_over_range"), `own_value` (the scenario's value, or None),
/// `own_value_stable` (None unless evaluated), `stable_island` ((low, high) containing the
/// own value, or None), `method`, `evaluations`, `samples` (a list of (value, stable,
/// growth_rate or None)). Ctrl-C (or SIGTERM) stops the scan, a simulation under way at its
/// next sample, and raises.
#[pyfunction]
#[pyo3(
    text_signature = "(path, parameter, lower, upper, overrides=None, method=\"eigen\", sampling=None, grid_points=9, log_grid=False)"
)]
#[pyo3(signature = (path, parameter, lower, upper, overrides=None, method="eigen", sampling=None, grid_points=Integer(9), log_grid=false))]
#[allow(clippy::too_many_arguments)] // the Python signature, keyword arguments with defaults
pub fn stability_margin_native<'py>(
    py: Python<'py>,
    path: PathBuf,
    parameter: &str,
    lower: Real,
    upper: Real,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    method: &str,
    sampling: Option<&str>,
    grid_points: Integer,
    log_grid: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (Real(lower), Real(upper), Integer(grid_points)) = (lower, upper, grid_points);
    let grid_points = usize::try_from(grid_points).map_err(|_| {
        let expected = format!("an integer from 2 to {MAX_SCAN_POINTS}");
        argument_error("grid_points", &expected, grid_points)
    })?;
    let pairs = override_pairs(overrides)?;
    let method = MarginMethod::parse(method).map_err(to_py)?;
    let scenario = sea_sim::scenario::Scenario::from_file(&path, &pairs).map_err(to_py)?;
    let mut options = MarginOptions {
        method,
        grid_points,
        log_grid,
        ..Default::default()
    };
    options.linearize.sampling = sampling_arg(sampling, &scenario)?;
    let (report, raised) = run_interruptible(py, |cancel| {
        let watch = MarginWatch::cancel_only(cancel);
        stability_margin_report(&path, &pairs, parameter, lower, upper, &options, watch)
    })?;
    if let Some(interrupt) = raised {
        return Err(interrupt);
    }
    let report = report.map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("parameter", &report.parameter)?;
    d.set_item("boundaries", report.boundaries.clone())?;
    d.set_item("integer", report.integer)?;
    d.set_item("conclusion", report.conclusion().name())?;
    d.set_item("own_value", report.own_value)?;
    d.set_item("own_value_stable", report.own_value_stable())?;
    let island = report
        .island()
        .map(|[low, high]| (low.value(), high.value()));
    d.set_item("stable_island", island)?;
    d.set_item("method", report.method.name())?;
    d.set_item("evaluations", report.evaluations())?;
    let samples = PyList::empty(py);
    for s in &report.samples {
        samples.append((s.value, s.stable, s.growth_rate))?;
    }
    d.set_item("samples", samples)?;
    let no_equilibrium: Vec<(f64, f64)> = report
        .without_equilibrium()
        .filter_map(|s| {
            s.no_equilibrium_residual
                .map(|residual| (s.value, residual))
        })
        .collect();
    d.set_item("no_equilibrium", no_equilibrium)?;
    d.set_item(
        "boundaries_beside_no_equilibrium",
        report.boundaries_beside_no_equilibrium.clone(),
    )?;
    d.set_item("growth_unchanged", report.growth_unchanged())?;
    Ok(d)
}
