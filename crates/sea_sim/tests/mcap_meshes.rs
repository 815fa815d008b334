//! The robot's meshes in the MCAP log are written once, on `/robot`: a 5 s log (the tracking
//! scenario's recording rate, 2.5 ms) of real robots made of meshes weighs its per-sample
//! channels plus one `/robot` message, not one per sample. The robots come from the PyPI
//! package `example-robot-data` (a test dependency) in the project's `.venv` or the active
//! `$VIRTUAL_ENV`; without it the test says so and checks nothing.
//! `cargo test --release -p sea_sim --test integration mcap_meshes:: -- --nocapture` prints the sizes.

use crate::support::robot;
use sea_ctrl::qp::QpStatus;
use sea_dyn::{LoadOptions, Model, StateLayout};
use sea_sim::closed_loop::Sample;
use sea_sim::foxglove::SceneSource;
use sea_sim::mcap_log::McapLogger;
use std::path::{Path, PathBuf};

/// Samples of a 5 s run recorded every 2.5 ms (scenarios/paper/tracking.toml).
const SAMPLES: usize = 2001;

/// Writes a 5 s log of `model` (with the scene of `urdf` when given) and returns its size.
fn log_size(model: &Model, urdf: Option<&Path>, file: &Path) -> u64 {
    let contacts: Vec<String> = Vec::new();
    let mut logger = McapLogger::create(file, model, &model.joint_names, &contacts).unwrap();
    if let Some(urdf) = urdf {
        let warnings = logger.set_scene(&SceneSource::new(urdf)).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
    }
    let n = model.n_joints();
    let layout = StateLayout {
        nq: model.nq(),
        nv: model.nv(),
        ne: n,
    };
    let zeros = vec![0.0; n];
    for k in 0..SAMPLES {
        let t = k as f64 * 0.0025;
        let mut state = model.neutral();
        state[2] = 1.0;
        for (j, s) in state[7..].iter_mut().enumerate() {
            *s = 0.2 * (t + j as f64).sin();
        }
        let q_joints = state[7..].to_vec();
        state.extend(q_joints);
        state.extend(std::iter::repeat_n(0.01, model.nv() + n));
        let sample = Sample {
            time_s: t,
            state: &state,
            layout,
            thetadot_desired: &zeros,
            com: [0.0, 0.0, 0.9],
            com_reference: [0.0, 0.0, 0.9],
            momentum: [0.0; 6],
            contact_wrenches: &[],
            planned_wrenches: &[],
            contact_point_positions: &[],
            contact_point_forces: &[],
            contact_point_active: &[],
            contact_checks: &[],
            motor_torques: &zeros,
            joint_torques: &zeros,
            com_error_norm: 0.0,
            joint_error_norm: 0.0,
            qp_status: &QpStatus::Solved,
            disturbance_wrenches: &[],
            external_wrench: [0.0; 6],
            qp_failures: 0,
        };
        logger.log(&sample).unwrap();
    }
    logger.finish().unwrap();
    std::fs::metadata(file).unwrap().len()
}

/// Size of the one `/robot` message of the log at `file`.
fn robot_message_size(file: &Path) -> u64 {
    let bytes = std::fs::read(file).unwrap();
    let robot: Vec<_> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .filter(|m| m.channel.topic == "/robot")
        .collect();
    assert_eq!(robot.len(), 1, "one /robot message");
    robot[0].data.len() as u64
}

#[test]
fn meshes_are_written_once_per_log() {
    let robots = [
        "talos_data/robots/talos_reduced.urdf",
        "romeo_description/urdf/romeo.urdf",
        "g1_description/urdf/g1_29dof_rev_1_0.urdf",
    ];
    let found: Vec<PathBuf> = robots.iter().filter_map(|r| robot(r)).collect();
    if found.is_empty() {
        eprintln!("example-robot-data is not installed (.venv, $VIRTUAL_ENV): nothing checked");
        return;
    }
    let dir = std::env::temp_dir().join(format!("sea_sim_mcap_meshes_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for urdf in found {
        let model = Model::from_urdf_file(&urdf, &LoadOptions::default()).unwrap();
        let name = urdf.file_stem().unwrap().to_string_lossy().into_owned();
        let with = dir.join(format!("{name}.mcap"));
        let without = dir.join(format!("{name}_bare.mcap"));
        let (size, bare) = (
            log_size(&model, Some(&urdf), &with),
            log_size(&model, None, &without),
        );
        let robot = robot_message_size(&with);
        eprintln!(
            "{name}: 5 s log {:.2} MB, without the scene {:.2} MB, /robot message {:.2} MB",
            size as f64 / 1e6,
            bare as f64 / 1e6,
            robot as f64 / 1e6
        );
        assert!(robot > 100_000, "{name}: the meshes are in /robot");
        // The URDF attachment and the support polygon are small; the meshes count once.
        assert!(
            size < bare + robot + 200_000,
            "{name}: {size} >= {bare} + {robot}"
        );
    }
    std::fs::remove_dir_all(dir).unwrap();
}
