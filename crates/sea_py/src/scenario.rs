//! `run_scenario`: a closed-loop scenario run natively (GIL released), results as numpy arrays.

use crate::arrays::{matrix_rows_out, table_out, vector_out};
use crate::errors::{to_py, warn_user};
use crate::interrupt::run_interruptible;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sea_sim::closed_loop::{build, run_setup_with_sinks, RecordSink, RunRecord};
use sea_sim::mcap_log::{McapSink, LOG_NEEDS_A_FILE};
use sea_sim::output::{check_distinct, OutputFile};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Runs the scenario file `path` with `overrides` ({"controller.kind": "rigid", ...}; values
/// are TOML literals or bare strings), optionally writing an MCAP log. Returns a dict of arrays
/// (time, x, thetadot_desired, com, com_reference, momentum, contact_wrenches, motor_torques,
/// joint_error_norm, qp_solved, disturbance_wrench, external_wrench; float64, one row per
/// recorded tick), the
/// layout (nq, nv, ne),
/// names, the contact points under unilateral contacts (their count per contact, positions,
/// forces, activity per row, the ground's normal; [`contact_point_fields`]), and the summary
/// as a dict of the fields of `sea_momentum.results.RunSummary`.
/// `package_dirs` are searched first for the URDF's `package://` meshes drawn in the log.
///
/// Ctrl-C stops the run at its next control tick (the MCAP log is finished) and raises
/// `KeyboardInterrupt` whose `partial` attribute is this dict for the samples computed, with
/// summary status "interrupted".
#[pyfunction]
#[pyo3(signature = (path, overrides=None, mcap=None, progress=false, package_dirs=None))]
pub fn run_scenario_native<'py>(
    py: Python<'py>,
    path: PathBuf,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    mcap: Option<PathBuf>,
    progress: bool,
    package_dirs: Option<Vec<PathBuf>>,
) -> PyResult<Bound<'py, PyDict>> {
    let package_dirs = crate::paths::package_dirs(package_dirs)?;
    let pairs = crate::overrides::override_pairs(overrides)?;
    let scenario = sea_sim::scenario::Scenario::from_file(&path, &pairs).map_err(to_py)?;
    let (built, interrupt) = run_interruptible(py, |_| build(&scenario))?;
    if let Some(error) = interrupt {
        return Err(error);
    }
    let mut setup = built.map_err(to_py)?;
    // The log is written beside its target and replaced at the end, as `sea-sim run` does: a
    // run that fails leaves an earlier log at the path untouched.
    let output = mcap
        .as_deref()
        .map(|target| open_log(&scenario, target))
        .transpose()
        .map_err(to_py)?;
    // What the build let pass (e.g. a walking command the step limits clip), before the run.
    for warning in &setup.warnings {
        warn_user(py, warning)?;
    }
    let (outcome, interrupt) = run_interruptible(py, |cancel| {
        let mut record = RunRecord::default();
        let mut log = output
            .as_ref()
            .map(|output| McapSink::new(output.path()).with_package_dirs(&package_dirs));
        let mut sinks: Vec<&mut dyn RecordSink> = vec![&mut record];
        if let Some(log) = log.as_mut() {
            sinks.push(log);
        }
        let summary =
            run_setup_with_sinks(&scenario, &mut setup, &mut sinks, cancel, |t, total| {
                if progress {
                    eprintln!("  {}: t = {t:5.2} / {total:.2} s", scenario.name);
                }
            });
        drop(sinks);
        let warnings = log.map(|log| log.warnings().to_vec()).unwrap_or_default();
        summary.map(|summary| (record, summary, warnings))
    })?;
    let (record, summary, warnings) = match (outcome, &output) {
        (Err(e), Some(output)) => return Err(to_py(output.explain(e))),
        (outcome, _) => outcome.map_err(to_py)?,
    };
    // Completed, diverged or interrupted: the log is finished and replaces its target.
    if let Some(output) = output {
        output.commit().map_err(to_py)?;
    }
    // The meshes the log could not draw, as Python warnings (the run and its log are kept).
    for warning in warnings {
        warn_user(py, &format!("MCAP log: {warning}"))?;
    }
    let dict = record_fields(py, &record, &scenario)?;
    dict.set_item("summary", summary_fields(py, &summary)?)?;
    match interrupt {
        // Ctrl-C: what was computed (status "interrupted") rides on the exception.
        Some(error) => {
            error.value(py).setattr("partial", dict)?;
            Err(error)
        }
        None => Ok(dict),
    }
}

/// The MCAP log's output file for `target`, checked to be none of the scenario's input files
/// (the scenario, its robot description, its URDF), opened beside the target ([`OutputFile`]).
fn open_log(scenario: &sea_sim::scenario::Scenario, target: &Path) -> sea_sim::Result<OutputFile> {
    check_distinct(&scenario.input_files(), &[("mcap", target)])?;
    OutputFile::create_regular(target, LOG_NEEDS_A_FILE)
}

/// The record's arrays into a new dict: `time`, `x`, `thetadot_desired`, `com`,
/// `com_reference`, `momentum`, `contact_wrenches` and `planned_wrenches` (rows, contacts,
/// 6), `motor_torques`, `joint_error_norm`, `qp_solved`, `disturbance_wrench`,
/// `external_wrench`, the layout (`nq`, `nv`, `ne`), the names and the contact points
/// ([`contact_point_fields`]).
fn record_fields<'py>(
    py: Python<'py>,
    record: &RunRecord,
    scenario: &sea_sim::scenario::Scenario,
) -> PyResult<Bound<'py, PyDict>> {
    let (nq, nv, ne) = record.layout;
    let nx = nq + nv + 2 * ne;
    let dict = PyDict::new(py);
    let rows = record.time.len();
    let n_contacts = scenario.robot.contacts.len();
    dict.set_item("time", vector_out(py, &record.time))?;
    dict.set_item("x", matrix_rows_out(py, &record.state, nx))?;
    dict.set_item(
        "thetadot_desired",
        table_out(py, &record.thetadot_desired, rows, ne),
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
    let planned = matrix_rows_out(py, &record.planned_wrenches, 6 * n_contacts);
    dict.set_item(
        "planned_wrenches",
        planned.call_method1("reshape", ((rows, n_contacts, 6),))?,
    )?;
    dict.set_item(
        "motor_torques",
        table_out(py, &record.motor_torques, rows, ne),
    )?;
    dict.set_item("joint_error_norm", vector_out(py, &record.joint_error_norm))?;
    dict.set_item("qp_solved", vector_out(py, &record.qp_solved))?;
    dict.set_item(
        "disturbance_wrench",
        matrix_rows_out(py, &record.disturbance_wrench, 6),
    )?;
    dict.set_item(
        "external_wrench",
        matrix_rows_out(py, &record.external_wrench, 6),
    )?;
    dict.set_item("nq", nq)?;
    dict.set_item("nv", nv)?;
    dict.set_item("ne", ne)?;
    dict.set_item("joint_names", record.joint_names.clone())?;
    dict.set_item("elastic_joints", record.elastic_joints.clone())?;
    dict.set_item("contacts", scenario.robot.contacts.clone())?;
    contact_point_fields(py, record, scenario, &dict)?;
    Ok(dict)
}

/// The contact points of the run into `dict`: `contact_points` (the number of points of each
/// contact; empty under bilateral contacts), `contact_point_positions` and
/// `contact_point_forces` (rows, n_points, 3) float64 (world; the force on the foot),
/// `contact_point_active` (rows, n_points) bool, and `ground_normal` (3,) float64, the
/// ground's unit normal (world axes), or `None` under bilateral contacts.
fn contact_point_fields<'py>(
    py: Python<'py>,
    record: &RunRecord,
    scenario: &sea_sim::scenario::Scenario,
    dict: &Bound<'py, PyDict>,
) -> PyResult<()> {
    let rows = record.time.len();
    let n_points: usize = record.contact_points.iter().sum();
    dict.set_item("contact_points", record.contact_points.clone())?;
    for (key, values) in [
        ("contact_point_positions", &record.contact_point_positions),
        ("contact_point_forces", &record.contact_point_forces),
    ] {
        let table = table_out(py, values, rows, 3 * n_points);
        dict.set_item(key, table.call_method1("reshape", ((rows, n_points, 3),))?)?;
    }
    let active = PyArray1::from_slice(py, &record.contact_point_active);
    dict.set_item(
        "contact_point_active",
        active.call_method1("reshape", ((rows, n_points),))?,
    )?;
    let ground = &scenario.ground;
    let normal = if record.contact_points.is_empty() {
        None
    } else {
        let plane = sea_plant::Ground::inclined(
            0.0,
            ground.incline_rad,
            ground.incline_heading_rad,
            ground.friction,
        )
        .map_err(to_py)?;
        Some(vector_out(py, plane.normal.as_slice()))
    };
    dict.set_item("ground_normal", normal)?;
    Ok(())
}

/// The URDF file of the scenario file `path` with `overrides`, found as `run_scenario` finds
/// it: `robot.urdf` or the robot description's `urdf`, a `package://` / `file://` URI resolved
/// (the scenario's `robot.package_dirs`, then the environment's), a relative path from the
/// scenario's folder when it exists there. The robot is not built.
#[pyfunction]
#[pyo3(signature = (path, overrides=None))]
pub fn scenario_urdf(
    path: PathBuf,
    overrides: Option<HashMap<String, Bound<'_, PyAny>>>,
) -> PyResult<PathBuf> {
    let pairs = crate::overrides::override_pairs(overrides)?;
    let scenario = sea_sim::scenario::Scenario::from_file(&path, &pairs).map_err(to_py)?;
    Ok(scenario.urdf_path())
}

/// The run summary as the keyword arguments of `sea_momentum.results.RunSummary`: the keys and
/// values of its one serialisation ([`sea_sim::closed_loop::Summary`]'s serde, also the
/// summary JSON's), as Python numbers, strings, `None` and dicts (no JSON text; a non-finite
/// number stays a float).
fn summary_fields<'py>(
    py: Python<'py>,
    summary: &sea_sim::closed_loop::Summary,
) -> PyResult<Bound<'py, PyAny>> {
    pythonize::pythonize(py, summary).map_err(PyErr::from)
}
