//! Fixtures shared by the sea_sim integration tests.

// Each test crate that includes this module uses some of its fixtures.
#![allow(dead_code)]

use sea_sim::scenario::Scenario;
use std::path::{Path, PathBuf};

/// The shipped robot-rate scenarios run the stiffness identification; the tests written for
/// the fixed estimates (the identification as the override of a test) start with it off.
pub const FIXED_ESTIMATES: (&str, &str) = ("controller.stiffness_identification", "false");

/// The proxy the robot-rate tests were written for, before the feet could leave the ground:
/// the feet welded (bilateral contacts: a fall is a foot's wrench that a unilateral contact
/// could not carry). The tests of a setting of the controller keep it, so that their figures
/// stay those of docs/findings; the feet on the ground are tested in `tests/impacts.rs`,
/// `sea_scenario`'s `tests/ground.rs` and `sea_plant`'s `tests/unilateral.rs`.
pub const WELDED_FEET: (&str, &str) = ("plant.contact_model", "\"bilateral\"");

/// The push scenario as the push tests were written for: the feet welded, a joint past its
/// URDF limit ending the run (the plant had no joint stops), the default error bounds.
pub const WELDED_PUSH: [(&str, &str); 4] = [
    WELDED_FEET,
    ("simulation.stop_at_joint_limits", "true"),
    ("simulation.divergence_joint_error_rad", "1.0"),
    ("simulation.divergence_com_error_m", "0.1"),
];

/// `pairs` after [`WELDED_FEET`] (a later pair overrides an earlier one).
pub fn welded(pairs: &[(String, String)]) -> Vec<(String, String)> {
    prefixed(&[WELDED_FEET], pairs)
}

/// `pairs` after [`WELDED_PUSH`].
pub fn welded_push(pairs: &[(String, String)]) -> Vec<(String, String)> {
    prefixed(&WELDED_PUSH, pairs)
}

/// `first`, then `pairs`.
fn prefixed(first: &[(&str, &str)], pairs: &[(String, String)]) -> Vec<(String, String)> {
    first
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .chain(pairs.iter().cloned())
        .collect()
}

/// The multi-rate tracking scenario (`scenarios/robot_rate/tracking_multi_rate.toml`) with
/// its fixed estimates ([`FIXED_ESTIMATES`]) and `overrides` (dotted key, TOML value).
///
/// # Panics
/// When the scenario does not load with them.
pub fn tracking(overrides: &[(&str, &str)]) -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/robot_rate/tracking_multi_rate.toml");
    let pairs: Vec<(String, String)> = std::iter::once(&FIXED_ESTIMATES)
        .chain(overrides)
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&path, &welded(&pairs)).unwrap()
}

/// `scenarios/walking/walk_straight.toml` (20 steps at 0.1 m/s) with `overrides` (dotted key,
/// TOML value).
///
/// # Panics
/// When the scenario does not load with them.
pub fn walk_straight(overrides: &[(&str, &str)]) -> Scenario {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/walking/walk_straight.toml");
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&path, &pairs).unwrap()
}

/// A state of `setup` (built from `scenario`) where the robot accelerates: the initial state
/// with every spring deflected `extra` [rad] more, the plant's outputs there and its
/// accelerations `nudot` (nv).
///
/// # Panics
/// When the plant's evaluation fails.
pub fn accelerating_state(
    scenario: &Scenario,
    setup: &sea_sim::scenario::Setup,
    extra: f64,
) -> (Vec<f64>, sea_plant::PlantOutputs, Vec<f64>) {
    let plant = &setup.plant;
    let layout = plant.layout();
    let mut x = setup.x0.clone();
    let theta = layout.theta_offset();
    for (e, parameters) in plant.actuation.elastic.iter().enumerate() {
        x[theta + e] += extra / parameters.ratio;
    }
    let mut pd = scenario.plant.plant_data(plant);
    let mut outputs = sea_plant::PlantOutputs::new(plant);
    let u = vec![0.0; plant.model.n_joints()];
    sea_plant::evaluate(plant, &mut pd.workspace, &x, &u, &mut outputs).unwrap();
    let nudot = layout.tangent().split(outputs.xdot.as_slice()).dnu.to_vec();
    (x, outputs, nudot)
}

/// Overrides that put the tracking scenario's iCub on both feet (the original study's two-feet
/// posture) with a 2 cm, 0.5 Hz CoM sinusoid about the initial CoM.
pub const TWO_FEET: [(&str, &str); 5] = [
    ("robot.contacts", "[\"l_sole\", \"r_sole\"]"),
    ("robot.initial_posture", "two_feet"),
    ("reference.com_origin", "initial"),
    ("reference.com_amplitude", "0.02"),
    ("reference.com_frequency", "0.5"),
];

/// The robot description's momentum gains and postural scale for two feet, which the push
/// scenario replaces with compliant horizontal CoM gains and a stiffer posture: they hold the
/// CoM stiffly (docs/findings/pushes.md).
pub const STIFF_COM_GAINS: [(&str, &str); 2] = [
    (
        "controller.momentum_integral",
        "[40.0, 45.0, 40.0, 1.0, 5.0, 1.0]",
    ),
    ("controller.postural_scale", "0.2"),
];

/// A file in the temporary folder named after its test (`prefix`), `tag` and this process,
/// removed when dropped.
pub struct TempFile(pub PathBuf);

impl TempFile {
    /// `<temp dir>/<prefix>_<tag>_<pid>.mcap`.
    pub fn new(prefix: &str, tag: &str) -> Self {
        let name = format!("{prefix}_{tag}_{}.mcap", std::process::id());
        Self(std::env::temp_dir().join(name))
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// The `share` folders of the cmeel prefixes of the project's `.venv` and of `$VIRTUAL_ENV`.
pub fn cmeel_shares() -> Vec<PathBuf> {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let envs = [
        Some(repo.join(".venv")),
        std::env::var_os("VIRTUAL_ENV").map(PathBuf::from),
    ];
    let mut shares = Vec::new();
    for env in envs.into_iter().flatten() {
        let Ok(entries) = std::fs::read_dir(env.join("lib")) else {
            continue;
        };
        for entry in entries.flatten() {
            let share = entry.path().join("site-packages/cmeel.prefix/share");
            if share.is_dir() {
                shares.push(share);
            }
        }
    }
    shares
}

/// The robot file `relative` of example-robot-data (the PyPI package, a test dependency) in
/// the project's `.venv` or `$VIRTUAL_ENV`, if installed.
pub fn robot(relative: &str) -> Option<PathBuf> {
    cmeel_shares()
        .into_iter()
        .map(|share| share.join("example-robot-data/robots").join(relative))
        .find(|path| path.is_file())
}
