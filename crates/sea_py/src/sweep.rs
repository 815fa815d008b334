//! Sweeps: the grid checked and expanded (`sweep_grid`), a whole sweep on this machine's cores
//! (`sweep`) and one batch of points (`sweep_batch`, what a Ray task runs). The GIL is released
//! while the runs go; Ctrl-C stops the sweep (no new run starts, the runs under way stop at
//! their next sample) and the rows done are returned with `interrupted = True`.
//!
//! A row is a dict: `index` (the point in the grid), the grid values by key, `status`,
//! `message` and every other summary field (None for a failed run).

use crate::errors::to_py;
use crate::interrupt::run_interruptible;
use crate::numbers::Integer;
use crate::overrides::override_pairs;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use sea_sim::sweep::{
    run_points, summary_columns, FieldValue, Grid, ScenarioSource, SweepProgress, SweepRow,
};
use std::collections::HashMap;
use std::path::PathBuf;

/// The column names of a sweep over `keys`: the keys, `status`, `message`, then the summary
/// fields.
fn columns(keys: &[String]) -> Vec<String> {
    let mut names = keys.to_vec();
    names.extend(["status".to_string(), "message".to_string()]);
    names.extend(summary_columns());
    names
}

/// A summary value as a Python object (None, int, float or str).
fn field_to_py<'py>(py: Python<'py>, value: &FieldValue) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        FieldValue::Missing => py.None().into_bound(py),
        FieldValue::Integer(whole) => whole.into_pyobject(py)?.into_any(),
        FieldValue::Real(real) => real.into_pyobject(py)?.into_any(),
        FieldValue::Text(text) => text.into_pyobject(py)?.into_any(),
    })
}

/// One row as a dict (see the module documentation).
fn row_dict<'py>(py: Python<'py>, keys: &[String], row: &SweepRow) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    dict.set_item("index", row.index)?;
    for (key, value) in keys.iter().zip(&row.values) {
        dict.set_item(key, value)?;
    }
    dict.set_item("status", &row.status)?;
    dict.set_item("message", &row.message)?;
    for (name, value) in row.summary_values() {
        dict.set_item(name, field_to_py(py, &value)?)?;
    }
    Ok(dict)
}

/// The rows as a list of dicts.
fn rows_list<'py>(
    py: Python<'py>,
    keys: &[String],
    rows: &[SweepRow],
) -> PyResult<Bound<'py, PyList>> {
    let dicts = rows
        .iter()
        .map(|row| row_dict(py, keys, row))
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, dicts)
}

/// A progress line on stderr after each run.
fn report(keys: &[String], progress: &SweepProgress<'_>) {
    let point: Vec<String> = keys
        .iter()
        .zip(&progress.row.values)
        .map(|(key, value)| format!("{key}={value}"))
        .collect();
    eprintln!(
        "  sweep {}/{} {}: {}",
        progress.done,
        progress.total,
        point.join(" "),
        progress.row.status
    );
}

/// Parses and checks the grid `grid` (`KEY=V1,V2,...` or `KEY=START:STOP:COUNT[:log]`) on the
/// scenario file `path` with `overrides`. Returns a dict: `keys` (list[str]), `points`
/// (list[list[float]], the last key varying fastest) and `columns` (the row fields in order).
/// Raises ScenarioError naming the key and the value.
#[pyfunction]
#[pyo3(signature = (path, grid, overrides=None))]
pub fn sweep_grid<'py>(
    py: Python<'py>,
    path: PathBuf,
    grid: Vec<String>,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
) -> PyResult<Bound<'py, PyDict>> {
    let overrides = override_pairs(overrides)?;
    let grid = Grid::parse(&grid).map_err(to_py)?;
    let source = ScenarioSource::read(&path).map_err(to_py)?;
    grid.check(&source, &overrides).map_err(to_py)?;
    let keys = grid.keys();
    let points: Vec<Vec<f64>> = (0..grid.len()).map(|k| grid.point(k)).collect();
    let dict = PyDict::new(py);
    dict.set_item("columns", columns(&keys))?;
    dict.set_item("keys", keys)?;
    dict.set_item("points", points)?;
    Ok(dict)
}

/// `workers` as a thread count; a negative one is refused naming it (the range is checked by
/// [`sea_sim::sweep::worker_count`]).
fn worker_arg(workers: Option<Integer>) -> PyResult<Option<usize>> {
    workers
        .map(|Integer(n)| {
            usize::try_from(n).map_err(|_| {
                crate::errors::argument_error("workers", "a positive integer or None", n)
            })
        })
        .transpose()
}

/// Runs every point of `grid` (see `sweep_grid`) on `workers` threads (None: every core), the
/// GIL released. Returns a dict: `keys`, `columns`, `rows` (list of dicts in grid order),
/// `total` (points in the grid) and `interrupted` (Ctrl-C stopped it; `rows` holds the runs
/// done). A failed run is a row with status "failed" and its message.
#[pyfunction]
#[pyo3(signature = (path, grid, overrides=None, workers=None, progress=false))]
pub fn sweep<'py>(
    py: Python<'py>,
    path: PathBuf,
    grid: Vec<String>,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    workers: Option<Integer>,
    progress: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let workers = worker_arg(workers)?;
    let overrides = override_pairs(overrides)?;
    let grid = Grid::parse(&grid).map_err(to_py)?;
    sea_sim::sweep::worker_count(workers).map_err(to_py)?;
    let source = ScenarioSource::read(&path).map_err(to_py)?;
    grid.check(&source, &overrides).map_err(to_py)?;
    let keys = grid.keys();
    let points = (0..grid.len()).map(|k| (k, grid.point(k))).collect();
    // Ctrl-C is consumed (the rows done are returned, marked interrupted).
    let (rows, raised) = run_interruptible(py, |cancel| {
        run_points(&source, &keys, points, &overrides, workers, cancel, &|p| {
            if progress {
                report(&keys, p);
            }
        })
    })?;
    let interrupted = raised.is_some();
    let rows = rows.map_err(to_py)?;
    let dict = PyDict::new(py);
    dict.set_item("columns", columns(&keys))?;
    dict.set_item("rows", rows_list(py, &keys, &rows)?)?;
    dict.set_item("keys", keys)?;
    dict.set_item("total", grid.len())?;
    dict.set_item("interrupted", interrupted)?;
    Ok(dict)
}

/// Runs the points `(index, values)` (values in the order of `keys`, as given by
/// `sweep_grid`) on `workers` threads (default 1: a cluster task has one core), the GIL
/// released. Returns the rows (list of dicts, in the order given); Ctrl-C returns the rows
/// done. The points are not checked again: a bad value is that row's failure.
#[pyfunction]
#[pyo3(signature = (path, keys, points, overrides=None, workers=Integer(1)))]
#[pyo3(text_signature = "(path, keys, points, overrides=None, workers=1)")]
pub fn sweep_batch<'py>(
    py: Python<'py>,
    path: PathBuf,
    keys: Vec<String>,
    points: Vec<(usize, Vec<f64>)>,
    overrides: Option<HashMap<String, Bound<'py, PyAny>>>,
    workers: Option<Integer>,
) -> PyResult<Bound<'py, PyList>> {
    let workers = worker_arg(workers)?;
    if let Some((index, values)) = points.iter().find(|(_, v)| v.len() != keys.len()) {
        return Err(crate::errors::argument_error(
            &format!("points[{index}]"),
            &format!("{} values (one per key)", keys.len()),
            values.len(),
        ));
    }
    let overrides = override_pairs(overrides)?;
    let source = ScenarioSource::read(&path).map_err(to_py)?;
    let (rows, _) = run_interruptible(py, |cancel| {
        run_points(&source, &keys, points, &overrides, workers, cancel, &|_| {})
    })?;
    rows_list(py, &keys, &rows.map_err(to_py)?)
}
