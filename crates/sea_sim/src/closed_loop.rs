//! The closed loop: the controller at its rate (zero-order hold), the plant with its motor
//! velocity loop in between, divergence detection, recording, summary and MCAP logging.
//!
//! A run stops as "diverged" when a step or a tick fails, the state is not finite, the CoM
//! error exceeds `simulation.divergence_com_error_m` or the joint error norm exceeds
//! `simulation.divergence_joint_error_rad`; everything recorded until then is kept and the log
//! is finished.

use crate::error::Result;
use crate::mcap_log::{LogSample, McapLogger, ThreadedMcapLogger};
use crate::scenario::Scenario;
use sea_ctrl::qp::QpStatus;
use sea_plant::{Method, PlantData};
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

pub use crate::scenario::build::{build, Setup};

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
