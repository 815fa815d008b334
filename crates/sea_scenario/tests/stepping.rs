//! `walking.stepping`: the iCub of `scenarios/walking/push_recovery_step.toml` standing on
//! two feet steps to recover a push beyond what its centres of pressure recover, and stands
//! without a step below the step threshold; runs are deterministic.

use sea_loop::RunRecord;
use sea_scenario::run::run_setup_with_sinks;
use sea_scenario::{build, Scenario};
use std::path::Path;
use std::sync::atomic::AtomicBool;

const RECOVERY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/walking/push_recovery_step.toml"
);

/// The override of one 0.1 s push on the pelvis at 1 s of `impulse` [N s] along world
/// (`x`, `y`).
fn push(x: f64, y: f64, impulse: f64) -> (String, String) {
    let force = [x * impulse / 0.1, y * impulse / 0.1];
    (
        "disturbances".to_string(),
        format!(
            "[{{link = \"root_link\", force = [{:e}, {:e}, 0.0], start_s = 1.0, duration_s = 0.1}}]",
            force[0], force[1]
        ),
    )
}

/// A run of the recovery scenario with `overrides`: its record, summary and setup after it.
fn run(overrides: &[(String, String)]) -> (RunRecord, sea_loop::Summary, sea_loop::Setup) {
    let scenario = Scenario::from_file(Path::new(RECOVERY), overrides).unwrap();
    let mut setup = build(&scenario).unwrap();
    let mut record = RunRecord::default();
    let summary = run_setup_with_sinks(
        &scenario,
        &mut setup,
        &mut [&mut record],
        &AtomicBool::new(false),
        |_, _| (),
    )
    .unwrap();
    (record, summary, setup)
}

/// Prints what a push does (`STEP_PUSH="x y impulse"`): the outcome, the recovery steps
/// planned, the CoM and soles every 50 ms.
#[test]
#[ignore]
fn print_a_push() {
    let spec = std::env::var("STEP_PUSH").unwrap_or("1 0 16".into());
    let v: Vec<f64> = spec.split_whitespace().map(|s| s.parse().unwrap()).collect();
    let mut overrides = vec![push(v[0], v[1], v[2])];
    if let Ok(extra) = std::env::var("STEP_SET") {
        for pair in extra.split(',') {
            let (k, val) = pair.split_once('=').unwrap();
            overrides.push((k.into(), val.into()));
        }
    }
    let (record, summary, setup) = run(&overrides);
    println!(
        "{} {} at {:.3} s, steps {:?}",
        summary.status, summary.reason, summary.duration_s, summary.steps_taken
    );
    for (t, step) in setup.controller.recovery_steps() {
        println!("planned at {t:.3}: {step:?}");
    }
    let model = &setup.model;
    let frames = setup.controller.contact_frames().to_vec();
    let nx = record.state.len() / record.time.len();
    let mut data = sea_dyn::Data::new(model);
    for (row, x) in record.state.chunks(nx).enumerate().step_by(5) {
        let t = record.time[row];
        if t < 0.95 {
            continue;
        }
        sea_dyn::forward_kinematics(model, &mut data, &x[..model.nq()]);
        let soles = [0, 1].map(|c| sea_dyn::frame_placement(model, &data, frames[c]).translation);
        let com = &record.com[3 * row..3 * row + 3];
        let reference = &record.com_reference[3 * row..3 * row + 3];
        println!(
            "t {t:.2} com ({:.3} {:.3}) ref ({:.3} {:.3}) l ({:.3} {:.3} {:.3}) r ({:.3} {:.3} {:.3})",
            com[0], com[1], reference[0], reference[1], soles[0].x, soles[0].y, soles[0].z,
            soles[1].x, soles[1].y, soles[1].z
        );
    }
}
