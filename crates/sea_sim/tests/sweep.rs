//! Sweeps: grid specifications and their errors, results that do not depend on the number of
//! workers, failed and diverged runs as rows, cancellation keeping the rows done, the CSV and
//! the `sea-sim sweep` command.

use sea_sim::sweep::{
    run_points, run_sweep, summary_columns, write_csv, Axis, Grid, ScenarioSource, SweepRow,
    STATUS_FAILED,
};
use sea_sim::Error;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// The paper's tracking scenario.
fn tracking_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper/tracking.toml")
}

/// Short runs with a record-free loop, in the sampled-data setting these tests use (1 kHz
/// zero-order hold, 1 ms plant step; the scenario file is continuous).
fn short(duration: &str) -> Vec<(String, String)> {
    vec![
        ("controller.sampling".into(), "zero_order_hold".into()),
        ("plant.dt".into(), "0.001".into()),
        ("simulation.duration_s".into(), duration.into()),
    ]
}

/// The key and the value named by a scenario error.
fn key_and_value(error: Error) -> (String, Option<String>) {
    match error {
        Error::Scenario { key, value, .. } => (key, value),
        other => panic!("expected a scenario error, got {other}"),
    }
}

/// The rows without the wall-clock fields (the only ones allowed to differ between runs).
fn comparable(rows: &[SweepRow]) -> Vec<String> {
    rows.iter()
        .map(|row| {
            let fields: Vec<String> = row
                .summary_values()
                .into_iter()
                .filter(|(name, _)| name != "wall_time_s" && name != "realtime_factor")
                .map(|(name, value)| format!("{name}={value:?}"))
                .collect();
            format!(
                "{} {:?} {} {} {}",
                row.index,
                row.values,
                row.status,
                row.message,
                fields.join(" ")
            )
        })
        .collect()
}

#[test]
fn bad_specifications_name_the_key_and_the_value() {
    let cases = [
        ("k=1:2:0", "k", "'0'"),
        ("k=3:1:4", "k", "3:1"),
        ("k=1:1:3", "k", "1:1"),
        ("k=0:1:3:log", "k", "0"),
        ("k=1,abc", "k", "'abc'"),
        ("k=1,,2", "k", "''"),
        ("k=1:2:3:cubic", "k", "'1:2:3:cubic'"),
        ("k", "grid", "'k'"),
        ("=1,2", "grid", "'=1,2'"),
    ];
    for (spec, key, value) in cases {
        let error = Axis::parse(spec).expect_err(spec);
        let message = error.to_string();
        assert_eq!(
            key_and_value(error),
            (key.into(), Some(value.into())),
            "{message}"
        );
    }
    let twice = Grid::parse(&["a=1", "a=2"]).unwrap_err();
    assert_eq!(key_and_value(twice).0, "a");
    assert_eq!(
        key_and_value(Grid::parse::<&str>(&[]).unwrap_err()).0,
        "grid"
    );
}

#[test]
fn keys_the_scenario_does_not_have_or_cannot_take_are_refused_before_any_run() {
    let source = ScenarioSource::read(&tracking_path()).unwrap();
    for (spec, key) in [
        ("controller.no_such_gain=1,2", "controller.no_such_gain"),
        ("nowhere.gain=1", "nowhere.gain"),
        ("controller.kind=1", "controller.kind"),
        ("controller=1", "controller"),
        // A value out of the key's range, found for the second value already.
        ("controller.rate_hz=1000,-5", "controller.rate_hz"),
    ] {
        let grid = Grid::parse(&[spec]).unwrap();
        let error = grid.check(&source, &short("0.1")).expect_err(spec);
        let message = error.to_string();
        assert_eq!(key_and_value(error).0, key, "{spec}: {message}");
    }
    let good = Grid::parse(&[
        "controller.damping_estimate_scale=0.5:2:4:log",
        "controller.rate_hz=500,1000",
    ]);
    good.unwrap().check(&source, &short("0.1")).unwrap();
}

#[test]
fn results_do_not_depend_on_the_number_of_workers() {
    let grid = Grid::parse(&[
        "controller.damping_estimate_scale=1.0,1.2",
        // Above the paper law's sampling limit (about 690 Hz at x1.0, lower at x1.2), where
        // every run completes.
        "controller.rate_hz=800:1000:2",
    ])
    .unwrap();
    let cancel = AtomicBool::new(false);
    let sweep = |workers| {
        run_sweep(
            &tracking_path(),
            &grid,
            &short("0.3"),
            Some(workers),
            &cancel,
            &|_| {},
        )
        .unwrap()
    };
    let (one, two) = (sweep(1), sweep(2));
    assert_eq!(one.len(), 4);
    let indices: Vec<usize> = two.iter().map(|row| row.index).collect();
    assert_eq!(indices, vec![0, 1, 2, 3]);
    assert_eq!(two[1].values, vec![1.0, 1000.0]);
    assert!(
        one.iter().all(|row| row.status == "completed"),
        "{:?}",
        comparable(&one)
    );
    assert_eq!(comparable(&one), comparable(&two));
}

#[test]
fn failed_and_diverged_runs_are_rows_beside_the_others() {
    let source = ScenarioSource::read(&tracking_path()).unwrap();
    let keys = vec!["controller.rate_hz".to_string()];
    // -5 Hz breaks the schema: unchecked points reach the runs, where it is that row's failure.
    let points = vec![(0, vec![1000.0]), (1, vec![-5.0]), (2, vec![100.0])];
    let cancel = AtomicBool::new(false);
    let rows = run_points(
        &source,
        &keys,
        points,
        &short("0.3"),
        Some(2),
        &cancel,
        &|_| {},
    )
    .unwrap();
    let statuses: Vec<&str> = rows.iter().map(|row| row.status.as_str()).collect();
    // 100 Hz is far below the paper law's sampling limit: the stance foot tips (CoP) before
    // the errors reach the divergence bounds.
    assert_eq!(statuses, vec!["completed", STATUS_FAILED, "fell"]);
    assert!(
        rows[1].message.contains("controller.rate_hz"),
        "{}",
        rows[1].message
    );
    assert!(rows[1].summary.is_none());
    assert!(!rows[2].message.is_empty());
    let fall = rows[2].summary.as_ref().unwrap().fall.as_ref().unwrap();
    assert!(fall.at_s < 0.3, "{fall:?}");
}

#[test]
fn a_cancelled_sweep_returns_the_rows_done() {
    let grid = Grid::parse(&["controller.damping_estimate_scale=0.8:1.2:6"]).unwrap();
    let cancel = AtomicBool::new(false);
    // Cancelled after the first finished run: the runs under way stop, none starts.
    let rows = run_sweep(
        &tracking_path(),
        &grid,
        &short("0.3"),
        Some(2),
        &cancel,
        &|progress| {
            assert_eq!(progress.total, 6);
            cancel.store(true, Ordering::Relaxed);
        },
    )
    .unwrap();
    assert!(!rows.is_empty() && rows.len() < 6, "{} rows", rows.len());
    // Runs start in grid order: the rows done are a prefix of the grid.
    assert!(rows.iter().enumerate().all(|(k, row)| row.index == k));
    assert!(rows.iter().any(|row| row.status == "completed"));
    assert!(rows
        .iter()
        .all(|row| row.status == "completed" || row.status == "interrupted"));
    let none = run_sweep(
        &tracking_path(),
        &grid,
        &short("0.3"),
        Some(1),
        &cancel,
        &|_| {},
    )
    .unwrap();
    assert!(none.is_empty());
}

#[test]
fn csv_has_the_grid_keys_then_every_summary_field() {
    let source = ScenarioSource::read(&tracking_path()).unwrap();
    let keys = vec!["controller.rate_hz".to_string()];
    let points = vec![(0, vec![1000.0]), (1, vec![-5.0])];
    let cancel = AtomicBool::new(false);
    let rows = run_points(
        &source,
        &keys,
        points,
        &short("0.1"),
        Some(1),
        &cancel,
        &|_| {},
    )
    .unwrap();
    let mut bytes = Vec::new();
    write_csv(&mut bytes, Path::new("out.csv"), &keys, &rows).unwrap();
    let text = String::from_utf8(bytes).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    assert_eq!(&header[..3], &["controller.rate_hz", "status", "message"]);
    assert_eq!(header.len(), 3 + summary_columns().len());
    assert!(header.contains(&"com_error_rms_m") && header.contains(&"motor_velocity_peak_rad_s"));
    assert_eq!(lines.len(), 3);
    assert!(lines[1].starts_with("1000,completed,,"), "{}", lines[1]);
    assert!(lines[2].starts_with("-5,failed,"), "{}", lines[2]);
}

#[test]
fn sea_sim_sweep_writes_the_csv() {
    let dir = std::env::temp_dir().join(format!("sea_sweep_cli_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("sweep.csv");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .arg("sweep")
        .arg(tracking_path())
        .args(["--grid", "controller.damping_estimate_scale=0.9,1.1"])
        .args(["--grid", "controller.rate_hz=1000"])
        .args(["--set", "simulation.duration_s=0.2", "--jobs", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("2/2"), "{stderr}");
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3);
    assert!(lines[0].starts_with("controller.damping_estimate_scale,controller.rate_hz,status"));
    assert!(lines[1].starts_with("0.9,1000,completed"), "{}", lines[1]);
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .arg("sweep")
        .arg(tracking_path())
        .args(["--grid", "controller.no_such_gain=1", "--out"])
        .arg(dir.join("bad.csv"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("controller.no_such_gain"));
    assert!(!dir.join("bad.csv").exists());
    // More workers than a process can start is refused before any run, naming the flag.
    let many = std::process::Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .arg("sweep")
        .arg(tracking_path())
        .args([
            "--grid",
            "controller.rate_hz=1000",
            "--jobs",
            "100000",
            "--out",
        ])
        .arg(dir.join("many.csv"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&many.stderr);
    assert!(!many.status.success(), "{stderr}");
    let most = sea_sim::sweep::MAX_WORKERS.to_string();
    assert!(
        stderr.contains("--jobs") && stderr.contains(&most),
        "{stderr}"
    );
    assert!(!dir.join("many.csv").exists());
    // The help and the CLI reference give the same bound.
    let help = std::process::Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .args(["sweep", "--help"])
        .output()
        .unwrap();
    let bound = format!("at most {most}");
    assert!(String::from_utf8_lossy(&help.stdout).contains(&bound));
    let reference = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/reference/cli.md");
    assert!(std::fs::read_to_string(reference).unwrap().contains(&bound));
    std::fs::remove_dir_all(&dir).unwrap();
}
