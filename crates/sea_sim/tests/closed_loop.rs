//! The closed loop: continuous sampling converges with the integrator's order, zero-order hold
//! takes any rate, the sample that crosses a divergence bound is the last one recorded, a
//! raised cancellation flag ends the run as "interrupted" with the sinks finished, and the
//! summary does not depend on what is recorded.

use sea_sim::closed_loop::{run, run_with_sinks, RecordSink, RunInfo, RunRecord, Sample, Summary};
use sea_sim::scenario::Scenario;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// The paper's tracking scenario in the sampled-data setting these tests were written for (1 kHz
/// zero-order hold, 1 ms plant step; the scenario file is continuous), then `overrides`.
fn tracking(overrides: &[(&str, &str)]) -> Scenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper/tracking.toml");
    let sampled = [
        ("controller.sampling", "zero_order_hold"),
        ("plant.dt", "0.001"),
    ];
    let pairs: Vec<(String, String)> = sampled
        .iter()
        .chain(overrides)
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&path, &pairs).unwrap()
}

/// Recorded CoM rows of a run.
fn com_rows(record: &RunRecord) -> Vec<[f64; 3]> {
    record.com.chunks(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Largest distance between CoM rows at the same times.
fn largest_difference(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

fn sci(values: &[f64]) -> String {
    let parts: Vec<String> = values.iter().map(|v| format!("{v:.3e}")).collect();
    parts.join(", ")
}

#[test]
fn continuous_sampling_converges_with_at_least_the_order_of_ros2() {
    // Records every millisecond at each step size, so the rows share their times.
    let levels = [
        ("1e-3", "1"),
        ("0.5e-3", "2"),
        ("0.25e-3", "4"),
        ("0.125e-3", "8"),
    ];
    let runs: Vec<Vec<[f64; 3]>> = levels
        .iter()
        .map(|(dt, every)| {
            let scenario = tracking(&[
                ("controller.sampling", "continuous"),
                ("plant.dt", dt),
                ("simulation.record_every", every),
                ("simulation.duration_s", "2.0"),
            ]);
            let (record, summary) = run(&scenario, |_, _| {}).unwrap();
            assert_eq!(summary.status, "completed", "{}", summary.reason);
            assert_eq!(summary.sampling, "continuous");
            com_rows(&record)
        })
        .collect();
    let differences: Vec<f64> = runs
        .windows(2)
        .map(|pair| largest_difference(&pair[0], &pair[1]))
        .collect();
    let orders: Vec<f64> = differences
        .windows(2)
        .map(|pair| (pair[0] / pair[1]).log2())
        .collect();
    println!(
        "continuous tracking, largest CoM differences between steps 1/0.5/0.25/0.125 ms: \
         {} m, observed orders {orders:.2?}",
        sci(&differences)
    );
    for order in orders {
        assert!(
            order > 1.8,
            "observed order {order:.2} ({})",
            sci(&differences)
        );
    }
    assert!(differences[0] < 1e-5, "{}", sci(&differences));
}

#[test]
fn zero_order_hold_takes_any_rate() {
    // 800 Hz with steps of at most 1 ms: 2 steps of 0.625 ms per tick.
    let scenario = tracking(&[
        ("controller.rate_hz", "800"),
        ("simulation.duration_s", "0.5"),
        ("simulation.record_every", "1"),
    ]);
    let (record, summary) = run(&scenario, |_, _| {}).unwrap();
    assert_eq!(summary.status, "completed", "{}", summary.reason);
    assert_eq!(summary.sampling, "zero_order_hold");
    assert_eq!(record.time.len(), 401);
    for (k, t) in record.time.iter().enumerate() {
        assert!((t - k as f64 / 800.0).abs() < 1e-12, "row {k}: {t}");
    }
}

#[test]
fn the_sample_that_crosses_a_bound_is_recorded() {
    // The CoM error of the tracking run peaks near 7.8 mm: a 5 mm bound is crossed.
    let scenario = tracking(&[
        ("simulation.divergence_com_error_m", "0.005"),
        ("simulation.record_every", "1000"),
    ]);
    let (record, summary) = run(&scenario, |_, _| {}).unwrap();
    assert_eq!(summary.status, "diverged");
    let at = summary.diverged_at_s.unwrap();
    assert_eq!(record.time.last(), Some(&at));
    assert_eq!(summary.duration_s, at);
    let rows = com_rows(&record);
    let (com, reference) = (
        rows.last().unwrap(),
        &record.com_reference[record.com.len() - 3..],
    );
    let error = (0..3)
        .map(|k| (com[k] - reference[k]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(error > 0.005, "{error}");
    assert_eq!(
        summary.reason,
        format!("CoM error {error:.4} m over the bound 0.005 m")
    );
    // Damping estimate x0.4 at 1 kHz: the joint error bound.
    let scenario = tracking(&[
        ("controller.damping_estimate_scale", "0.4"),
        ("simulation.record_every", "1000"),
        // The joint error bound, on the model's bilateral contacts (a real foot tips first).
        ("simulation.stop_on_fall", "false"),
    ]);
    let (record, summary) = run(&scenario, |_, _| {}).unwrap();
    assert_eq!(summary.status, "diverged");
    assert_eq!(record.time.last().copied(), summary.diverged_at_s);
    let last = *record.joint_error_norm.last().unwrap();
    assert!(last > 1.0);
    assert_eq!(summary.joint_error_norm_final_rad, last);
    assert_eq!(
        summary.reason,
        format!("joint error norm {last:.4} rad over the bound 1 rad")
    );
}

/// A sink that counts samples and raises `cancel` once a sample reaches `stop_at` seconds.
struct Canceller<'a> {
    cancel: &'a AtomicBool,
    stop_at: f64,
    times: Vec<f64>,
    began: bool,
    finished: bool,
}

impl RecordSink for Canceller<'_> {
    fn begin(&mut self, _run: &RunInfo<'_>) -> sea_sim::Result<()> {
        self.began = true;
        Ok(())
    }

    fn record(&mut self, sample: &Sample<'_>) -> sea_sim::Result<()> {
        self.times.push(sample.time_s);
        if sample.time_s >= self.stop_at {
            self.cancel.store(true, Ordering::Relaxed);
        }
        Ok(())
    }

    fn finish(&mut self) -> sea_sim::Result<()> {
        self.finished = true;
        Ok(())
    }
}

#[test]
fn a_raised_flag_interrupts_the_run_at_the_next_sample() {
    for sampling in ["zero_order_hold", "continuous"] {
        let scenario = tracking(&[
            ("controller.sampling", sampling),
            ("simulation.record_every", "1"),
        ]);
        let cancel = AtomicBool::new(false);
        let mut sink = Canceller {
            cancel: &cancel,
            stop_at: 0.1,
            times: Vec::new(),
            began: false,
            finished: false,
        };
        let mut record = RunRecord::default();
        let summary =
            run_with_sinks(&scenario, &mut [&mut sink, &mut record], &cancel, |_, _| {}).unwrap();
        assert_eq!(summary.status, "interrupted", "{sampling}");
        assert_eq!(summary.reason, "interrupted");
        assert!(summary.diverged_at_s.is_none());
        // The flag went up at the sample at 0.1 s; the next one is the last.
        assert!(
            (summary.duration_s - 0.101).abs() < 1e-9,
            "{}",
            summary.duration_s
        );
        assert_eq!(sink.times.last(), Some(&summary.duration_s));
        assert_eq!(record.time, sink.times);
        assert!(sink.began && sink.finished);
    }
}

/// Summary fields that do not depend on wall time.
fn figures(summary: &Summary) -> Vec<f64> {
    vec![
        summary.duration_s,
        summary.com_error_rms_m,
        summary.com_error_max_m,
        summary.com_error_lateral_max_m,
        summary.joint_error_norm_final_rad,
        summary.motor_velocity_peak_rad_s,
        summary.qp_failures as f64,
    ]
}

#[test]
fn the_summary_does_not_depend_on_the_sinks() {
    let scenario = tracking(&[("simulation.duration_s", "1.5")]);
    let (record, recorded) = run(&scenario, |_, _| {}).unwrap();
    let unrecorded =
        run_with_sinks(&scenario, &mut [], &AtomicBool::new(false), |_, _| {}).unwrap();
    assert_eq!(figures(&recorded), figures(&unrecorded));
    assert_eq!(record.time.len(), 151);
    assert!(recorded.com_error_rms_m > 0.0);
}
