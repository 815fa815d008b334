//! A native loop: many fixed steps with the input held, recording the state and the contact
//! outputs. Divergence (a failed step or a non-finite or exploding state) stops the run with
//! a status and the time it happened; everything recorded until then is kept.

use crate::dynamics::PlantData;
use crate::error::Result;
use crate::integrator::{step, Method};
use crate::plant::Plant;

/// How a simulation ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// Every step was taken.
    Completed,
    /// Stopped at `time` [s] because of `reason`.
    Diverged {
        /// Simulation time of the failed step [s].
        time: f64,
        /// What went wrong.
        reason: String,
    },
}

/// Records of a simulation, one row per recorded sample (`rows` of them).
#[derive(Clone, Debug)]
pub struct SimulationLog {
    /// Sample times [s] (rows).
    pub time: Vec<f64>,
    /// States, row-major (rows x nx).
    pub state: Vec<f64>,
    /// Contact wrenches at each sample, row-major (rows x 6 n_contacts).
    pub contact_wrench: Vec<f64>,
    /// Motor torques after saturation, row-major (rows x n_e).
    pub motor_torque: Vec<f64>,
    /// Largest contact position error [m] (rows).
    pub drift_position: Vec<f64>,
    /// Largest contact rotation error [rad] (rows).
    pub drift_rotation: Vec<f64>,
    /// How the run ended.
    pub status: Status,
}

/// States with a norm above this are taken as diverged (finite but meaningless).
const DIVERGENCE_NORM: f64 = 1e8;

/// Simulates `n_steps` of size `dt` from `x0` with `u` held, recording every
/// `record_every`-th state (and the last one). `progress(k)` is called after each step.
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    plant: &Plant,
    pd: &mut PlantData,
    x0: &[f64],
    u: &[f64],
    dt: f64,
    n_steps: usize,
    method: Method,
    record_every: usize,
    mut progress: impl FnMut(usize),
) -> Result<SimulationLog> {
    plant.check_state(x0)?;
    plant.check_input(u)?;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(crate::Error::invalid("dt", "a positive finite number", dt));
    }
    let record_every = record_every.max(1);
    let rows = n_steps / record_every + 2;
    let mut log = SimulationLog {
        time: Vec::with_capacity(rows),
        state: Vec::with_capacity(rows * x0.len()),
        contact_wrench: Vec::with_capacity(rows * 6 * plant.contacts.len()),
        motor_torque: Vec::with_capacity(rows * plant.actuation.n_elastic()),
        drift_position: Vec::with_capacity(rows),
        drift_rotation: Vec::with_capacity(rows),
        status: Status::Completed,
    };
    let mut x = x0.to_vec();
    let mut x_next = x0.to_vec();
    for k in 0..=n_steps {
        let time = k as f64 * dt;
        let last = k == n_steps;
        let outcome = if last {
            crate::dynamics::evaluate(plant, pd, &x, u)
        } else {
            step(plant, pd, &x, u, dt, method, &mut x_next)
        };
        if let Err(error) = outcome {
            log.status = Status::Diverged {
                time,
                reason: error.to_string(),
            };
            break;
        }
        if k % record_every == 0 || last {
            log.time.push(time);
            log.state.extend_from_slice(&x);
            log.contact_wrench
                .extend_from_slice(pd.contact_wrench.as_slice());
            log.motor_torque
                .extend_from_slice(pd.motor_torque.as_slice());
            log.drift_position.push(pd.drift_position);
            log.drift_rotation.push(pd.drift_rotation);
        }
        if last {
            break;
        }
        let norm = x_next.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !norm.is_finite() || norm > DIVERGENCE_NORM {
            log.status = Status::Diverged {
                time: time + dt,
                reason: format!("state norm {norm:e} after the step"),
            };
            break;
        }
        std::mem::swap(&mut x, &mut x_next);
        progress(k + 1);
    }
    Ok(log)
}
