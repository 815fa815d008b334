//! `sea-sim push` and `sea-sim margin` stopped by a signal: no run starts, the runs under way
//! stop at their next sample, what was done is reported with `"interrupted": true`, and the
//! exit status is the signal's. `sea-sim init` stopped while the robot loads writes nothing;
//! stopped while it runs the walk it wrote, it leaves the walk at the standing CoM height.

use super::cli::{Running, Workspace};
use std::path::{Path, PathBuf};
use std::process::Stdio;

const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A run that takes far longer than the test: a push it recovers goes on for 300 s.
const LONG_RUN: &str = "simulation.duration_s=300";

/// Starts `sea-sim COMMAND` on the scenario `scenario` (in the repository) with `args`, its
/// stdout to a file of `ws`; returns the run and the file's path.
fn start(ws: &Workspace, (command, scenario): (&str, &str), args: &[&str]) -> (Running, PathBuf) {
    let scenario = format!("{REPO}/scenarios/{scenario}");
    let report = ws.path("report.json");
    let file = std::fs::File::create(&report).unwrap();
    let run = Running::start_command((command, &scenario), args, Stdio::from(file));
    (run, report)
}

/// The JSON report at `path`.
fn report(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap();
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// Sends `signal` to `run` and waits: the exit status is `status` and stderr says the signal
/// stopped it with `finished` (e.g. "the pushes done reported").
fn stop(run: Running, signal: &str, status: i32, finished: &str) {
    run.signal(signal);
    let (code, stderr) = run.wait();
    assert_eq!(code, Some(status), "{stderr}");
    let said = format!("stopped by SIG{signal}; {finished}");
    assert!(stderr.contains(&said), "{stderr}");
}

/// The standing push scenario.
const STANDING: &str = "robot_rate/push_two_feet.toml";

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
    let ws = Workspace::new("push_fixed_signal");
    let (mut push, path) = start(&ws, ("push", STANDING), &args);
    push.wait_for_line("push forward 40 N s:");
    stop(push, "TERM", 143, "the pushes done reported");
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
    let ws = Workspace::new("push_bisection_signal");
    let (mut push, path) = start(&ws, ("push", STANDING), &args);
    let first = push.wait_for_line("push forward ");
    let twice: f64 = first
        .trim_start_matches("sea-sim: push forward ")
        .split(' ')
        .next()
        .and_then(|impulse| impulse.parse().ok())
        .unwrap_or_else(|| panic!("an impulse in '{first}'"));
    push.wait_for_line(&format!("push forward {} N s:", 0.5 * twice));
    stop(push, "INT", 130, "the pushes done reported");
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
    let ws = Workspace::new("margin_signal");
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
    let (mut margin, path) = start(&ws, ("margin", "paper/tracking.toml"), &args);
    margin.wait_for_line("simulation.duration_s = 0.3: stable");
    stop(margin, "TERM", 143, "the evaluations done reported");
    let json = report(&path);
    assert_eq!(json["interrupted"], true, "{json}");
    assert_eq!(json["conclusion"], "interrupted", "{json}");
    assert_eq!(json["evaluations"], 2, "{json}");
    assert_eq!(json["own_value_stable"], true, "{json}");
    // The scan did not reach 300 s: no island is claimed.
    assert!(json["stable_island"].is_null(), "{json}");
}

/// Waits until the process `pid` catches SIGTERM (its handlers installed): `SigCgt` of
/// /proc/PID/status has bit 15 - 1.
fn wait_until_catching_sigterm(pid: u32) {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(30);
    loop {
        let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap_or_default();
        let caught = status
            .lines()
            .find_map(|line| line.strip_prefix("SigCgt:"))
            .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
            .is_some_and(|mask| (mask >> 14) & 1 == 1);
        if caught {
            return;
        }
        assert!(std::time::Instant::now() < deadline, "SIGTERM never caught");
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
}

#[test]
fn a_signal_while_init_loads_the_robot_writes_nothing() {
    // The iCub with a 30 MB comment: its load takes a large part of a second, and the signal
    // comes as soon as the handlers are in place, before anything is written.
    let ws = Workspace::new("init_signal");
    let text = std::fs::read_to_string(format!("{REPO}/urdf/icub25.urdf")).unwrap();
    let at = text.find("<robot").unwrap();
    let at = at + text[at..].find('>').unwrap() + 1;
    let padding = format!("<!-- {} -->", "x".repeat(30_000_000));
    let urdf = ws.path("big_icub.urdf");
    std::fs::write(&urdf, format!("{}{padding}{}", &text[..at], &text[at..])).unwrap();
    let out = ws.path("big_icub_two_feet.toml");
    let args = [
        "--contacts",
        "l_sole",
        "r_sole",
        "--foot=-0.05,0.10,-0.025,0.025",
        "--out",
        out.to_str().unwrap(),
    ];
    let init = Running::start_command(("init", urdf.to_str().unwrap()), &args, Stdio::null());
    wait_until_catching_sigterm(init.id());
    stop(init, "TERM", 143, "nothing written");
    let written: Vec<_> = std::fs::read_dir(out.parent().unwrap())
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().to_string())
        .filter(|name| name.contains("two_feet"))
        .collect();
    assert!(written.is_empty(), "{written:?}");
}

#[test]
fn a_signal_while_init_runs_the_walk_leaves_it_written_unchecked() {
    // The walk's run starts as the file appears and lasts most of a second; the signal comes
    // within milliseconds of the file.
    let ws = Workspace::new("init_walk_signal");
    let out = ws.path("icub_walk.toml");
    let args = [
        "--contacts",
        "l_sole",
        "r_sole",
        "--foot=-0.05,0.10,-0.025,0.025",
        "--walking",
        "--out",
        out.to_str().unwrap(),
    ];
    let urdf = format!("{REPO}/urdf/icub25.urdf");
    let init = Running::start_command(("init", &urdf), &args, Stdio::null());
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while !out.exists() {
        assert!(
            std::time::Instant::now() < deadline,
            "the walk was never written"
        );
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    init.signal("TERM");
    let (code, stderr) = init.wait();
    assert_eq!(code, Some(143), "{stderr}");
    for said in [
        "walk check: com_height 0.507 m: interrupted",
        "walk check stopped: the walk is written at the standing CoM height 0.507 m, not \
         confirmed to walk",
        "stopped by SIGTERM; nothing written unless said above",
    ] {
        assert!(stderr.contains(said), "{said}: {stderr}");
    }
    let written: toml::Table = toml::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(written["walking"]["com_height"].as_float(), Some(0.507));
}
