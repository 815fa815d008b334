//! `sea-sim push` and `sea-sim margin` stopped by a signal: no run starts, the runs under way
//! stop at their next sample, what was done is reported with `"interrupted": true`, and the
//! exit status is the signal's.

use super::cli::Running;
use std::process::Stdio;

const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A run that takes far longer than the test: a push it recovers goes on for 300 s.
const LONG_RUN: &str = "simulation.duration_s=300";

/// Starts `sea-sim push` on the standing scenario with `args`, its report to a file; returns
/// the run and the report's path (in the temporary directory, unique to `tag`).
fn start_push(tag: &str, args: &[&str]) -> (Running, std::path::PathBuf) {
    let scenario = format!("{REPO}/scenarios/robot_rate/push_two_feet.toml");
    let report = std::env::temp_dir().join(format!("sea_push_{tag}_{}.json", std::process::id()));
    let file = std::fs::File::create(&report).unwrap();
    let run = Running::start_command(("push", &scenario), args, Stdio::from(file));
    (run, report)
}

/// The JSON report at `path` (removed once read).
fn report(path: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap();
    let _ = std::fs::remove_file(path);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[test]
fn a_signal_stops_fixed_pushes_with_the_ones_done_reported() {
    // 40 N s (three times the capture-point bound) falls within 2 s; the unpushed run would
    // go on for 300 s. 40 first, so that one thread alone also runs it first.
    let args = [
        "--directions",
        "forward",
        "--impulses",
        "40,0",
        "--set",
        LONG_RUN,
    ];
    let (mut push, path) = start_push("fixed", &args);
    push.wait_for_line("push forward 40 N s:");
    push.signal("TERM");
    let (status, stderr) = push.wait();
    assert_eq!(status, Some(143), "{stderr}");
    assert!(
        stderr.contains("stopped by SIGTERM; the pushes done reported"),
        "{stderr}"
    );
    let json = report(&path);
    assert_eq!(json["interrupted"], true, "{json}");
    let row = &json["directions"][0];
    assert_eq!(row["outcomes"], "x-", "{row}");
    assert_eq!(row["interrupted"], true, "{row}");
    assert_eq!(row["recovered_count"], 0, "{row}");
    assert_eq!(row["pushes"][1]["status"], "interrupted", "{row}");
    assert!(row["pushes"][1]["end_s"].is_null(), "{row}");
}

#[test]
fn a_signal_stops_a_bisection_with_the_bracket_so_far() {
    // Twice and once the bound fall at once; half the bound is recovered, after 300 s.
    let args = ["--directions", "forward", "--set", LONG_RUN];
    let (mut push, path) = start_push("bisection", &args);
    push.wait_for_line("push forward 13.");
    push.signal("INT");
    let (status, stderr) = push.wait();
    assert_eq!(status, Some(130), "{stderr}");
    let json = report(&path);
    let row = &json["directions"][0];
    assert_eq!(row["interrupted"], true, "{row}");
    assert_eq!(row["runs"], 2, "{row}");
    assert_eq!(row["recovered_impulse_n_s"], 0.0, "{row}");
    let bound = row["capture_point_impulse_n_s"].as_f64().unwrap();
    assert_eq!(row["failed_impulse_n_s"].as_f64(), Some(bound), "{row}");
}

#[test]
fn a_signal_stops_a_margin_scan_with_the_evaluations_done_reported() {
    // The scanned key is the run's length: 0.2 and the scenario's own 0.3 s end at once, 300 s
    // does not.
    let scenario = format!("{REPO}/scenarios/paper/tracking.toml");
    let path = std::env::temp_dir().join(format!("sea_margin_signal_{}.json", std::process::id()));
    let file = std::fs::File::create(&path).unwrap();
    let args = [
        "--param",
        "simulation.duration_s",
        "--range",
        "0.2:300",
        "--points",
        "2",
        "--method",
        "simulate",
        "--set",
        "simulation.duration_s=0.3",
        "--json",
    ];
    let mut margin = Running::start_command(("margin", &scenario), &args, Stdio::from(file));
    margin.wait_for_line("simulation.duration_s = 0.3: stable");
    margin.signal("TERM");
    let (status, stderr) = margin.wait();
    assert_eq!(status, Some(143), "{stderr}");
    assert!(
        stderr.contains("stopped by SIGTERM; the evaluations done reported"),
        "{stderr}"
    );
    let json = report(&path);
    assert_eq!(json["interrupted"], true, "{json}");
    assert_eq!(json["conclusion"], "interrupted", "{json}");
    assert_eq!(json["evaluations"], 2, "{json}");
    assert_eq!(json["own_value_stable"], true, "{json}");
    // The scan did not reach 300 s: no island is claimed.
    assert!(json["stable_island"].is_null(), "{json}");
}
