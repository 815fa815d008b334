//! The run summary has one list of keys: the serde names of `sea_sim::closed_loop::Summary`.
//! The JSON of every outcome, `sea-sim run`'s summary and the fields of the Python
//! `sea_momentum.results.RunSummary` (built from the same keys) must all have them.

use sea_sim::closed_loop::{FallSummary, RunEnd, RunTotals, RunningStatistics, Summary};
use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

/// The workspace root.
fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The keys of a JSON object.
fn keys(json: &serde_json::Value) -> BTreeSet<String> {
    json.as_object()
        .expect("an object")
        .keys()
        .cloned()
        .collect()
}

/// The summary of a run that ended with `end`, no sample taken.
fn summary(end: &RunEnd) -> Summary {
    let totals = RunTotals::default();
    Summary::new(
        end,
        "zero_order_hold",
        &RunningStatistics::default(),
        totals,
    )
}

/// The field names of the dataclass `class` in the Python file `text`: the annotated names
/// (`name: type`) indented by four spaces in its body.
fn dataclass_fields(text: &str, class: &str) -> BTreeSet<String> {
    let start = text.find(&format!("class {class}(")).expect("the class");
    let body = text[start..].lines().skip(1);
    let body = body.take_while(|line| line.is_empty() || line.starts_with(' '));
    body.filter_map(|line| {
        let field = line.strip_prefix("    ")?.split_once(": ")?.0;
        let plain = field.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        (plain && !field.is_empty()).then(|| field.to_string())
    })
    .collect()
}

#[test]
fn every_outcome_writes_the_same_keys() {
    let completed = keys(&summary(&RunEnd::Completed).to_json());
    assert!(completed.contains("reason_kind") && completed.contains("fall_foot"));
    let mut fell = summary(&RunEnd::Interrupted);
    fell.fall = Some(FallSummary::default());
    assert_eq!(keys(&fell.to_json()), completed);
}

#[test]
fn the_python_run_summary_has_the_json_keys() {
    let text = std::fs::read_to_string(root().join("python/sea_momentum/results.py")).unwrap();
    let python = dataclass_fields(&text, "RunSummary");
    let rust = keys(&summary(&RunEnd::Completed).to_json());
    assert_eq!(
        python, rust,
        "the fields of sea_momentum.results.RunSummary differ from the Rust summary's JSON keys"
    );
}

#[test]
fn sea_sim_run_prints_the_json_keys() {
    let scenario = root().join("scenarios/paper/tracking.toml");
    let output = Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .arg("run")
        .arg(&scenario)
        .args(["--set", "simulation.duration_s=0.01", "--quiet"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    let printed: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(keys(&printed), keys(&summary(&RunEnd::Completed).to_json()));
}
