//! Every test file of the workspace runs. A crate with `autotests = false` compiles only the
//! test targets its Cargo.toml names (`tests/integration.rs`, whose modules are the other
//! files, and `tests/no_alloc.rs`), so a new file of its `tests/` folder that neither names
//! would never be compiled nor run.

use std::fs;
use std::path::{Path, PathBuf};

/// The `tests/*.rs` files of the crate at `crate_dir` that no test binary compiles: neither a
/// `mod` of its `tests/integration.rs` nor the path of a `[[test]]` target. Empty for a crate
/// whose tests Cargo discovers itself (no `autotests = false`).
fn files_no_binary_compiles(crate_dir: &Path) -> Vec<PathBuf> {
    let tests = crate_dir.join("tests");
    let manifest = fs::read_to_string(crate_dir.join("Cargo.toml")).unwrap_or_default();
    if !tests.is_dir() || !manifest.contains("autotests = false") {
        return Vec::new();
    }
    let root = fs::read_to_string(tests.join("integration.rs")).unwrap_or_default();
    let mut missing = Vec::new();
    for entry in fs::read_dir(&tests).unwrap() {
        let path = entry.unwrap().path();
        let Some(stem) = path.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        if path.extension().is_none_or(|e| e != "rs") || stem == "integration" {
            continue;
        }
        let a_module = root
            .lines()
            .any(|line| line.trim() == format!("mod {stem};"));
        let a_target = manifest.contains(&format!("path = \"tests/{stem}.rs\""));
        if !a_module && !a_target {
            missing.push(path);
        }
    }
    missing
}

#[test]
fn every_test_file_of_the_workspace_is_compiled_into_a_test_binary() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut crate_dirs: Vec<PathBuf> = fs::read_dir(&crates)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.join("Cargo.toml").is_file())
        .collect();
    crate_dirs.sort();
    assert!(
        crate_dirs.iter().any(|dir| dir.ends_with("sea_sim")),
        "{crate_dirs:?}"
    );
    let missing: Vec<PathBuf> = crate_dirs
        .iter()
        .flat_map(|dir| files_no_binary_compiles(dir))
        .collect();
    assert!(
        missing.is_empty(),
        "test files no test binary compiles (add `mod <file>;` to the crate's \
         tests/integration.rs): {missing:?}"
    );
}

#[test]
fn a_file_left_out_of_the_integration_binary_is_found() {
    let dir = std::env::temp_dir().join(format!("sea_sim_test_layout_{}", std::process::id()));
    fs::create_dir_all(dir.join("tests")).unwrap();
    fs::write(dir.join("Cargo.toml"), "[package]\nautotests = false\n").unwrap();
    fs::write(dir.join("tests/integration.rs"), "mod listed;\n").unwrap();
    fs::write(dir.join("tests/listed.rs"), "").unwrap();
    fs::write(dir.join("tests/forgotten.rs"), "").unwrap();
    let missing = files_no_binary_compiles(&dir);
    fs::remove_dir_all(&dir).unwrap();
    assert_eq!(missing, vec![dir.join("tests/forgotten.rs")]);
}
