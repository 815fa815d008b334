//! What a run records: one [`Sample`] per recorded tick, handed to [`RecordSink`]s as it is
//! taken, so a run keeps only what its sinks keep. The loop knows sinks only through the
//! trait: the in-memory [`RunRecord`] (what Python gets) is here; the MCAP log and the live
//! view (`sea_viz`) sit above the loop. With no sink, only the summary statistics are computed (online).

use super::contact_check::{ContactCheckEvent, WrenchCheck};
use super::impacts::Impact;
use super::statistics::RunEnd;
use crate::error::Result;
use crate::settings::RunScene;
use sea_ctrl::qp::QpStatus;
use sea_ctrl::walking::Gait;
use sea_dyn::{Model, StateLayout};
use std::sync::atomic::AtomicBool;

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
    /// What the logs draw: the URDF, the contact surfaces.
    pub scene: &'a RunScene,
    /// The link of each disturbance, in order (the logs name and draw pushes by it).
    pub disturbance_links: &'a [String],
    /// Unilateral contacts: the number of points of each contact (the order of the samples'
    /// contact points); empty under bilateral contacts.
    pub contact_points: &'a [usize],
    /// `[walking]`: the walk the controller follows at the start (footsteps, DCM plan, swings;
    /// times from the run's start), which the logs draw until the controller changes it
    /// ([`RecordSink::walking`]); `None` when the robot does not walk.
    pub walking: Option<&'a Gait>,
    /// The run's cancellation flag: a sink whose `begin` waits on slow work (reading a large
    /// mesh) gives that work up once it is raised; the run then ends "interrupted" at its
    /// first sample.
    pub cancel: &'a AtomicBool,
}

/// One recorded sample of a run: the plant state at `time_s`, the controller's evaluation
/// there and the plant outputs at that state (world axes, SI units). A view of the loop's
/// buffers; [`Sample::to_owned`] copies it (e.g. to cross to a writer thread).
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
    /// The external wrench the controller's dynamics took at this tick, `[force; moment about
    /// the CoM]` (`controller.external_wrench = "observed"`: the observer's estimate; zero
    /// otherwise).
    pub external_wrench: [f64; 6],
    /// Simulated contact wrenches, 6 per contact `[force; moment]` at the frame origins. Under
    /// unilateral contacts those delivered over the sample's first plant step (what moves the
    /// robot and what the feet's sensors read), at a run's last sample those at its state.
    pub contact_wrenches: &'a [f64],
    /// The wrenches the controller's QP planned for the contacts at this tick (6 per contact,
    /// `[force; moment]` at the frame origins, world axes, as `contact_wrenches`): what the
    /// law asked each contact to carry, to compare with `contact_wrenches`. A swinging foot's
    /// are zero (hundredths of a newton while an early touchdown holds it).
    pub planned_wrenches: &'a [f64],
    /// Unilateral contacts: each contact point's position [m], 3 per point (contacts in
    /// order, [`RunInfo::contact_points`] each); empty under bilateral contacts.
    pub contact_point_positions: &'a [f64],
    /// Unilateral contacts: each contact point's force on its foot [N], 3 per point, at the
    /// sample's state (they add up to `contact_wrenches` but at an impact or a stick-slip
    /// change within the sample's first plant step).
    pub contact_point_forces: &'a [f64],
    /// Unilateral contacts: whether each contact point carries a force.
    pub contact_point_active: &'a [bool],
    /// Unilateral contacts: each foot's delivered wrench checked against a unilateral
    /// contact with friction (contacts in order), a diagnostic; empty when the check did not
    /// run at this sample (bilateral contacts, where a violation ends the run as a fall;
    /// `simulation.stop_on_fall` off; a diverged sample).
    pub contact_checks: &'a [WrenchCheck],
    /// Motor torques applied by the plant [Nm] (n_e).
    pub motor_torques: &'a [f64],
    /// Joint torques applied to the links [Nm] (n).
    pub joint_torques: &'a [f64],
    /// The wrench of each `[[disturbances]]` entry acting from this sample on (during the
    /// plant step that starts here), 6 per entry `[force; torque]` (world axes, at its link
    /// origin; zero when inactive).
    pub disturbance_wrenches: &'a [f64],
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

    /// `[walking]`: takes the walk as the controller changed it (a step adjusted or
    /// retimed, a recovery step planned, the settling after a recovery step's touchdown
    /// planned from the measured state), at the end of the whole-body period of the change, so
    /// each change, also several between two recorded samples, and before the first sample
    /// recorded after it (under `controller.sampling = "continuous"`, where the law runs
    /// within plant steps, the change may be up to one plant step older than the period's
    /// end); [`RunInfo::walking`] was the walk before any.
    fn walking(&mut self, _gait: &Gait) -> Result<()> {
        Ok(())
    }

    /// Takes one impact (a touchdown or a joint reaching its stop) once its window after is
    /// complete, i.e. up to [`crate::impacts::PEAK_WINDOW_S`] after its time (after the
    /// samples up to then; impacts in the order their windows closed).
    fn impact(&mut self, _impact: &Impact) -> Result<()> {
        Ok(())
    }

    /// Takes one change of a foot's contact check under unilateral contacts (it starts or
    /// stops violating a constraint), after the sample it happened at.
    fn contact_check(&mut self, _event: &ContactCheckEvent) -> Result<()> {
        Ok(())
    }

    /// Called once after the last sample with how the run ended (not when it failed with an
    /// error: a sink's or the model's), before [`RecordSink::finish`].
    fn end(&mut self, _end: &RunEnd) -> Result<()> {
        Ok(())
    }

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
    /// The external wrench the controller took (rows x 6), `[force; moment about the CoM]`.
    pub external_wrench: Vec<f64>,
    /// Simulated contact wrenches (rows x 6 n_contacts), as [`Sample::contact_wrenches`].
    pub contact_wrenches: Vec<f64>,
    /// The QP's planned contact wrenches (rows x 6 n_contacts), as
    /// [`Sample::planned_wrenches`].
    pub planned_wrenches: Vec<f64>,
    /// Motor torques applied by the plant (rows x n_e).
    pub motor_torques: Vec<f64>,
    /// Joint error norm |s - s_d| (rows) [rad].
    pub joint_error_norm: Vec<f64>,
    /// 1 when the sample's QP was solved (the relaxed momentum task included), 0 when it fell
    /// back (rows).
    pub qp_solved: Vec<f64>,
    /// The `[[disturbances]]` acting at each sample, summed (rows x 6): `[force; torque]`,
    /// world axes, each torque about its own link's origin (zero without a push).
    pub disturbance_wrench: Vec<f64>,
    /// `(nq, nv, n_e)` of the state rows.
    pub layout: (usize, usize, usize),
    /// Joint names (coordinate order).
    pub joint_names: Vec<String>,
    /// Elastic joint names (order of theta).
    pub elastic_joints: Vec<String>,
    /// The run's impacts (touchdowns, joints reaching their stops), in the order their
    /// windows closed.
    pub impacts: Vec<Impact>,
    /// Unilateral contacts: the number of points of each contact (the order of the contact
    /// point columns); empty under bilateral contacts.
    pub contact_points: Vec<usize>,
    /// Unilateral contacts: each contact point's position (rows x 3 n_points) [m], world.
    pub contact_point_positions: Vec<f64>,
    /// Unilateral contacts: each contact point's force on its foot (rows x 3 n_points) [N],
    /// world axes.
    pub contact_point_forces: Vec<f64>,
    /// Unilateral contacts: whether each contact point carries a force (rows x n_points).
    pub contact_point_active: Vec<bool>,
}

impl RecordSink for RunRecord {
    fn begin(&mut self, run: &RunInfo<'_>) -> Result<()> {
        self.layout = (run.layout.nq, run.layout.nv, run.layout.ne);
        self.joint_names = run.model.joint_names.clone();
        self.elastic_joints = run.elastic_joints.to_vec();
        self.contact_points = run.contact_points.to_vec();
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
        self.external_wrench
            .extend_from_slice(&sample.external_wrench);
        self.contact_wrenches
            .extend_from_slice(sample.contact_wrenches);
        self.planned_wrenches
            .extend_from_slice(sample.planned_wrenches);
        self.contact_point_positions
            .extend_from_slice(sample.contact_point_positions);
        self.contact_point_forces
            .extend_from_slice(sample.contact_point_forces);
        self.contact_point_active
            .extend_from_slice(sample.contact_point_active);
        self.motor_torques.extend_from_slice(sample.motor_torques);
        self.joint_error_norm.push(sample.joint_error_norm);
        let solved = !matches!(sample.qp_status, QpStatus::Fallback(_));
        self.qp_solved.push(if solved { 1.0 } else { 0.0 });
        let mut total = [0.0; 6];
        for wrench in sample.disturbance_wrenches.chunks_exact(6) {
            total.iter_mut().zip(wrench).for_each(|(t, w)| *t += w);
        }
        self.disturbance_wrench.extend_from_slice(&total);
        Ok(())
    }

    fn impact(&mut self, impact: &Impact) -> Result<()> {
        self.impacts.push(impact.clone());
        Ok(())
    }
}

impl<'a> Sample<'a> {
    /// Configuration `[p_B; quaternion (w, x, y, z); s]` (nq).
    pub fn q(&self) -> &'a [f64] {
        self.layout.q(self.state)
    }

    /// Velocity `[pdot_B; omega_B; sdot]` (nv).
    pub fn nu(&self) -> &'a [f64] {
        self.layout.nu(self.state)
    }

    /// Motor angles of the elastic joints [rad] (n_e; empty for a rigid robot).
    pub fn theta(&self) -> &'a [f64] {
        self.layout.theta(self.state)
    }

    /// Motor velocities of the elastic joints [rad/s] (n_e).
    pub fn thetadot(&self) -> &'a [f64] {
        self.layout.thetadot(self.state)
    }

    /// A copy that owns its data; [`OwnedSample::sample`] views it as this sample.
    pub fn to_owned(&self) -> OwnedSample {
        let parts = [
            self.state,
            self.thetadot_desired,
            self.contact_wrenches,
            self.motor_torques,
            self.joint_torques,
            self.disturbance_wrenches,
            self.contact_point_positions,
            self.contact_point_forces,
            self.planned_wrenches,
        ];
        let mut values = Vec::with_capacity(parts.iter().map(|p| p.len()).sum());
        let mut ends = [0; 9];
        for (end, part) in ends.iter_mut().zip(parts) {
            values.extend_from_slice(part);
            *end = values.len();
        }
        OwnedSample {
            values,
            ends,
            active: self.contact_point_active.to_vec(),
            checks: self.contact_checks.to_vec(),
            qp_status: self.qp_status.clone(),
            scalars: Sample {
                state: &[],
                thetadot_desired: &[],
                contact_wrenches: &[],
                motor_torques: &[],
                joint_torques: &[],
                disturbance_wrenches: &[],
                contact_point_positions: &[],
                contact_point_forces: &[],
                planned_wrenches: &[],
                contact_point_active: &[],
                contact_checks: &[],
                qp_status: &NO_STATUS,
                ..*self
            },
        }
    }
}

/// The QP status of [`OwnedSample::scalars`], a placeholder never read.
static NO_STATUS: QpStatus = QpStatus::Solved;

/// A [`Sample`] that owns its data ([`Sample::to_owned`]): the slices concatenated in one
/// buffer, the QP status cloned.
#[derive(Clone, Debug)]
pub struct OwnedSample {
    /// `state`, `thetadot_desired`, `contact_wrenches`, `motor_torques`, `joint_torques`,
    /// `disturbance_wrenches`, `contact_point_positions`, `contact_point_forces`,
    /// `planned_wrenches`, concatenated; `ends` marks where each stops.
    values: Vec<f64>,
    ends: [usize; 9],
    /// `contact_point_active`.
    active: Vec<bool>,
    /// `contact_checks`.
    checks: Vec<WrenchCheck>,
    qp_status: QpStatus,
    /// The sample's other fields (its slices empty).
    scalars: Sample<'static>,
}

impl OwnedSample {
    /// The sample this copy was made of.
    pub fn sample(&self) -> Sample<'_> {
        let part = |k: usize| {
            let start = if k == 0 { 0 } else { self.ends[k - 1] };
            &self.values[start..self.ends[k]]
        };
        Sample {
            state: part(0),
            thetadot_desired: part(1),
            contact_wrenches: part(2),
            motor_torques: part(3),
            joint_torques: part(4),
            disturbance_wrenches: part(5),
            contact_point_positions: part(6),
            contact_point_forces: part(7),
            planned_wrenches: part(8),
            contact_point_active: &self.active,
            contact_checks: &self.checks,
            qp_status: &self.qp_status,
            ..self.scalars
        }
    }
}
