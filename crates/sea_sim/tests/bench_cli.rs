//! `sea-sim bench --scenario`: the dynamics of a scenario's robot, one tick of its controller
//! and its first simulated second, or an error naming why that second did not complete.

use super::cli::{sea_sim, text};

const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

#[test]
fn a_scenario_is_benchmarked_with_its_controller_tick_and_its_first_second() {
    let walk = format!("{REPO}/scenarios/walking/walk_straight.toml");
    let quick = ["--batches", "1", "--calls", "1", "--json"];
    let out = sea_sim(&[&["bench", "--scenario", &walk][..], &quick].concat());
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["scenario"], walk.as_str());
    assert_eq!(report["nv"], 31);
    for key in ["rnea_us", "controller_tick_us", "scenario_second_ms"] {
        let value = report[key].as_f64().unwrap_or(f64::NAN);
        assert!(value > 0.0 && value.is_finite(), "{key}: {report}");
    }
    // A first second that diverges (a CoM error bound of 1 um) is an error naming it.
    let tight = "simulation.divergence_com_error_m=1e-6";
    let args = [&["bench", "--scenario", &walk, "--set", tight][..], &quick].concat();
    let out = sea_sim(&args);
    assert_eq!(out.status.code(), Some(1));
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains("the benchmark's run did not complete: diverged"),
        "{stderr}"
    );
    // --set belongs to --scenario, --joints to --urdf.
    let icub = format!("{REPO}/urdf/icub25.urdf");
    for args in [
        vec!["bench", "--urdf", &icub, "--set", tight],
        vec!["bench", "--scenario", &walk, "--joints", "l_knee"],
        vec!["bench", "--scenario", &walk, "--urdf", &icub],
    ] {
        let out = sea_sim(&args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        assert!(
            text(&out.stderr).contains("cannot be used with"),
            "{args:?}"
        );
    }
}
