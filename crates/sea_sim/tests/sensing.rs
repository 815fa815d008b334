//! `[sensing]`: the controller reads a noisy, delayed measurement of the state while the plant
//! integrates, and the record keeps, the true state. Short runs (1 s) of the paper's tracking
//! at the robot's rates (whole-body 100 Hz, joint loops 1 kHz).

use sea_sim::closed_loop::{run, RunRecord, Summary};
use sea_sim::error::Error;
use sea_sim::scenario::Scenario;
use std::path::PathBuf;

/// Realistic encoder noise: joint and motor encoders 1e-4 rad, velocities 1e-2 rad/s.
const NOISE: [(&str, &str); 4] = [
    ("sensing.joint_position_noise_rad", "1e-4"),
    ("sensing.motor_position_noise_rad", "1e-4"),
    ("sensing.joint_velocity_noise_rad_s", "1e-2"),
    ("sensing.motor_velocity_noise_rad_s", "1e-2"),
];

fn scenario_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/robot_rate/tracking_multi_rate.toml")
}

/// The multi-rate tracking scenario, 1 s, every sample recorded, with `overrides`.
fn load(overrides: &[(&str, &str)]) -> Result<Scenario, Error> {
    let base = [
        ("simulation.duration_s", "1.0"),
        ("simulation.record_every", "1"),
        // Written for the fixed estimates: the file's stiffness identification off.
        ("controller.stiffness_identification", "false"),
    ];
    let pairs: Vec<(String, String)> = base
        .iter()
        .chain(overrides)
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&scenario_path(), &pairs)
}

/// The run of `load(overrides)`, which must complete.
fn run_with(overrides: &[(&str, &str)]) -> (RunRecord, Summary) {
    let scenario = load(overrides).unwrap();
    let (record, summary) = run(&scenario, |_, _| {}).unwrap();
    assert_eq!(summary.status, "completed", "{overrides:?}: {summary:?}");
    (record, summary)
}

/// The recorded trajectory and every tracking figure of the summary, bitwise.
fn fingerprint(record: &RunRecord, summary: &Summary) -> (Vec<u64>, [u64; 5]) {
    let series = [
        &record.state,
        &record.com,
        &record.motor_torques,
        &record.thetadot_desired,
    ];
    let bits = series.iter().flat_map(|s| s.iter().map(|v| v.to_bits()));
    let figures = [
        summary.com_error_rms_m,
        summary.com_error_max_m,
        summary.com_error_lateral_max_m,
        summary.joint_error_norm_final_rad,
        summary.motor_velocity_peak_rad_s,
    ];
    (bits.collect(), figures.map(f64::to_bits))
}

fn with<'a>(extra: &[(&'a str, &'a str)]) -> Vec<(&'a str, &'a str)> {
    NOISE.iter().chain(extra).copied().collect()
}

/// The same seed gives bitwise the same run, another seed another run; the noise reaches the
/// controller (the run differs from the noiseless one) but not the record, whose errors are the
/// true state's (zero at the start, where the state is the initial posture).
#[test]
fn noise_is_reproducible_by_seed_and_the_record_keeps_the_truth() {
    let (record_a, summary_a) = run_with(&with(&[("sensing.seed", "7")]));
    let (record_b, summary_b) = run_with(&with(&[("sensing.seed", "7")]));
    let (record_c, summary_c) = run_with(&with(&[("sensing.seed", "8")]));
    let (clean, clean_summary) = run_with(&[]);
    let a = fingerprint(&record_a, &summary_a);
    assert_eq!(a, fingerprint(&record_b, &summary_b), "same seed");
    assert_ne!(a.0, fingerprint(&record_c, &summary_c).0, "another seed");
    assert_ne!(a.0, fingerprint(&clean, &clean_summary).0, "no noise");
    // t = 0: the true joint error of the initial posture is 0 (a measured one would be about
    // 1e-4 rad x sqrt(25)), the CoM the true one.
    assert_eq!(record_a.joint_error_norm[0], 0.0);
    for (noisy, true_com) in record_a.com[..3].iter().zip(&clean.com[..3]) {
        assert!((noisy - true_com).abs() < 1e-12, "{noisy} vs {true_com}");
    }
    // Realistic encoder noise costs little: the CoM error rms within 20 % of the clean run's.
    let (noisy, clean) = (summary_a.com_error_rms_m, clean_summary.com_error_rms_m);
    assert!(noisy < 1.2 * clean, "{noisy} vs {clean}");
}

/// A `[sensing]` table with zero noise and no delay is perfect sensing: bitwise the run
/// without it, whatever the seed.
#[test]
fn zero_noise_is_the_run_without_sensing() {
    let (clean, clean_summary) = run_with(&[]);
    let zero = [
        ("sensing.joint_position_noise_rad", "0.0"),
        ("sensing.motor_velocity_noise_rad_s", "0.0"),
        ("sensing.delay_inner_periods", "0"),
        ("sensing.seed", "123"),
    ];
    let (record, summary) = run_with(&zero);
    assert_eq!(
        fingerprint(&record, &summary),
        fingerprint(&clean, &clean_summary)
    );
}

/// A delay alone (no noise) changes the trajectory, the more the longer it is, and is
/// reproducible.
#[test]
fn a_delay_changes_the_trajectory() {
    let (clean, clean_summary) = run_with(&[]);
    let clean = fingerprint(&clean, &clean_summary);
    let delayed = |d: &str| {
        let (record, summary) = run_with(&[("sensing.delay_inner_periods", d)]);
        (fingerprint(&record, &summary), summary.com_error_rms_m)
    };
    let (one, rms_one) = delayed("1");
    let (two, rms_two) = delayed("2");
    assert_ne!(one.0, clean.0);
    assert_ne!(one.0, two.0);
    assert_eq!(one, delayed("1").0);
    assert!(rms_one.is_finite() && rms_two.is_finite());
}

/// The linearisation carries a delay's states (the history of `d + 1` states, refused in
/// continuous time where it has no finite state, naming the key); noise alone is the
/// noiseless loop's linearisation.
#[test]
fn linearize_carries_a_delay_and_ignores_noise() {
    use sea_sim::analysis::{linearize_with, ControlTiming, LinearizeOptions};
    let delayed = load(&[("sensing.delay_inner_periods", "1")]).unwrap();
    let clean = sea_sim::analysis::linearize(&load(&[]).unwrap(), None).unwrap();
    let lin = sea_sim::analysis::linearize(&delayed, None).unwrap();
    let nd = clean.matrix.nrows();
    assert_eq!(lin.matrix.shape(), (2 * nd, 2 * nd));
    assert_eq!(lin.state_names[nd], format!("{}@-1", lin.state_names[0]));
    assert_ne!(lin.least_stable_rate, clean.least_stable_rate);
    let continuous = LinearizeOptions {
        sampling: Some(ControlTiming::Continuous),
        ..Default::default()
    };
    let message = linearize_with(&delayed, &continuous)
        .unwrap_err()
        .to_string();
    assert!(message.contains("sensing.delay_inner_periods"), "{message}");
    let noisy = sea_sim::analysis::linearize(&load(&NOISE).unwrap(), None).unwrap();
    assert_eq!(noisy.least_stable_rate, clean.least_stable_rate);
}

/// The error of `load(overrides)`, which must name `key`.
fn assert_refused(overrides: &[(&str, &str)], key: &str) {
    match load(overrides) {
        Err(error) => {
            let message = error.to_string();
            assert!(message.contains(key), "{overrides:?}: {message}");
        }
        Ok(_) => panic!("{overrides:?}: accepted"),
    }
}

/// Each bad value is refused before a run, the error naming its key.
#[test]
fn bad_sensing_values_name_their_key() {
    let continuous = ("controller.sampling", "continuous");
    for (name, _) in NOISE {
        assert_refused(&[(name, "-1e-4")], name);
        assert_refused(&[(name, "nan")], name);
        assert_refused(&[continuous, (name, "1e-4")], name);
    }
    let delay = "sensing.delay_inner_periods";
    // 100 Hz whole-body, 1 kHz joint loops: at most 10 inner periods.
    assert!(load(&[(delay, "10")]).is_ok());
    assert_refused(&[(delay, "11")], delay);
    assert_refused(&[continuous, (delay, "1")], delay);
    let held = ("controller.sampling", "zero_order_hold");
    assert!(load(&[held, (delay, "1")]).is_ok());
    assert_refused(&[held, (delay, "2")], delay);
    assert_refused(&[(delay, "-1")], delay);
    assert_refused(&[("sensing.encoder_noise", "1e-4")], "encoder_noise");
    // Perfect sensing is allowed with continuous sampling (the seed alone changes nothing).
    assert!(load(&[continuous, ("sensing.seed", "3")]).is_ok());
}
