//! What a run records: one [`Sample`] per recorded tick, handed to [`RecordSink`]s as it is
//! taken, so a run keeps only what its sinks keep. Sinks: [`RunRecord`] (in memory, what
//! Python gets), [`McapSink`] (the MCAP log, written on its own thread with a bounded queue),
//! or none (the summary statistics are computed online either way).

use crate::error::Result;
use crate::foxglove::SceneSource;
use crate::mcap_log::{LogSample, McapLogger, ThreadedMcapLogger};
use sea_ctrl::qp::QpStatus;
use sea_dyn::{Model, StateLayout};
use std::path::PathBuf;

/// What a sink learns before the first sample.
#[derive(Clone, Copy, Debug)]
pub struct RunInfo<'a> {
    /// The robot model.
    pub model: &'a Model,
    /// Layout of the plant state.
    pub layout: StateLayout,
    /// Elastic joint names (order of theta).
    pub elastic_joints: &'a [String],
    /// Contact frame names (order of the contact wrenches).
    pub contacts: &'a [String],
    /// The scenario being run (e.g. its URDF and contact surface, drawn by the logs).
    pub scenario: &'a crate::scenario::Scenario,
}

/// One recorded sample of a run: the plant state at `time_s`, the controller's evaluation
/// there and the plant outputs at that state (world axes, SI units).
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    /// Time [s].
    pub time_s: f64,
    /// Plant state `[q; theta; nu; thetadot]` (nx).
    pub state: &'a [f64],
    /// Layout of `state`.
    pub layout: StateLayout,
    /// Desired motor velocities [rad/s] (n_e; empty for the rigid controller).
    pub thetadot_desired: &'a [f64],
    /// CoM [m].
    pub com: [f64; 3],
    /// CoM reference [m].
    pub com_reference: [f64; 3],
    /// Centroidal momentum `[m pdot_com; L_com]`.
    pub momentum: [f64; 6],
    /// Simulated contact wrenches, 6 per contact `[force; moment]` at the frame origins.
    pub contact_wrenches: &'a [f64],
    /// Motor torques applied by the plant [Nm] (n_e).
    pub motor_torques: &'a [f64],
    /// Joint torques applied to the links [Nm] (n).
    pub joint_torques: &'a [f64],
    /// `|p_com - p_com_d|` [m].
    pub com_error_norm: f64,
    /// `|s - s_d|` [rad].
    pub joint_error_norm: f64,
    /// Outcome of the QP of this evaluation.
    pub qp_status: &'a QpStatus,
    /// QP failures so far.
    pub qp_failures: usize,
}

/// A consumer of recorded samples.
pub trait RecordSink {
    /// Called once before the first sample.
    fn begin(&mut self, _run: &RunInfo<'_>) -> Result<()> {
        Ok(())
    }

    /// Takes one sample (in time order).
    fn record(&mut self, sample: &Sample<'_>) -> Result<()>;

    /// Called once after the last sample, also when the run diverged, was interrupted or a
    /// sink failed.
    fn finish(&mut self) -> Result<()> {
        Ok(())
    }
}

/// Everything recorded, one row per recorded sample (row-major arrays): the in-memory sink.
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
    /// 1 when the sample's QP was solved, 0 when it fell back (rows).
    pub qp_solved: Vec<f64>,
    /// `(nq, nv, n_e)` of the state rows.
    pub layout: (usize, usize, usize),
    /// Joint names (coordinate order).
    pub joint_names: Vec<String>,
    /// Elastic joint names (order of theta).
    pub elastic_joints: Vec<String>,
}

impl RecordSink for RunRecord {
    fn begin(&mut self, run: &RunInfo<'_>) -> Result<()> {
        self.layout = (run.layout.nq, run.layout.nv, run.layout.ne);
        self.joint_names = run.model.joint_names.clone();
        self.elastic_joints = run.elastic_joints.to_vec();
        Ok(())
    }

    fn record(&mut self, sample: &Sample<'_>) -> Result<()> {
        let ne = sample.layout.ne;
        self.time.push(sample.time_s);
        self.state.extend_from_slice(sample.state);
        if sample.thetadot_desired.len() == ne {
            self.thetadot_desired
                .extend_from_slice(sample.thetadot_desired);
        } else {
            self.thetadot_desired.extend(std::iter::repeat_n(0.0, ne));
        }
        self.com.extend_from_slice(&sample.com);
        self.com_reference.extend_from_slice(&sample.com_reference);
        self.momentum.extend_from_slice(&sample.momentum);
        self.contact_wrenches
            .extend_from_slice(sample.contact_wrenches);
        self.motor_torques.extend_from_slice(sample.motor_torques);
        self.joint_error_norm.push(sample.joint_error_norm);
        let solved = *sample.qp_status == QpStatus::Solved;
        self.qp_solved.push(if solved { 1.0 } else { 0.0 });
        Ok(())
    }
}

/// The MCAP log as a sink: the file is created by `begin` and finished (summary and index
/// written) by `finish`, or when the sink is dropped, so a diverged or interrupted run leaves
/// a readable log. Memory stays bounded: samples wait in the writer thread's bounded queue.
pub struct McapSink {
    path: PathBuf,
    logger: Option<ThreadedMcapLogger>,
}

impl McapSink {
    /// A sink that will write `path`.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            logger: None,
        }
    }
}

impl Sample<'_> {
    /// The logged row of this sample (MCAP and live view), with `qp_status` the text of
    /// [`Sample::qp_status`] ([`write_qp_status`]).
    pub fn log_sample<'s>(&'s self, qp_status: &'s str) -> LogSample<'s> {
        let layout = &self.layout;
        LogSample {
            time_s: self.time_s,
            q: layout.q(self.state),
            nu: layout.nu(self.state),
            theta: layout.theta(self.state),
            thetadot: layout.thetadot(self.state),
            thetadot_desired: self.thetadot_desired,
            com: self.com,
            com_reference: self.com_reference,
            momentum: self.momentum,
            contact_wrenches: self.contact_wrenches,
            motor_torques: self.motor_torques,
            joint_torques: self.joint_torques,
            qp_status,
            qp_failures: self.qp_failures,
        }
    }
}

/// The logged text of a QP status, `"solved"` or `"fallback: <reason>"`, into `text` (cleared
/// first; no allocation once `text` is large enough).
pub fn write_qp_status(status: &QpStatus, text: &mut String) {
    text.clear();
    match status {
        QpStatus::Solved => text.push_str("solved"),
        QpStatus::Fallback(reason) => {
            text.push_str("fallback: ");
            text.push_str(reason);
        }
    }
}

impl RecordSink for McapSink {
    fn begin(&mut self, run: &RunInfo<'_>) -> Result<()> {
        let mut logger =
            McapLogger::create(&self.path, run.model, run.elastic_joints, run.contacts)?;
        logger.set_scene(&SceneSource::of_scenario(run.scenario))?;
        self.logger = Some(ThreadedMcapLogger::spawn(logger));
        Ok(())
    }

    fn record(&mut self, sample: &Sample<'_>) -> Result<()> {
        let Some(logger) = self.logger.as_mut() else {
            return Ok(());
        };
        let mut qp_status = String::new();
        write_qp_status(sample.qp_status, &mut qp_status);
        logger.log(&sample.log_sample(&qp_status))
    }

    fn finish(&mut self) -> Result<()> {
        match self.logger.take() {
            Some(logger) => logger.finish(),
            None => Ok(()),
        }
    }
}
