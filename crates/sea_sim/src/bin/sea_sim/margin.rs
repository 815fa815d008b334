//! `sea-sim margin`: where the closed loop's stability changes along one key.

use crate::common::{
    fixed_number, parse_key_value, parse_range, print_out, readable_number, say, Outcome,
};
use crate::signals::Interrupts;
use clap::Args;
use sea_sim::analysis::margin::{
    MarginOptions, MarginReport, MarginSample, MarginWatch, MAX_SCAN_POINTS, MIN_RELATIVE_TOLERANCE,
};
use sea_sim::output::{check_distinct, OutputFile};
use sea_sim::scenario::Scenario;
use std::path::PathBuf;

/// Options of `sea-sim margin`.
#[derive(Args, Debug)]
pub(crate) struct MarginArgs {
    /// Scenario file (TOML).
    scenario: PathBuf,
    /// The numeric scenario key to vary, e.g. `actuators.damping`.
    #[arg(long, value_name = "KEY")]
    param: String,
    /// The range searched, `LOWER:UPPER`.
    #[arg(long, value_name = "LOWER:UPPER", value_parser = parse_range, allow_hyphen_values = true)]
    range: (f64, f64),
    /// How stability is judged: `eigen` (growth rate of the linearisation) or `simulate`
    /// (the run completes).
    #[arg(long, value_name = "METHOD", default_value = "eigen",
          value_parser = ["eigen", "simulate"])]
    method: String,
    /// Points of the initial scan, ends included.
    #[arg(long, value_name = "N", default_value_t = MarginOptions::default().grid_points as u32,
          value_parser = clap::value_parser!(u32).range(2..=MAX_SCAN_POINTS as i64))]
    points: u32,
    /// Space the scan logarithmically (both ends positive).
    #[arg(long)]
    log: bool,
    /// Bisection stops below this fraction of `UPPER - LOWER` (1e-12 to below 1).
    #[arg(long, value_name = "F", default_value_t = MarginOptions::default().relative_tolerance,
          value_parser = parse_tolerance)]
    tolerance: f64,
    /// Override a scenario value, e.g. `--set simulation.duration_s=2` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
    /// Also write the JSON report to FILE.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Print the JSON report on stdout instead of a table.
    #[arg(long)]
    json: bool,
    /// No progress lines on stderr (one per evaluation as it ends).
    #[arg(short, long)]
    quiet: bool,
}

/// The progress line of an evaluation that ended: the value and its verdict.
fn sample_line(parameter: &str, sample: &MarginSample) -> String {
    let verdict = if sample.stable { "stable" } else { "unstable" };
    let no_equilibrium = no_equilibrium_note(sample, "; ");
    let growth = sample.growth_rate.map_or(String::new(), |g| {
        format!(
            " (growth {} 1/s{no_equilibrium})",
            fixed_number(g, 12, 4).trim_start()
        )
    });
    format!(
        "sea-sim: margin {parameter} = {}: {verdict}{growth}",
        readable_number(sample.value)
    )
}

/// `separator` and "no equilibrium found (residual R)" for an evaluation whose
/// linearisation is about no equilibrium; empty otherwise.
fn no_equilibrium_note(sample: &MarginSample, separator: &str) -> String {
    sample
        .no_equilibrium_residual
        .map_or(String::new(), |residual| {
            format!("{separator}no equilibrium found (residual {residual:.2e})")
        })
}

/// The warning that closes the verdict when Newton's method found no equilibrium at some
/// evaluations: how many, the boundaries beside them, and what to try.
fn no_equilibrium_warning(report: &MarginReport) -> Option<String> {
    let count = report.without_equilibrium().count();
    let largest = report
        .without_equilibrium()
        .filter_map(|s| s.no_equilibrium_residual)
        .fold(0.0_f64, f64::max);
    let beside = match report.boundaries_beside_no_equilibrium.as_slice() {
        [] => String::new(),
        values => {
            let values: Vec<String> = values.iter().map(|&v| readable_number(v)).collect();
            format!(
                "; the boundaries at [{}] lie next to such an evaluation and may be the edge of \
                 the equilibria rather than of stability",
                values.join(", ")
            )
        }
    };
    (count > 0).then(|| {
        format!(
            "; but at {count} of {} evaluations Newton's method found no equilibrium (residual \
             up to {largest:.2e}), so their verdicts do not judge stability{beside} (feet \
             creeping on the compliant ground have none: where the scenario allows, weld them \
             with --set plant.contact_model=bilateral, or judge with --method simulate)",
            report.evaluations(),
        )
    })
}

/// `sea-sim margin`: the report as a table or (`--json`) JSON on stdout; JSON in `--out`.
/// After a stop signal no evaluation starts, a simulation under way stops at its next sample,
/// and the report of what was found so far is written (conclusion "interrupted").
pub(crate) fn run_margin(args: &MarginArgs, interrupts: &Interrupts) -> sea_sim::Result<Outcome> {
    use sea_sim::analysis::margin::{stability_margin_report, MarginMethod};
    let out = match &args.out {
        Some(path) => {
            // A scenario that does not parse is the analysis's error, after the range's.
            let inputs = match Scenario::from_file(&args.scenario, &args.overrides) {
                Ok(scenario) => scenario.input_files(),
                Err(_) => vec![("the scenario file", args.scenario.clone())],
            };
            check_distinct(&inputs, &[("--out", path)])?;
            Some(OutputFile::create(path)?)
        }
        None => None,
    };
    let options = MarginOptions {
        method: MarginMethod::parse(&args.method)?,
        grid_points: args.points as usize,
        log_grid: args.log,
        relative_tolerance: args.tolerance,
        ..Default::default()
    };
    let (lower, upper) = args.range;
    let report = stability_margin_report(
        &args.scenario,
        &args.overrides,
        &args.param,
        lower,
        upper,
        &options,
        MarginWatch {
            cancel: &interrupts.stop,
            on_sample: &|sample| {
                if !args.quiet {
                    say(sample_line(&args.param, sample));
                }
            },
        },
    )
    .map_err(|e| {
        let flags = [
            (sea_sim::analysis::margin::RANGE_ARGUMENT, "--range"),
            ("grid_points", "--points"),
            ("relative_tolerance", "--tolerance"),
        ];
        e.argument_named(&flags)
    })?;
    let text = serde_json::to_string_pretty(&margin_json(&report))
        .map_err(|e| sea_sim::Error::Output(format!("margin JSON: {e}")))?;
    // Printed first: a report that cannot be written to `--out` (a full disk) is not lost.
    let printed = print_out(if args.json {
        text.clone()
    } else {
        margin_table(&report)
    });
    if let Some(mut out) = out {
        out.write_all(text.as_bytes())?;
        out.write_all(b"\n")?;
        out.commit()?;
    }
    printed?;
    // A signal that came as the last evaluation ended stopped nothing: the scan is whole.
    Ok(match interrupts.received() {
        Some(sig) if report.interrupted => Outcome::Interrupted(sig),
        _ => Outcome::Completed,
    })
}

/// The JSON report of `sea-sim margin`.
fn margin_json(report: &MarginReport) -> serde_json::Value {
    let samples: Vec<serde_json::Value> = report
        .samples
        .iter()
        .map(|s| {
            serde_json::json!({
                "value": s.value,
                "stable": s.stable,
                "growth_rate": s.growth_rate,
                "no_equilibrium_residual": s.no_equilibrium_residual,
            })
        })
        .collect();
    serde_json::json!({
        "parameter": report.parameter,
        "method": report.method.name(),
        "range": report.range,
        "boundaries": report.boundaries,
        "integer": report.integer,
        "conclusion": report.conclusion().name(),
        "own_value": report.own_value,
        "own_value_stable": report.own_value_stable(),
        "stable_island": report.island().map(|ends| ends.map(|end| end.value())),
        "evaluations": report.evaluations(),
        "evaluations_without_equilibrium": report.without_equilibrium().count(),
        "boundaries_beside_no_equilibrium": report.boundaries_beside_no_equilibrium,
        "growth_unchanged": report.growth_unchanged(),
        "samples": samples,
        "interrupted": report.interrupted,
    })
}

/// What the margin scan found, in words: the boundaries or the range's one verdict, then the
/// scenario's own value and its stable island.
pub(crate) fn margin_verdict(report: &sea_sim::analysis::margin::MarginReport) -> String {
    use sea_sim::analysis::margin::{IslandEnd, MarginConclusion};
    let [lower, upper] = report.range;
    let (lower_text, upper_text) = (readable_number(lower), readable_number(upper));
    let mut text = match report.conclusion() {
        MarginConclusion::Boundaries if report.integer => {
            let between: Vec<String> = report
                .boundaries
                .iter()
                .map(|b| format!("between {} and {}", b - 0.5, b + 0.5))
                .collect();
            format!("stability changes {}", between.join(", "))
        }
        MarginConclusion::Boundaries => {
            let boundaries: Vec<String> = report
                .boundaries
                .iter()
                .map(|&b| readable_number(b))
                .collect();
            format!("stability changes at [{}]", boundaries.join(", "))
        }
        MarginConclusion::StableOverRange => format!("stable over [{lower_text}, {upper_text}]"),
        MarginConclusion::UnstableOverRange => {
            format!("unstable over the whole scanned range [{lower_text}, {upper_text}]")
        }
        MarginConclusion::Interrupted if report.boundaries.is_empty() => {
            "stopped before the scan's end, no boundary bisected yet".to_string()
        }
        MarginConclusion::Interrupted => {
            let boundaries: Vec<String> = report
                .boundaries
                .iter()
                .map(|&b| readable_number(b))
                .collect();
            format!(
                "stopped before the scan's end; stability changes at [{}] and maybe elsewhere",
                boundaries.join(", ")
            )
        }
    };
    let end = |end: IslandEnd| match end {
        IslandEnd::Boundary(value) => readable_number(value),
        IslandEnd::RangeEnd(value) => format!("{} (range end)", readable_number(value)),
    };
    let own_text = report.own_value.map(readable_number);
    let own = own_text.as_deref().unwrap_or("NaN");
    text += &match (report.own_value, report.own_value_stable(), report.island()) {
        (_, _, Some([low, high])) => format!(
            "; the scenario's own value {own} lies in the stable island [{}, {}]",
            end(low),
            end(high)
        ),
        (Some(_), Some(false), _) => format!("; the scenario's own value {own} is unstable"),
        (Some(_), Some(true), _) => format!("; the scenario's own value {own} is stable"),
        (Some(value), None, _) if report.interrupted && (lower..=upper).contains(&value) => {
            format!("; the scenario's own value {own} was not evaluated")
        }
        (Some(_), _, _) => format!("; the scenario's own value {own} is outside the range"),
        (None, _, _) => "; the scenario's own value is not a readable number".to_string(),
    };
    text += &no_equilibrium_warning(report).unwrap_or_default();
    text += &growth_unchanged_warning(report).unwrap_or_default();
    text
}

/// The warning that closes the verdict when the growth rate is the same at every evaluation
/// ([`MarginReport::growth_unchanged`]): the parameter does not enter the linearisation.
fn growth_unchanged_warning(report: &MarginReport) -> Option<String> {
    report.growth_unchanged().then(|| {
        format!(
            "; but the growth rate is the same at every evaluation: {} does not enter the \
             linearisation about the standing equilibrium (judge with --method simulate)",
            report.parameter
        )
    })
}

/// The margin report for a reader: the verdict, then every evaluation in value order.
pub(crate) fn margin_table(report: &sea_sim::analysis::margin::MarginReport) -> String {
    let mut table = format!(
        "{} ({} method, {} evaluations): {}",
        report.parameter,
        report.method.name(),
        report.evaluations(),
        margin_verdict(report)
    );
    let mut samples: Vec<_> = report.samples.iter().collect();
    samples.sort_by(|a, b| a.value.total_cmp(&b.value));
    for sample in samples {
        let growth = sample.growth_rate.map_or(String::new(), |g| {
            format!("  growth {} 1/s", fixed_number(g, 10, 4))
        });
        let verdict = if sample.stable { "stable" } else { "unstable" };
        let value = fixed_number(sample.value, 14, 6);
        let no_equilibrium = no_equilibrium_note(sample, "  ");
        table += &format!("\n  {value}  {verdict:<8}{growth}{no_equilibrium}");
    }
    table
}

/// `--tolerance`: a number from [`MIN_RELATIVE_TOLERANCE`] to below 1 (clap names the flag in
/// its error).
fn parse_tolerance(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(value) if (MIN_RELATIVE_TOLERANCE..1.0).contains(&value) => Ok(value),
        _ => Err(format!(
            "expected a number from {MIN_RELATIVE_TOLERANCE:e} to below 1, got '{text}'"
        )),
    }
}
