//! Stability margins: the values of one numeric scenario key where the closed loop's stability
//! changes, found by scanning a grid and bisecting every change.
//!
//! Two judges of stability: [`MarginMethod::Eigen`] (the growth rate of the linearisation,
//! negative = stable; the bisection follows the sign of that continuous function) and
//! [`MarginMethod::Simulate`] (the scenario run completes without diverging).

use super::linearize::{linearize_with, LinearizeOptions};
use crate::error::{Error, Result};
use crate::scenario::Scenario;
use std::path::Path;

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
            other => Err(Error::config(
                "method",
                format!("expected \"eigen\" or \"simulate\", got \"{other}\""),
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

/// Options of [`stability_margin_report`].
#[derive(Clone, Debug)]
pub struct MarginOptions {
    /// How stability is judged.
    pub method: MarginMethod,
    /// Points of the initial scan (at least 2), ends included.
    pub grid_points: usize,
    /// Space the scan logarithmically (both ends must be positive).
    pub log_grid: bool,
    /// Bisection stops when the bracket is narrower than this fraction of `upper - lower`.
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

/// One evaluation of the judge.
#[derive(Clone, Copy, Debug)]
pub struct MarginSample {
    /// Parameter value.
    pub value: f64,
    /// Whether the loop is stable there.
    pub stable: bool,
    /// Growth rate [1/s] (method `Eigen`).
    pub growth_rate: Option<f64>,
}

/// The result of a margin search.
#[derive(Clone, Debug)]
pub struct MarginReport {
    /// The scenario key.
    pub parameter: String,
    /// The judge.
    pub method: MarginMethod,
    /// Values where stability changes, ascending.
    pub boundaries: Vec<f64>,
    /// Every evaluation, in the order done.
    pub samples: Vec<MarginSample>,
}

impl MarginReport {
    /// Number of evaluations (linearisations or simulations).
    pub fn evaluations(&self) -> usize {
        self.samples.len()
    }
}

/// Checks the range: finite, `lower < upper`, positive for a log grid.
fn check_range(lower: f64, upper: f64, options: &MarginOptions) -> Result<()> {
    if !(lower.is_finite() && upper.is_finite()) {
        return Err(Error::config(
            "range",
            format!("bounds must be finite, got [{lower}, {upper}]"),
        ));
    }
    if lower >= upper {
        return Err(Error::config(
            "range",
            format!("empty or inverted range: lower {lower} must be below upper {upper}"),
        ));
    }
    if options.log_grid && lower <= 0.0 {
        return Err(Error::config(
            "range",
            format!("a logarithmic grid needs positive bounds, got lower {lower}"),
        ));
    }
    if options.grid_points < 2 {
        return Err(Error::config(
            "grid_points",
            format!("at least 2, got {}", options.grid_points),
        ));
    }
    Ok(())
}

/// The scenario with `parameter = value` on top of `overrides`. When the scenario loads without
/// the parameter but not with it, the error names the parameter: either its value is out of
/// range (the schema's own message, which names the key) or the key is unknown or not a
/// number (serde's "unknown field" or "invalid type").
pub fn scenario_with(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
    value: f64,
) -> Result<Scenario> {
    let mut all = overrides.to_vec();
    all.push((parameter.to_string(), toml::Value::Float(value).to_string()));
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
    samples: Vec<MarginSample>,
}

impl Judge<'_> {
    /// Evaluates stability at `value`; returns a signed indicator (negative = stable).
    fn indicator(&mut self, value: f64) -> Result<f64> {
        let scenario = scenario_with(self.path, self.overrides, self.parameter, value)?;
        let (stable, growth_rate) = match self.options.method {
            MarginMethod::Eigen => {
                let lin = linearize_with(&scenario, &self.options.linearize)?;
                (lin.stable, Some(lin.growth_rate))
            }
            MarginMethod::Simulate => {
                let (_, summary) = crate::closed_loop::run(&scenario, |_, _| {})?;
                (summary.status == "completed", None)
            }
        };
        self.samples.push(MarginSample {
            value,
            stable,
            growth_rate,
        });
        Ok(growth_rate.unwrap_or(if stable { -1.0 } else { 1.0 }))
    }
}

/// The scan's values.
fn grid(lower: f64, upper: f64, options: &MarginOptions) -> Vec<f64> {
    let n = options.grid_points;
    (0..n)
        .map(|k| {
            let a = k as f64 / (n - 1) as f64;
            if options.log_grid {
                (lower.ln() + a * (upper.ln() - lower.ln())).exp()
            } else {
                lower + a * (upper - lower)
            }
        })
        .collect()
}

/// The values of `parameter` in `[lower, upper]` where stability changes, with every
/// evaluation (see the module doc).
pub fn stability_margin_report(
    path: &Path,
    overrides: &[(String, String)],
    parameter: &str,
    lower: f64,
    upper: f64,
    options: &MarginOptions,
) -> Result<MarginReport> {
    check_range(lower, upper, options)?;
    let mut judge = Judge {
        path,
        overrides,
        parameter,
        options,
        samples: Vec::new(),
    };
    let values = grid(lower, upper, options);
    let mut signs = Vec::with_capacity(values.len());
    for &value in &values {
        signs.push(judge.indicator(value)? >= 0.0);
    }
    let width = options.relative_tolerance * (upper - lower);
    let mut boundaries = Vec::new();
    for k in 1..values.len() {
        if signs[k] == signs[k - 1] {
            continue;
        }
        let (mut a, mut b) = (values[k - 1], values[k]);
        while b - a > width {
            let middle = 0.5 * (a + b);
            if (judge.indicator(middle)? >= 0.0) == signs[k - 1] {
                a = middle;
            } else {
                b = middle;
            }
        }
        boundaries.push(0.5 * (a + b));
    }
    Ok(MarginReport {
        parameter: parameter.to_string(),
        method: options.method,
        boundaries,
        samples: judge.samples,
    })
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
    Ok(stability_margin_report(path, overrides, parameter, lower, upper, &options)?.boundaries)
}
