//! The SEA plant: floating-base robot with mixed rigid/elastic joints in rigid contact.
//!
//! State `x = [q (nq); theta (n_e); nu (nv); thetadot (n_e)]` (nx = nq + nv + 2 n_e); its
//! tangent `dx = [dq (nv); dtheta; dnu; dthetadot]` (nd = 2 nv + 2 n_e). Input `u` (n), per
//! joint in coordinate order: rigid joint, the joint torque; elastic joint, the motor torque
//! (`MotorInput::Torque`) or the desired motor velocity of the motor velocity loop
//! (`MotorInput::VelocityLoop`, paper eq:tauMotors:
//! `tau_m = -b K_m (thetadot - thetadot_d) + eta tau`, saturated at the torque limit).
//!
//! Equations (paper eq:elasticSystem, eq:constraints_acc):
//! - elastic joint torque `tau = k_s (eta theta - s) + k_d (eta thetadot - sdot)`,
//!   motor `b thetaddot = tau_m - eta tau`;
//! - `M nudot + h = B tau + J^T f`, `J nudot + Jdot nu = -(K_d J nu + K_p e)` (Baumgarte), where
//!   `J` stacks the contact frame Jacobians (6 rows each, `[v; omega]` of the frame origin,
//!   world axes), `e` stacks the pose errors `[p - p_ref; rotation error]` and `f` the contact
//!   wrenches `[force; moment about the frame origin]`, world axes, the Lagrange multipliers.
//!   Solved with `M = L L^T` and the Schur complement `J M^-1 J^T` (k x k).

use crate::actuator::Actuation;
use crate::crba::crba_from_kinematics;
use crate::data::Data;
use crate::dense::{cholesky_in_place, cholesky_solve_in_place};
use crate::error::{check_vector, Error, Result};
use crate::jacobian::{frame_bias_acceleration, frame_jacobian_from_kinematics};
use crate::kinematics::frame_placement;
use crate::model::{FrameId, Model};
use crate::rnea::bias_forces;
use crate::spatial::Pose;
use crate::tree_factor::TreeFactor;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// What the input of an elastic joint means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotorInput {
    /// `u` is the motor torque [Nm], motor side (clipped at the torque limit).
    Torque,
    /// `u` is the desired motor velocity [rad/s]; the velocity loop of gain `K_m` [1/s] is
    /// evaluated with the plant.
    VelocityLoop {
        /// Motor velocity gain `K_m` [1/s].
        gain: f64,
    },
}

/// Friction and foot-size limits used to report the margins of the simulated wrenches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLimits {
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Foot rectangle along the sole x axis `[min, max]` [m].
    pub foot_x: [f64; 2],
    /// Foot rectangle along the sole y axis `[min, max]` [m].
    pub foot_y: [f64; 2],
}

impl Default for ContactLimits {
    /// The original study's values (REFERENCE.md): mu = 1, x in [-0.05, 0.10], y in
    /// [-0.025, 0.025] m.
    fn default() -> Self {
        Self {
            friction: 1.0,
            foot_x: [-0.05, 0.10],
            foot_y: [-0.025, 0.025],
        }
    }
}

/// A rigid contact: the frame is held at its reference pose.
#[derive(Clone, Debug)]
pub struct Contact {
    /// Frame name.
    pub name: String,
    /// Frame index.
    pub frame: FrameId,
    /// Desired `world_H_frame`.
    pub reference: Pose,
}

/// The plant: model, actuation, contacts and constraint stabilisation.
#[derive(Clone, Debug)]
pub struct Plant {
    /// Robot model.
    pub model: Model,
    /// Actuators of every joint.
    pub actuation: Actuation,
    /// Rigid contacts (zero, one or two feet).
    pub contacts: Vec<Contact>,
    /// Baumgarte position gain `K_p` [1/s^2] (default 50, REFERENCE.md).
    pub baumgarte_kp: f64,
    /// Baumgarte velocity gain `K_d` [1/s] (default `2 sqrt(K_p)`).
    pub baumgarte_kd: f64,
    /// Meaning of the elastic joints' inputs.
    pub motor_input: MotorInput,
    /// Added to the joint diagonal of `M` (the original study used 0.1 for the reflected motor
    /// inertia); default 0.
    pub joint_inertia_regularization: f64,
    /// Limits for the reported wrench margins.
    pub contact_limits: ContactLimits,
}

/// Layout of the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StateLayout {
    /// Configuration size.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
    /// Number of elastic joints.
    pub ne: usize,
}

impl StateLayout {
    /// State size `nq + nv + 2 n_e`.
    pub fn nx(&self) -> usize {
        self.nq + self.nv + 2 * self.ne
    }
    /// Tangent size `2 nv + 2 n_e`.
    pub fn nd(&self) -> usize {
        2 * self.nv + 2 * self.ne
    }
    /// Offset of `theta` in `x`.
    pub fn theta(&self) -> usize {
        self.nq
    }
    /// Offset of `nu` in `x`.
    pub fn nu(&self) -> usize {
        self.nq + self.ne
    }
    /// Offset of `thetadot` in `x`.
    pub fn thetadot(&self) -> usize {
        self.nq + self.ne + self.nv
    }
}

impl Plant {
    /// A plant with the given actuation and no contacts, default gains, torque input.
    pub fn new(model: Model, actuation: Actuation) -> Self {
        let kp = 50.0;
        Self {
            model,
            actuation,
            contacts: Vec::new(),
            baumgarte_kp: kp,
            baumgarte_kd: 2.0 * f64::sqrt(kp),
            motor_input: MotorInput::Torque,
            joint_inertia_regularization: 0.0,
            contact_limits: ContactLimits::default(),
        }
    }

    /// State layout.
    pub fn layout(&self) -> StateLayout {
        StateLayout {
            nq: self.model.nq(),
            nv: self.model.nv(),
            ne: self.actuation.n_elastic(),
        }
    }

    /// Sets the contact frames, each held at its pose in configuration `q`.
    pub fn set_contacts(&mut self, frames: &[String], q: &[f64]) -> Result<()> {
        self.model.check_configuration(q)?;
        let mut data = Data::new(&self.model);
        crate::kinematics::forward_kinematics(&self.model, &mut data, q);
        let mut contacts = Vec::with_capacity(frames.len());
        for name in frames {
            let frame = self.model.frame_id(name)?;
            if contacts.iter().any(|c: &Contact| c.frame == frame) {
                return Err(Error::input(format!(
                    "contact frame '{name}' is listed twice"
                )));
            }
            contacts.push(Contact {
                name: name.clone(),
                frame,
                reference: frame_placement(&self.model, &data, frame),
            });
        }
        self.contacts = contacts;
        Ok(())
    }

    /// Checks gains and parameters; errors name the offending setting.
    pub fn validate(&self) -> Result<()> {
        let gains = [
            ("baumgarte_kp", self.baumgarte_kp),
            ("baumgarte_kd", self.baumgarte_kd),
            (
                "joint_inertia_regularization",
                self.joint_inertia_regularization,
            ),
        ];
        for (name, value) in gains {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::input(format!(
                    "{name} must be non-negative and finite, got {value}"
                )));
            }
        }
        if let MotorInput::VelocityLoop { gain } = self.motor_input {
            if !(gain.is_finite() && gain > 0.0) {
                return Err(Error::input(format!(
                    "motor_velocity_gain must be positive and finite, got {gain}"
                )));
            }
        }
        Ok(())
    }

    /// Checks a state: size nx, finite, unit quaternion within [`crate::model::QUATERNION_TOLERANCE`].
    pub fn check_state(&self, x: &[f64]) -> Result<()> {
        check_vector("x", x, self.layout().nx())?;
        self.model.check_configuration(&x[..self.model.nq()])
    }

    /// Checks an input: size n, finite.
    pub fn check_input(&self, u: &[f64]) -> Result<()> {
        check_vector("u", u, self.model.n_joints())
    }

    /// A state from its parts; `theta = s / eta` (springs at rest) and zero velocities when
    /// `theta`/`thetadot` are `None`.
    pub fn make_state(
        &self,
        q: &[f64],
        nu: &[f64],
        theta: Option<&[f64]>,
        thetadot: Option<&[f64]>,
    ) -> Result<Vec<f64>> {
        let layout = self.layout();
        self.model.check_configuration(q)?;
        self.model.check_velocity("nu", nu)?;
        let mut x = vec![0.0; layout.nx()];
        x[..layout.nq].copy_from_slice(q);
        x[layout.nu()..layout.nu() + layout.nv].copy_from_slice(nu);
        match theta {
            Some(theta) => {
                check_vector("theta", theta, layout.ne)?;
                x[layout.theta()..layout.theta() + layout.ne].copy_from_slice(theta);
            }
            None => {
                for (e, &j) in self.actuation.elastic_joints.iter().enumerate() {
                    x[layout.theta() + e] = q[7 + j] / self.actuation.elastic[e].ratio;
                }
            }
        }
        if let Some(thetadot) = thetadot {
            check_vector("thetadot", thetadot, layout.ne)?;
            x[layout.thetadot()..layout.thetadot() + layout.ne].copy_from_slice(thetadot);
        }
        Ok(x)
    }
}

/// Rotation error `vee(R R_ref^T - R_ref R^T) / 2` (the rotation vector for small errors).
fn rotation_error(r: &Matrix3<f64>, r_ref: &Matrix3<f64>) -> Vector3<f64> {
    let d = r * r_ref.transpose();
    Vector3::new(
        d[(2, 1)] - d[(1, 2)],
        d[(0, 2)] - d[(2, 0)],
        d[(1, 0)] - d[(0, 1)],
    ) * 0.5
}

/// Margins of one simulated contact wrench (sole frame), negative when violated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WrenchMargins {
    /// Normal force [N] (negative: the foot pulls on the ground).
    pub normal_force: f64,
    /// `mu f_z - |f_xy|` [N].
    pub friction: f64,
    /// Distance of the centre of pressure inside the foot rectangle [m] (negative: outside).
    pub center_of_pressure: f64,
}

/// Workspace of the plant: every buffer of the dynamics and of the implicit step.
#[derive(Clone, Debug)]
pub struct PlantData {
    /// Rigid-body workspace.
    pub data: Data,
    /// Tangent derivative `[nu; thetadot; nudot; thetaddot]` of the last evaluation (nd).
    pub xdot: DVector<f64>,
    /// Contact wrenches `[f; n]` per contact at the frame origins, world axes (6 per contact).
    pub contact_wrench: DVector<f64>,
    /// Joint torques applied to the links (n): spring-damper torque or rigid input.
    pub joint_torque: DVector<f64>,
    /// Motor torques after saturation (n_e), motor side.
    pub motor_torque: DVector<f64>,
    /// Whether each motor torque hit its limit in the last evaluation (n_e).
    pub saturated: Vec<bool>,
    /// Largest contact position error [m] of the last evaluation.
    pub drift_position: f64,
    /// Largest contact rotation error [rad] of the last evaluation.
    pub drift_rotation: f64,
    /// `M = L^T L` with the tree's sparsity.
    mass_factor: TreeFactor,
    /// Diagonal added to `M` (joint inertia regularisation), then to `M~` (nv).
    diagonal: Vec<f64>,
    /// Stacked contact Jacobian (k x nv).
    contact_jacobian: DMatrix<f64>,
    /// `Y = L^-T J^T` with `M = L^T L` (nv x k).
    linv_jt: DMatrix<f64>,
    /// `J M^-1 J^T`, then its factor (k x k).
    schur: DMatrix<f64>,
    /// Constraint acceleration target, then multipliers (k).
    constraint_rhs: DVector<f64>,
    /// Velocity-sized scratch (nv).
    scratch_v: DVector<f64>,
    /// Implicit step: factor of `M~` (nv x nv), `J` at the step start (k x nv), `L~^-1 J^T`
    /// (nv x k), Schur factor (k x k), per elastic joint `den`, `a1`, `t1` and flags.
    w_factor: TreeFactor,
    w_jacobian: DMatrix<f64>,
    w_linv_jt: DMatrix<f64>,
    w_schur: DMatrix<f64>,
    w_den: Vec<f64>,
    w_a1: Vec<f64>,
    w_t1: Vec<f64>,
    w_torque_driven: Vec<bool>,
    w_gain: Vec<f64>,
    w_g: f64,
    /// Stage buffers of the integrators (nd each) and a state buffer (nx).
    pub(crate) stage: [DVector<f64>; 4],
    pub(crate) x_stage: Vec<f64>,
    /// Outputs of the step-start evaluation, kept while later stages evaluate elsewhere.
    saved: SavedOutputs,
}

/// Copies of the evaluation outputs (same sizes as in [`PlantData`]).
#[derive(Clone, Debug)]
struct SavedOutputs {
    xdot: DVector<f64>,
    contact_wrench: DVector<f64>,
    joint_torque: DVector<f64>,
    motor_torque: DVector<f64>,
    saturated: Vec<bool>,
    drift: (f64, f64),
}

impl PlantData {
    /// Buffers for `plant`.
    pub fn new(plant: &Plant) -> Self {
        let layout = plant.layout();
        let (nv, ne, n) = (layout.nv, layout.ne, plant.model.n_joints());
        let k = 6 * plant.contacts.len();
        let nd = layout.nd();
        Self {
            data: Data::new(&plant.model),
            xdot: DVector::zeros(nd),
            contact_wrench: DVector::zeros(k),
            joint_torque: DVector::zeros(n),
            motor_torque: DVector::zeros(ne),
            saturated: vec![false; ne],
            drift_position: 0.0,
            drift_rotation: 0.0,
            mass_factor: TreeFactor::new(&plant.model),
            diagonal: vec![0.0; nv],
            contact_jacobian: DMatrix::zeros(k, nv),
            linv_jt: DMatrix::zeros(nv, k),
            schur: DMatrix::zeros(k, k),
            constraint_rhs: DVector::zeros(k),
            scratch_v: DVector::zeros(nv),
            w_factor: TreeFactor::new(&plant.model),
            w_jacobian: DMatrix::zeros(k, nv),
            w_linv_jt: DMatrix::zeros(nv, k),
            w_schur: DMatrix::zeros(k, k),
            w_den: vec![1.0; ne],
            w_a1: vec![0.0; ne],
            w_t1: vec![0.0; ne],
            w_torque_driven: vec![true; ne],
            w_gain: vec![0.0; ne],
            w_g: 0.0,
            stage: std::array::from_fn(|_| DVector::zeros(nd)),
            x_stage: vec![0.0; layout.nx()],
            saved: SavedOutputs {
                xdot: DVector::zeros(nd),
                contact_wrench: DVector::zeros(k),
                joint_torque: DVector::zeros(n),
                motor_torque: DVector::zeros(ne),
                saturated: vec![false; ne],
                drift: (0.0, 0.0),
            },
        }
    }

    /// Saves the outputs of the last evaluation (no allocation).
    pub(crate) fn save_outputs(&mut self) {
        let s = &mut self.saved;
        s.xdot.copy_from(&self.xdot);
        s.contact_wrench.copy_from(&self.contact_wrench);
        s.joint_torque.copy_from(&self.joint_torque);
        s.motor_torque.copy_from(&self.motor_torque);
        s.saturated.copy_from_slice(&self.saturated);
        s.drift = (self.drift_position, self.drift_rotation);
    }

    /// Restores the outputs saved by [`PlantData::save_outputs`].
    pub(crate) fn restore_outputs(&mut self) {
        let s = &self.saved;
        self.xdot.copy_from(&s.xdot);
        self.contact_wrench.copy_from(&s.contact_wrench);
        self.joint_torque.copy_from(&s.joint_torque);
        self.motor_torque.copy_from(&s.motor_torque);
        self.saturated.copy_from_slice(&s.saturated);
        (self.drift_position, self.drift_rotation) = s.drift;
    }

    /// Margins of each contact's last simulated wrench, in its sole frame.
    pub fn wrench_margins(&self, plant: &Plant, x: &[f64]) -> Vec<WrenchMargins> {
        let limits = &plant.contact_limits;
        let mut data = self.data.clone();
        crate::kinematics::forward_kinematics(&plant.model, &mut data, &x[..plant.model.nq()]);
        plant
            .contacts
            .iter()
            .enumerate()
            .map(|(c, contact)| {
                let rotation = frame_placement(&plant.model, &data, contact.frame).rotation;
                let w = &self.contact_wrench;
                let force =
                    rotation.transpose() * Vector3::new(w[6 * c], w[6 * c + 1], w[6 * c + 2]);
                let moment =
                    rotation.transpose() * Vector3::new(w[6 * c + 3], w[6 * c + 4], w[6 * c + 5]);
                sole_margins(&force, &moment, limits)
            })
            .collect()
    }
}

/// Margins of a wrench `[force; moment about the sole origin]` given in the sole frame.
pub fn sole_margins(
    force: &Vector3<f64>,
    moment: &Vector3<f64>,
    limits: &ContactLimits,
) -> WrenchMargins {
    let fz = force.z;
    let friction = limits.friction * fz - force.xy().norm();
    let center_of_pressure = if fz > 0.0 {
        let (cop_x, cop_y) = (-moment.y / fz, moment.x / fz);
        (cop_x - limits.foot_x[0])
            .min(limits.foot_x[1] - cop_x)
            .min(cop_y - limits.foot_y[0])
            .min(limits.foot_y[1] - cop_y)
    } else {
        f64::NEG_INFINITY
    };
    WrenchMargins {
        normal_force: fz,
        friction,
        center_of_pressure,
    }
}

/// Evaluates the dynamics at `x` with input `u`: fills `pd.xdot` (tangent derivative),
/// the contact wrenches, joint and motor torques and the drift. Sizes are not checked here
/// (see [`Plant::check_state`]); a singular mass matrix or contact set is an error.
pub fn evaluate(plant: &Plant, pd: &mut PlantData, x: &[f64], u: &[f64]) -> Result<()> {
    let model = &plant.model;
    let layout = plant.layout();
    let (nq, nv, ne) = (layout.nq, layout.nv, layout.ne);
    let q = &x[..nq];
    let theta = &x[layout.theta()..layout.theta() + ne];
    let nu = &x[layout.nu()..layout.nu() + nv];
    let thetadot = &x[layout.thetadot()..layout.thetadot() + ne];

    // h(q, nu) into scratch_v (negated below), then M from the same kinematics.
    bias_forces(model, &mut pd.data, q, nu);
    pd.scratch_v.copy_from(&pd.data.tau);
    crba_from_kinematics(model, &mut pd.data);
    joint_diagonal(plant, &mut pd.diagonal);
    pd.mass_factor
        .factor(&pd.data.mass_matrix, &pd.diagonal)
        .map_err(|e| Error::input(format!("mass matrix: {e}")))?;

    joint_and_motor_torques(plant, pd, q, theta, nu, thetadot, u);

    // Unconstrained acceleration, kept as L^-T (B tau - h) until the multipliers are known:
    // nudot = L^-1 (L^-T (B tau - h) + Y f), Y = L^-T J^T, S = Y^T Y,
    // f = S^-1 (a_target - Y^T L^-T (B tau - h)).
    pd.scratch_v.neg_mut();
    for j in 0..model.n_joints() {
        pd.scratch_v[6 + j] += pd.joint_torque[j];
    }
    pd.mass_factor.solve_lt(pd.scratch_v.as_mut_slice());
    if !plant.contacts.is_empty() {
        contact_terms(plant, pd, nu);
        pd.constraint_rhs
            .gemv_tr(-1.0, &pd.linv_jt, &pd.scratch_v, 1.0);
        cholesky_in_place(&mut pd.schur).map_err(|i| {
            Error::input(format!(
                "contact constraints are degenerate (Schur complement pivot {i})"
            ))
        })?;
        cholesky_solve_in_place(&pd.schur, pd.constraint_rhs.as_mut_slice());
        pd.scratch_v.gemv(1.0, &pd.linv_jt, &pd.constraint_rhs, 1.0);
        pd.contact_wrench.copy_from(&pd.constraint_rhs);
    }
    pd.mass_factor.solve_l(pd.scratch_v.as_mut_slice());

    let nd = layout.nd();
    let xdot = &mut pd.xdot;
    xdot.rows_mut(0, nv).copy_from_slice(nu);
    xdot.rows_mut(nv, ne).copy_from_slice(thetadot);
    xdot.rows_mut(nv + ne, nv).copy_from(&pd.scratch_v);
    for e in 0..ne {
        let p = &plant.actuation.elastic[e];
        let j = plant.actuation.elastic_joints[e];
        xdot[2 * nv + ne + e] =
            (pd.motor_torque[e] - p.ratio * pd.joint_torque[j]) / p.motor_inertia;
    }
    debug_assert_eq!(2 * nv + 2 * ne, nd);
    Ok(())
}

/// The joint inertia regularisation on the joint diagonal (nv; base entries zero).
fn joint_diagonal(plant: &Plant, diagonal: &mut [f64]) {
    diagonal[..6].fill(0.0);
    diagonal[6..].fill(plant.joint_inertia_regularization);
}

/// Spring-damper torques of elastic joints, inputs of rigid joints, and motor torques.
fn joint_and_motor_torques(
    plant: &Plant,
    pd: &mut PlantData,
    q: &[f64],
    theta: &[f64],
    nu: &[f64],
    thetadot: &[f64],
    u: &[f64],
) {
    let actuation = &plant.actuation;
    for (j, actuator) in actuation.actuators.iter().enumerate() {
        if matches!(actuator, crate::actuator::Actuator::Rigid) {
            pd.joint_torque[j] = u[j];
        }
    }
    for (e, (&j, p)) in actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .enumerate()
    {
        let tau = p.stiffness * (p.ratio * theta[e] - q[7 + j])
            + p.damping * (p.ratio * thetadot[e] - nu[6 + j]);
        pd.joint_torque[j] = tau;
        let demanded = match plant.motor_input {
            MotorInput::Torque => u[j],
            MotorInput::VelocityLoop { gain } => {
                -p.motor_inertia * gain * (thetadot[e] - u[j]) + p.ratio * tau
            }
        };
        let (torque, saturated) = match p.torque_limit {
            Some(limit) if demanded.abs() > limit => (demanded.signum() * limit, true),
            _ => (demanded, false),
        };
        pd.motor_torque[e] = torque;
        pd.saturated[e] = saturated;
    }
}

/// Contact Jacobian, `M^-1 J^T`, Schur complement and the Baumgarte acceleration target
/// `-(Jdot nu + K_d J nu + K_p e)` (into `constraint_rhs`), plus the drift.
fn contact_terms(plant: &Plant, pd: &mut PlantData, nu: &[f64]) {
    let model = &plant.model;
    let nv = model.nv();
    pd.drift_position = 0.0;
    pd.drift_rotation = 0.0;
    for (c, contact) in plant.contacts.iter().enumerate() {
        frame_jacobian_from_kinematics(model, &mut pd.data, contact.frame);
        pd.contact_jacobian
            .rows_mut(6 * c, 6)
            .copy_from(&pd.data.frame_jacobian);
        let bias = frame_bias_acceleration(model, &mut pd.data, contact.frame);
        let pose = frame_placement(model, &pd.data, contact.frame);
        let position_error = pose.translation - contact.reference.translation;
        let rotation_err = rotation_error(&pose.rotation, &contact.reference.rotation);
        pd.drift_position = pd.drift_position.max(position_error.norm());
        pd.drift_rotation = pd.drift_rotation.max(rotation_err.norm());
        for r in 0..6 {
            let velocity: f64 = (0..nv)
                .map(|i| pd.data.frame_jacobian[(r, i)] * nu[i])
                .sum();
            let error = if r < 3 {
                position_error[r]
            } else {
                rotation_err[r - 3]
            };
            pd.constraint_rhs[6 * c + r] =
                -(bias[r] + plant.baumgarte_kd * velocity + plant.baumgarte_kp * error);
        }
    }
    pd.mass_factor
        .schur_complement(&pd.contact_jacobian, &mut pd.linv_jt, &mut pd.schur);
}

/// Prepares the implicit step's matrix `W = I - g Jf` at the last evaluated state, with `g`
/// the step scale (`gamma dt`). `Jf` keeps the stiff linear terms exactly: springs, dampers,
/// the motor velocity loop and the Baumgarte terms, with `M` and `J` frozen (see
/// `integrator.rs`). Elastic motors are eliminated per joint, leaving an nv-size system.
pub(crate) fn prepare_implicit(plant: &Plant, pd: &mut PlantData, g: f64) -> Result<()> {
    let actuation = &plant.actuation;
    pd.w_g = g;
    joint_diagonal(plant, &mut pd.diagonal);
    for (e, p) in actuation.elastic.iter().enumerate() {
        let (torque_driven, gain) = match plant.motor_input {
            MotorInput::VelocityLoop { gain } if !pd.saturated[e] => (false, gain),
            _ => (true, 0.0),
        };
        let coupling = if torque_driven {
            g / p.motor_inertia
        } else {
            0.0
        };
        let eta = p.ratio;
        let den = 1.0 + g * gain + coupling * (g * eta * eta * p.stiffness + eta * eta * p.damping);
        let a1 = coupling * eta * (g * p.stiffness + p.damping) / den;
        let t1 = (g * p.stiffness + p.damping) * (eta * a1 - 1.0);
        pd.w_den[e] = den;
        pd.w_a1[e] = a1;
        pd.w_t1[e] = t1;
        pd.w_torque_driven[e] = torque_driven;
        pd.w_gain[e] = gain;
        let vj = 6 + actuation.elastic_joints[e];
        pd.diagonal[vj] -= g * t1;
    }
    pd.w_factor
        .factor(&pd.data.mass_matrix, &pd.diagonal)
        .map_err(|e| Error::input(format!("implicit step matrix: {e}")))?;
    if plant.contacts.is_empty() {
        return Ok(());
    }
    pd.w_jacobian.copy_from(&pd.contact_jacobian);
    pd.w_factor
        .schur_complement(&pd.w_jacobian, &mut pd.w_linv_jt, &mut pd.w_schur);
    cholesky_in_place(&mut pd.w_schur).map_err(|i| {
        Error::input(format!(
            "implicit step: contact constraints are degenerate (pivot {i})"
        ))
    })
}

/// Solves `W k = r` (tangent vectors, size nd) with the matrix of [`prepare_implicit`].
///
/// Per elastic joint the motor unknowns are `k_thetadot = a0 + a1 k_sdot`,
/// `k_theta = r_theta + g k_thetadot`, and the torque perturbation `t0 + t1 k_sdot`; the
/// velocity part solves `[M~ J^T; J 0] [z; -df] = [B (t0 + t1 r_sdot); c]` with
/// `c = -(K_d J r_nu + K_p J (r_q + g r_nu)) / (1 + g K_d + g^2 K_p)`; then `k_nu = r_nu + g z`,
/// `k_q = r_q + g k_nu`.
pub(crate) fn solve_implicit(
    plant: &Plant,
    pd: &mut PlantData,
    r: &DVector<f64>,
    k: &mut DVector<f64>,
) {
    let layout = plant.layout();
    let (nv, ne) = (layout.nv, layout.ne);
    let g = pd.w_g;
    let (o_theta, o_nu, o_thetadot) = (nv, nv + ne, 2 * nv + ne);
    let actuation = &plant.actuation;
    // z <- B (t0 + t1 r_sdot), keeping a0 per joint in k's thetadot slots for later.
    let z = &mut pd.scratch_v;
    z.fill(0.0);
    for (e, p) in actuation.elastic.iter().enumerate() {
        let vj = 6 + actuation.elastic_joints[e];
        let (r_s, r_theta, r_thetadot) = (r[vj], r[o_theta + e], r[o_thetadot + e]);
        let eta = p.ratio;
        let coupling = if pd.w_torque_driven[e] {
            g / p.motor_inertia
        } else {
            0.0
        };
        let a0 = (r_thetadot
            - coupling * (eta * eta * p.stiffness * r_theta - eta * p.stiffness * r_s))
            / pd.w_den[e];
        let t0 = p.stiffness * (eta * r_theta - r_s) + (g * p.stiffness + p.damping) * eta * a0;
        z[vj] = t0 + pd.w_t1[e] * r[o_nu + vj];
        k[o_thetadot + e] = a0;
    }
    pd.w_factor.solve_lt(z.as_mut_slice());
    if !plant.contacts.is_empty() {
        let kp = plant.baumgarte_kp;
        let kd = plant.baumgarte_kd;
        let scale = 1.0 / (1.0 + g * kd + g * g * kp);
        let rhs = &mut pd.constraint_rhs;
        for row in 0..pd.w_jacobian.nrows() {
            let mut target = 0.0;
            for i in 0..nv {
                let r_nu = r[o_nu + i];
                target += pd.w_jacobian[(row, i)] * (kd * r_nu + kp * (r[i] + g * r_nu));
            }
            rhs[row] = -target * scale;
        }
        rhs.gemv_tr(-1.0, &pd.w_linv_jt, z, 1.0);
        cholesky_solve_in_place(&pd.w_schur, rhs.as_mut_slice());
        z.gemv(1.0, &pd.w_linv_jt, rhs, 1.0);
    }
    pd.w_factor.solve_l(z.as_mut_slice());
    for i in 0..nv {
        let k_nu = r[o_nu + i] + g * z[i];
        k[o_nu + i] = k_nu;
        k[i] = r[i] + g * k_nu;
    }
    for e in 0..ne {
        let vj = 6 + actuation.elastic_joints[e];
        let k_thetadot = k[o_thetadot + e] + pd.w_a1[e] * k[o_nu + vj];
        k[o_thetadot + e] = k_thetadot;
        k[o_theta + e] = r[o_theta + e] + g * k_thetadot;
    }
}

/// `x_out = x (+) scale * dx` on the state manifold (quaternion stays unit).
pub fn retract(plant: &Plant, x: &[f64], dx: &DVector<f64>, scale: f64, x_out: &mut [f64]) {
    let layout = plant.layout();
    let (nq, nv, ne) = (layout.nq, layout.nv, layout.ne);
    crate::configuration::integrate(
        &plant.model,
        &x[..nq],
        &dx.as_slice()[..nv],
        scale,
        &mut x_out[..nq],
    );
    for e in 0..ne {
        x_out[nq + e] = x[nq + e] + scale * dx[nv + e];
    }
    for i in 0..nv + ne {
        x_out[nq + ne + i] = x[nq + ne + i] + scale * dx[nv + ne + i];
    }
}

/// Time derivative of the state vector itself (nx), for external integrators: the quaternion
/// rate is `0.5 [0; omega] * quat` (world angular velocity, left product).
pub fn state_derivative(plant: &Plant, x: &[f64], xdot_tangent: &DVector<f64>, out: &mut [f64]) {
    let layout = plant.layout();
    let (nq, nv, ne) = (layout.nq, layout.nv, layout.ne);
    let omega = [xdot_tangent[3], xdot_tangent[4], xdot_tangent[5]];
    out[..3].copy_from_slice(&xdot_tangent.as_slice()[..3]);
    let rate = crate::configuration::quaternion_multiply(
        [0.0, omega[0], omega[1], omega[2]],
        [x[3], x[4], x[5], x[6]],
    );
    for c in 0..4 {
        out[3 + c] = 0.5 * rate[c];
    }
    out[7..nq].copy_from_slice(&xdot_tangent.as_slice()[6..nv]);
    out[nq..].copy_from_slice(&xdot_tangent.as_slice()[nv..nv + ne + nv + ne]);
}
