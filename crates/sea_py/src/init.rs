//! `sea_momentum.init_scenario`: `sea-sim init` from Python (a two-feet balancing scenario for
//! a new robot, written to a file).

use crate::errors::{argument_error, to_py};
use crate::interrupt::run_interruptible;
use crate::numbers::Real;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sea_ctrl::walking::RobotWalkingFigures;
use sea_sim::init::walking::WalkCheck;
use sea_sim::init::{check_foot, init_unless_stopped, InitOptions};
use sea_sim::scenario::robots::FootRectangle;
use std::path::PathBuf;

/// Writes the scenario of `sea-sim init` (with `walking` a walk, run unless `walk_check` is
/// false) and returns what it found: `out`, `robot`, `mass`, `joints`, `foot_x`, `foot_y`,
/// `measured`, `lowering_m`, `residual`, `com_offset_m`, `feet_rank`, `warnings`,
/// `walking_figures`, `walk_check`. Ctrl-C raises `KeyboardInterrupt` (nothing written before
/// the file; during the walk's runs the walk stays at the standing CoM height).
#[pyfunction]
#[pyo3(signature = (urdf, contacts, out, foot=None, package_dirs=None, walking=false, walk_check=true))]
#[allow(clippy::too_many_arguments)]
pub fn init_scenario<'py>(
    py: Python<'py>,
    urdf: PathBuf,
    contacts: &Bound<'py, PyAny>,
    out: PathBuf,
    foot: Option<&Bound<'py, PyAny>>,
    package_dirs: Option<Vec<PathBuf>>,
    walking: bool,
    walk_check: bool,
) -> PyResult<Bound<'py, PyDict>> {
    // A path or a `package://` / `file://` URI, given as a str or a path-like object.
    let urdf = match urdf.to_str() {
        Some(text) => text.to_string(),
        None => {
            return Err(argument_error(
                "urdf",
                "a UTF-8 path or URI",
                urdf.display(),
            ))
        }
    };
    if !walking && !walk_check {
        return Err(argument_error(
            "walk_check",
            "True unless walking=True (the check runs the walk that walking writes)",
            "False",
        ));
    }
    let contacts: [String; 2] = items(contacts, "contacts", CONTACTS_EXPECTED)?;
    let foot: Option<[Real; 4]> = foot.map(|f| items(f, "foot", FOOT_EXPECTED)).transpose()?;
    let foot = foot
        .map(|[Real(x0), Real(x1), Real(y0), Real(y1)]| {
            check_foot(&FootRectangle {
                x: [x0, x1],
                y: [y0, y1],
            })
        })
        .transpose()
        .map_err(to_py)?;
    let options = InitOptions {
        urdf,
        contacts,
        foot,
        package_dirs: crate::paths::package_dirs(package_dirs)?,
        out,
        name: None,
        walking,
        skip_walk_check: !walk_check,
    };
    let (result, raised) = run_interruptible(py, |stop| init_unless_stopped(&options, stop))?;
    if let Some(error) = raised {
        return Err(error);
    }
    let report = result.map_err(to_py)?.ok_or_else(|| {
        pyo3::exceptions::PyRuntimeError::new_err("init stopped without a signal raised")
    })?;
    let dict = PyDict::new(py);
    dict.set_item("out", report.out.display().to_string())?;
    dict.set_item("robot", &report.robot.0)?;
    dict.set_item("mass", report.robot.1)?;
    dict.set_item("joints", report.robot.2)?;
    dict.set_item("foot_x", report.feet[0].x.to_vec())?;
    dict.set_item("foot_y", report.feet[0].y.to_vec())?;
    dict.set_item("measured", report.measured)?;
    dict.set_item("lowering_m", report.lowering_m)?;
    dict.set_item("residual", report.residual)?;
    dict.set_item("com_offset_m", report.com_offset_m)?;
    dict.set_item("feet_rank", report.feet_rank)?;
    dict.set_item("warnings", report.warnings)?;
    dict.set_item(
        "walking_figures",
        figures_dict(py, &report.walking_figures)?,
    )?;
    let runs = report
        .walk_check
        .as_ref()
        .map(|check| walk_check_list(py, check))
        .transpose()?;
    dict.set_item("walk_check", runs)?;
    Ok(dict)
}

/// The standing figures the walking settings scale with, as a dict [m].
fn figures_dict<'py>(
    py: Python<'py>,
    figures: &RobotWalkingFigures,
) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("com_height", figures.com_height)?;
    dict.set_item("feet_distance", figures.feet_distance)?;
    dict.set_item("leg_length", figures.leg_length)?;
    dict.set_item("reach", figures.reach)?;
    Ok(dict)
}

/// The walk check's runs, each a dict of `com_height`, `status`, `reason`, `duration_s`.
fn walk_check_list<'py>(py: Python<'py>, check: &WalkCheck) -> PyResult<Vec<Bound<'py, PyDict>>> {
    check
        .tries
        .iter()
        .map(|run| {
            let dict = PyDict::new(py);
            dict.set_item("com_height", run.com_height)?;
            dict.set_item("status", &run.status)?;
            dict.set_item("reason", &run.reason)?;
            dict.set_item("duration_s", run.duration_s)?;
            Ok(dict)
        })
        .collect()
}

/// What `contacts` must be, in its error message.
const CONTACTS_EXPECTED: &str =
    "2 contacts (left, right) as a tuple or list of 2 str, e.g. ('l_sole', 'r_sole')";
/// What `foot` must be, in its error message.
const FOOT_EXPECTED: &str = "the sole rectangle (x0, x1, y0, y1) as a tuple or list of 4 float";

/// `value` as exactly `N` items of `T` from a tuple or list, else a `ValueError` naming
/// `argument`, what is `expected` and what was given (PyO3's own message for a tuple of the
/// wrong length names no argument).
fn items<'py, T, const N: usize>(
    value: &Bound<'py, PyAny>,
    argument: &str,
    expected: &str,
) -> PyResult<[T; N]>
where
    T: pyo3::conversion::FromPyObjectOwned<'py>,
{
    let given = || describe(value);
    let list: Vec<Bound<'py, PyAny>> = match value.extract() {
        Ok(list) if !value.is_instance_of::<pyo3::types::PyString>() => list,
        _ => return Err(argument_error(argument, expected, given())),
    };
    let extracted = list
        .iter()
        .map(|item| item.extract::<T>().ok())
        .collect::<Option<Vec<T>>>();
    extracted
        .and_then(|v| <[T; N]>::try_from(v).ok())
        .ok_or_else(|| argument_error(argument, expected, given()))
}

/// `value` for an error message: its `repr` (shortened) and, for a sequence, its length.
fn describe(value: &Bound<'_, PyAny>) -> String {
    let mut repr = value
        .repr()
        .map(|r| r.to_string())
        .unwrap_or_else(|_| "an object without repr".into());
    if repr.chars().count() > 80 {
        repr = repr.chars().take(77).collect::<String>() + "...";
    }
    match value.len() {
        Ok(n) if !value.is_instance_of::<pyo3::types::PyString>() => {
            format!("{repr} (length {n})")
        }
        _ => repr,
    }
}
