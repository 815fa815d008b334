//! `plant.contact_model = "unilateral"` and `[ground]`: the plant built from them, and bad
//! grounds refused naming the key.

use sea_scenario::{build, Scenario};
use std::path::Path;

const PUSH: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/robot_rate/push_two_feet.toml"
);

fn scenario(overrides: &[(&str, &str)]) -> sea_scenario::Result<Scenario> {
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(Path::new(PUSH), &pairs)
}

/// The error message of building the push scenario with `overrides` (read or build).
fn refused(overrides: &[(&str, &str)]) -> String {
    match scenario(overrides).and_then(|s| build(&s).map(|_| ())) {
        Ok(()) => panic!("{overrides:?} accepted"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn the_push_scenario_stands_on_eight_points_of_a_ground_at_rest_penetration() {
    let setup = build(&scenario(&[]).unwrap()).unwrap();
    let plant = &setup.plant;
    let unilateral = plant.unilateral().expect("unilateral contacts");
    assert_eq!(plant.n_contact_points(), 8);
    assert!(plant.joint_stops.is_some(), "joint stops on by default");
    // The soles' points sit at the static penetration below the plane.
    let weight = plant.model.total_mass() * plant.model.gravity.norm();
    let penetration = weight / (8.0 * unilateral.law.stiffness);
    assert!((penetration - 5e-4).abs() < 1e-12, "{penetration}");
    let bilateral = build(&scenario(&[("plant.contact_model", "\"bilateral\"")]).unwrap()).unwrap();
    assert!(bilateral.plant.unilateral().is_none());
    assert!(
        bilateral.plant.joint_stops.is_none(),
        "no stops under bilateral by default"
    );
}

#[test]
fn bad_grounds_are_refused_naming_the_key() {
    let cases: &[(&[(&str, &str)], &str)] = &[
        (&[("ground.friction", "-0.5")], "ground.friction"),
        (&[("ground.friction", "nan")], "ground.friction"),
        (
            &[("ground.incline_rad", "1.5707963267948966")],
            "ground.incline_rad",
        ),
        (&[("ground.incline_rad", "2.0")], "ground.incline_rad"),
        (&[("ground.points", "[[0.5, 0.0]]")], "ground.points[0]"),
        (&[("ground.points", "[]")], "ground.points"),
        (&[("ground.height_m", "2.0")], "ground.height_m"),
        (&[("ground.height_m", "0.05")], "ground.height_m"),
        (
            &[("ground.stiffness_n_per_m", "0")],
            "ground.stiffness_n_per_m",
        ),
        (
            &[("ground.stiction_velocity_m_s", "-1")],
            "ground.stiction_velocity_m_s",
        ),
        (
            &[("plant.joint_stop_stiffness", "0")],
            "plant.joint_stop_stiffness",
        ),
    ];
    for (overrides, key) in cases {
        let message = refused(overrides);
        assert!(message.contains(key), "{overrides:?}: {message}");
    }
    // The incline is a scenario key's error when the file is read, whatever the contacts
    // (bilateral contacts build no ground).
    for incline in ["2.0", "-0.1"] {
        let bilateral = ("plant.contact_model", "\"bilateral\"");
        match scenario(&[("ground.incline_rad", incline), bilateral]) {
            Err(sea_loop::Error::Scenario { key, .. }) => assert_eq!(key, "ground.incline_rad"),
            other => panic!("incline {incline}: {other:?}"),
        }
    }
}

/// A joint list naming a joint the URDF lacks is the list's key's error, in the scenario
/// (`robot.joints`) or in the robot description's file (`robot description FILE: joints`).
#[test]
fn a_listed_joint_the_urdf_lacks_names_the_list() {
    let joints = ("robot.joints", "[\"torso_pitch\", \"l_kneee\"]");
    let message = refused(&[joints]);
    assert!(
        message.contains("push_two_feet.toml: scenario key 'robot.joints'")
            && message.contains("'l_kneee'"),
        "{message}"
    );
    let dir = std::env::temp_dir().join(format!("sea_joint_list_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let robots = concat!(env!("CARGO_MANIFEST_DIR"), "/../../robots/icub_paper.toml");
    let text = std::fs::read_to_string(robots).unwrap();
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/../../urdf/icub25.urdf");
    let text = text.replace("\"l_knee\"", "\"l_kneee\"");
    let description = dir.join("robot.toml");
    std::fs::write(&description, text).unwrap();
    let overrides = [
        ("robot.description", format!("{description:?}")),
        ("robot.urdf", format!("{urdf:?}")),
    ];
    let pairs: Vec<(&str, &str)> = overrides.iter().map(|(k, v)| (*k, v.as_str())).collect();
    let message = refused(&pairs);
    assert!(
        message.contains(&format!(
            "push_two_feet.toml: scenario key 'robot description {}: joints'",
            description.display()
        )) && message.contains("'l_kneee'"),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_push_that_starts_after_the_runs_end_is_a_warning_naming_it() {
    // The push starts at 1 s: a run cut to 0.5 s warns that it never acts, a run of 3 s does not.
    let short = build(&scenario(&[("simulation.duration_s", "0.5")]).unwrap()).unwrap();
    let warned: Vec<&String> = short
        .warnings
        .iter()
        .filter(|w| w.starts_with("disturbances[0].start_s"))
        .collect();
    assert_eq!(warned.len(), 1, "{:?}", short.warnings);
    assert!(warned[0].contains("never acts"), "{}", warned[0]);
    let whole = build(&scenario(&[]).unwrap()).unwrap();
    assert!(
        whole.warnings.iter().all(|w| !w.contains("disturbances")),
        "{:?}",
        whole.warnings
    );
}
