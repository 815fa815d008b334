//! `[walking]`: the iCub of `scenarios/walking/` steps at the robot's rates on unilateral
//! contacts (feet lift and land, no fall, determinism, the swing sole reaching its target,
//! no jump of the planned wrenches at a switch), and bad walking settings refused naming the
//! key.

use sea_ctrl::walking::FootTask;
use sea_loop::RunRecord;
use sea_scenario::run::run_setup_with_sinks;
use sea_scenario::{build, Scenario};
use std::path::Path;
use std::sync::atomic::AtomicBool;

const STEPS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/walking/steps_in_place.toml"
);

fn scenario(path: &str, overrides: &[(&str, &str)]) -> sea_scenario::Result<Scenario> {
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(Path::new(path), &pairs)
}

/// The error message of building `path` with `overrides` (read or build).
fn refused(path: &str, overrides: &[(&str, &str)]) -> String {
    match scenario(path, overrides).and_then(|s| build(&s).map(|_| ())) {
        Ok(()) => panic!("{overrides:?} accepted"),
        Err(error) => error.to_string(),
    }
}

/// A run of `path` with `overrides`: its record, summary and built setup after the run.
fn walk(path: &str, overrides: &[(&str, &str)]) -> (RunRecord, sea_loop::Summary, sea_loop::Setup) {
    let scenario = scenario(path, overrides).unwrap();
    let mut setup = build(&scenario).unwrap();
    let mut record = RunRecord::default();
    let cancel = AtomicBool::new(false);
    let summary = run_setup_with_sinks(
        &scenario,
        &mut setup,
        &mut [&mut record],
        &cancel,
        |_, _| (),
    )
    .unwrap();
    (record, summary, setup)
}

/// Each sole's world position at every recorded sample (rows x 2 contacts).
fn sole_positions(record: &RunRecord, setup: &sea_loop::Setup) -> Vec<[nalgebra::Vector3<f64>; 2]> {
    let model = &setup.model;
    let frames = setup.controller.contact_frames().to_vec();
    let nx = record.state.len() / record.time.len();
    let mut data = sea_dyn::Data::new(model);
    record
        .state
        .chunks(nx)
        .map(|x| {
            sea_dyn::forward_kinematics(model, &mut data, &x[..model.nq()]);
            [0, 1].map(|c| sea_dyn::frame_placement(model, &data, frames[c]).translation)
        })
        .collect()
}

#[test]
#[ignore = "diagnostic"]
fn print_the_walk() {
    // Overrides from WALK_SET="key=value;key=value".
    let set = std::env::var("WALK_SET").unwrap_or_default();
    let mut overrides = vec![("simulation.record_every", "10")];
    overrides.extend(set.split(';').filter_map(|kv| kv.split_once('=')));
    let (record, summary, setup) = walk(STEPS, &overrides);
    println!("{}", serde_json::to_string(&summary).unwrap());
    let soles = sole_positions(&record, &setup);
    let gait = setup.controller.gait().unwrap();
    for (row, t) in record.time.iter().enumerate() {
        let tasks = gait.foot_tasks(*t);
        let desired: Vec<String> = tasks
            .iter()
            .map(|task| match task {
                FootTask::Swing(s) => format!("{:.3},{:.4}", s.world_p_sole.x, s.world_p_sole.z),
                FootTask::Contact { share } => format!("c{share:.2}"),
            })
            .collect();
        let w = &record.contact_wrenches[12 * row..12 * row + 12];
        let com = &record.com[3 * row..3 * row + 3];
        let reference = &record.com_reference[3 * row..3 * row + 3];
        println!(
            "{t:.3} x {:.3} {:.3} z {:.4} {:.4} d {:?} fz {:.1} {:.1} com {:.4} {:.4} ref {:.4} {:.4} je {:.3}",
            soles[row][0].x,
            soles[row][1].x,
            soles[row][0].z,
            soles[row][1].z,
            desired,
            w[2],
            w[8],
            com[0],
            com[1],
            reference[0],
            reference[1],
            record.joint_error_norm[row]
        );
    }
    let (nq, n) = (setup.model.nq(), setup.model.n_joints());
    let nx = record.state.len() / record.time.len();
    let last = &record.state[nx * (record.time.len() - 1)..][7..nq];
    let first = &record.state[7..nq];
    for j in 0..n {
        println!("{} {:.3}", record.joint_names[j], last[j] - first[j]);
    }
}
