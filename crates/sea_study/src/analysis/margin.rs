//! Stability margins: the values of one numeric scenario key where the closed loop's stability
//! changes, found by scanning a grid and bisecting every change.
//!
//! Two judges of stability: [`MarginMethod::Eigen`] (the growth rate of the linearisation,
//! negative = stable; the bisection follows the sign of that continuous function) and
//! [`MarginMethod::Simulate`] (the scenario run completes without diverging or falling).
//! The eigen judge's linearisation is about the loop's equilibrium; where Newton's method
//! finds none (e.g. feet creeping on the compliant ground, or a controller that cannot hold
//! its reference) each such evaluation is marked ([`MarginReport::without_equilibrium`]), its
//! verdict is no judgement of stability, and a boundary next to one is marked too
//! ([`MarginReport::boundaries_beside_no_equilibrium`]): it may be the edge of the
//! equilibria rather than a change of stability.
//!
//! The scan includes the scenario's own value of the parameter when it lies in the range
//! ([`scenario_value`]), so that a stable island narrower than the grid's spacing around it
//! is still seen and bisected on both sides; the report names the stable interval that
//! contains the scenario's value ([`MarginReport::island`]) and, when the scan saw one side
//! only, says so ([`MarginReport::conclusion`]) instead of "no boundary".
//!
//! A key that takes whole numbers (e.g. `sensing.delay_inner_periods`) is scanned at whole
//! numbers only: the grid rounded, bisection down to neighbours, and each boundary reported
//! halfway between the last value on one side and the first on the other (8.5: one verdict
//! at 8, the other at 9; [`MarginReport::integer`]).

use super::linearize::{linearize_with, LinearizeOptions};
use crate::error::{Error, Result};
use sea_scenario::run::run_with_sinks;
use sea_scenario::Scenario;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// How stability is judged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarginMethod {
    /// Eigenvalues of the linearised closed loop.
    Eigen,
    /// A simulation of the scenario completes.
    Simulate,
}

impl MarginMethod {
    /// Parses "eigen" or "simulate".
    pub fn parse(name: &str) -> Result<MarginMethod> {
        match name {
            "eigen" => Ok(MarginMethod::Eigen),
            "simulate" => Ok(MarginMethod::Simulate),
            other => Err(Error::argument(
                "method",
                "\"eigen\" or \"simulate\"",
                format!("\"{other}\""),
            )),
        }
    }

    /// "eigen" or "simulate".
    pub fn name(&self) -> &'static str {
        match self {
            MarginMethod::Eigen => "eigen",
            MarginMethod::Simulate => "simulate",
        }
    }
}

/// The most points of the initial scan ([`MarginOptions::grid_points`]).
pub const MAX_SCAN_POINTS: usize = 10_000;

/// The smallest [`MarginOptions::relative_tolerance`]: about 40 bisections.
pub const MIN_RELATIVE_TOLERANCE: f64 = 1e-12;

/// Options of [`stability_margin_report`].
#[derive(Clone, Debug)]
pub struct MarginOptions {
    /// How stability is judged.
    pub method: MarginMethod,
    /// Points of the initial scan (2 to [`MAX_SCAN_POINTS`]), ends included.
    pub grid_points: usize,
    /// Space the scan logarithmically (both ends must be positive).
    pub log_grid: bool,
    /// Bisection stops when the bracket is narrower than this fraction of `upper - lower`
    /// ([`MIN_RELATIVE_TOLERANCE`] to below 1).
    pub relative_tolerance: f64,
    /// Linearisation options (method `Eigen`; its time and sampling are used).
    pub linearize: LinearizeOptions,
}

impl Default for MarginOptions {
    fn default() -> Self {
        Self {
            method: MarginMethod::Eigen,
            grid_points: 9,
            log_grid: false,
            relative_tolerance: 1e-3,
            linearize: LinearizeOptions {
                check_step: None,
                ..Default::default()
            },
        }
    }
}

/// How a caller follows and stops a [`stability_margin_report`].
#[derive(Clone, Copy)]
pub struct MarginWatch<'a> {
    /// Once raised no evaluation starts and a simulation under way stops at its next sample.
    pub cancel: &'a AtomicBool,
    /// Told of every evaluation as it ends.
    pub on_sample: &'a dyn Fn(&MarginSample),
}

impl<'a> MarginWatch<'a> {
    /// Stopped by `cancel` alone, telling no one of the evaluations.
    pub fn cancel_only(cancel: &'a AtomicBool) -> Self {
        Self {
            cancel,
            on_sample: &|_| {},
        }
    }
}

/// The residual `|f|_inf` of Newton's method [units of the tangent derivative] above which the
/// eigen judge's linearisation is taken as about no equilibrium
/// ([`MarginSample::no_equilibrium_residual`]). Newton's own tolerance is 1e-8
/// ([`LinearizeOptions::tolerance`](super::LinearizeOptions)); round-off stops its line search
/// above it at some real equilibria (measured on the shipped scenarios: up to 7.8e-6, the
/// paper's tracking at a damping of 1e-4), where no equilibrium left 10.9 to 3.8e5.
pub const NO_EQUILIBRIUM_RESIDUAL: f64 = 1e-3;

/// One evaluation of the judge.
#[derive(Clone, Copy, Debug)]
pub struct MarginSample {
    /// Parameter value.
    pub value: f64,
    /// Whether the loop is stable there.
    pub stable: bool,
    /// Growth rate [1/s] (method `Eigen`).
    pub growth_rate: Option<f64>,
    /// Newton's residual `|f|_inf` where it stopped, when it is above
    /// [`NO_EQUILIBRIUM_RESIDUAL`] (or NaN): no equilibrium was found, and the growth rate
    /// about that point does not judge the loop's stability (method `Eigen`; `None` at an
    /// equilibrium, and for `Simulate`).
    pub no_equilibrium_residual: Option<f64>,
}

/// The result of a margin search.
#[derive(Clone, Debug)]
pub struct MarginReport {
    /// The scenario key.
    pub parameter: String,
    /// The judge.
    pub method: MarginMethod,
    /// The scanned range `[lower, upper]`.
    pub range: [f64; 2],
    /// The scenario's own value of the parameter (with the overrides; `None` when the key is
    /// not one [`scenario_value`] can read).
    pub own_value: Option<f64>,
    /// Values where stability changes, ascending.
    pub boundaries: Vec<f64>,
    /// The boundaries (also in [`Self::boundaries`]) whose final bracket has an evaluation
    /// about no equilibrium at one end: the edge of the equilibria may be what was found,
    /// not a change of stability.
    pub boundaries_beside_no_equilibrium: Vec<f64>,
    /// Whether the key takes whole numbers (each boundary then lies halfway between two).
    pub integer: bool,
    /// Every evaluation, in the order done.
    pub samples: Vec<MarginSample>,
    /// Whether the cancellation flag stopped the scan before its end: the samples and
    /// boundaries are those found so far, and more may lie in the range.
    pub interrupted: bool,
}

/// What the scan saw over its whole range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarginConclusion {
    /// Every evaluation was stable: no boundary inside the range (one may lie outside).
    StableOverRange,
    /// Every evaluation was unstable: no boundary inside the range (a stable island narrower
    /// than the scan's resolution, or one outside the range, is not excluded).
    UnstableOverRange,
    /// Stability changes inside the range ([`MarginReport::boundaries`]).
    Boundaries,
    /// The scan was stopped before its end ([`MarginReport::interrupted`]): the boundaries
    /// found so far are boundaries, and nothing is said of the rest of the range.
    Interrupted,
}

impl MarginConclusion {
    /// `"stable_over_range"`, `"unstable_over_range"` or `"boundaries"`.
    pub fn name(&self) -> &'static str {
        match self {
            MarginConclusion::StableOverRange => "stable_over_range",
            MarginConclusion::UnstableOverRange => "unstable_over_range",
            MarginConclusion::Boundaries => "boundaries",
            MarginConclusion::Interrupted => "interrupted",
        }
    }
}

/// One end of a stable interval: a boundary found by bisection, or the end of the scanned
/// range (the interval may extend beyond it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IslandEnd {
    /// A stability boundary.
    Boundary(f64),
    /// The scanned range ends here, still stable.
    RangeEnd(f64),
}

impl IslandEnd {
    /// The value.
    pub fn value(&self) -> f64 {
        match *self {
            IslandEnd::Boundary(value) | IslandEnd::RangeEnd(value) => value,
        }
    }
}

impl MarginReport {
    /// Number of evaluations (linearisations or simulations).
    pub fn evaluations(&self) -> usize {
        self.samples.len()
    }

    /// The evaluations whose linearisation is about no equilibrium
    /// ([`MarginSample::no_equilibrium_residual`]): their verdicts are no judgement of
    /// stability.
    pub fn without_equilibrium(&self) -> impl Iterator<Item = &MarginSample> {
        self.samples
            .iter()
            .filter(|s| s.no_equilibrium_residual.is_some())
    }

    /// Whether the eigen method's growth rate came out the same at every one of three or more
    /// evaluations: the parameter then does not enter the linearisation about the standing
    /// equilibrium (a `walking.*` key of a walk, a key read only while the robot moves), and
    /// the verdict says nothing about it.
    pub fn growth_unchanged(&self) -> bool {
        let mut growths = self.samples.iter().filter_map(|s| s.growth_rate);
        let Some(first) = growths.next() else {
            return false;
        };
        self.samples.len() >= 3
            && self.samples.iter().all(|s| s.growth_rate.is_some())
            && growths.all(|g| g == first)
    }

    /// Whether every evaluation was stable, every one unstable, or stability changes; or that
    /// the scan was stopped before its end.
    pub fn conclusion(&self) -> MarginConclusion {
        if self.interrupted {
            MarginConclusion::Interrupted
        } else if !self.boundaries.is_empty() {
            MarginConclusion::Boundaries
        } else if self.samples.iter().all(|s| s.stable) {
            MarginConclusion::StableOverRange
        } else {
            MarginConclusion::UnstableOverRange
        }
    }

    /// Whether the scenario's own value was judged stable (`None` when it was not evaluated:
    /// unknown, or outside the range).
    pub fn own_value_stable(&self) -> Option<bool> {
        let own = self.own_value?;
        self.samples
            .iter()
            .find(|s| s.value == own)
            .map(|s| s.stable)
    }

    /// The stable interval that contains the scenario's own value: its ends are the nearest
    /// boundaries on either side, or the range's ends. `None` when the own value is unstable
    /// or was not evaluated, or the scan was stopped before its end (a boundary nearer the own
    /// value may lie where it did not look).
    pub fn island(&self) -> Option<[IslandEnd; 2]> {
        if self.interrupted || self.own_value_stable() != Some(true) {
            return None;
        }
        let own = self.own_value?;
        let below = self.boundaries.iter().rev().find(|&&b| b < own);
        let above = self.boundaries.iter().find(|&&b| b > own);
        Some([
            below.map_or(IslandEnd::RangeEnd(self.range[0]), |&b| {
                IslandEnd::Boundary(b)
            }),
            above.map_or(IslandEnd::RangeEnd(self.range[1]), |&b| {
                IslandEnd::Boundary(b)
            }),
        ])
    }
}

/// The sections of a scenario whose keys [`scenario_value`] reads, as they were parsed
/// (defaults filled in).
#[derive(serde::Serialize)]
struct ParsedSections<'a> {
    sensing: &'a sea_scenario::SensingConfig,
    plant: &'a sea_scenario::PlantConfig,
    controller: toml::Table,
    reference: &'a sea_scenario::ReferenceConfig,
    simulation: &'a sea_scenario::SimulationConfig,
    #[serde(skip_serializing_if = "Option::is_none")]
    walking: Option<&'a sea_ctrl::walking::WalkingSettings>,
}

/// The value of the numeric key `parameter` (dotted, e.g. `controller.stiffness_estimate_scale`)
/// in the scenario at `path` with `overrides`, the schema's default when the file does not set
/// it. Reads the keys of `[sensing]`, `[plant]`, `[controller]`, `[reference]`,
/// `[simulation]` and (for the paper's iCub) `[walking]` as parsed; any other key
/// (`actuators.damping`, another robot's `walking.*`) only as the file and the overrides give
/// it; `Ok(None)` for such a key left to its default, or one without a number.
pub fn scenario_value(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
) -> Result<Option<f64>> {
    Ok(match scenario_number(path, overrides, parameter)? {
        Some(toml::Value::Float(x)) => Some(x),
        Some(toml::Value::Integer(n)) => Some(n as f64),
        _ => None,
    })
}

/// The parsed scenario's value of `parameter` as TOML (a float, an integer, or anything else
/// the key holds); `None` when [`scenario_value`] finds no value.
fn scenario_number(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
) -> Result<Option<toml::Value>> {
    let scenario = Scenario::from_file(path, overrides)?;
    let sections = ParsedSections {
        sensing: &scenario.sensing,
        plant: &scenario.plant,
        controller: scenario
            .controller
            .table()
            .map_err(|e| Error::config(parameter, format!("reading the scenario's value: {e}")))?,
        reference: &scenario.reference,
        simulation: &scenario.simulation,
        // Another robot's walking keys left out are scaled to it at build: only those the
        // file gives are its own values then (read below, as given).
        walking: scenario
            .walking
            .as_ref()
            .filter(|_| scenario.walking_given.is_none()),
    };
    let table = toml::Table::try_from(&sections)
        .map_err(|e| Error::config(parameter, format!("reading the scenario's value: {e}")))?;
    let mut value = Some(&toml::Value::Table(table));
    for part in parameter.split('.') {
        value = value.and_then(|v| v.get(part));
    }
    Ok(value
        .cloned()
        .or_else(|| scenario.origin.given_value(parameter)))
}

/// The name the range's errors give it: the arguments of [`stability_margin_report`].
pub const RANGE_ARGUMENT: &str = "lower, upper";

/// Checks the range: finite, `lower < upper`, positive for a log grid; the scan's points and
/// the bisection's tolerance within their bounds. Errors name the arguments
/// ([`RANGE_ARGUMENT`], `grid_points`, `relative_tolerance`).
fn check_range(lower: f64, upper: f64, options: &MarginOptions) -> Result<()> {
    let range = format!("[{lower}, {upper}]");
    if !(lower.is_finite() && upper.is_finite()) {
        return Err(Error::argument(RANGE_ARGUMENT, "finite bounds", range));
    }
    if lower >= upper {
        let rule = "lower below upper (an empty or inverted range)";
        return Err(Error::argument(RANGE_ARGUMENT, rule, range));
    }
    if options.log_grid && lower <= 0.0 {
        let rule = "positive bounds for a logarithmic grid";
        return Err(Error::argument(RANGE_ARGUMENT, rule, range));
    }
    if !(2..=MAX_SCAN_POINTS).contains(&options.grid_points) {
        let rule = format!("from 2 to {MAX_SCAN_POINTS}");
        return Err(Error::argument("grid_points", rule, options.grid_points));
    }
    let tolerance = options.relative_tolerance;
    if !(MIN_RELATIVE_TOLERANCE..1.0).contains(&tolerance) {
        let rule = format!("from {MIN_RELATIVE_TOLERANCE:e} to below 1");
        return Err(Error::argument("relative_tolerance", rule, tolerance));
    }
    Ok(())
}

/// The scenario with `parameter = literal` (a TOML value: a float, or an integer for a key
/// that takes whole numbers) on top of `overrides`. When the scenario loads without the
/// parameter but not with it, the error names the parameter: either its value is out of range
/// (the schema's own message, which names the key) or the key is unknown or not a number
/// (serde's "unknown field" or "invalid type").
pub fn scenario_with(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
    literal: toml::Value,
) -> Result<Scenario> {
    let mut all = overrides.to_vec();
    all.push((parameter.to_string(), literal.to_string()));
    match Scenario::from_file(path, &all) {
        Ok(scenario) => Ok(scenario),
        Err(Error::Scenario {
            key, rule: message, ..
        }) if key != parameter || message.contains("invalid type") => {
            // Is the base scenario itself at fault? Then its error stands.
            Scenario::from_file(path, overrides)?;
            Err(Error::config(
                parameter,
                format!("not a numeric scenario key (unknown, or not a number): {message}"),
            ))
        }
        Err(other) => Err(other),
    }
}

/// The judge, with its evaluation log.
struct Judge<'a> {
    path: &'a Path,
    overrides: &'a [(String, String)],
    parameter: &'a str,
    options: &'a MarginOptions,
    /// Whether the key takes whole numbers (the values are then integral).
    integer: bool,
    samples: Vec<MarginSample>,
    /// The cancellation flag and the progress callback.
    watch: MarginWatch<'a>,
}

impl Judge<'_> {
    /// A numerical failure of the evaluation at `value`, its operation naming the key and the
    /// value (a scan's other errors pass through unchanged).
    fn at_value(&self, error: Error, value: f64) -> Error {
        match error {
            Error::Dynamics(sea_dyn::Error::Numerical { operation, detail }) => {
                let operation = format!("{operation} at {} = {value:e}", self.parameter);
                Error::Dynamics(sea_dyn::Error::numerical(operation, detail))
            }
            other => other,
        }
    }

    /// Whether the evaluation at `a` or at `b` was about no equilibrium.
    fn without_equilibrium_at(&self, a: f64, b: f64) -> bool {
        self.samples
            .iter()
            .any(|s| (s.value == a || s.value == b) && s.no_equilibrium_residual.is_some())
    }

    /// Evaluates stability at `value`; returns a signed indicator (negative = stable), or
    /// `None` when the cancellation flag kept the evaluation from its end.
    fn indicator(&mut self, value: f64) -> Result<Option<f64>> {
        if self.watch.cancel.load(Ordering::Relaxed) {
            return Ok(None);
        }
        let literal = if self.integer {
            toml::Value::Integer(value as i64)
        } else {
            toml::Value::Float(value)
        };
        let scenario = scenario_with(self.path, self.overrides, self.parameter, literal)?;
        let (stable, growth_rate, no_equilibrium_residual) = match self.options.method {
            MarginMethod::Eigen => {
                let lin = linearize_with(&scenario, &self.options.linearize)
                    .map_err(|e| self.at_value(e, value))?;
                let residual = lin.equilibrium.residual;
                // A NaN residual is no equilibrium either.
                let none = residual.is_nan() || residual > NO_EQUILIBRIUM_RESIDUAL;
                (lin.stable, Some(lin.growth_rate), none.then_some(residual))
            }
            MarginMethod::Simulate => {
                let summary = run_with_sinks(&scenario, &mut [], self.watch.cancel, |_, _| {})?;
                if summary.interrupted() {
                    return Ok(None);
                }
                (summary.completed(), None, None)
            }
        };
        let sample = MarginSample {
            value,
            stable,
            growth_rate,
            no_equilibrium_residual,
        };
        (self.watch.on_sample)(&sample);
        self.samples.push(sample);
        Ok(Some(growth_rate.unwrap_or(if stable { -1.0 } else { 1.0 })))
    }
}

/// The scan's values (rounded to whole numbers, ends inside the range and duplicates
/// dropped, for an `integer` key).
fn grid(lower: f64, upper: f64, options: &MarginOptions, integer: bool) -> Vec<f64> {
    let n = options.grid_points;
    let mut values: Vec<f64> = (0..n)
        .map(|k| {
            let a = k as f64 / (n - 1) as f64;
            if options.log_grid {
                (lower.ln() + a * (upper.ln() - lower.ln())).exp()
            } else {
                lower + a * (upper - lower)
            }
        })
        .collect();
    if integer {
        for value in &mut values {
            *value = value.round().clamp(lower.ceil(), upper.floor());
        }
        values.dedup();
    }
    values
}

/// Whether a bracket `[a, b]` is narrow enough to stop bisecting: neighbours for an
/// integer key, else narrower than `width`.
fn bracket_closed(a: f64, b: f64, width: f64, integer: bool) -> bool {
    if integer {
        b - a <= 1.0
    } else {
        b - a <= width
    }
}

/// The values of `parameter` in `[lower, upper]` where stability changes, with every
/// evaluation (see the module doc), each told to `watch` as it ends. Once `watch.cancel` is
/// raised no evaluation starts, a simulation under way stops at its next sample, and the
/// report holds what was found so far ([`MarginReport::interrupted`]).
pub fn stability_margin_report(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
    lower: f64,
    upper: f64,
    options: &MarginOptions,
    watch: MarginWatch<'_>,
) -> Result<MarginReport> {
    check_range(lower, upper, options)?;
    let integer = matches!(
        scenario_number(path, overrides, parameter)?,
        Some(toml::Value::Integer(_))
    );
    if integer && lower.ceil() >= upper.floor() {
        let rule = format!("a range that holds two whole numbers ({parameter} takes them)");
        return Err(Error::argument(
            RANGE_ARGUMENT,
            rule,
            format!("[{lower}, {upper}]"),
        ));
    }
    let mut judge = Judge {
        path,
        overrides,
        parameter,
        options,
        integer,
        samples: Vec::new(),
        watch,
    };
    let own_value = scenario_value(path, overrides, parameter)?;
    let mut values = grid(lower, upper, options, integer);
    if let Some(own) = own_value.filter(|v| (lower..=upper).contains(v)) {
        if !values.contains(&own) {
            values.push(own);
            values.sort_by(f64::total_cmp);
        }
    }
    let width = options.relative_tolerance * (upper - lower);
    let mut boundaries = Vec::new();
    let done = find_boundaries(&mut judge, &values, width, &mut boundaries)?;
    let (boundaries, beside): (Vec<_>, Vec<_>) = boundaries.into_iter().unzip();
    let boundaries_beside_no_equilibrium = boundaries
        .iter()
        .zip(beside)
        .filter_map(|(&boundary, beside)| beside.then_some(boundary))
        .collect();
    Ok(MarginReport {
        parameter: parameter.to_string(),
        method: options.method,
        range: [lower, upper],
        own_value,
        boundaries,
        boundaries_beside_no_equilibrium,
        integer,
        samples: judge.samples,
        interrupted: !done,
    })
}

/// Scans `values` (ascending) with `judge` and bisects every change of stability down to
/// `width`, each boundary found pushed onto `boundaries` with whether an end of its final
/// bracket had no equilibrium; `Ok(false)` when the judge was cancelled before the end.
fn find_boundaries(
    judge: &mut Judge<'_>,
    values: &[f64],
    width: f64,
    boundaries: &mut Vec<(f64, bool)>,
) -> Result<bool> {
    let mut signs = Vec::with_capacity(values.len());
    for &value in values {
        let Some(indicator) = judge.indicator(value)? else {
            return Ok(false);
        };
        signs.push(indicator >= 0.0);
    }
    for k in 1..values.len() {
        if signs[k] == signs[k - 1] {
            continue;
        }
        let (mut a, mut b) = (values[k - 1], values[k]);
        while !bracket_closed(a, b, width, judge.integer) {
            let middle = if judge.integer {
                (0.5 * (a + b)).floor()
            } else {
                0.5 * (a + b)
            };
            let Some(indicator) = judge.indicator(middle)? else {
                return Ok(false);
            };
            if (indicator >= 0.0) == signs[k - 1] {
                a = middle;
            } else {
                b = middle;
            }
        }
        boundaries.push((0.5 * (a + b), judge.without_equilibrium_at(a, b)));
    }
    Ok(true)
}

/// The values of `parameter` in `[lower, upper]` where stability changes (ascending; empty
/// when it never changes), judged by `method`, with the default options otherwise.
pub fn stability_margin(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
    lower: f64,
    upper: f64,
    method: MarginMethod,
) -> Result<Vec<f64>> {
    let options = MarginOptions {
        method,
        ..Default::default()
    };
    let never = AtomicBool::new(false);
    let watch = MarginWatch::cancel_only(&never);
    let report =
        stability_margin_report(path, overrides, parameter, lower, upper, &options, watch)?;
    Ok(report.boundaries)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A report of eigen evaluations with these growth rates (`None`: a simulation's verdict).
    fn report_of(growths: &[Option<f64>]) -> MarginReport {
        let samples = growths
            .iter()
            .enumerate()
            .map(|(k, &growth_rate)| MarginSample {
                value: k as f64,
                stable: growth_rate.is_some_and(|g| g < 0.0),
                growth_rate,
                no_equilibrium_residual: None,
            })
            .collect();
        MarginReport {
            parameter: "walking.com_height".into(),
            method: MarginMethod::Eigen,
            range: [0.0, 1.0],
            own_value: None,
            boundaries: Vec::new(),
            boundaries_beside_no_equilibrium: Vec::new(),
            integer: false,
            samples,
            interrupted: false,
        }
    }

    #[test]
    fn a_growth_rate_the_same_at_three_evaluations_or_more_is_unchanged() {
        let g = Some(4e-4);
        assert!(report_of(&[g, g, g]).growth_unchanged());
        assert!(!report_of(&[g, g]).growth_unchanged(), "two are too few");
        assert!(!report_of(&[g, g, Some(4.000001e-4)]).growth_unchanged());
        assert!(
            !report_of(&[None, None, None]).growth_unchanged(),
            "simulated"
        );
        assert!(!report_of(&[]).growth_unchanged());
    }
}
