//! The touchdowns of `scenarios/walking/walk_straight.toml` with series elastic actuators
//! against the rigid-joint robot under the same gait (`actuators.kind = "rigid"`): per
//! touchdown the foot's velocity jump, the largest joint torque change and joint velocity jump
//! over the joints, the peak spring torque and motor velocity (elastic). Prints the table of
//! docs/findings/walking_impacts.md:
//! `cargo test --release -p sea_sim --test integration walking_impacts:: -- --ignored --nocapture`.
//! The test that runs by default checks that both actuations report the joint-side figures of
//! every touchdown of a short walk.

use crate::support;

use sea_loop::impacts::SPEED_AFTER_S;
use sea_sim::closed_loop::{run_with_sinks, ImpactKind, RecordSink, RunRecord, Summary};
use sea_sim::scenario::Scenario;
use std::sync::atomic::AtomicBool;
use support::walk_straight;

/// Runs `scenario`: its summary and record (the impacts).
fn run(scenario: &Scenario) -> (Summary, RunRecord) {
    let mut record = RunRecord::default();
    let mut sinks: Vec<&mut dyn RecordSink> = vec![&mut record];
    let summary = run_with_sinks(scenario, &mut sinks, &AtomicBool::new(false), |_, _| {});
    (summary.unwrap(), record)
}

/// Each touchdown's before `until_s` [s] (foot velocity jump, joint torque change, joint
/// velocity jump, spring torque peak, motor velocity peak).
fn touchdowns(record: &RunRecord, until_s: f64) -> Vec<[f64; 5]> {
    record
        .impacts
        .iter()
        .filter(|i| i.kind == ImpactKind::Touchdown && i.time_s < until_s)
        .map(|i| {
            [
                i.velocity_jump(),
                i.peak_joint_torque_change_nm,
                i.joint_velocity_jump_rad_s,
                i.peak_spring_torque_after_nm,
                i.peak_motor_velocity_after_rad_s,
            ]
        })
        .collect()
}

/// Median and maximum of the finite `values`.
fn median_max(mut values: Vec<f64>) -> (f64, f64) {
    values.retain(|v| v.is_finite());
    values.sort_by(f64::total_cmp);
    if values.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    (values[values.len() / 2], values[values.len() - 1])
}

#[test]
fn both_actuations_report_the_joint_side_of_every_touchdown() {
    for kind in ["elastic", "rigid"] {
        let actuation = format!("\"{kind}\"");
        let walk = walk_straight(&[
            ("actuators.kind", &actuation),
            ("walking.command", "{ forward_velocity = 0.1, steps = 2 }"),
            ("simulation.duration_s", "1.6"),
        ]);
        let (summary, record) = run(&walk);
        assert_eq!(summary.status, "completed", "{kind}: {summary:?}");
        let complete: Vec<_> = record
            .impacts
            .iter()
            .filter(|i| i.kind == ImpactKind::Touchdown && i.window_after_s >= SPEED_AFTER_S)
            .collect();
        assert!(!complete.is_empty(), "{kind}: no touchdown");
        for impact in complete {
            let torque_change = impact.peak_joint_torque_change_nm;
            let velocity_jump = impact.joint_velocity_jump_rad_s;
            assert!(torque_change > 0.0 && torque_change.is_finite(), "{impact}");
            assert!(velocity_jump > 0.0 && velocity_jump.is_finite(), "{impact}");
            if kind == "rigid" {
                // No spring, no motor state: the elastic figures are zero.
                let elastic = (
                    impact.peak_spring_torque_after_nm,
                    impact.peak_motor_velocity_after_rad_s,
                );
                assert_eq!(elastic, (0.0, 0.0), "{impact}");
            }
        }
    }
}

/// The touchdowns compared: those of the whole walk (20 steps and the stop, 14.5 s; both
/// actuations complete it).
const COMPARED_S: f64 = 14.5;

#[test]
#[ignore = "prints the findings' table (two 14.5 s walks)"]
fn print_the_touchdowns_of_both_actuations() {
    println!(
        "| actuation | outcome | steps | touchdowns before {COMPARED_S} s | foot velocity jump \
         [m/s] | largest joint torque change [Nm] | joint velocity jump [rad/s] | peak spring \
         torque [Nm] | peak motor velocity [rad/s] | wall [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for kind in ["elastic", "rigid"] {
        let actuation = format!("\"{kind}\"");
        let (summary, record) = run(&walk_straight(&[("actuators.kind", &actuation)]));
        let figures = touchdowns(&record, COMPARED_S);
        let column = |k: usize| {
            let (median, max) = median_max(figures.iter().map(|f| f[k]).collect());
            format!("{median:.3} / {max:.3}")
        };
        println!(
            "| {kind} | {} at {:.2} s ({}) | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            summary.status,
            summary.duration_s,
            summary.reason,
            summary.steps_taken.unwrap_or(0),
            figures.len(),
            column(0),
            column(1),
            column(2),
            column(3),
            column(4),
            summary.wall_time_s,
        );
    }
}
