//! Parameter sweeps: the closed loop of one scenario over the cartesian product of value grids
//! of numeric scenario keys, in parallel on a local thread pool (rayon).
//!
//! - [`Grid`]: the axes, parsed from `KEY=V1,V2,...` or `KEY=START:STOP:COUNT[:log]` and
//!   checked against the scenario ([`Grid::check`]); point `k` of the product has the last
//!   axis varying fastest.
//! - [`run_sweep`]: every point of a grid; [`run_points`]: chosen points (a batch, e.g. one
//!   task of a cluster). Each run is the closed loop without a record (summary only, constant
//!   memory). Rows come back in grid order with their index, so the result does not depend on
//!   the number of workers. A run that fails (bad value, model error, panic) is a row with
//!   status "failed" and the message, never an error that loses the other rows. Once `cancel`
//!   is raised no new run starts and the runs under way stop at their next sample (status
//!   "interrupted"); the rows done are returned.
//! - [`write_csv`]: one line per row, the grid values in columns named by their keys, then
//!   the status, the message and every other summary field.

use crate::error::{Error, Result};
use sea_dyn::files::{read_text_within, MAX_TOML_BYTES};
use sea_loop::error::panic_message;
use sea_loop::{RunEnd, RunTotals, RunningStatistics, Summary, NON_SCALAR_FIELDS};
use sea_scenario::run::run_with_sinks;
use sea_scenario::Scenario;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

/// The accepted forms of a grid specification (for error messages).
const GRID_FORMS: &str = "expected KEY=V1,V2,... or KEY=START:STOP:COUNT[:log]";

/// Status of a row whose run could not be done (its scenario or model failed, or it panicked).
pub const STATUS_FAILED: &str = "failed";

/// One axis of a grid: a scenario key and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// Dotted scenario key, e.g. `controller.rate_hz`.
    pub key: String,
    /// Values, in the order given (never empty, all finite).
    pub values: Vec<f64>,
}

/// A number of a grid specification, finite; the error names `key`, what `part` is and the text.
fn parse_number(key: &str, part: &str, text: &str) -> Result<f64> {
    match text.trim().parse::<f64>() {
        Ok(value) if value.is_finite() => Ok(value),
        _ => Err(Error::invalid(
            key,
            format!("{part} must be a finite number"),
            format!("'{}'", text.trim()),
        )),
    }
}

/// `COUNT` values from `start` to `stop` (both included), evenly spaced, or evenly spaced in
/// logarithm when `log`; `COUNT = 1` gives `start`.
fn range_values(key: &str, start: f64, stop: f64, count: usize, log: bool) -> Result<Vec<f64>> {
    if start > stop || (start == stop && count > 1) {
        return Err(Error::invalid(
            key,
            "empty or inverted range: START must be below STOP (or equal with COUNT 1)",
            format!("{start}:{stop}"),
        ));
    }
    if log && start <= 0.0 {
        return Err(Error::invalid(
            key,
            "a logarithmic range needs START > 0",
            start,
        ));
    }
    let last = count.saturating_sub(1).max(1) as f64;
    let values = (0..count).map(|k| {
        let fraction = k as f64 / last;
        match (k, log) {
            (0, _) => start,
            (k, _) if k + 1 == count => stop,
            (_, true) => (start.ln() + fraction * (stop.ln() - start.ln())).exp(),
            (_, false) => start + fraction * (stop - start),
        }
    });
    Ok(values.collect())
}

/// The values of `START:STOP:COUNT[:log]` for `key`.
fn parse_range(key: &str, text: &str) -> Result<Vec<f64>> {
    let parts: Vec<&str> = text.split(':').map(str::trim).collect();
    let log = match parts.get(3) {
        None => false,
        Some(&"log") if parts.len() == 4 => true,
        Some(_) => {
            return Err(Error::invalid(
                key,
                "a range is START:STOP:COUNT or START:STOP:COUNT:log",
                format!("'{text}'"),
            ))
        }
    };
    if parts.len() < 3 {
        return Err(Error::invalid(
            key,
            "a range is START:STOP:COUNT or START:STOP:COUNT:log",
            format!("'{text}'"),
        ));
    }
    let start = parse_number(key, "START", parts[0])?;
    let stop = parse_number(key, "STOP", parts[1])?;
    let count = match parts[2].parse::<usize>() {
        Ok(count) if (1..=MAX_GRID_POINTS).contains(&count) => count,
        _ => {
            return Err(Error::invalid(
                key,
                format!("COUNT must be a whole number from 1 to {MAX_GRID_POINTS}"),
                format!("'{}'", parts[2]),
            ))
        }
    };
    range_values(key, start, stop, count, log)
}

impl Axis {
    /// Parses `KEY=V1,V2,...` or `KEY=START:STOP:COUNT[:log]` (logarithmic spacing with
    /// `log`; both ends included).
    ///
    /// Errors: [`Error::Scenario`] naming the key (or the whole specification when it has no
    /// key) and the offending value: no `=`, an empty key, an empty value, a value that is not
    /// a finite number, COUNT below 1, an empty or inverted range, a log range from a value
    /// not above 0.
    pub fn parse(spec: &str) -> Result<Axis> {
        let (key, text) = spec
            .split_once('=')
            .ok_or_else(|| Error::invalid("grid", GRID_FORMS, format!("'{spec}'")))?;
        let (key, text) = (key.trim(), text.trim());
        if key.is_empty() {
            return Err(Error::invalid("grid", GRID_FORMS, format!("'{spec}'")));
        }
        let values = if text.contains(':') {
            parse_range(key, text)?
        } else {
            text.split(',')
                .map(|item| parse_number(key, "every value", item))
                .collect::<Result<Vec<f64>>>()?
        };
        Ok(Axis {
            key: key.to_string(),
            values,
        })
    }
}

/// The TOML literal given to the scenario for a grid value: a whole number as an integer (so
/// it also fits integer keys; TOML integers are accepted by real-valued keys), anything else
/// as a float.
pub fn override_literal(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e15 {
        format!("{}", value as i64)
    } else {
        toml::Value::Float(value).to_string()
    }
}

/// A scenario read once: its text and folder, parsed again with each run's overrides.
#[derive(Clone, Debug)]
pub struct ScenarioSource {
    path: PathBuf,
    text: String,
}

impl ScenarioSource {
    /// Reads the scenario file.
    ///
    /// Errors: [`Error::Io`] naming the file.
    pub fn read(path: &Path) -> Result<ScenarioSource> {
        let text =
            read_text_within(path, MAX_TOML_BYTES).map_err(|source| Error::io(path, source))?;
        Ok(ScenarioSource {
            path: path.to_path_buf(),
            text,
        })
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The scenario with `overrides` (errors name the file and the key).
    pub fn load(&self, overrides: &[(String, String)]) -> Result<Scenario> {
        Scenario::from_file_text(&self.path, &self.text, overrides)
    }
}

/// `overrides`, then `key = value` for every axis (a grid key wins over an override of the
/// same key: it comes later).
fn overrides_with(
    overrides: &[(String, String)],
    keys: &[String],
    values: &[f64],
) -> Vec<(String, String)> {
    let mut all = overrides.to_vec();
    all.extend(
        keys.iter()
            .zip(values)
            .map(|(key, value)| (key.clone(), override_literal(*value))),
    );
    all
}

/// The most points a grid may have (each is a whole simulation).
pub const MAX_GRID_POINTS: usize = 1_000_000;

/// The cartesian product of axes.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    axes: Vec<Axis>,
}

impl Grid {
    /// The grid of `specs` (see [`Axis::parse`]).
    ///
    /// Errors: as [`Axis::parse`], no specification, or a key given twice.
    pub fn parse<S: AsRef<str>>(specs: &[S]) -> Result<Grid> {
        let axes = specs
            .iter()
            .map(|spec| Axis::parse(spec.as_ref()))
            .collect::<Result<Vec<Axis>>>()?;
        Grid::new(axes)
    }

    /// The grid of `axes`.
    ///
    /// Errors: [`Error::Scenario`] for no axis, an axis without values, a key given twice or
    /// more than [`MAX_GRID_POINTS`] points.
    pub fn new(axes: Vec<Axis>) -> Result<Grid> {
        if axes.is_empty() {
            return Err(Error::config("grid", "at least one KEY=... is needed"));
        }
        for (k, axis) in axes.iter().enumerate() {
            if axis.values.is_empty() {
                return Err(Error::config(&axis.key, "the grid has no value"));
            }
            if axes[..k].iter().any(|other| other.key == axis.key) {
                return Err(Error::config(&axis.key, "given twice in the grid"));
            }
        }
        let points = axes
            .iter()
            .try_fold(1usize, |product, axis| {
                product.checked_mul(axis.values.len())
            })
            .filter(|&points| points <= MAX_GRID_POINTS);
        if points.is_none() {
            return Err(Error::config(
                "grid",
                format!("more than {MAX_GRID_POINTS} points (each a simulation)"),
            ));
        }
        Ok(Grid { axes })
    }

    /// The axes, in the order given.
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// The keys, in the order given.
    pub fn keys(&self) -> Vec<String> {
        self.axes.iter().map(|axis| axis.key.clone()).collect()
    }

    /// Number of points (the product of the axis lengths).
    pub fn len(&self) -> usize {
        self.axes.iter().map(|axis| axis.values.len()).product()
    }

    /// Whether the grid has no point (never, for a grid built by [`Grid::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The values of point `index` (one per axis; the last axis varies fastest).
    pub fn point(&self, index: usize) -> Vec<f64> {
        let mut rest = index;
        let mut values = vec![0.0; self.axes.len()];
        for (axis, value) in self.axes.iter().zip(values.iter_mut()).rev() {
            *value = axis.values[rest % axis.values.len()];
            rest /= axis.values.len();
        }
        values
    }

    /// Checks every value of every axis by loading the scenario with it (on top of
    /// `overrides`, the other axes at their first value), so a key the scenario does not
    /// have, a key that is not a number or a value out of its range is refused before any run.
    ///
    /// Errors: [`Error::Scenario`] naming the grid key and the value; the scenario's own
    /// error when it does not load without the grid.
    pub fn check(&self, source: &ScenarioSource, overrides: &[(String, String)]) -> Result<()> {
        source.load(overrides)?;
        let keys = self.keys();
        let mut values = self.point(0);
        for (a, axis) in self.axes.iter().enumerate() {
            for &value in &axis.values {
                values[a] = value;
                if let Err(error) = source.load(&overrides_with(overrides, &keys, &values)) {
                    return Err(grid_value_error(error, &axis.key, value));
                }
            }
            values[a] = axis.values[0];
        }
        Ok(())
    }
}

/// The error of loading the scenario with `key = value`: the scenario's error when it names
/// `key`, else a key that is unknown or not a number (the override made a table or a type the
/// schema refuses elsewhere).
fn grid_value_error(error: Error, key: &str, value: f64) -> Error {
    match error {
        Error::Scenario { key: ref named, .. } if named == key => error,
        Error::Scenario {
            key: named, rule, ..
        } => Error::invalid(
            key,
            format!("not a numeric scenario key (unknown, or not a number): '{named}': {rule}"),
            value,
        ),
        other => Error::invalid(
            key,
            format!("the scenario does not accept this value: {other}"),
            value,
        ),
    }
}

/// One run of a sweep.
#[derive(Clone, Debug)]
pub struct SweepRow {
    /// Index of the point in the grid.
    pub index: usize,
    /// The grid values (one per key).
    pub values: Vec<f64>,
    /// "completed", "diverged", "interrupted" or [`STATUS_FAILED`].
    pub status: String,
    /// Why it diverged, was interrupted or failed; empty when completed.
    pub message: String,
    /// The run's summary (`None` when the run failed).
    pub summary: Option<Summary>,
}

/// A summary field's value in a row.
#[derive(Clone, Debug, PartialEq)]
pub enum FieldValue {
    /// No value (a failed run, or a field without a value such as `diverged_at_s` of a
    /// completed run).
    Missing,
    /// A count.
    Integer(i64),
    /// A real number.
    Real(f64),
    /// Text.
    Text(String),
}

impl FieldValue {
    /// The value of a summary's JSON field.
    fn from_json(value: &serde_json::Value) -> FieldValue {
        use serde_json::Value;
        match value {
            Value::Null => FieldValue::Missing,
            Value::Number(number) => match number.as_i64() {
                Some(whole) if !number.is_f64() => FieldValue::Integer(whole),
                _ => FieldValue::Real(number.as_f64().unwrap_or(f64::NAN)),
            },
            Value::String(text) => FieldValue::Text(text.clone()),
            other => FieldValue::Text(other.to_string()),
        }
    }

    /// As a CSV field (missing: empty; numbers in their shortest exact form).
    fn csv(&self) -> String {
        match self {
            FieldValue::Missing => String::new(),
            FieldValue::Integer(whole) => whole.to_string(),
            FieldValue::Real(real) => format!("{real}"),
            FieldValue::Text(text) => csv_field(text),
        }
    }
}

impl SweepRow {
    /// The summary fields other than `status` and `reason` (those are [`Self::status`] and
    /// [`Self::message`]) and `reason_kind`, named as in [`summary_columns`]; missing for a
    /// failed run.
    pub fn summary_values(&self) -> Vec<(String, FieldValue)> {
        let json = self.summary.as_ref().map(Summary::to_json);
        summary_columns()
            .into_iter()
            .map(|name| {
                let value = json
                    .as_ref()
                    .and_then(|json| json.get(&name))
                    .map_or(FieldValue::Missing, FieldValue::from_json);
                (name, value)
            })
            .collect()
    }
}

/// The summary fields of a row after its status and message, in the order of
/// [`Summary::to_json`] (the summary's one list of fields).
pub fn summary_columns() -> Vec<String> {
    let totals = RunTotals::default();
    let blank = Summary::new(
        &RunEnd::Completed,
        "",
        &RunningStatistics::default(),
        totals,
    );
    match blank.to_json() {
        serde_json::Value::Object(map) => map
            .keys()
            .filter(|name| !matches!(name.as_str(), "status" | "reason" | "reason_kind"))
            .filter(|name| !NON_SCALAR_FIELDS.contains(&name.as_str()))
            .cloned()
            .collect(),
        _ => Vec::new(),
    }
}

/// Progress of a sweep, reported after each run.
#[derive(Clone, Copy, Debug)]
pub struct SweepProgress<'a> {
    /// Runs finished so far (this one included).
    pub done: usize,
    /// Runs in the sweep.
    pub total: usize,
    /// The row just finished.
    pub row: &'a SweepRow,
}

/// What every run of a sweep shares.
struct SweepJob<'a> {
    source: &'a ScenarioSource,
    keys: &'a [String],
    overrides: &'a [(String, String)],
    cancel: &'a AtomicBool,
}

impl SweepJob<'_> {
    /// The summary of the closed loop at `values` (no record kept).
    fn summary(&self, values: &[f64]) -> Result<Summary> {
        let scenario = self
            .source
            .load(&overrides_with(self.overrides, self.keys, values))?;
        run_with_sinks(&scenario, &mut [], self.cancel, |_, _| {})
    }

    /// Runs point `index`; `None` when the sweep was cancelled before it started.
    fn run(&self, index: usize, values: Vec<f64>) -> Option<SweepRow> {
        if self.cancel.load(Ordering::Relaxed) {
            return None;
        }
        // A panic in one run must not lose the others: it becomes that run's failure.
        let outcome =
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.summary(&values)));
        let (status, message, summary) = match outcome {
            Ok(Ok(summary)) => (
                summary.status.clone(),
                summary.reason.clone(),
                Some(summary),
            ),
            Ok(Err(error)) => (STATUS_FAILED.to_string(), error.to_string(), None),
            Err(payload) => (
                STATUS_FAILED.to_string(),
                format!("panic: {}", panic_message(payload.as_ref())),
                None,
            ),
        };
        Some(SweepRow {
            index,
            values,
            status,
            message,
            summary,
        })
    }
}

/// The most workers a sweep takes: each is an operating-system thread with its own stack, and
/// tens of thousands of them exhaust the process's memory maps (a thread then fails to start
/// inside the pool, which cannot be reported as an error).
pub const MAX_WORKERS: usize = 1024;

/// The number of workers: `workers`, or every core when `None`.
///
/// Errors: a bad argument ([`Error::argument`], `workers`) for 0 or more than [`MAX_WORKERS`].
pub fn worker_count(workers: Option<usize>) -> Result<usize> {
    match workers {
        Some(n) if n == 0 || n > MAX_WORKERS => Err(Error::argument(
            "workers",
            format!("from 1 to {MAX_WORKERS}"),
            n,
        )),
        Some(n) => Ok(n),
        None => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// Runs the points `(index, values)` (values in the order of `keys`) of the scenario read in
/// `source` with `overrides`, on a pool of `workers` threads (every core when `None`); see the
/// module documentation. Rows are in the order of `points`; `progress` is called after each
/// run, from the worker that did it.
///
/// The pool has no more threads than points.
///
/// Errors: only for `workers` 0 or above [`MAX_WORKERS`], or a pool that cannot start; a run's
/// failure is its row.
pub fn run_points(
    source: &ScenarioSource,
    keys: &[String],
    points: Vec<(usize, Vec<f64>)>,
    overrides: &[(String, String)],
    workers: Option<usize>,
    cancel: &AtomicBool,
    progress: &(dyn Fn(&SweepProgress<'_>) + Sync),
) -> Result<Vec<SweepRow>> {
    let threads = worker_count(workers)?.min(points.len().max(1));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(|k| format!("sea-sweep-{k}"))
        .build()
        .map_err(|e| {
            Error::invalid("workers", format!("cannot start the threads: {e}"), threads)
        })?;
    let job = SweepJob {
        source,
        keys,
        overrides,
        cancel,
    };
    let total = points.len();
    let (next, done) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let slots: Vec<Mutex<Option<SweepRow>>> = (0..total).map(|_| Mutex::new(None)).collect();
    // Every worker takes the next point in order, so runs start in grid order (an interrupted
    // sweep has done a prefix of the grid, give or take the runs under way) and a long run
    // never holds back points queued behind it.
    pool.broadcast(|_| loop {
        let k = next.fetch_add(1, Ordering::Relaxed);
        let Some((index, values)) = points.get(k) else {
            break;
        };
        let Some(row) = job.run(*index, values.clone()) else {
            break;
        };
        let done = done.fetch_add(1, Ordering::Relaxed) + 1;
        progress(&SweepProgress {
            done,
            total,
            row: &row,
        });
        *slots[k].lock().unwrap_or_else(PoisonError::into_inner) = Some(row);
    });
    let rows = slots
        .into_iter()
        .filter_map(|slot| slot.into_inner().unwrap_or_else(PoisonError::into_inner))
        .collect();
    Ok(rows)
}

/// Runs every point of `grid` (checked first, see [`Grid::check`]) on the scenario file
/// `path` with `overrides`; see [`run_points`] and the module documentation.
///
/// Errors: the scenario file cannot be read or loaded, a grid key or value is refused,
/// `workers = 0`. Failed runs are rows, not errors.
pub fn run_sweep(
    path: &Path,
    grid: &Grid,
    overrides: &[(String, String)],
    workers: Option<usize>,
    cancel: &AtomicBool,
    progress: &(dyn Fn(&SweepProgress<'_>) + Sync),
) -> Result<Vec<SweepRow>> {
    let source = ScenarioSource::read(path)?;
    grid.check(&source, overrides)?;
    worker_count(workers)?;
    let points = (0..grid.len()).map(|k| (k, grid.point(k))).collect();
    run_points(
        &source,
        &grid.keys(),
        points,
        overrides,
        workers,
        cancel,
        progress,
    )
}

/// A CSV field: as is, or quoted (quotes doubled) when it holds a comma, a quote or a line
/// break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Writes the rows as CSV: a header `KEY...,status,message,<summary fields>`, then one line
/// per row (grid values in their shortest exact form, empty fields for a failed run).
///
/// Errors: [`Error::Io`] naming `target` (used in messages only).
pub fn write_csv(
    out: &mut dyn Write,
    target: &Path,
    keys: &[String],
    rows: &[SweepRow],
) -> Result<()> {
    let columns = summary_columns();
    let mut text = String::new();
    let header = keys
        .iter()
        .map(String::as_str)
        .chain(["status", "message"])
        .chain(columns.iter().map(String::as_str))
        .map(csv_field)
        .collect::<Vec<_>>();
    text += &header.join(",");
    text.push('\n');
    for row in rows {
        let mut fields: Vec<String> = row.values.iter().map(|v| format!("{v}")).collect();
        fields.push(csv_field(&row.status));
        fields.push(csv_field(&row.message));
        fields.extend(row.summary_values().iter().map(|(_, v)| v.csv()));
        text += &fields.join(",");
        text.push('\n');
    }
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|source| Error::io(target, source))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_enumerate_the_product_with_the_last_axis_fastest() {
        let grid = Grid::parse(&["a=1,2", "b=10,20,30"]).unwrap();
        assert_eq!(grid.len(), 6);
        let points: Vec<Vec<f64>> = (0..6).map(|k| grid.point(k)).collect();
        assert_eq!(points[0], vec![1.0, 10.0]);
        assert_eq!(points[2], vec![1.0, 30.0]);
        assert_eq!(points[3], vec![2.0, 10.0]);
        assert_eq!(points[5], vec![2.0, 30.0]);
    }

    #[test]
    fn worker_counts_outside_one_to_the_maximum_are_refused_naming_workers() {
        assert_eq!(worker_count(Some(MAX_WORKERS)).unwrap(), MAX_WORKERS);
        for bad in [0, MAX_WORKERS + 1, 100_000] {
            let message = worker_count(Some(bad)).unwrap_err().to_string();
            assert!(message.contains("workers"), "{message}");
            assert!(message.contains(&bad.to_string()), "{message}");
        }
    }

    #[test]
    fn ranges_include_both_ends() {
        let axis = Axis::parse("k=0.2:3:5:log").unwrap();
        assert_eq!(axis.values.len(), 5);
        assert_eq!(axis.values[0], 0.2);
        assert_eq!(axis.values[4], 3.0);
        let ratios: Vec<f64> = axis.values.windows(2).map(|w| w[1] / w[0]).collect();
        assert!(ratios.iter().all(|r| (r - ratios[0]).abs() < 1e-12));
        let linear = Axis::parse("k=1:2:3").unwrap();
        assert_eq!(linear.values, vec![1.0, 1.5, 2.0]);
        assert_eq!(Axis::parse("k=4:4:1").unwrap().values, vec![4.0]);
    }

    #[test]
    fn literals_fit_integer_and_real_keys() {
        assert_eq!(override_literal(1000.0), "1000");
        assert_eq!(override_literal(0.25), "0.25");
        assert_eq!(override_literal(-3.0), "-3");
        // Beyond exact integers: a float literal, exact.
        let large = override_literal(1e20);
        assert!(large.contains('.') || large.contains('e'), "{large}");
        assert_eq!(large.parse::<f64>().unwrap(), 1e20);
    }

    #[test]
    fn csv_fields_are_quoted_when_needed() {
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(csv_field("plain"), "plain");
    }
}
