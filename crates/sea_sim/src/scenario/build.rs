//! From a parsed scenario to objects: the model, actuation, plant, controller, initial state
//! and references of one run.

use crate::error::{Error, Result};
use crate::scenario::{
    expand_joint_groups, Scenario, ICUB25_JOINTS, ICUB_LEFT_STANCE, ICUB_TWO_FEET_DEG,
};
use nalgebra::Vector3;
use sea_ctrl::controller::{ControllerKind, MomentumController};
use sea_ctrl::references::{ComTrajectory, PostureReference};
use sea_dyn::spatial::quaternion_from_rotation;
use sea_dyn::{Actuation, Actuator, Data, ElasticParameters, LoadOptions, Model};
use sea_plant::{MotorInput, Plant};
use std::collections::HashMap;

/// A built scenario: model, plant, controller and initial state.
pub struct Setup {
    /// Robot model.
    pub model: Model,
    /// Plant.
    pub plant: Plant,
    /// Controller.
    pub controller: MomentumController,
    /// Initial plant state.
    pub x0: Vec<f64>,
    /// CoM reference.
    pub com_reference: ComTrajectory,
    /// Postural reference.
    pub posture: PostureReference,
    /// Elastic joint names (order of theta).
    pub elastic_names: Vec<String>,
}

fn elastic_parameters(c: &crate::scenario::ActuatorConfig, key: &str) -> Result<Actuator> {
    match c.kind.as_str() {
        "rigid" => Ok(Actuator::Rigid),
        "elastic" => Ok(Actuator::Elastic(ElasticParameters {
            ratio: c.ratio,
            motor_inertia: c.motor_inertia,
            stiffness: c.stiffness,
            damping: c.damping,
            torque_limit: c.torque_limit,
        })),
        other => Err(Error::config(
            key,
            format!("kind must be \"elastic\" or \"rigid\", got \"{other}\""),
        )),
    }
}

fn initial_posture(scenario: &Scenario, model: &Model) -> Result<Vec<f64>> {
    let value = &scenario.robot.initial_posture;
    let paper_order = |values: &[f64]| -> Result<Vec<f64>> {
        model
            .joint_names
            .iter()
            .map(|name| {
                ICUB25_JOINTS
                    .iter()
                    .position(|j| j == name)
                    .map(|k| values[k])
                    .ok_or_else(|| {
                        Error::config(
                            "robot.initial_posture",
                            format!("no value for joint '{name}'"),
                        )
                    })
            })
            .collect()
    };
    match value {
        toml::Value::String(s) if s == "left_stance" => paper_order(&ICUB_LEFT_STANCE),
        toml::Value::String(s) if s == "two_feet" => paper_order(&ICUB_TWO_FEET_DEG.map(f64::to_radians)),
        toml::Value::String(s) if s == "zero" => Ok(vec![0.0; model.n_joints()]),
        toml::Value::Array(items) => {
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
        other => Err(Error::config(
            "robot.initial_posture",
            format!("expected \"left_stance\", \"two_feet\", \"zero\" or a list of radians, got {other}"),
        )),
    }
}

/// Static joint torques holding `q` with the contacts taking the base wrench (least norm).
fn static_torques(model: &Model, q: &[f64], contacts: &[usize]) -> Vec<f64> {
    let mut data = Data::new(model);
    let gravity = sea_dyn::gravity_forces(model, &mut data, q).clone();
    let n = model.n_joints();
    let mut jacobian = nalgebra::DMatrix::zeros(6 * contacts.len(), model.nv());
    for (c, &frame) in contacts.iter().enumerate() {
        jacobian
            .rows_mut(6 * c, 6)
            .copy_from(sea_dyn::frame_jacobian(model, &mut data, q, frame));
    }
    let jb_t = jacobian.columns(0, 6).transpose();
    let f = jb_t
        .clone()
        .pseudo_inverse(1e-12)
        .map(|p| p * gravity.rows(0, 6))
        .unwrap_or_else(|_| nalgebra::DVector::zeros(6 * contacts.len()));
    let torques = gravity.rows(6, n) - jacobian.columns(6, n).transpose() * f;
    torques.as_slice().to_vec()
}

/// Builds the model, plant, controller and initial state of a scenario.
pub fn build(scenario: &Scenario) -> Result<Setup> {
    let urdf = scenario.resolve(&scenario.robot.urdf);
    let joints = scenario
        .robot
        .joints
        .clone()
        .unwrap_or_else(|| ICUB25_JOINTS.iter().map(|s| s.to_string()).collect());
    let model = Model::from_urdf_file(
        &urdf,
        &LoadOptions {
            joints: Some(joints),
            ..Default::default()
        },
    )?;
    let default = elastic_parameters(&scenario.actuators.default_actuator(), "actuators")?;
    let mut overrides = HashMap::new();
    for (name, config) in &scenario.actuators.overrides {
        if model.joint_index(name).is_none() {
            return Err(Error::config(
                format!("actuators.overrides.{name}"),
                "unknown joint",
            ));
        }
        let actuator = scenario.actuators.overridden(config);
        overrides.insert(
            name.clone(),
            elastic_parameters(&actuator, &format!("actuators.overrides.{name}"))?,
        );
    }
    let actuation = Actuation::new(&model, default, &overrides)
        .map_err(|e| Error::config("actuators", e.to_string()))?;
    // Initial configuration: stance sole flat at the world origin.
    let s0 = initial_posture(scenario, &model)?;
    let mut q = model.neutral();
    q[7..].copy_from_slice(&s0);
    let mut contact_ids = Vec::new();
    for name in &scenario.robot.contacts {
        contact_ids.push(
            model
                .frame_id(name)
                .map_err(|_| Error::config("robot.contacts", format!("unknown frame '{name}'")))?,
        );
    }
    let mut data = Data::new(&model);
    sea_dyn::forward_kinematics(&model, &mut data, &q);
    let world_h_base = sea_dyn::frame_placement(&model, &data, contact_ids[0]).inverse();
    q[..3].copy_from_slice(world_h_base.translation.as_slice());
    q[3..7].copy_from_slice(&quaternion_from_rotation(&world_h_base.rotation));

    let kind = scenario.controller_kind();
    let mut plant = Plant::new(model.clone(), actuation.clone());
    plant.baumgarte_kp = scenario.plant.baumgarte_kp;
    plant.baumgarte_kd = scenario
        .plant
        .baumgarte_kd
        .unwrap_or(2.0 * scenario.plant.baumgarte_kp.sqrt());
    plant.joint_inertia_regularization = scenario.plant.joint_inertia_regularization;
    plant.motor_input = match kind {
        ControllerKind::Sea => MotorInput::VelocityLoop {
            gain: scenario.plant.motor_velocity_gain,
        },
        ControllerKind::Rigid => MotorInput::Torque,
    };
    let c = &scenario.controller.contact;
    plant.contact_limits = sea_plant::ContactLimits {
        friction: c.friction,
        foot_x: c.foot_x,
        foot_y: c.foot_y,
    };
    plant
        .validate()
        .map_err(|e| Error::config("plant", e.to_string()))?;
    plant.set_contacts(&scenario.robot.contacts, &q)?;
    // Springs preloaded with the static torques, so the run starts in equilibrium.
    let torques = static_torques(&model, &q, &contact_ids);
    let theta: Vec<f64> = actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .map(|(&j, p)| (s0[j] + torques[j] / p.stiffness) / p.ratio)
        .collect();
    let x0 = plant.make_state(&q, &vec![0.0; model.nv()], Some(&theta), None)?;

    let settings = scenario.controller_settings(&model.joint_names)?;
    let controller = MomentumController::new(&model, &actuation, settings, &q)?;
    let com0 = sea_dyn::com(&model, &mut data, &q);
    let origin = match scenario.reference.com_origin.as_str() {
        "stance_sole" => {
            sea_dyn::forward_kinematics(&model, &mut data, &q);
            let sole = sea_dyn::frame_placement(&model, &data, contact_ids[0]).translation;
            Vector3::new(sole.x, sole.y, com0.z)
        }
        "initial" => com0,
        other => {
            return Err(Error::config(
                "reference.com_origin",
                format!("expected \"stance_sole\" or \"initial\", got \"{other}\""),
            ))
        }
    };
    let r = &scenario.reference;
    let direction = Vector3::from(r.com_direction);
    if direction.norm() < 1e-12 {
        return Err(Error::config("reference.com_direction", "must be non-zero"));
    }
    let com_reference = ComTrajectory {
        origin,
        amplitude: r.com_amplitude,
        frequency: r.com_frequency,
        direction: direction.normalize(),
        smooth_start: r.com_smooth_start,
    };
    let stepped = expand_joint_groups(&r.posture_step_joints, &model.joint_names)?;
    let step: Vec<f64> = model
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
    let posture = PostureReference {
        initial: s0,
        step,
        step_time: r.posture_step_time,
    };
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
    })
}
