//! `sea-sim push`: the largest push recovered per direction, bisected.

use crate::common::{parse_key_value, parse_positive, print_out};
use clap::Args;
use sea_sim::analysis::push::PushOptions;
use std::path::PathBuf;

/// Options of `sea-sim push`.
#[derive(Args, Debug)]
pub(crate) struct PushArgs {
    /// Scenario file (TOML), e.g. scenarios/robot_rate/push_two_feet.toml; its own
    /// `[[disturbances]]` are replaced by the push.
    scenario: PathBuf,
    /// Directions, comma-separated: forward, backward, left, right (the first contact's sole
    /// axes).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "forward,backward,left,right"
    )]
    directions: Vec<String>,
    /// The pushed link.
    #[arg(long, default_value_t = PushOptions::default().link)]
    link: String,
    /// Start of the push [s].
    #[arg(long, default_value_t = PushOptions::default().start_s)]
    start: f64,
    /// Length of the push [s] (finite, positive).
    #[arg(long, default_value_t = PushOptions::default().duration_s, value_parser = parse_positive)]
    duration: f64,
    /// Bisection resolution [N s] (finite, positive).
    #[arg(long, default_value_t = PushOptions::default().tolerance_n_s, value_parser = parse_positive)]
    tolerance: f64,
    /// Override a scenario value, e.g. `--set controller.kind=rigid` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
}

/// `sea-sim push`: the push table as JSON on stdout.
pub(crate) fn run_push(args: &PushArgs) -> sea_sim::Result<()> {
    use sea_sim::analysis::push::{push_table, PushDirection};
    let directions = args
        .directions
        .iter()
        .map(|name| PushDirection::parse(name))
        .collect::<sea_sim::Result<Vec<_>>>()?;
    let options = PushOptions {
        link: args.link.clone(),
        start_s: args.start,
        duration_s: args.duration,
        tolerance_n_s: args.tolerance,
    };
    let table = push_table(&args.scenario, &args.overrides, &options, &directions)?;
    let rows: Vec<serde_json::Value> = table
        .iter()
        .map(|row| {
            let fall = row.failed_summary.as_ref().map(|s| s.to_json());
            serde_json::json!({
                "direction": row.direction.name(),
                "capture_point_impulse_n_s": row.capture_point_impulse,
                "recovered_impulse_n_s": row.recovered_impulse,
                "failed_impulse_n_s": row.failed_impulse,
                "failed_status": fall.as_ref().map(|j| j["status"].clone()),
                "failed_reason": fall.as_ref().map(|j| j["reason"].clone()),
                "runs": row.runs,
            })
        })
        .collect();
    let json = serde_json::json!({
        "scenario": args.scenario,
        "overrides": args.overrides.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>(),
        "link": options.link,
        "start_s": options.start_s,
        "duration_s": options.duration_s,
        "directions": rows,
    });
    let text = serde_json::to_string_pretty(&json)
        .map_err(|e| sea_sim::Error::Log(format!("push JSON: {e}")))?;
    print_out(text);
    Ok(())
}
