//! `actuators.torque_limit_from_urdf`: each elastic joint's motor torque limit from its URDF
//! effort limit, checked against the numbers of the iCub URDF the walking scenarios load, and
//! bad combinations refused naming the key.

use crate::walking::scenario as load;
use sea_dyn::Actuator;
use sea_scenario::{build, Scenario};

const WALK: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/walking/walk_fast.toml"
);

fn scenario(overrides: &[(&str, &str)]) -> sea_scenario::Result<Scenario> {
    load(WALK, overrides)
}

/// Each elastic joint's motor torque limit in the walk built with `overrides`, by joint name.
fn torque_limits(overrides: &[(&str, &str)]) -> Vec<(String, Option<f64>)> {
    let setup = build(&scenario(overrides).unwrap()).unwrap();
    let plant = &setup.plant;
    (plant.model.joint_names.iter())
        .zip(&plant.actuation.actuators)
        .filter_map(|(name, actuator)| match actuator {
            Actuator::Elastic(p) => Some((name.clone(), p.torque_limit)),
            Actuator::Rigid => None,
        })
        .collect()
}

fn limit_of(limits: &[(String, Option<f64>)], joint: &str) -> Option<f64> {
    limits.iter().find(|(name, _)| name == joint).unwrap().1
}

#[test]
fn the_urdf_effort_limits_become_the_motor_torque_limits() {
    let unlimited = torque_limits(&[]);
    assert!(unlimited.iter().all(|(_, limit)| limit.is_none()));
    let limits = torque_limits(&[
        ("actuators.torque_limit_from_urdf", "true"),
        ("actuators.overrides.l_ankle_roll.torque_limit", "0.34"),
        ("actuators.overrides.r_elbow.kind", "\"rigid\""),
    ]);
    // urdf/icub25.urdf: <limit effort="37.0"> on the knees, "55.5" on the hip pitches,
    // "50000" on the torso and the arms; the transmission ratio is 0.01.
    let close = |joint: &str, expected: f64| {
        let limit = limit_of(&limits, joint).unwrap();
        assert!((limit - expected).abs() < 1e-12, "{joint}: {limit}");
    };
    close("l_knee", 0.37);
    close("r_knee", 0.37);
    close("r_hip_pitch", 0.555);
    close("torso_pitch", 500.0);
    // A joint's own limit stays; a rigid joint has no motor.
    close("l_ankle_roll", 0.34);
    assert!(limits.iter().all(|(name, _)| name != "r_elbow"));
}

#[test]
fn a_limit_for_every_joint_and_one_from_the_urdf_are_refused_naming_the_key() {
    for overrides in [
        &[
            ("actuators.torque_limit_from_urdf", "true"),
            ("actuators.torque_limit", "0.5"),
        ][..],
        &[("actuators.torque_limit_from_urdf", "1")][..],
        &[("actuators.overrides.l_knee.torque_limit_from_urdf", "true")][..],
    ] {
        let message = match scenario(overrides).and_then(|s| build(&s).map(|_| ())) {
            Ok(()) => panic!("{overrides:?} accepted"),
            Err(error) => error.to_string(),
        };
        let key = overrides[0].0;
        assert!(message.contains(key), "{overrides:?}: {message}");
    }
}
