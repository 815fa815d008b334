//! The JSON Schema of scenario files: the committed `schemas/scenario.schema.json` is the one
//! the types derive, and every shipped scenario names it in its `#:schema` header.

use sea_sim::scenario::reference::markdown;
use sea_sim::scenario::schema::{json_schema, json_schema_text};
use sea_sim::scenario::Scenario;
use std::path::{Path, PathBuf};

/// The workspace root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The committed file `relative` (under the workspace root) equals `generated`; otherwise the
/// failure says how to regenerate it.
fn assert_current(relative: &str, generated: &str, command: &str) {
    let path = root().join(relative);
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{relative} is not the one the code generates; regenerate it with\n  {command}"
    );
}

#[test]
fn the_committed_schema_is_current() {
    assert_current(
        "schemas/scenario.schema.json",
        &json_schema_text(),
        "cargo run --release -p sea_sim --bin sea-sim -- schema > schemas/scenario.schema.json",
    );
}

#[test]
fn the_committed_reference_page_is_current() {
    assert_current(
        "docs/reference/scenario_keys.md",
        &markdown(&json_schema()),
        "cargo run --release -p sea_sim --bin sea-sim -- schema --markdown \
         > docs/reference/scenario_keys.md",
    );
}

/// The `.toml` files under `dir`, recursively.
fn toml_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            toml_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push(path);
        }
    }
}

/// The path of `schemas/scenario.schema.json` relative to the folder of `file` (under
/// `scenarios/`).
fn schema_path_from(file: &Path) -> String {
    let scenarios = root().join("scenarios");
    let depth = file.strip_prefix(&scenarios).unwrap().components().count();
    "../".repeat(depth) + "schemas/scenario.schema.json"
}

#[test]
fn every_shipped_scenario_names_the_schema_and_reads() {
    let mut files = Vec::new();
    toml_files(&root().join("scenarios"), &mut files);
    assert!(!files.is_empty());
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let header = format!("#:schema {}", schema_path_from(&file));
        let first = text.lines().next().unwrap_or_default();
        assert_eq!(first, header, "{}: first line", file.display());
        let schema = file.parent().unwrap().join(schema_path_from(&file));
        assert!(schema.is_file(), "{}", schema.display());
        text.parse::<toml::Table>()
            .unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        // The robots' scenarios need their robots' packages (python_tests/test_robots_init.py).
        if !file.parent().unwrap().ends_with("robots") {
            Scenario::from_file(&file, &[]).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        }
    }
}

#[test]
fn sea_sim_schema_prints_it() {
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .arg("schema")
        .output()
        .unwrap();
    assert!(output.status.success());
    assert_eq!(
        String::from_utf8(output.stdout).unwrap(),
        json_schema_text()
    );
}
