//! `controller.sampling = "multi_rate"`: the whole-body controller at 100 Hz with the joint
//! torque loops at 1 kHz on the paper's tracking scenario, its period map's growth rate
//! against simulation, and the scenario errors of its keys.

use sea_sim::analysis::system::difference;
use sea_sim::analysis::{linearize, Linearization};
use sea_sim::scenario::Scenario;
use std::path::PathBuf;

fn scenario_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/robot_rate/tracking_multi_rate.toml")
}

fn load(overrides: &[(&str, &str)]) -> Scenario {
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&scenario_path(), &pairs).unwrap()
}

/// Growth rate [1/s] of the largest tangent-space deviation from the linearisation's
/// equilibrium, sample by sample (one per whole-body period), fitted by least squares in log
/// scale from `start` to the divergence time less `margin`.
fn simulated_growth(scenario: &Scenario, lin: &Linearization, start: f64, margin: f64) -> f64 {
    let (record, summary) = sea_sim::closed_loop::run(scenario, |_, _| {}).unwrap();
    assert_eq!(summary.status, "diverged", "{summary:?}");
    let end = summary.diverged_at_s.unwrap() - margin;
    let layout = sea_sim::scenario::build(scenario).unwrap().plant.layout();
    let mut deviation = nalgebra::DVector::zeros(layout.nd());
    let points: Vec<(f64, f64)> = record
        .state
        .chunks(layout.nx())
        .zip(&record.time)
        .map(|(x, &t)| {
            difference(&layout, &lin.equilibrium.state, x, &mut deviation);
            (t, deviation.norm().ln())
        })
        .filter(|(t, _)| *t >= start && *t <= end)
        .collect();
    assert!(points.len() >= 5, "too few points: {points:?}");
    let count = points.len() as f64;
    let (mean_t, mean_y) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (t, y)| (a + t / count, b + y / count));
    let (cov, var) = points.iter().fold((0.0, 0.0), |(c, v), (t, y)| {
        (
            c + (t - mean_t) * (y - mean_y),
            v + (t - mean_t) * (t - mean_t),
        )
    });
    cov / var
}

/// The goals of the robot-rate architecture on the paper's tracking (one foot, 10 s): CoM
/// error rms within 1.5 x the rigid robot's under the rigid controller at 100 Hz (2.32 mm,
/// README "At the robot's rate"), lateral CoM error below 2 mm.
#[test]
fn tracking_at_100_hz_with_1_khz_joint_loops_meets_the_goals() {
    let (_, summary) = sea_sim::closed_loop::run(&load(&[]), |_, _| {}).unwrap();
    assert_eq!(summary.status, "completed", "{summary:?}");
    assert!(summary.com_error_rms_m < 1.5 * 2.32e-3, "{summary:?}");
    assert!(summary.com_error_lateral_max_m < 2e-3, "{summary:?}");
}

/// The paper's law (SEA controller, bandwidth `K_S^ / K_D^`) with its joint loops at 500 Hz
/// diverges (its two-state model needs 665 Hz); the period map's growth rate predicts the
/// simulated one within 5 %.
#[test]
fn period_map_growth_matches_simulation_for_the_paper_law_at_500_hz() {
    let scenario = load(&[
        ("controller.kind", "sea"),
        ("controller.torque_loop_paper_law", "true"),
        ("controller.inner_rate_hz", "500"),
        ("simulation.record_every", "1"),
        // The mode's growth on the model's bilateral contacts, past the foot's tipping.
        ("simulation.stop_on_fall", "false"),
    ]);
    let lin = linearize(&scenario, None).unwrap();
    assert!(lin.equilibrium.converged, "{}", lin.equilibrium.residual);
    assert!(!lin.stable && lin.growth_rate > 1.0, "{}", lin.growth_rate);
    let simulated = simulated_growth(&scenario, &lin, 0.02, 0.02);
    let error = (simulated - lin.growth_rate).abs() / lin.growth_rate;
    println!(
        "paper law, 100 Hz / 500 Hz: predicted {:.2} 1/s, simulated {simulated:.2} 1/s ({:.1} %), {:?}",
        lin.growth_rate,
        100.0 * error,
        lin.dominant_states
    );
    assert!(
        error < 0.05,
        "predicted {} simulated {simulated}",
        lin.growth_rate
    );
}

/// The default design's period map is stable at 100 Hz / 1 kHz.
#[test]
fn nominal_multi_rate_period_map_is_stable() {
    let lin = linearize(&load(&[]), None).unwrap();
    assert!(lin.equilibrium.converged);
    println!(
        "nominal multi-rate: growth {:.4} 1/s, {:?}",
        lin.growth_rate, lin.dominant_states
    );
    assert!(lin.stable, "{}", lin.growth_rate);
}

/// Bad joint loop rates and bandwidths name their key.
#[test]
fn bad_joint_loop_settings_name_their_key() {
    for (key, value, rule) in [
        ("controller.inner_rate_hz", "1050", "whole multiple"),
        (
            "controller.inner_rate_hz",
            "50",
            "at least controller.rate_hz",
        ),
        ("controller.torque_bandwidth_hz", "0", "positive"),
        ("controller.torque_bandwidth_hz", "-3", "positive"),
    ] {
        let pairs = vec![(key.to_string(), value.to_string())];
        let message = Scenario::from_file(&scenario_path(), &pairs)
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(&format!("scenario key '{key}'")) && message.contains(rule),
            "{key}={value}: {message}"
        );
    }
}
