//! The closed loop: the controller at its rate (zero-order hold), the plant with its motor
//! velocity loop in between, divergence detection, recording, summary and MCAP logging.
//!
//! A run stops as "diverged" when a step or a tick fails, the state is not finite, the CoM
//! error exceeds `simulation.divergence_com_error_m` or the joint error norm exceeds
//! `simulation.divergence_joint_error_rad`; everything recorded until then is kept and the log
//! is finished.

use crate::error::{Error, Result};
use crate::mcap_log::{LogSample, McapLogger, ThreadedMcapLogger};
use crate::scenario::{
    expand_joint_groups, Scenario, ICUB25_JOINTS, ICUB_LEFT_STANCE, ICUB_TWO_FEET_DEG,
};
use nalgebra::Vector3;
use sea_ctrl::controller::{ControllerKind, MomentumController};
use sea_ctrl::qp::QpStatus;
use sea_ctrl::references::{ComTrajectory, PostureReference};
use sea_dyn::spatial::quaternion_from_rotation;
use sea_dyn::{Actuation, Actuator, Data, ElasticParameters, LoadOptions, Model};
use sea_plant::{Method, MotorInput, Plant, PlantData};
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// Everything recorded, one row per recorded tick (row-major arrays).
#[derive(Clone, Debug, Default)]
pub struct RunRecord {
    /// Time [s] (rows).
    pub time: Vec<f64>,
    /// Plant states (rows x nx).
    pub state: Vec<f64>,
    /// Desired motor velocities (rows x n_e; zeros for the rigid controller).
    pub thetadot_desired: Vec<f64>,
    /// CoM (rows x 3) [m].
    pub com: Vec<f64>,
    /// CoM reference (rows x 3) [m].
    pub com_reference: Vec<f64>,
    /// Centroidal momentum (rows x 6).
    pub momentum: Vec<f64>,
    /// Simulated contact wrenches (rows x 6 n_contacts).
    pub contact_wrenches: Vec<f64>,
    /// Motor torques applied by the plant (rows x n_e).
    pub motor_torques: Vec<f64>,
    /// Joint error norm |s - s_d| (rows) [rad].
    pub joint_error_norm: Vec<f64>,
    /// 1 when the tick's QP was solved, 0 when it fell back (rows).
    pub qp_solved: Vec<f64>,
    /// `(nq, nv, n_e)` of the state rows.
    pub layout: (usize, usize, usize),
    /// Joint names (coordinate order).
    pub joint_names: Vec<String>,
    /// Elastic joint names (order of theta).
    pub elastic_joints: Vec<String>,
}

/// The summary of a run (also written as JSON by `sea-sim`).
#[derive(Clone, Debug)]
pub struct Summary {
    /// "completed" or "diverged".
    pub status: String,
    /// Time of divergence [s].
    pub diverged_at_s: Option<f64>,
    /// Why it diverged.
    pub reason: String,
    /// Simulated time reached [s].
    pub duration_s: f64,
    /// RMS of the CoM error norm [m].
    pub com_error_rms_m: f64,
    /// Maximum CoM error norm [m].
    pub com_error_max_m: f64,
    /// Maximum lateral (y) CoM error after the first second [m].
    pub com_error_lateral_max_m: f64,
    /// |s - s_d| at the end [rad].
    pub joint_error_norm_final_rad: f64,
    /// Largest |thetadot| [rad/s].
    pub motor_velocity_peak_rad_s: f64,
    /// QP solves that fell back.
    pub qp_failures: usize,
    /// QP solves done by Clarabel (the others: the minimiser without inequalities was
    /// feasible, hence optimal).
    pub qp_clarabel_solves: usize,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
    /// Simulated time / wall time.
    pub realtime_factor: f64,
}

impl Summary {
    /// As JSON.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "status": self.status,
            "diverged_at_s": self.diverged_at_s,
            "reason": self.reason,
            "duration_s": self.duration_s,
            "com_error_rms_m": self.com_error_rms_m,
            "com_error_max_m": self.com_error_max_m,
            "com_error_lateral_max_m": self.com_error_lateral_max_m,
            "joint_error_norm_final_rad": self.joint_error_norm_final_rad,
            "motor_velocity_peak_rad_s": self.motor_velocity_peak_rad_s,
            "qp_failures": self.qp_failures,
            "qp_clarabel_solves": self.qp_clarabel_solves,
            "wall_time_s": self.wall_time_s,
            "realtime_factor": self.realtime_factor,
        })
    }
}

/// Plant outputs at the start of a control tick (copied out of `PlantData`).
#[derive(Default)]
struct StepOutputs {
    wrench: Vec<f64>,
    motor_torque: Vec<f64>,
    joint_torque: Vec<f64>,
}

impl StepOutputs {
    fn copy_from(
        &mut self,
        wrench: &nalgebra::DVector<f64>,
        motor: &nalgebra::DVector<f64>,
        joint: &nalgebra::DVector<f64>,
    ) {
        for (target, source) in [
            (&mut self.wrench, wrench),
            (&mut self.motor_torque, motor),
            (&mut self.joint_torque, joint),
        ] {
            target.clear();
            target.extend_from_slice(source.as_slice());
        }
    }
}

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
            let values: Vec<f64> = items.iter().filter_map(|v| v.as_float().or(v.as_integer().map(|i| i as f64))).collect();
            if values.len() != model.n_joints() {
                return Err(Error::config("robot.initial_posture", format!("needs {} numbers", model.n_joints())));
            }
            Ok(values)
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

/// Runs a scenario; `mcap` (optional) receives every recorded tick; `progress(t, duration)` is
/// called about once per simulated second.
pub fn run(
    scenario: &Scenario,
    mcap: Option<&Path>,
    mut progress: impl FnMut(f64, f64),
) -> Result<(RunRecord, Summary)> {
    let mut setup = build(scenario)?;
    let mut logger = match mcap {
        Some(path) => Some(ThreadedMcapLogger::spawn(McapLogger::create(
            path,
            &setup.model,
            &setup.elastic_names,
            &scenario.robot.contacts,
        )?)),
        None => None,
    };
    let start = Instant::now();
    let plant = &setup.plant;
    let layout = plant.layout();
    let n = setup.model.n_joints();
    let ne = layout.ne;
    let method = Method::parse(&scenario.plant.method)?;
    let control_period = 1.0 / scenario.controller.rate_hz;
    let steps_per_tick = (control_period / scenario.plant.dt).round() as usize;
    let ticks = (scenario.simulation.duration_s / control_period).round() as usize;
    let record_every = scenario.simulation.record_every.max(1);
    let mut pd = PlantData::new(plant);
    let mut x = setup.x0.clone();
    let mut x_next = x.clone();
    let mut x_step = x.clone();
    let mut s_desired = vec![0.0; n];
    let mut record = RunRecord {
        layout: (layout.nq, layout.nv, ne),
        joint_names: setup.model.joint_names.clone(),
        elastic_joints: setup.elastic_names.clone(),
        ..Default::default()
    };
    let mut status: Option<(f64, String)> = None;
    let mut last_progress = 0.0;
    let mut time = 0.0;
    let mut com_errors: Vec<f64> = Vec::new();
    let mut first_outputs = StepOutputs::default();
    let mut lateral_after_start = 0.0f64;
    let mut motor_peak = 0.0f64;
    for tick in 0..=ticks {
        time = tick as f64 * control_period;
        let reference = setup.com_reference.sample(time);
        setup.posture.at(time, &mut s_desired);
        let output = match setup
            .controller
            .compute(&x, &layout, &reference, &s_desired)
        {
            Ok(o) => o,
            Err(e) => {
                status = Some((time, format!("controller: {e}")));
                break;
            }
        };
        let com_error = (output.com - reference.position).norm();
        let joint_error: f64 = x[7..7 + n]
            .iter()
            .zip(&s_desired)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        // Advance the plant; its step-start evaluation (kept in `pd`) gives the outputs at `x`
        // for the record (wrenches, motor torques), so nothing is evaluated twice. The last
        // tick only evaluates.
        let mut plant_error = None;
        if tick == ticks {
            if let Err(e) = sea_plant::evaluate(plant, &mut pd, &x, &output.input) {
                plant_error = Some(format!("plant: {e}"));
            }
        } else {
            x_step.copy_from_slice(&x);
            for k in 0..steps_per_tick {
                if let Err(e) = sea_plant::step(
                    plant,
                    &mut pd,
                    &x_step,
                    &output.input,
                    scenario.plant.dt,
                    method,
                    &mut x_next,
                ) {
                    plant_error = Some(format!("plant step: {e}"));
                    break;
                }
                if k == 0 {
                    first_outputs.copy_from(&pd.contact_wrench, &pd.motor_torque, &pd.joint_torque);
                }
                if x_next.iter().any(|v| !v.is_finite()) {
                    plant_error = Some("non-finite state".into());
                    break;
                }
                std::mem::swap(&mut x_step, &mut x_next);
            }
            x_next.copy_from_slice(&x_step);
        }
        if tick == ticks || plant_error.is_some() {
            first_outputs.copy_from(&pd.contact_wrench, &pd.motor_torque, &pd.joint_torque);
        }
        com_errors.push(com_error);
        if time >= 1.0 {
            lateral_after_start =
                lateral_after_start.max((output.com.y - reference.position.y).abs());
        }
        let thetadot = layout.thetadot(&x);
        motor_peak = thetadot.iter().fold(motor_peak, |m, v| m.max(v.abs()));
        if tick % record_every == 0 || tick == ticks || plant_error.is_some() {
            record.time.push(time);
            record.state.extend_from_slice(&x);
            if output.thetadot_desired.len() == ne {
                record
                    .thetadot_desired
                    .extend_from_slice(&output.thetadot_desired);
            } else {
                record.thetadot_desired.extend(std::iter::repeat_n(0.0, ne));
            }
            record.com.extend_from_slice(output.com.as_slice());
            record
                .com_reference
                .extend_from_slice(reference.position.as_slice());
            record
                .momentum
                .extend_from_slice(output.momentum.as_slice());
            record
                .contact_wrenches
                .extend_from_slice(&first_outputs.wrench);
            record
                .motor_torques
                .extend_from_slice(&first_outputs.motor_torque);
            record.joint_error_norm.push(joint_error);
            record
                .qp_solved
                .push(if output.qp_status == QpStatus::Solved {
                    1.0
                } else {
                    0.0
                });
            if let Some(logger) = logger.as_mut() {
                let status_text = match &output.qp_status {
                    QpStatus::Solved => "solved".to_string(),
                    QpStatus::Fallback(reason) => format!("fallback: {reason}"),
                };
                logger.log(&LogSample {
                    time_s: time,
                    q: &x[..layout.nq],
                    nu: layout.nu(&x),
                    theta: layout.theta(&x),
                    thetadot,
                    thetadot_desired: &output.thetadot_desired,
                    com: [output.com.x, output.com.y, output.com.z],
                    com_reference: [
                        reference.position.x,
                        reference.position.y,
                        reference.position.z,
                    ],
                    momentum: [
                        output.momentum[0],
                        output.momentum[1],
                        output.momentum[2],
                        output.momentum[3],
                        output.momentum[4],
                        output.momentum[5],
                    ],
                    contact_wrenches: &first_outputs.wrench,
                    motor_torques: &first_outputs.motor_torque,
                    joint_torques: &first_outputs.joint_torque,
                    qp_status: &status_text,
                    qp_failures: setup.controller.qp_failures(),
                })?;
            }
        }
        if let Some(reason) = plant_error {
            status = Some((time, reason));
            break;
        }
        if com_error > scenario.simulation.divergence_com_error_m {
            status = Some((time, format!("CoM error {com_error:.3} m over the bound")));
            break;
        }
        if joint_error > scenario.simulation.divergence_joint_error_rad {
            status = Some((
                time,
                format!("joint error norm {joint_error:.3} rad over the bound"),
            ));
            break;
        }
        if tick == ticks {
            break;
        }
        std::mem::swap(&mut x, &mut x_next);
        if time - last_progress >= 1.0 {
            last_progress = time;
            progress(time, scenario.simulation.duration_s);
        }
    }
    if let Some(logger) = logger {
        logger.finish()?;
    }
    let wall = start.elapsed().as_secs_f64();
    let rms =
        (com_errors.iter().map(|e| e * e).sum::<f64>() / com_errors.len().max(1) as f64).sqrt();
    let summary = Summary {
        status: if status.is_some() {
            "diverged".into()
        } else {
            "completed".into()
        },
        diverged_at_s: status.as_ref().map(|(t, _)| *t),
        reason: status.map(|(_, r)| r).unwrap_or_default(),
        duration_s: time,
        com_error_rms_m: rms,
        com_error_max_m: com_errors.iter().cloned().fold(0.0, f64::max),
        com_error_lateral_max_m: lateral_after_start,
        joint_error_norm_final_rad: record.joint_error_norm.last().copied().unwrap_or(0.0),
        motor_velocity_peak_rad_s: motor_peak,
        qp_failures: setup.controller.qp_failures(),
        qp_clarabel_solves: setup.controller.qp_solves().0,
        wall_time_s: wall,
        realtime_factor: if wall > 0.0 { time / wall } else { 0.0 },
    };
    Ok((record, summary))
}
