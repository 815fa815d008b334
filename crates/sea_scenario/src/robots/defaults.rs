//! A scenario takes its defaults from its robot description: before the schema reads the
//! scenario's TOML tree, every key the description decides and the file leaves out is written
//! into the tree ([`apply`]). So the schema reads one tree, a key given in the file (or by
//! `--set`) always wins, and the description's values are written once, in its file.
//!
//! The keys: `robot.urdf`, `robot.contacts`, `robot.initial_posture`,
//! `plant.motor_velocity_gain`, `plant.joint_inertia_regularization`,
//! `controller.postural_scale`, `controller.pinv_damping`, `controller.qp_regularization`,
//! `controller.joint_inertia_regularization`, `controller.contact.foot_x` and `foot_y` (from
//! the foot rectangle), the keys of `[actuators]` (from the description's actuator) and of
//! `[actuators.overrides.NAME]` (from its per-joint actuators). The joints, postures, joint
//! groups, postural stiffness and momentum gains are read from the description when the
//! scenario is built.

use super::source::{load_description, DescriptionSource};
use super::RobotDescription;
use crate::error::{Error, Result};
use std::path::Path;

/// Removes `robot.description` from `root`, loads the description it names (the paper's iCub
/// when absent) and writes its defaults into `root` ([`apply`]).
pub fn take_and_apply(root: &mut toml::Table, scenario_dir: &Path) -> Result<DescriptionSource> {
    let named = match root.get_mut("robot") {
        Some(toml::Value::Table(robot)) => robot.remove("description"),
        _ => None,
    };
    let source = load_description(named, scenario_dir)?;
    apply(root, &source)?;
    Ok(source)
}

/// Writes into `root` every default of `source`'s description that `root` leaves out.
pub fn apply(root: &mut toml::Table, source: &DescriptionSource) -> Result<()> {
    let robot = &source.description;
    if let Some(urdf) = &robot.urdf {
        let urdf = if urdf.contains("://") || Path::new(urdf).is_absolute() {
            urdf.clone()
        } else {
            source.dir.join(urdf).display().to_string()
        };
        insert_absent(root, &["robot", "urdf"], urdf.into());
    }
    let contacts = robot.contacts.iter().map(|c| toml::Value::from(c.as_str()));
    insert_absent(
        root,
        &["robot", "contacts"],
        contacts.collect::<Vec<_>>().into(),
    );
    let posture = robot.initial_posture.as_str().into();
    insert_absent(root, &["robot", "initial_posture"], posture);
    gains(root, robot);
    if let Some(foot) = &robot.foot {
        insert_absent(root, &["controller", "contact", "foot_x"], pair(foot.x));
        insert_absent(root, &["controller", "contact", "foot_y"], pair(foot.y));
    }
    actuators(root, robot)
}

/// The plant's and the controller's settings of the description.
fn gains(root: &mut toml::Table, robot: &RobotDescription) {
    let regularization = robot.joint_inertia_regularization;
    for (path, value) in [
        (["plant", "motor_velocity_gain"], robot.motor_velocity_gain),
        (["plant", "joint_inertia_regularization"], regularization),
        (["controller", "postural_scale"], robot.postural_scale),
        (["controller", "pinv_damping"], robot.pinv_damping),
        (["controller", "qp_regularization"], robot.qp_regularization),
        (
            ["controller", "joint_inertia_regularization"],
            regularization,
        ),
    ] {
        insert_absent(root, &path, value.into());
    }
}

/// `[min, max]` as a TOML array.
fn pair(values: [f64; 2]) -> toml::Value {
    toml::Value::Array(values.iter().map(|&v| v.into()).collect())
}

/// The description's actuator into `[actuators]`, its per-joint actuators into
/// `[actuators.overrides.NAME]`.
fn actuators(root: &mut toml::Table, robot: &RobotDescription) -> Result<()> {
    if let Some(actuator) = &robot.actuator {
        for (key, value) in keys_of(actuator)? {
            insert_absent(root, &["actuators", &key], value);
        }
    }
    for (joint, actuator) in &robot.actuator_overrides {
        for (key, value) in keys_of(actuator)? {
            insert_absent(root, &["actuators", "overrides", joint, &key], value);
        }
    }
    Ok(())
}

/// The keys of a serialisable table.
fn keys_of(value: &impl serde::Serialize) -> Result<toml::Table> {
    toml::Table::try_from(value)
        .map_err(|e| Error::config("robot.description.actuator", e.to_string()))
}

/// Writes `value` at `path` of `root` unless a value is there, creating tables on the way; a
/// non-table on the way is left for the schema to refuse.
fn insert_absent(root: &mut toml::Table, path: &[&str], value: toml::Value) {
    let (last, tables) = path.split_last().expect("a non-empty path");
    let mut table = root;
    for name in tables {
        let entry = table
            .entry(name.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let Some(inner) = entry.as_table_mut() else {
            return;
        };
        table = inner;
    }
    table.entry(last.to_string()).or_insert(value);
}

#[cfg(test)]
mod tests {
    use super::super::icub;
    use super::*;
    use crate::robots::FootRectangle;
    use sea_dyn::ElasticParameters;

    fn source(description: RobotDescription) -> DescriptionSource {
        DescriptionSource {
            description,
            dir: "descriptions".into(),
            file: None,
        }
    }

    #[test]
    fn the_file_wins_and_absent_keys_take_the_descriptions_values() {
        let mut robot = icub().clone();
        robot.urdf = Some("robot.urdf".into());
        robot.foot = Some(FootRectangle {
            x: [-0.1, 0.2],
            y: [-0.05, 0.05],
        });
        robot.actuator_overrides.insert(
            "knee".into(),
            ElasticParameters {
                stiffness: 900.0,
                ..Default::default()
            },
        );
        let mut root: toml::Table =
            toml::from_str("[plant]\nmotor_velocity_gain = 50.0\n[actuators]\nkind = \"rigid\"")
                .unwrap();
        apply(&mut root, &source(robot)).unwrap();
        assert_eq!(root["plant"]["motor_velocity_gain"].as_float(), Some(50.0));
        assert_eq!(
            root["plant"]["joint_inertia_regularization"].as_float(),
            Some(0.1)
        );
        assert_eq!(
            root["robot"]["urdf"].as_str(),
            Some("descriptions/robot.urdf")
        );
        assert_eq!(
            root["robot"]["initial_posture"].as_str(),
            Some("left_stance")
        );
        assert_eq!(
            root["controller"]["contact"]["foot_x"],
            toml::Value::Array(vec![(-0.1).into(), 0.2.into()])
        );
        let knee = &root["actuators"]["overrides"]["knee"];
        assert_eq!(knee["stiffness"].as_float(), Some(900.0));
        assert_eq!(root["actuators"]["kind"].as_str(), Some("rigid"));
    }
}
