//! The scenario `sea-sim init` writes: its robot description inline (`[robot.description]`)
//! and the paper's CoM sinusoid on two feet, written beside the target and renamed over it
//! when complete.

use super::posture::Standing;
use super::{actuators, gains, walking, InitOptions};
use crate::error::{Error, Result};
use crate::output::OutputFile;
use crate::scenario::robots::AngleUnit;
use crate::scenario::robots::{
    icub, FootRectangle, MomentumIntegral, PosturalStiffness, Posture, RobotDescription,
};
use crate::scenario::schema::TORQUE_LIMIT_FROM_URDF;
use sea_ctrl::walking::WalkingSettings;
use sea_dyn::Model;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The CoM sinusoid of the scenario: amplitude [m], frequency [Hz], duration [s].
pub const COM_SINUSOID: (f64, f64, f64) = (0.01, 0.2, 5.0);

/// The pseudo-inverse damping `controller.pinv_damping` written for a robot whose two feet's
/// constraints are redundant (rank 11 of 12: legs of 5 joints). Under the paper's 5e-4 the
/// mini biped's one zero-momentum mode (the pelvis pitching against the torso and hips, the
/// null space of `Lambda`) drifts and the run ends at 2.45 s; from 1e-2 it stays bounded
/// (60 s, docs/findings/robots.md).
pub const REDUNDANT_PINV_DAMPING: f64 = 3e-2;

/// What the scenario is made of besides the options.
pub struct Body<'a> {
    /// The foot rectangles (left, right).
    pub rectangles: [FootRectangle; 2],
    /// The standing posture.
    pub standing: &'a Standing,
    /// The joint torques holding it [Nm] (n, [`actuators::standing_torques`]).
    pub standing_torques: &'a [f64],
    /// The rank of the two feet's constraints (12, or fewer when redundant: then
    /// [`REDUNDANT_PINV_DAMPING`]).
    pub feet_rank: usize,
    /// `Some`: a walking scenario with these settings (`super::walking`).
    pub walking: Option<&'a WalkingSettings>,
}

/// Writes the scenario of `body`; returns the path written.
pub fn write_scenario(options: &InitOptions, model: &Model, body: &Body<'_>) -> Result<PathBuf> {
    let mut description = describe(options, model, body)?;
    if body.feet_rank < 12 {
        description.pinv_damping = REDUNDANT_PINV_DAMPING;
    }
    let suffix = if body.walking.is_some() {
        "walk"
    } else {
        "two_feet"
    };
    let name = options
        .name
        .clone()
        .unwrap_or_else(|| format!("{}_{suffix}", model.name));
    let text = match body.walking {
        None => scenario_text(options, &name, &description, model.total_mass())?,
        Some(settings) => walking_text(options, &name, &description, settings)?,
    };
    let mut file = OutputFile::create(&options.out)?;
    file.write_all(text.as_bytes())?;
    file.commit()?;
    Ok(options.out.clone())
}

/// The robot description of the new robot.
fn describe(options: &InitOptions, model: &Model, body: &Body<'_>) -> Result<RobotDescription> {
    let (standing, rectangles) = (body.standing, body.rectangles);
    let mut q = model.neutral();
    q[7..].copy_from_slice(&standing.joints);
    let elastic = actuators::scaled_actuators(body.standing_torques);
    let regularization = gains::joint_inertia_regularization(model.total_mass());
    let stiffness = gains::postural_stiffness(model, &q, regularization)?;
    let paper = icub();
    Ok(RobotDescription {
        urdf: Some(urdf_as_written(&options.urdf, &options.out)),
        joints: model.joint_names.clone(),
        postures: BTreeMap::from([(
            "standing".to_string(),
            Posture {
                unit: AngleUnit::Rad,
                angles: standing.joints.clone(),
            },
        )]),
        contacts: options.contacts.to_vec(),
        initial_posture: "standing".into(),
        foot: Some(common_rectangle(rectangles)?),
        actuator: None,
        actuator_overrides: model.joint_names.iter().cloned().zip(elastic).collect(),
        joint_groups: BTreeMap::new(),
        postural_stiffness: PosturalStiffness {
            sides: Vec::new(),
            leg_joints: Vec::new(),
            stance_leg: Vec::new(),
            swing_leg: Vec::new(),
            by_name: model.joint_names.iter().cloned().zip(stiffness).collect(),
            by_suffix: Vec::new(),
            other: 0.0,
        },
        postural_scale: 1.0,
        momentum_integral: MomentumIntegral {
            one_foot: paper.momentum_integral.one_foot,
            two_feet: paper.momentum_integral.two_feet,
        },
        motor_velocity_gain: paper.motor_velocity_gain,
        joint_inertia_regularization: regularization,
        pinv_damping: paper.pinv_damping,
        qp_regularization: paper.qp_regularization,
    })
}

/// The rectangle inside both feet's (one rectangle serves both contacts).
fn common_rectangle(rectangles: [FootRectangle; 2]) -> Result<FootRectangle> {
    let [left, right] = rectangles;
    let both = |a: [f64; 2], b: [f64; 2]| [a[0].max(b[0]), a[1].min(b[1])];
    let common = FootRectangle {
        x: both(left.x, right.x),
        y: both(left.y, right.y),
    };
    super::check_foot(&common).map_err(|_| {
        Error::argument(
            "foot",
            "a rectangle given (X0,X1,Y0,Y1): the two measured ones do not overlap in their \
             contact frames",
            format!("none, measured {left} and {right}"),
        )
    })
}

/// The URDF as the scenario names it: a URI as given, a path relative to the scenario's folder
/// (absolute when no relative path joins them).
fn urdf_as_written(urdf: &str, out: &Path) -> String {
    if urdf.contains("://") {
        return urdf.to_string();
    }
    let absolute = |p: &Path| std::path::absolute(p).ok();
    let folder = out.parent().filter(|p| !p.as_os_str().is_empty());
    let (Some(file), Some(dir)) = (
        absolute(Path::new(urdf)),
        absolute(folder.unwrap_or(Path::new("."))),
    ) else {
        return urdf.to_string();
    };
    relative(&file, &dir).unwrap_or(file).display().to_string()
}

/// `file` relative to `dir` (both absolute).
fn relative(file: &Path, dir: &Path) -> Option<PathBuf> {
    let file: Vec<_> = file.components().collect();
    let dir: Vec<_> = dir.components().collect();
    let common = file.iter().zip(&dir).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return None;
    }
    let mut out: PathBuf = dir[common..].iter().map(|_| "..").collect();
    out.extend(file[common..].iter());
    Some(out)
}

/// The scenario's TOML text, for a robot of `robot_mass` [kg].
fn scenario_text(
    options: &InitOptions,
    name: &str,
    robot: &RobotDescription,
    robot_mass: f64,
) -> Result<String> {
    let (amplitude, frequency, duration) = COM_SINUSOID;
    let mut root = toml::Table::new();
    root.insert("name".into(), name.into());
    root.insert("robot".into(), robot_table(options, robot)?.into());
    let mut actuators = toml::Table::new();
    actuators.insert(TORQUE_LIMIT_FROM_URDF.into(), true.into());
    root.insert("actuators".into(), actuators.into());
    let reference: toml::Table = toml::from_str(&format!(
        "com_amplitude = {amplitude:?}\ncom_frequency = {frequency:?}\n\
         com_direction = [0.0, 1.0, 0.0]\ncom_origin = \"initial\"\n"
    ))
    .map_err(|e| Error::config("reference", e.to_string()))?;
    root.insert("reference".into(), reference.into());
    // The feet stand on the ground: unilateral contacts, joint stops at the URDF's limits.
    let mut plant = toml::Table::new();
    plant.insert("contact_model".into(), "unilateral".into());
    root.insert("plant".into(), plant.into());
    if let Some(force) = gains::min_normal_force(robot_mass) {
        let mut contact = toml::Table::new();
        contact.insert("min_normal_force".into(), force.into());
        let mut controller = toml::Table::new();
        controller.insert("contact".into(), contact.into());
        root.insert("controller".into(), controller.into());
    }
    let mut simulation = toml::Table::new();
    simulation.insert("duration_s".into(), duration.into());
    root.insert("simulation".into(), simulation.into());
    let body = toml::to_string(&root).map_err(|e| Error::config("scenario", e.to_string()))?;
    Ok(format!("{}{body}", header(options)))
}

/// The walking scenario's TOML text: the robot, [`walking::WALKING_CONTROLLER`]'s tables, the
/// `[walking]` table of `settings` and the duration of the walk and the standing after.
fn walking_text(
    options: &InitOptions,
    name: &str,
    robot: &RobotDescription,
    settings: &WalkingSettings,
) -> Result<String> {
    let mut root: toml::Table = toml::from_str(walking::WALKING_CONTROLLER)
        .map_err(|e| Error::config("controller", e.to_string()))?;
    root.insert("name".into(), name.into());
    root.insert("robot".into(), robot_table(options, robot)?.into());
    root["plant"]
        .as_table_mut()
        .expect("a table")
        .insert("contact_model".into(), "unilateral".into());
    root["simulation"].as_table_mut().expect("a table").insert(
        "duration_s".into(),
        walking::walking_duration(settings).into(),
    );
    let table =
        toml::Table::try_from(settings).map_err(|e| Error::config("walking", e.to_string()))?;
    root.insert("walking".into(), table.into());
    let body = toml::to_string(&root).map_err(|e| Error::config("scenario", e.to_string()))?;
    Ok(format!("{}{body}", walking_header(options, settings)))
}

/// The `[robot]` table: the package folders given and the description inline.
fn robot_table(options: &InitOptions, robot: &RobotDescription) -> Result<toml::Table> {
    let mut robot_table = toml::Table::new();
    if !options.package_dirs.is_empty() {
        let dirs = options
            .package_dirs
            .iter()
            .map(|d| d.display().to_string().into());
        robot_table.insert("package_dirs".into(), toml::Value::Array(dirs.collect()));
    }
    let description = toml::Table::try_from(robot)
        .map_err(|e| Error::config("robot.description", e.to_string()))?;
    robot_table.insert("description".into(), description.into());
    Ok(robot_table)
}

/// The comment on top of a walking scenario.
fn walking_header(options: &InitOptions, settings: &WalkingSettings) -> String {
    let made = header(options);
    let first = made.lines().next().unwrap_or_default().replace(
        "`: a two-feet balancing scenario",
        " --walking`: a walking scenario",
    );
    format!(
        "{first}\n\
         # with its robot description inline ([robot.description], docs/guide/your_robot.md).\n\
         # [walking]: the defaults scaled to the robot (com_height its CoM's standing height\n\
         # unless init's run of this walk lowered it, which init then printed, nominal_width its\n\
         # feet's distance, max_step_length 0.6 of the legs' reach, durations times sqrt(k) and\n\
         # swing_height times k, k = leg length / the iCub's: docs/explanation/walking.md), then\n\
         # {} steps forward of {:.3} m and the stop; the controller as the iCub walks\n\
         # (scenarios/walking/walk_straight.toml).\n\n",
        walking::WALK_STEPS,
        settings.command.forward_velocity * settings.step_duration,
    )
}

/// The comment on top of the file: how it was made.
/// `text` as it may stand in a TOML comment: its control characters (a newline in a file
/// name would end the comment and make the rest TOML) escaped as `\n`, `\u{1b}`.
fn in_comment(text: &str) -> std::borrow::Cow<'_, str> {
    sea_dyn::error::escaped_controls(text, &[])
}

fn header(options: &InitOptions) -> String {
    let foot = match &options.foot {
        Some(f) => format!(" --foot {},{},{},{}", f.x[0], f.x[1], f.y[0], f.y[1]),
        None => String::new(),
    };
    format!(
        "# Written by `sea-sim init {} --contacts {} {}{foot}`: a two-feet balancing scenario\n\
         # with its robot description inline ([robot.description]): SEA on every joint scaled\n\
         # to the robot, the standing posture found by inverse kinematics, the foot rectangle\n\
         # {}, gains scaled to the robot (docs/guide/your_robot.md).\n\
         # The run: the CoM follows a lateral sinusoid (1 cm, 0.2 Hz) for 5 s, the feet on the\n\
         # ground (unilateral contacts with friction, joint stops at the URDF's limits).\n\n",
        in_comment(&options.urdf),
        in_comment(&options.contacts[0]),
        in_comment(&options.contacts[1]),
        if options.foot.is_some() {
            "given"
        } else {
            "measured on the feet's collision geometry"
        }
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn control_characters_are_escaped_in_comments() {
        assert_eq!(
            super::in_comment("odd/a\n[controller]\nrate_hz = 5.urdf"),
            "odd/a\\n[controller]\\nrate_hz = 5.urdf"
        );
        assert_eq!(super::in_comment("plain é.urdf"), "plain é.urdf");
    }
}
