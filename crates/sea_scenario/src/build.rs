//! From a parsed scenario to objects: the model, actuation, plant, controller, initial state
//! and references of one run.

use crate::error::{Error, Result};
use crate::schema::{ActuatorsConfig, TORQUE_LIMIT_FROM_URDF};
use crate::{
    expand_joint_groups, ComOrigin, ControllerKind, InitialSprings, RobotDescription, Sampling,
    Scenario,
};
use nalgebra::Vector3;
use sea_ctrl::controller::MomentumController;
use sea_ctrl::references::{ComTrajectory, PostureReference};
use sea_dyn::spatial::quaternion_from_rotation;
use sea_dyn::urdf::UNKNOWN_LISTED_JOINT;
use sea_dyn::{Actuation, Actuator, Data, FrameId, LoadOptions, Model, WarningKind};
use sea_plant::{MotorInput, Plant};
use std::collections::HashMap;
use std::path::Path;

/// A built scenario (typed by the loop, its input).
pub use sea_loop::Setup;

/// The robot model: the URDF reduced to `robot.joints` (default: the robot description's),
/// with a frame for each `LINK:x,y,z` contact.
pub fn load_model(scenario: &Scenario) -> Result<Model> {
    let urdf = scenario.urdf_path();
    let (joints, key) = match &scenario.robot.joints {
        Some(joints) => (joints.clone(), "robot.joints".to_string()),
        None => (
            scenario.description.joints.clone(),
            scenario.description_key("joints"),
        ),
    };
    let options = LoadOptions {
        joints: Some(joints),
        ..Default::default()
    };
    let mut model = Model::from_urdf_file(&urdf, &options).map_err(|e| match e {
        sea_dyn::Error::Model {
            element, message, ..
        } if message == UNKNOWN_LISTED_JOINT => {
            let rule = format!("names a joint that {} does not have", urdf.display());
            Error::invalid(key, rule, element)
        }
        other => other.into(),
    })?;
    crate::robots::add_contact_frames(&mut model, &scenario.robot.contacts)?;
    Ok(model)
}

/// Every joint's actuator: `[actuators]`, then the per-joint overrides.
pub fn actuation(scenario: &Scenario, model: &Model) -> Result<Actuation> {
    let actuators = &scenario.actuators;
    let default = actuators.default.actuator();
    let mut overrides = HashMap::new();
    for (name, config) in &actuators.overrides {
        if model.joint_index(name).is_none() {
            let key = format!("actuators.overrides.{name}");
            return Err(Error::config(key, "unknown joint"));
        }
        overrides.insert(name.clone(), config.actuator());
    }
    if actuators.torque_limit_from_urdf {
        limit_torques_from_urdf(actuators, model, default, &mut overrides)?;
    }
    Actuation::new(model, default, &overrides)
        .map_err(|e| Error::config("actuators", e.to_string()))
}

/// `actuators.torque_limit_from_urdf`: every elastic joint without a `torque_limit` of its
/// own gets `ratio` times its URDF effort limit (motor side), where the URDF gives one.
fn limit_torques_from_urdf(
    actuators: &ActuatorsConfig,
    model: &Model,
    default: Actuator,
    overrides: &mut HashMap<String, Actuator>,
) -> Result<()> {
    if actuators.default.parameters.torque_limit.is_some() {
        return Err(Error::config(
            format!("actuators.{TORQUE_LIMIT_FROM_URDF}"),
            "takes each joint's limit from the URDF; `actuators.torque_limit` sets every \
             joint's: set one of them (a joint's own limit goes in `actuators.overrides`)",
        ));
    }
    for joint in &model.joints {
        let actuator = overrides.get(&joint.name).copied().unwrap_or(default);
        if let Actuator::Elastic(mut p) = actuator {
            if p.torque_limit.is_none() && joint.effort_limit.is_finite() {
                p.torque_limit = Some(p.ratio * joint.effort_limit);
                overrides.insert(joint.name.clone(), Actuator::Elastic(p));
            }
        }
    }
    Ok(())
}

/// The initial joint positions `s0` (n) of `robot.initial_posture`: a posture of the robot
/// description (in the model's joint order), zero, or explicit radians.
fn initial_posture(scenario: &Scenario, model: &Model) -> Result<Vec<f64>> {
    let robot = scenario.description.as_ref();
    match &scenario.robot.initial_posture {
        toml::Value::String(name) if name == "zero" => Ok(vec![0.0; model.n_joints()]),
        toml::Value::String(name) if robot.postures.contains_key(name) => {
            described_posture(robot, name, model)
        }
        toml::Value::Array(items) => explicit_posture(items, model),
        other => {
            let names = robot.postures.keys().map(|name| format!("\"{name}\", "));
            Err(Error::config(
                "robot.initial_posture",
                format!(
                    "expected {}\"zero\" or a list of radians, got {other}",
                    names.collect::<String>()
                ),
            ))
        }
    }
}

/// The posture `name` of `robot` in the model's joint order.
fn described_posture(robot: &RobotDescription, name: &str, model: &Model) -> Result<Vec<f64>> {
    let angles = robot.postures[name].radians();
    model
        .joint_names
        .iter()
        .map(|joint| {
            robot
                .joints
                .iter()
                .position(|j| j == joint)
                .map(|k| angles[k])
                .ok_or_else(|| {
                    Error::config(
                        "robot.initial_posture",
                        format!("no value for joint '{joint}'"),
                    )
                })
        })
        .collect()
}

/// Explicit radians, one per joint of the model.
fn explicit_posture(items: &[toml::Value], model: &Model) -> Result<Vec<f64>> {
    if items.len() != model.n_joints() {
        return Err(Error::invalid(
            "robot.initial_posture",
            format!("needs {} numbers (one per joint)", model.n_joints()),
            format!("{} entries", items.len()),
        ));
    }
    items
        .iter()
        .enumerate()
        .map(|(i, v)| {
            v.as_float()
                .or(v.as_integer().map(|i| i as f64))
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    Error::invalid(
                        format!("robot.initial_posture[{i}]"),
                        "must be a finite number (radians)",
                        v,
                    )
                })
        })
        .collect()
}

/// The contact frames of `robot.contacts`, stance foot first.
pub fn contact_frames(scenario: &Scenario, model: &Model) -> Result<Vec<FrameId>> {
    scenario
        .robot
        .contacts
        .iter()
        .map(|name| {
            model
                .frame_id(name)
                .map_err(|_| Error::config("robot.contacts", format!("unknown frame '{name}'")))
        })
        .collect()
}

/// The initial configuration: joints `s0`, base placed so that the stance sole is flat at the
/// world origin.
fn initial_configuration(model: &Model, s0: &[f64], stance: FrameId) -> Vec<f64> {
    let mut q = model.neutral();
    q[7..].copy_from_slice(s0);
    let mut data = Data::new(model);
    sea_dyn::forward_kinematics(model, &mut data, &q);
    let world_h_base = sea_dyn::frame_placement(model, &data, stance).inverse();
    q[..3].copy_from_slice(world_h_base.translation.as_slice());
    q[3..7].copy_from_slice(&quaternion_from_rotation(&world_h_base.rotation));
    q
}

/// The plant of `[plant]` with the contacts of `robot.contacts` held at their pose in `q`; the
/// elastic joints take desired motor velocities (motor velocity loop) under the SEA controller
/// or the joint loops of `multi_rate`, and motor torques under the rigid one otherwise.
fn plant(scenario: &Scenario, model: &Model, actuation: &Actuation, q: &[f64]) -> Result<Plant> {
    let config = &scenario.plant;
    let mut plant = Plant::new(model.clone(), actuation.clone());
    plant.baumgarte_kp = config.baumgarte_kp;
    plant.baumgarte_kd = config.baumgarte_kd();
    plant.joint_inertia_regularization = config.joint_inertia_regularization;
    let joint_loops = scenario.controller.sampling == Sampling::MultiRate;
    plant.motor_input = match scenario.controller.kind {
        ControllerKind::Rigid if !joint_loops => MotorInput::Torque,
        _ => MotorInput::VelocityLoop {
            gain: config.motor_velocity_gain,
        },
    };
    plant.contact_limits = scenario.controller.contact.surface;
    plant
        .validate()
        .map_err(|e| Error::config("plant", e.to_string()))?;
    plant.set_contacts(&scenario.robot.contacts, q)?;
    if config.contact_model == crate::ground::ContactModelKind::Unilateral {
        crate::ground::make_unilateral(&mut plant, scenario, q)?;
    }
    plant.joint_stops = crate::ground::joint_stops(scenario);
    Ok(plant)
}

/// The initial state at rest in `q`, springs as `robot.initial_springs` says: preloaded with
/// the static torques (the run starts in equilibrium) or at rest (no deflection).
fn initial_state(plant: &Plant, q: &[f64], springs: InitialSprings) -> Result<Vec<f64>> {
    let theta = match springs {
        InitialSprings::Preloaded => Some(sea_plant::equilibrium::static_motor_angles(plant, q)?),
        // `make_state` without motor angles leaves every spring undeflected.
        InitialSprings::AtRest => None,
    };
    let nu = vec![0.0; plant.model.nv()];
    Ok(plant.make_state(q, &nu, theta.as_deref(), None)?)
}

/// The CoM reference of `[reference]`; its origin is the initial CoM or (`stance_sole`) the
/// point above the stance sole origin at the initial CoM height.
pub fn com_reference(
    scenario: &Scenario,
    model: &Model,
    q: &[f64],
    stance: FrameId,
) -> Result<ComTrajectory> {
    let r = &scenario.reference;
    let mut data = Data::new(model);
    let com0 = sea_dyn::com(model, &mut data, q);
    let origin = match r.com_origin {
        ComOrigin::StanceSole => {
            sea_dyn::forward_kinematics(model, &mut data, q);
            let sole = sea_dyn::frame_placement(model, &data, stance).translation;
            Vector3::new(sole.x, sole.y, com0.z)
        }
        ComOrigin::Initial => com0,
    };
    let direction = Vector3::from(r.com_direction);
    if direction.norm() < 1e-12 {
        return Err(Error::config("reference.com_direction", "must be non-zero"));
    }
    Ok(ComTrajectory {
        origin,
        amplitude: r.com_amplitude,
        frequency: r.com_frequency,
        direction: direction.normalize(),
        smooth_start: r.com_smooth_start,
    })
}

/// The postural reference: `s0`, plus the step of `[reference]` on its joints and groups.
pub fn posture_reference(
    scenario: &Scenario,
    model: &Model,
    s0: Vec<f64>,
) -> Result<PostureReference> {
    let r = &scenario.reference;
    let stepped = expand_joint_groups(
        &scenario.description,
        &r.posture_step_joints,
        &model.joint_names,
    )?;
    let step = model
        .joint_names
        .iter()
        .map(|n| {
            if stepped.contains(n) {
                r.posture_step_deg.to_radians()
            } else {
                0.0
            }
        })
        .collect();
    Ok(PostureReference {
        initial: s0,
        step,
        step_time: r.posture_step_time,
    })
}

/// Builds the model, plant, controller and initial state of a scenario; a key's error gives
/// the scenario's file and the key's line ([`crate::Origin::locate`]).
pub fn build(scenario: &Scenario) -> Result<Setup> {
    build_setup(scenario).map_err(|e| scenario.origin.locate(e))
}

/// The warnings of the `model` loaded from `urdf` that a run reports, each naming the URDF:
/// all but the point masses ([`WarningKind::SingularInertia`]: the sensor and tool frames'
/// idealisation that most humanoids' URDFs have, e.g. Talos's five).
pub fn model_warnings(urdf: &Path, model: &Model) -> Vec<String> {
    model
        .warnings
        .iter()
        .filter(|warning| warning.kind != WarningKind::SingularInertia)
        .map(|warning| format!("{}: {warning}", urdf.display()))
        .collect()
}

/// [`build`] without the key's place in the file.
fn build_setup(scenario: &Scenario) -> Result<Setup> {
    let model = load_model(scenario)?;
    super::validate::against_model(scenario, model.total_mass(), model.gravity.norm())?;
    let actuation = actuation(scenario, &model)?;
    let s0 = initial_posture(scenario, &model)?;
    let contacts = contact_frames(scenario, &model)?;
    let q = initial_configuration(&model, &s0, contacts[0]);
    let plant = plant(scenario, &model, &actuation, &q)?;
    let x0 = initial_state(&plant, &q, scenario.robot.initial_springs)?;
    let settings = scenario.controller_settings(&model.joint_names)?;
    let controller_model = scenario.controller_model(&model)?;
    let mut controller = MomentumController::new(&controller_model, &actuation, settings, &q)?;
    let mut warnings = model_warnings(&scenario.urdf_path(), &model);
    warnings.extend(crate::walking::set_up(
        scenario,
        &model,
        &contacts,
        &q,
        &mut controller,
    )?);
    warnings.extend(disturbances_after_the_end(scenario));
    let com_reference = com_reference(scenario, &model, &q, contacts[0])?;
    let posture = posture_reference(scenario, &model, s0)?;
    let elastic_names = actuation
        .elastic_joints
        .iter()
        .map(|&j| model.joint_names[j].clone())
        .collect();
    Ok(Setup {
        model,
        plant,
        controller,
        x0,
        com_reference,
        posture,
        elastic_names,
        warnings,
    })
}

/// A warning for each disturbance that starts at or after the run's end: it never acts (a
/// run shortened by an override keeps its file's pushes; an error would refuse that run).
fn disturbances_after_the_end(scenario: &Scenario) -> Vec<String> {
    let end = scenario.simulation.duration_s;
    scenario
        .disturbances
        .iter()
        .enumerate()
        .filter(|(_, d)| d.start_s >= end)
        .map(|(i, d)| {
            format!(
                "disturbances[{i}].start_s = {} s is at or after the run's end \
                 (simulation.duration_s = {end} s): that disturbance never acts",
                d.start_s
            )
        })
        .collect()
}
