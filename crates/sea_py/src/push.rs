//! `push_table_native`: the push study of `sea-sim push` (`sea_study::analysis::push`) from
//! Python, the GIL released and the directions in parallel. Ctrl-C stops it as it stops a sweep
//! (no run starts, the runs under way stop at their next sample) and the rows done are
//! returned with `interrupted = True`.

use crate::errors::{argument_error, to_py, warn_user};
use crate::interrupt::run_interruptible;
use crate::numbers::count_arg;
use crate::numbers::{real_or_none, Real};
use crate::overrides::override_pairs;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sea_sim::analysis::push::{
    check_impulses, fixed_push_table, push_table, swing_push_start, FixedPushRow, PushDirection,
    PushOptions, PushProgress, PushResult, SwingPhase,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Mutex;

/// The study's runs as they ended, per direction: `(impulse, status)`.
type RunsSeen = Mutex<Vec<(PushDirection, f64, String)>>;

/// The rows of the push study of the scenario file `path`: per direction of `directions`
/// ("forward", "backward", "left", "right": the first contact's sole axes), the bisected
/// largest recovered impulse of a push of `duration_s` on `link` at `start_s` (default 1 s),
/// or at fraction `phase` of the swing of step `step` (default 3) of the scenario's walk
/// (to `tolerance_n_s`), or with `impulses` one run per impulse. Returns a dict: `start_s`
/// (the push's start), `rows` (one dict per direction: `direction`,
/// `capture_point_impulse_n_s`, `recovered_impulse_n_s`, `failed_impulse_n_s`, `pushes` (a
/// list of (impulse, status) in the order given, or the bisection's in the order run),
/// `interrupted`) and `interrupted`.
#[pyfunction]
#[pyo3(
    text_signature = "(path, directions, overrides=None, impulses=None, link=\"root_link\", start_s=None, duration_s=0.1, tolerance_n_s=0.1, phase=None, step=None)"
)]
#[pyo3(signature = (path, directions, overrides=None, impulses=None, link="root_link", start_s=None, duration_s=Real(0.1), tolerance_n_s=Real(0.1), phase=None, step=None))]
#[allow(clippy::too_many_arguments)] // the Python signature, keyword arguments with defaults
pub fn push_table_native<'py>(
    py: Python<'py>,
    path: PathBuf,
    directions: Vec<String>,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    impulses: Option<Vec<Real>>,
    link: &str,
    start_s: Option<Real>,
    duration_s: Real,
    tolerance_n_s: Real,
    phase: Option<Real>,
    step: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let impulses = impulses.map(|list| list.into_iter().map(|Real(v)| v).collect::<Vec<f64>>());
    let (start_s, phase) = (real_or_none(start_s), real_or_none(phase));
    let (Real(duration_s), Real(tolerance_n_s)) = (duration_s, tolerance_n_s);
    let pairs = override_pairs(overrides)?;
    let directions = parse_directions(&directions)?;
    let start_s = push_start(&path, &pairs, start_s, phase, step)?;
    let start = if phase.is_some() { "phase" } else { "start_s" };
    let python_names = |error| python_names(error, start);
    let options = PushOptions {
        link: link.to_string(),
        start_s,
        duration_s,
        tolerance_n_s,
    };
    options.check().map_err(python_names)?;
    if let Some(impulses) = &impulses {
        check_impulses(impulses).map_err(to_py)?;
    }
    if let Ok(scenario) = sea_sim::scenario::Scenario::from_file(&path, &pairs) {
        if let Some(warning) = options.short_run_warning(&scenario) {
            warn_user(py, &format!("sea_momentum.push_table: {warning}"))?;
        }
    }
    let seen = RunsSeen::default();
    // Ctrl-C is consumed (the rows done are returned, marked interrupted), as in a sweep.
    let (table, raised) = run_interruptible(py, |cancel| {
        let study = Study {
            path: &path,
            overrides: &pairs,
            options: &options,
            directions: &directions,
        };
        study.run(impulses.as_deref(), &seen, cancel)
    })?;
    let rows = PyList::empty(py);
    let stopped = match table.map_err(python_names)? {
        Table::Fixed(table) => fixed_rows(py, &table, &rows)?,
        Table::Bisected(table) => {
            let seen = seen
                .into_inner()
                .unwrap_or_else(|poisoned| poisoned.into_inner());
            bisected_rows(py, &table, &seen, &rows)?
        }
    };
    let dict = PyDict::new(py);
    dict.set_item("start_s", start_s)?;
    dict.set_item("rows", rows)?;
    dict.set_item("interrupted", stopped || raised.is_some())?;
    Ok(dict)
}

/// The push directions named `names`: refused (naming `directions`) when none, one is given
/// twice, or a name is not a direction.
pub(crate) fn parse_directions(names: &[String]) -> PyResult<Vec<PushDirection>> {
    let directions = names
        .iter()
        .map(|name| PushDirection::parse(name))
        .collect::<sea_sim::Result<Vec<_>>>()
        .map_err(to_py)?;
    let distinct = (0..directions.len()).all(|k| !directions[..k].contains(&directions[k]));
    if directions.is_empty() || !distinct {
        let expected = "distinct directions, at least one";
        return Err(argument_error("directions", expected, format!("{names:?}")));
    }
    Ok(directions)
}

/// A push study's inputs.
struct Study<'a> {
    path: &'a Path,
    overrides: &'a [(String, String)],
    options: &'a PushOptions,
    directions: &'a [PushDirection],
}

impl Study<'_> {
    /// The bisection, or with `impulses` the fixed pushes; every run that ends is added to
    /// `seen`; stopped by `cancel`.
    fn run(
        &self,
        impulses: Option<&[f64]>,
        seen: &RunsSeen,
        cancel: &AtomicBool,
    ) -> sea_sim::Result<Table> {
        let on_run = |run: &PushProgress<'_>| {
            let mut seen = seen.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
            seen.push((run.direction, run.impulse_n_s, run.summary.status.clone()));
        };
        let (path, overrides, options) = (self.path, self.overrides, self.options);
        let directions = self.directions;
        match impulses {
            Some(impulses) => fixed_push_table(
                path, overrides, options, directions, impulses, &on_run, cancel,
            )
            .map(Table::Fixed),
            None => push_table(path, overrides, options, directions, &on_run, cancel)
                .map(Table::Bisected),
        }
    }
}

/// `error` with the library's `PushOptions.NAME` given as the Python argument `NAME`, the
/// start as `start` (`start_s`, or `phase` when the push starts at a phase of a swing).
fn python_names(error: sea_sim::Error, start: &str) -> PyErr {
    to_py(error.argument_named(&[
        ("PushOptions.link", "link"),
        ("PushOptions.start_s", start),
        ("PushOptions.duration_s", "duration_s"),
        ("PushOptions.tolerance_n_s", "tolerance_n_s"),
    ]))
}

/// The push's start [s]: `start_s` (default [`PushOptions`]'s), or with `phase` the time
/// at that fraction of the swing of step `step` (default: `pushed_step`'s) of the
/// walk of the scenario at `path` with `overrides` (`swing_push_start`). Refused, naming the
/// argument: `phase` with `start_s`, `step` without `phase`, and `swing_push_start`'s errors.
fn push_start(
    path: &Path,
    overrides: &[(String, String)],
    start_s: Option<f64>,
    phase: Option<f64>,
    step: Option<&Bound<'_, PyAny>>,
) -> PyResult<f64> {
    let Some(phase) = phase else {
        if let Some(step) = step {
            let expected = "no step without phase (the step whose swing phase pushes)";
            return Err(argument_error("step", expected, step.to_string()));
        }
        return Ok(start_s.unwrap_or(PushOptions::default().start_s));
    };
    if let Some(start_s) = start_s {
        let expected = "no start_s with phase (the push starts at the phase)";
        return Err(argument_error("start_s", expected, start_s));
    }
    let step = step.map(|step| count_arg("step", step, 0)).transpose()?;
    let at = SwingPhase { step, phase };
    let names = [("--phase", "phase"), ("--step", "step")];
    let (start, _) =
        swing_push_start(path, overrides, at).map_err(|e| to_py(e.argument_named(&names)))?;
    Ok(start)
}

/// The two kinds of study.
enum Table {
    Fixed(Vec<FixedPushRow>),
    Bisected(Vec<PushResult>),
}

/// The fixed impulses' rows appended to `rows`; whether a push was stopped.
fn fixed_rows(py: Python<'_>, table: &[FixedPushRow], rows: &Bound<'_, PyList>) -> PyResult<bool> {
    for row in table {
        let pushes: Vec<(f64, String)> = row
            .outcomes
            .iter()
            .map(|(impulse, summary)| {
                let status = summary.as_ref().map_or("interrupted", |s| &s.status);
                (*impulse, status.to_string())
            })
            .collect();
        let failed = row
            .outcomes
            .iter()
            .filter(|(_, summary)| summary.as_ref().is_some_and(|s| !s.completed()))
            .map(|(impulse, _)| *impulse)
            .reduce(f64::min);
        let dict = PyDict::new(py);
        dict.set_item("direction", row.direction.name())?;
        dict.set_item("capture_point_impulse_n_s", row.capture_point_impulse)?;
        dict.set_item("recovered_impulse_n_s", row.recovered_up_to())?;
        dict.set_item("failed_impulse_n_s", failed)?;
        dict.set_item("pushes", pushes)?;
        dict.set_item("interrupted", row.interrupted())?;
        rows.append(dict)?;
    }
    Ok(table.iter().any(FixedPushRow::interrupted))
}

/// The bisection's rows appended to `rows`, each with the runs `seen` in its direction;
/// whether a bisection was stopped.
fn bisected_rows(
    py: Python<'_>,
    table: &[PushResult],
    seen: &[(PushDirection, f64, String)],
    rows: &Bound<'_, PyList>,
) -> PyResult<bool> {
    for row in table {
        let pushes: Vec<(f64, &str)> = seen
            .iter()
            .filter(|(direction, _, _)| *direction == row.direction)
            .map(|(_, impulse, status)| (*impulse, status.as_str()))
            .collect();
        let dict = PyDict::new(py);
        dict.set_item("direction", row.direction.name())?;
        dict.set_item("capture_point_impulse_n_s", row.capture_point_impulse)?;
        dict.set_item("recovered_impulse_n_s", row.recovered_impulse)?;
        dict.set_item("failed_impulse_n_s", row.failed_impulse)?;
        dict.set_item("pushes", pushes)?;
        dict.set_item("interrupted", row.interrupted)?;
        rows.append(dict)?;
    }
    Ok(table.iter().any(|row| row.interrupted))
}
