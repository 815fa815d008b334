//! `controller.sampling = "multi_rate"`: the whole-body controller at 100 Hz with the joint
//! torque loops at 1 kHz on the paper's tracking scenario, its period map's growth rate
//! against simulation, and the scenario errors of its keys.

use crate::support;

use sea_sim::analysis::linearize::{closed_loop_system, LinearizeOptions};
use sea_sim::analysis::system::{difference, difference_slots};
use sea_sim::analysis::{linearize, Linearization};
use sea_sim::scenario::Scenario;
use std::path::PathBuf;

fn scenario_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/robot_rate/tracking_multi_rate.toml")
}

fn load(overrides: &[(&str, &str)]) -> Scenario {
    // Written for the fixed estimates: the file's stiffness identification off.
    let pairs: Vec<(String, String)> = [("controller.stiffness_identification", "false")]
        .iter()
        .chain(overrides)
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&scenario_path(), &support::welded(&pairs)).unwrap()
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
    slope(&points)
}

/// Prints the predicted and the observed growth rate of `case` and checks that they agree
/// within 5 % of the predicted one.
fn assert_growth_within_5_percent(case: &str, lin: &Linearization, observed: f64) {
    let error = (observed - lin.growth_rate).abs() / lin.growth_rate;
    println!(
        "{case}: predicted {:.3} 1/s, observed {observed:.3} 1/s ({:.1} %), {:?}",
        lin.growth_rate,
        100.0 * error,
        lin.dominant_states
    );
    assert!(
        error < 0.05,
        "predicted {} observed {observed}",
        lin.growth_rate
    );
}

/// Least-squares slope of `points` `(t, y)`.
fn slope(points: &[(f64, f64)]) -> f64 {
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
/// docs/findings/robot_rate.md), lateral CoM error below 2 mm.
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
    assert_growth_within_5_percent("paper law, 100 Hz / 500 Hz", &lin, simulated);
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
        // Above the sampled loop's stability limit (329.3 Hz at 1 kHz, K_m = 200 1/s).
        (
            "controller.torque_bandwidth_hz",
            "1e9",
            "must be in (0, 329.3) Hz",
        ),
        (
            "controller.torque_bandwidth_hz",
            "330",
            "unstable from 329.3 Hz",
        ),
    ] {
        let pairs = vec![(key.to_string(), value.to_string())];
        let message = Scenario::from_file(&scenario_path(), &support::welded(&pairs))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(&format!("scenario key '{key}'")) && message.contains(rule),
            "{key}={value}: {message}"
        );
    }
    // Just below the limit the scenario is accepted.
    let pairs = vec![("controller.torque_bandwidth_hz".into(), "329".into())];
    Scenario::from_file(&scenario_path(), &support::welded(&pairs)).unwrap();
}

/// The tracking scenario with its references held (the deviation from the equilibrium is the
/// modes' alone) and a measurement delay of `delay` inner periods.
fn delayed(delay: &str) -> Scenario {
    load(&[
        ("sensing.delay_inner_periods", delay),
        ("reference.com_amplitude", "0"),
        ("simulation.record_every", "1"),
        ("simulation.stop_on_fall", "false"),
    ])
}

/// The period map with a measurement delay (`sensing.delay_inner_periods`): its state is the
/// history of `d + 1` states, and iterated from the run's initial history (the initial state in
/// every slot) it is the run itself, period by period, to the last bit.
#[test]
fn delayed_period_map_is_the_run() {
    let mut scenario = delayed("10");
    scenario.simulation.duration_s = 0.5;
    let (record, _) = sea_sim::closed_loop::run(&scenario, |_, _| {}).unwrap();
    let mut system = closed_loop_system(&scenario, &LinearizeOptions::default()).unwrap();
    assert_eq!(system.slots(), 11);
    let nx = system.layout.nx();
    let mut z = system.setup.x0.repeat(system.slots());
    let mut next = z.clone();
    for x in record.state.chunks(nx) {
        assert_eq!(x, &z[..nx]);
        system.period_map(&z, &mut next).unwrap();
        std::mem::swap(&mut z, &mut next);
    }
}

/// The new design at 100 Hz / 1 kHz holds a measurement delay of 5 inner periods and not one
/// of 10 (a whole control period): the delayed period map (`(d + 1) nd` square) is stable at 5
/// and unstable at 10, and the map itself, started at the equilibrium displaced along the
/// least stable mode, grows at the predicted rate within 5 %. (The run from the initial state
/// diverges at 10 ms of delay too, at 2.1 s, but many modes of nearly the same rate grow in it,
/// to amplitudes where the loop is no longer linear.)
#[test]
fn delayed_period_map_predicts_the_growth_of_a_delayed_loop() {
    let nd = linearize(&load(&[]), None).unwrap().matrix.nrows();
    let holds = linearize(&delayed("5"), None).unwrap();
    assert!(holds.stable, "{}", holds.growth_rate);
    assert_eq!(holds.matrix.shape(), (6 * nd, 6 * nd));
    let scenario = delayed("10");
    let lin = linearize(&scenario, None).unwrap();
    assert_eq!(lin.state_names.len(), 11 * nd);
    assert!(
        lin.state_names[nd].ends_with("@-1"),
        "{}",
        lin.state_names[nd]
    );
    assert!(!lin.stable && lin.growth_rate > 1.0, "{}", lin.growth_rate);
    let simulated = map_growth(&scenario, &lin, 100, 20);
    assert_growth_within_5_percent("new design, 10 ms delay", &lin, simulated);
}

/// Growth rate [1/s] of the period map of `scenario` started at `lin`'s equilibrium history
/// displaced by 1e-6 along the real part of its least stable mode: least squares on the log
/// of the history's deviation over `periods` periods, from period `skip` on.
fn map_growth(scenario: &Scenario, lin: &Linearization, periods: usize, skip: usize) -> f64 {
    let mut system = closed_loop_system(scenario, &LinearizeOptions::default()).unwrap();
    let (nx, nd, slots) = (system.layout.nx(), system.layout.nd(), system.slots());
    let plant = system.plant().clone();
    let z_eq = lin.equilibrium.state.repeat(slots);
    let mut z = z_eq.clone();
    let mode = lin.least_stable_mode.map(|c| c.re);
    let scale = 1e-6 / mode.amax();
    for slot in 0..slots {
        let direction = mode.rows(slot * nd, nd).clone_owned();
        let range = slot * nx..(slot + 1) * nx;
        sea_plant::retract(
            &plant,
            &z_eq[range.clone()],
            &direction,
            scale,
            &mut z[range],
        );
    }
    let mut next = z.clone();
    let mut deviation = nalgebra::DVector::zeros(slots * nd);
    let period = 1.0 / scenario.controller.rate_hz();
    let mut points = Vec::new();
    for k in 0..periods {
        difference_slots(&system.layout, &z_eq, &z, &mut deviation);
        if k >= skip {
            points.push((k as f64 * period, deviation.norm().ln()));
        }
        system.period_map(&z, &mut next).unwrap();
        std::mem::swap(&mut z, &mut next);
    }
    slope(&points)
}
