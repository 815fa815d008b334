//! The momentum-based balancing controller, rigid (paper section "Balancing control with robot
//! rigid transmissions") and SEA (section "The balancing control for series elastic
//! actuators"), in the implementation form of DESIGN.md ("sea_ctrl"):
//!
//! - momentum task `Hdot* = Hdot_d - K_p (H - H_d) - K_i I_H`, `I_H = [m (p_com - p_com_d);
//!   J_G^omega(s_d) (s - s_d)]` (eq:dotH_f, eq:IhTilde), and `Hdot(f) = A f + m g`,
//!   `A_k = [[I, 0], [skew(p_k - p_com), I]]`;
//! - joint torques affine in the wrenches (eq:torques, eq:posturalNew):
//!   `Lambda = J M^-1 B`, damped `Lambda^+`, `N = I - Lambda^+ Lambda`,
//!   `tau(f) = Lambda^+ (J M^-1 h - Jdot nu) + N (hbar_j + u0) + Sigma f`,
//!   `Sigma = -(Lambda^+ J M^-1 J^T + N Jbar^T)`,
//!   `u0 = -K_p^j N Mbar (s - s_d) - K_d^j N Mbar sdot`;
//! - the QP (eq:inputTorquesSOT): one foot `min |A f - (Hdot* - m g)|^2`, two feet
//!   `min |tau(f)|^2` s.t. `A f = Hdot* - m g`; both s.t. the contact constraints;
//! - SEA (eq:newJointDynamics, eq:inputDesMotVel): `tau` becomes `beta = K_D Gamma thetadot`,
//!   `h_j` becomes `h_j - p`, `p = K_S (Gamma theta - s) - K_D sdot` (the controller's own
//!   estimates of `K_S`, `K_D`), and the output is `thetadot_d = Gamma^-1 K_D^-1 beta*`, tracked
//!   by the motor velocity loop of the plant (eq:tauMotors). Mixed actuation: rigid joints keep
//!   `tau`, `p = 0`.
//! - Rigid controller on an SEA robot: the rigid model with the motor reflected inertia
//!   `Gamma^-1 I_m Gamma^-1` on the joint diagonal (Remark 1), output `tau_m = Gamma tau*`.
//!
//! `g` is the gravity vector (`m g = [0, 0, -m 9.81]`), so `Hdot(f) = A f + [m g; 0]`.
//!
//! The torque map is computed by [`crate::torque_map`], the QP by [`crate::qp`]; this file
//! assembles the model terms, the momentum task and the QP's objective, and maps the result to
//! the plant input.

use crate::error::{Error, Result};
use crate::qp::{ContactConstraints, QpStatus, WrenchQp};
use crate::references::ComSample;
use crate::torque_map::{PosturalTask, TorqueMap};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use sea_dyn::spatial::{quaternion_from_rotation, skew};
use sea_dyn::{Actuation, Data, FrameId, Model, StateLayout};

/// Which controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControllerKind {
    /// The SEA controller (desired motor velocities).
    Sea,
    /// The rigid-joint controller (joint torques, `tau_m = Gamma tau` on elastic joints).
    Rigid,
}

/// Settings of the controller.
#[derive(Clone, Debug)]
pub struct ControllerSettings {
    /// Rigid or SEA.
    pub kind: ControllerKind,
    /// Contact frames (one or two feet).
    pub contacts: Vec<String>,
    /// Momentum proportional gains `K_p` (diagonal, linear then angular).
    pub momentum_proportional: [f64; 6],
    /// Momentum integral gains `K_i` (diagonal).
    pub momentum_integral: [f64; 6],
    /// Postural stiffness `K_p^j` (n, diagonal).
    pub postural_stiffness: Vec<f64>,
    /// Postural damping `K_d^j` (n, diagonal).
    pub postural_damping: Vec<f64>,
    /// Contact constraints of the QP.
    pub constraints: ContactConstraints,
    /// Controller's damping estimate = true damping x this scale.
    pub damping_estimate_scale: f64,
    /// Controller's stiffness estimate = true stiffness x this scale.
    pub stiffness_estimate_scale: f64,
    /// Damping of the pseudo-inverse of `Lambda` (REFERENCE.md: 5e-4).
    pub pinv_damping: f64,
    /// QP Hessian regulariser (REFERENCE.md: 1e-3).
    pub qp_regularization: f64,
    /// Rigid controller: add the motor reflected inertia of elastic joints to `M_j`.
    pub reflected_inertia: bool,
    /// Added to the joint diagonal of the controller's `M` [kg m^2].
    pub joint_inertia_regularization: f64,
    /// Try the QP's minimiser without inequalities first: when it satisfies them all it is the
    /// QP's optimum (the KKT conditions hold with zero multipliers) and Clarabel is not called.
    pub qp_unconstrained_first: bool,
}

/// One tick's outputs.
#[derive(Clone, Debug)]
pub struct ControlOutput {
    /// Plant input (n): rigid joints torque; elastic joints desired motor velocity (SEA
    /// controller) or motor torque `eta tau*` (rigid controller).
    pub input: Vec<f64>,
    /// `tau*` (rigid) or `beta*` (SEA), joint side (n).
    pub joint_command: Vec<f64>,
    /// Desired motor velocities of elastic joints (n_e; empty for the rigid controller).
    pub thetadot_desired: Vec<f64>,
    /// QP wrenches (6 per contact).
    pub wrenches: DVector<f64>,
    /// QP outcome.
    pub qp_status: QpStatus,
    /// CoM in world [m].
    pub com: Vector3<f64>,
    /// Centroidal momentum `[m pdot_com; L_com]`.
    pub momentum: Vector6<f64>,
}

/// The terms of `tau(f) = tau_bias + Sigma f` and of the momentum task `A f = b` at one state.
#[derive(Clone, Debug)]
pub struct TaskTerms {
    /// `tau_bias` (n).
    pub tau_bias: DVector<f64>,
    /// `Sigma` (n x 6 n_contacts).
    pub sigma: DMatrix<f64>,
    /// `A` (6 x 6 n_contacts).
    pub momentum_map: DMatrix<f64>,
    /// `b = Hdot* - m g` (6).
    pub momentum_target: DVector<f64>,
    /// `world_R_contact` of each contact.
    pub rotations: Vec<Matrix3<f64>>,
}

impl TaskTerms {
    /// Zeroed terms for `n` joints and `n_contacts` contacts (the identity blocks of `A` set).
    fn new(n: usize, n_contacts: usize) -> Self {
        let k = 6 * n_contacts;
        let mut momentum_map = DMatrix::zeros(6, k);
        for c in 0..n_contacts {
            momentum_map
                .view_mut((0, 6 * c), (6, 6))
                .fill_with_identity();
        }
        Self {
            tau_bias: DVector::zeros(n),
            sigma: DMatrix::zeros(n, k),
            momentum_map,
            momentum_target: DVector::zeros(6),
            rotations: vec![Matrix3::identity(); n_contacts],
        }
    }
}

/// The momentum controller with its own model and estimates.
pub struct MomentumController {
    model: Model,
    data: Data,
    actuation: Actuation,
    settings: ControllerSettings,
    contact_frames: Vec<FrameId>,
    /// Reference placements `world_H_contact` (where the feet are held).
    contact_references: Vec<sea_dyn::spatial::Pose>,
    qp: WrenchQp,
    /// The torque map's inputs, buffers and results.
    torque_map: TorqueMap,
    /// This tick's `tau(f) = tau_bias + Sigma f` and momentum task `A f = b`.
    terms: TaskTerms,
    /// `s - s_d` (n) [rad].
    posture_error: Vec<f64>,
    /// QP Hessian `P` (k x k) and gradient `c` (k) of `0.5 f^T P f + c^T f`.
    qp_hessian: DMatrix<f64>,
    qp_gradient: DVector<f64>,
    /// `J_G^omega(s_d)` (3 x n) and the `s_d` it was computed at.
    jg_angular: DMatrix<f64>,
    jg_posture: Vec<f64>,
    /// Total mass [kg].
    mass: f64,
}

fn vec_in(x: &[f64], start: usize, len: usize) -> &[f64] {
    &x[start..start + len]
}

impl MomentumController {
    /// A controller for `model` with the plant's `actuation` (true parameters; the estimates
    /// are scaled from them), holding the contacts at their pose in `q0`.
    pub fn new(
        model: &Model,
        actuation: &Actuation,
        settings: ControllerSettings,
        q0: &[f64],
    ) -> Result<Self> {
        let n = model.n_joints();
        if settings.contacts.is_empty() || settings.contacts.len() > 2 {
            return Err(Error::config(
                "controller.contacts",
                "needs one or two contact frames",
            ));
        }
        for (key, v) in [
            (
                "controller.damping_estimate_scale",
                settings.damping_estimate_scale,
            ),
            (
                "controller.stiffness_estimate_scale",
                settings.stiffness_estimate_scale,
            ),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::config(key, format!("must be positive, got {v}")));
            }
        }
        let gains = settings
            .momentum_proportional
            .iter()
            .chain(&settings.momentum_integral)
            .chain(&settings.postural_stiffness)
            .chain(&settings.postural_damping);
        if gains.clone().any(|g| !(g.is_finite() && *g >= 0.0)) {
            return Err(Error::config(
                "controller gains",
                "must be finite and non-negative",
            ));
        }
        if settings.postural_stiffness.len() != n || settings.postural_damping.len() != n {
            return Err(Error::config(
                "controller.postural_stiffness",
                format!("needs {n} entries (one per joint)"),
            ));
        }
        let mut data = Data::new(model);
        sea_dyn::forward_kinematics(model, &mut data, q0);
        let mut contact_frames = Vec::new();
        let mut contact_references = Vec::new();
        for name in &settings.contacts {
            let id = model.frame_id(name).map_err(|_| {
                Error::config("controller.contacts", format!("unknown frame '{name}'"))
            })?;
            contact_frames.push(id);
            contact_references.push(sea_dyn::frame_placement(model, &data, id));
        }
        let k = 6 * contact_frames.len();
        let equalities = if contact_frames.len() > 1 { 6 } else { 0 };
        let mut torque_map = TorqueMap::new(model, k);
        for j in 0..n {
            torque_map.diagonal[6 + j] = settings.joint_inertia_regularization;
        }
        if settings.kind == ControllerKind::Rigid && settings.reflected_inertia {
            for (&j, p) in actuation.elastic_joints.iter().zip(&actuation.elastic) {
                torque_map.diagonal[6 + j] += p.motor_inertia / (p.ratio * p.ratio);
            }
        }
        let mut qp = WrenchQp::new(contact_frames.len(), equalities, &settings.constraints);
        qp.unconstrained_first = settings.qp_unconstrained_first;
        Ok(Self {
            model: model.clone(),
            data,
            actuation: actuation.clone(),
            qp,
            torque_map,
            terms: TaskTerms::new(n, contact_frames.len()),
            posture_error: vec![0.0; n],
            qp_hessian: DMatrix::zeros(k, k),
            qp_gradient: DVector::zeros(k),
            jg_angular: DMatrix::zeros(3, n),
            jg_posture: Vec::new(),
            mass: model.total_mass(),
            settings,
            contact_frames,
            contact_references,
        })
    }

    /// QP solves that fell back to the unconstrained solution so far.
    pub fn qp_failures(&self) -> usize {
        self.qp.failures
    }

    /// QP solves so far: `(by Clarabel, skipped because the minimiser without inequalities
    /// was feasible)`.
    pub fn qp_solves(&self) -> (usize, usize) {
        (self.qp.clarabel_solves, self.qp.unconstrained_solves)
    }

    /// Settings.
    pub fn settings(&self) -> &ControllerSettings {
        &self.settings
    }

    /// `J_G^omega(s_d)`: angular rows of the centroidal momentum map restricted to motions that
    /// keep the contacts fixed, `J_G = A_Gj - A_Gb J_b^+ J_j`, at the configuration with joints
    /// `s_d` and the first contact at its reference.
    fn update_jg(&mut self, s_desired: &[f64]) -> Result<()> {
        if self.jg_posture == s_desired {
            return Ok(());
        }
        let model = &self.model;
        let n = model.n_joints();
        let mut q = model.neutral();
        q[7..].copy_from_slice(s_desired);
        sea_dyn::forward_kinematics(model, &mut self.data, &q);
        let base_h_contact = sea_dyn::frame_placement(model, &self.data, self.contact_frames[0]);
        let world_h_base = self.contact_references[0].compose(&base_h_contact.inverse());
        let quat = quaternion_from_rotation(&world_h_base.rotation);
        q[..3].copy_from_slice(world_h_base.translation.as_slice());
        q[3..7].copy_from_slice(&quat);
        let a_g = sea_dyn::centroidal_momentum_matrix(model, &mut self.data, &q).clone();
        let k = 6 * self.contact_frames.len();
        let mut jacobian = DMatrix::zeros(k, model.nv());
        for (c, &frame) in self.contact_frames.iter().enumerate() {
            let j = sea_dyn::frame_jacobian(model, &mut self.data, &q, frame);
            jacobian.rows_mut(6 * c, 6).copy_from(j);
        }
        let j_b = jacobian.columns(0, 6).into_owned();
        let j_j = jacobian.columns(6, n).into_owned();
        let jb_pinv = (j_b.transpose() * &j_b).try_inverse().ok_or_else(|| {
            Error::config(
                "controller.contacts",
                "contact Jacobian has no full column rank",
            )
        })? * j_b.transpose();
        let jg = a_g.columns(6, n) - a_g.columns(0, 6) * jb_pinv * j_j;
        self.jg_angular.copy_from(&jg.rows(3, 3));
        self.jg_posture = s_desired.to_vec();
        Ok(())
    }

    /// Computes the control at plant state `x` (layout `layout`) for the CoM reference and the
    /// desired posture `s_desired`.
    pub fn compute(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
    ) -> Result<ControlOutput> {
        self.update_jg(s_desired)?;
        let (com, momentum) = self.task_terms(x, layout, reference, s_desired)?;
        let terms = &self.terms;
        let k = self.qp_gradient.len();
        let reg = self.settings.qp_regularization;
        let (hessian, gradient) = (&mut self.qp_hessian, &mut self.qp_gradient);
        let two_feet = self.contact_frames.len() > 1;
        if two_feet {
            // min |tau_bias + Sigma f|^2 + reg |f|^2 s.t. A f = b:
            // P = 2 (Sigma^T Sigma + reg I), c = 2 Sigma^T tau_bias.
            hessian.gemm_tr(2.0, &terms.sigma, &terms.sigma, 0.0);
            gradient.gemv_tr(2.0, &terms.sigma, &terms.tau_bias, 0.0);
        } else {
            // min |A f - b|^2 + reg |f|^2: P = 2 (A^T A + reg I), c = -2 A^T b.
            let a = &terms.momentum_map;
            hessian.gemm_tr(2.0, a, a, 0.0);
            gradient.gemv_tr(-2.0, a, &terms.momentum_target, 0.0);
        }
        for i in 0..k {
            hessian[(i, i)] += 2.0 * reg;
        }
        let equality = two_feet.then_some((&terms.momentum_map, &terms.momentum_target));
        let unconstrained = match equality {
            Some((a, b)) => equality_constrained_minimum(hessian, gradient, a, b),
            None => unconstrained_minimum(hessian, gradient),
        };
        let (wrenches, qp_status) = self.qp.solve(
            hessian,
            gradient,
            equality,
            &terms.rotations,
            unconstrained.as_ref(),
        );
        let mut command = terms.tau_bias.clone();
        command.gemv(1.0, &terms.sigma, &wrenches, 1.0);
        Ok(self.plant_input(command, wrenches, qp_status, com, momentum))
    }

    /// Maps the joint-side command to the plant input.
    fn plant_input(
        &self,
        command: DVector<f64>,
        wrenches: DVector<f64>,
        qp_status: QpStatus,
        com: Vector3<f64>,
        momentum: Vector6<f64>,
    ) -> ControlOutput {
        let mut input = command.as_slice().to_vec();
        let mut thetadot_desired = Vec::new();
        for (&j, p) in self
            .actuation
            .elastic_joints
            .iter()
            .zip(&self.actuation.elastic)
        {
            match self.settings.kind {
                ControllerKind::Sea => {
                    let damping = p.damping * self.settings.damping_estimate_scale;
                    let velocity = command[j] / (p.ratio * damping);
                    input[j] = velocity;
                    thetadot_desired.push(velocity);
                }
                ControllerKind::Rigid => input[j] = p.ratio * command[j],
            }
        }
        ControlOutput {
            input,
            joint_command: command.as_slice().to_vec(),
            thetadot_desired,
            wrenches,
            qp_status,
            com,
            momentum,
        }
    }

    /// Model terms, the torque map and the momentum task at the state, into `self.terms`;
    /// returns the CoM [m] and the centroidal momentum.
    fn task_terms(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
    ) -> Result<(Vector3<f64>, Vector6<f64>)> {
        let model = &self.model;
        let _nv = model.nv();
        let q = vec_in(x, 0, layout.nq);
        let theta = layout.theta(x);
        let nu = layout.nu(x);
        let (s, sdot) = (&q[7..], &nu[6..]);
        let data = &mut self.data;
        let map = &mut self.torque_map;
        // One kinematic pass: the bias forces leave the body velocities and inertias the
        // momentum needs; CRBA reuses the placements.
        map.bias.copy_from(sea_dyn::bias_forces(model, data, q, nu));
        let momentum = sea_dyn::centroidal_momentum_from_dynamics(data);
        let com = data.p_base_world + data.p_com_rel;
        sea_dyn::crba_from_kinematics(model, data);
        if self.settings.kind == ControllerKind::Sea {
            for (e, (&j, p)) in self
                .actuation
                .elastic_joints
                .iter()
                .zip(&self.actuation.elastic)
                .enumerate()
            {
                // h_j - p, p = K_S (Gamma theta - s) - K_D sdot (the controller's estimates).
                let k_s = p.stiffness * self.settings.stiffness_estimate_scale;
                let k_d = p.damping * self.settings.damping_estimate_scale;
                map.bias[6 + j] -= k_s * (p.ratio * theta[e] - s[j]) - k_d * sdot[j];
            }
        }
        let terms = &mut self.terms;
        for (c, &frame) in self.contact_frames.iter().enumerate() {
            sea_dyn::jacobian::frame_jacobian_from_kinematics(model, data, frame);
            map.jacobian
                .rows_mut(6 * c, 6)
                .copy_from(&data.frame_jacobian);
            let bias = sea_dyn::jacobian::frame_bias_acceleration(model, data, frame);
            map.jdot_nu.fixed_rows_mut::<6>(6 * c).copy_from(&bias);
            let pose = sea_dyn::frame_placement(model, data, frame);
            terms.rotations[c] = pose.rotation;
            // A_c = [[I, 0], [skew(p_c - p_com), I]]; the identity blocks never change.
            terms
                .momentum_map
                .fixed_view_mut::<3, 3>(3, 6 * c)
                .copy_from(&skew(&(pose.translation - com)));
        }
        for (e, value) in self.posture_error.iter_mut().enumerate() {
            *value = s[e] - s_desired[e];
        }
        let posture = PosturalTask {
            error: &self.posture_error,
            velocity: sdot,
            stiffness: &self.settings.postural_stiffness,
            damping: &self.settings.postural_damping,
        };
        map.compute(&data.mass_matrix, &posture, self.settings.pinv_damping)?;
        terms.tau_bias.copy_from(&map.tau_bias);
        terms.sigma.copy_from(&map.sigma);
        self.momentum_target(reference, com, &momentum);
        Ok((com, momentum))
    }

    /// `b = Hdot* - m g` into `self.terms.momentum_target`, `Hdot* = Hdot_d - K_p (H - H_d) -
    /// K_i I_H`, `I_H = [m (p_com - p_com_d); J_G^omega(s_d) (s - s_d)]`.
    fn momentum_target(
        &mut self,
        reference: &ComSample,
        com: Vector3<f64>,
        momentum: &Vector6<f64>,
    ) {
        let m = self.mass;
        let desired_linear = reference.velocity * m;
        let angular_integral = Vector3::from_fn(|r, _| {
            let row = self.jg_angular.row(r);
            row.iter()
                .zip(&self.posture_error)
                .map(|(a, b)| a * b)
                .sum()
        });
        let linear_integral = (com - reference.position) * m;
        let gravity = self.model.gravity * m;
        let settings = &self.settings;
        for r in 0..6 {
            let (feedforward, desired, integral, weight) = if r < 3 {
                (
                    m * reference.acceleration[r],
                    desired_linear[r],
                    linear_integral[r],
                    gravity[r],
                )
            } else {
                (0.0, 0.0, angular_integral[r - 3], 0.0)
            };
            let hdot_star = feedforward
                - settings.momentum_proportional[r] * (momentum[r] - desired)
                - settings.momentum_integral[r] * integral;
            self.terms.momentum_target[r] = hdot_star - weight;
        }
    }

    /// The torque map and momentum task at a state (what the QP of [`Self::compute`] uses).
    pub fn torque_map(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
    ) -> Result<TaskTerms> {
        self.update_jg(s_desired)?;
        self.task_terms(x, layout, reference, s_desired)?;
        Ok(self.terms.clone())
    }
}

/// `argmin 0.5 f^T P f + c^T f` (`P` positive definite): `-P^-1 c`; `None` if `P` is not.
fn unconstrained_minimum(p: &DMatrix<f64>, c: &DVector<f64>) -> Option<DVector<f64>> {
    p.clone().cholesky().map(|chol| -chol.solve(c))
}

/// `argmin 0.5 f^T P f + c^T f` s.t. `A f = b` (the KKT system), the QP without its
/// inequalities; `None` if the KKT matrix is singular.
fn equality_constrained_minimum(
    p: &DMatrix<f64>,
    c: &DVector<f64>,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
) -> Option<DVector<f64>> {
    let (m, n) = a.shape();
    let mut kkt = DMatrix::zeros(n + m, n + m);
    kkt.view_mut((0, 0), (n, n)).copy_from(p);
    kkt.view_mut((0, n), (n, m)).tr_copy_from(a);
    kkt.view_mut((n, 0), (m, n)).copy_from(a);
    let mut rhs = DVector::zeros(n + m);
    rhs.rows_mut(0, n).copy_from(&(-c));
    rhs.rows_mut(n, m).copy_from(b);
    let solution = kkt.lu().solve(&rhs)?;
    let f = solution.rows(0, n).into_owned();
    f.iter().all(|v| v.is_finite()).then_some(f)
}
