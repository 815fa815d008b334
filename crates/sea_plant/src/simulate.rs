//! A native loop: many fixed steps with the input held, recording the state and the contact
//! outputs. Divergence (a failed step or a non-finite or exploding state) stops the run with
//! a status and the time it happened; everything recorded until then is kept.

use crate::error::Result;
use crate::evaluation::evaluate;
use crate::integrator::{step, Method, PlantData};
use crate::plant::Plant;
use sea_dyn::error::check_positive;

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
    /// Stopped at `time` [s] because `progress` asked to (e.g. Ctrl-C); the state at `time`
    /// is the last one recorded.
    Interrupted {
        /// Simulation time reached [s].
        time: f64,
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
/// `record_every`-th state (and the last one). `progress(k)` is called after each step and
/// returns whether to go on: `false` records the state reached and ends the run with
/// [`Status::Interrupted`]. A step that fails ends the run with [`Status::Diverged`], the
/// state it started from recorded (when its outputs evaluate), so the initial state is always
/// in a record that has a row. A record that cannot be allocated is an error, not an abort.
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
    mut progress: impl FnMut(usize) -> bool,
) -> Result<SimulationLog> {
    plant.check_state(x0)?;
    plant.check_input(u)?;
    check_positive("dt", dt)?;
    let record_every = record_every.max(1);
    let rows = (n_steps / record_every).saturating_add(2);
    let mut log = SimulationLog {
        time: Vec::new(),
        state: Vec::new(),
        contact_wrench: Vec::new(),
        motor_torque: Vec::new(),
        drift_position: Vec::new(),
        drift_rotation: Vec::new(),
        status: Status::Completed,
    };
    reserve_rows(&mut log, rows, x0.len(), plant)?;
    let mut x = x0.to_vec();
    let mut x_next = x0.to_vec();
    for k in 0..=n_steps {
        let time = k as f64 * dt;
        let last = k == n_steps;
        let outcome = if last {
            evaluate(plant, &mut pd.workspace, &x, u, &mut pd.outputs)
        } else {
            step(plant, pd, &x, u, dt, method, &mut x_next)
        };
        if let Err(error) = outcome {
            log.status = Status::Diverged {
                time,
                reason: error.to_string(),
            };
            let recorded = log.time.last() == Some(&time);
            if !recorded && evaluate(plant, &mut pd.workspace, &x, u, &mut pd.outputs).is_ok() {
                push_row(&mut log, pd, time, &x);
            }
            break;
        }
        if k % record_every == 0 || last {
            push_row(&mut log, pd, time, &x);
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
        if !progress(k + 1) {
            log.status = Status::Interrupted { time: time + dt };
            record_interrupted(plant, pd, &x, u, &mut log, time + dt)?;
            break;
        }
    }
    Ok(log)
}

/// Reserves the whole record up front (no allocation while stepping); a record too large for
/// memory (or for `usize`) is an [`crate::Error`] naming `n_steps`, not an allocation abort.
fn reserve_rows(log: &mut SimulationLog, rows: usize, nx: usize, plant: &Plant) -> Result<()> {
    let widths = [
        1,
        nx,
        6 * plant.contacts.len(),
        plant.actuation.n_elastic(),
        1,
        1,
    ];
    let too_large = || {
        let bytes = widths.iter().sum::<usize>() as f64 * rows as f64 * 8.0;
        crate::error::Error::invalid(
            "n_steps",
            "a record that fits in memory (raise record_every)",
            format!("{rows} rows, {:.3e} bytes", bytes),
        )
    };
    let vectors = [
        &mut log.time,
        &mut log.state,
        &mut log.contact_wrench,
        &mut log.motor_torque,
        &mut log.drift_position,
        &mut log.drift_rotation,
    ];
    for (vector, width) in vectors.into_iter().zip(widths) {
        let entries = rows.checked_mul(width).ok_or_else(too_large)?;
        vector.try_reserve_exact(entries).map_err(|_| too_large())?;
    }
    Ok(())
}

/// Records the state `x` reached at `time` when the run is interrupted (its outputs evaluated
/// so the row is complete).
fn record_interrupted(
    plant: &Plant,
    pd: &mut PlantData,
    x: &[f64],
    u: &[f64],
    log: &mut SimulationLog,
    time: f64,
) -> Result<()> {
    evaluate(plant, &mut pd.workspace, x, u, &mut pd.outputs)?;
    push_row(log, pd, time, x);
    Ok(())
}

/// Appends the row of state `x` at `time` with the outputs last evaluated into `pd.outputs`.
fn push_row(log: &mut SimulationLog, pd: &PlantData, time: f64, x: &[f64]) {
    let outputs = &pd.outputs;
    log.time.push(time);
    log.state.extend_from_slice(x);
    log.contact_wrench
        .extend_from_slice(outputs.contact_wrench.as_slice());
    log.motor_torque
        .extend_from_slice(outputs.motor_torque.as_slice());
    log.drift_position.push(outputs.drift_position);
    log.drift_rotation.push(outputs.drift_rotation);
}
