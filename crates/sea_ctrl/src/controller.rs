//! The momentum-based balancing controller, rigid (paper section "Balancing control with robot
//! rigid transmissions") and SEA (section "The balancing control for series elastic
//! actuators"). One tick ([`MomentumController::compute_into`]):
//!
//! 1. model terms at the state: `M`, `h` (for the SEA controller with hjBar, `h_j - p`,
//!    [`crate::sea`]), the contact Jacobians and `Jdot nu`, the CoM and the momentum `H`;
//! 2. the momentum task ([`crate::momentum`]): `Hdot(f) = A f + [m g; 0]` (hDot), `Hdot*`
//!    (eq:dotH_f) with the integral term (eq:IhTilde), hence `A f = b`, `b = Hdot* - [m g; 0]`;
//! 3. the torque map ([`crate::torque_map`], eq:torques with posturalNew): `tau(f) = tau_bias
//!    + Sigma f` (`beta(f)` for the SEA controller, newJointDynamics);
//! 4. the QP ([`crate::qp`], inputTorquesSOT / inputTorquesSOTu): one foot `min |A f - b|^2`,
//!    two feet `min |tau(f)|^2` s.t. `A f = b`; both s.t. the contact constraints
//!    (frictionCones); two feet, when `A f = b` is infeasible under them and
//!    [`MomentumRelaxation::WhenInfeasible`] is set, the closest feasible momentum rate;
//! 5. the plant input: rigid joints `tau*`; elastic joints the desired motor velocity
//!    `thetadot_d = Gamma^-1 K_D^-1 beta*` (SEA controller, inputDesMotVel, tracked by the
//!    plant's motor velocity loop eq:tauMotors) or the motor torque `Gamma tau*` (rigid
//!    controller on an SEA robot, with the reflected inertia of remark1 in its `M_j`).
//!
//! Mixed actuation: rigid joints keep `tau` and `p = 0`. The SEA terms use the controller's
//! own estimates of `K_S`, `K_D` (scaled, for the paper's mismatch study). Every buffer of the
//! tick is allocated in [`MomentumController::new`].

use crate::error::{Error, Result};
use crate::external_wrench::base_generalized_force;
use crate::momentum::{
    desired_momentum, momentum_equality_target, momentum_integral_error,
    momentum_map_identity_blocks, momentum_rate_star, set_momentum_map_contact, MomentumJacobian,
};
use crate::qp::{
    add_moment_regularization, momentum_tracking_objective, relaxed_momentum_objective,
    torque_norm_objective, ContactConstraints, Minimizer, QpAgreement, QpCounters, QpSolver,
    QpStatus, RelaxedMomentumWeights, WrenchQp,
};
use crate::references::ComSample;
use crate::sea::{
    controller_estimates, desired_motor_velocity, rigid_motor_torque, subtract_spring_torque,
};
use crate::torque_map::{PosturalTask, TorqueMap};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};
use sea_dyn::dense::copy_contiguous;
use sea_dyn::spatial::{Force, Pose};
use sea_dyn::{Actuation, Data, ElasticParameters, FrameId, Model, StateLayout};

/// Which controller; with the `serde` feature, named "sea" or "rigid".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum ControllerKind {
    /// The SEA controller (desired motor velocities).
    Sea,
    /// The rigid-joint controller (joint torques, `tau_m = Gamma tau` on elastic joints).
    Rigid,
}

/// What the two-feet QP does when its momentum equality `A f = b` is infeasible under the
/// contact constraints; with the `serde` feature, named "none" or "when_infeasible".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum MomentumRelaxation {
    /// The paper's QP only: an infeasible tick falls back to the minimiser without the contact
    /// constraints ([`QpStatus::Fallback`]), whose wrenches the contacts cannot carry.
    #[default]
    None,
    /// An infeasible tick solves the relaxed momentum task instead: the closest momentum rate
    /// the contacts can produce, the CoM's before the angular momentum
    /// ([`relaxed_momentum_objective`], [`QpStatus::MomentumRelaxed`]). The centre of pressure
    /// then sits on the edge of the QP's sole (keep `cop_margin` above 0).
    WhenInfeasible,
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
    /// Per joint (n, coordinate order), a further factor on the stiffness estimate of each
    /// elastic joint; empty for none.
    pub stiffness_estimate_joint_scales: Vec<f64>,
    /// Damping of the pseudo-inverse of `Lambda` (original study: 5e-4,
    /// docs/references.md#original-study-contact-wrench-qp).
    pub pinv_damping: f64,
    /// QP Hessian regulariser (original study: 1e-3,
    /// docs/references.md#original-study-contact-wrench-qp).
    pub qp_regularization: f64,
    /// Two feet: weight of the contact moments `|n_k|^2` added to the torque-norm objective
    /// ([`add_moment_regularization`]; 0 in the original study).
    pub qp_moment_regularization: f64,
    /// Two feet: what an infeasible momentum equality does.
    pub momentum_relaxation: MomentumRelaxation,
    /// Rigid controller: add the motor reflected inertia of elastic joints to `M_j`.
    pub reflected_inertia: bool,
    /// Added to the joint diagonal of the controller's `M` [kg m^2].
    pub joint_inertia_regularization: f64,
    /// Try the QP's minimiser without inequalities first: when it satisfies them all it is the
    /// QP's optimum (the KKT conditions hold with zero multipliers) and no QP solver is called.
    pub qp_unconstrained_first: bool,
    /// The QP solver ([`QpSolver::default`]: the active set, Clarabel as fallback).
    pub qp_solver: QpSolver,
}

/// One tick's outputs; [`MomentumController::new_output`] sizes one for a controller.
#[derive(Clone, Debug)]
pub struct ControlOutput {
    /// Plant input (n): rigid joints torque; elastic joints desired motor velocity (SEA
    /// controller) or motor torque `Gamma tau*` (rigid controller).
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
    /// The external wrench the tick's dynamics took, `[force; moment about the CoM]` (world
    /// axes; zero: none): the one set by [`MomentumController::set_external_wrench`] plus the
    /// generalized disturbance's base rows as a wrench about the CoM
    /// ([`MomentumController::set_generalized_disturbance`]), which the contacts carry.
    pub external_wrench: Vector6<f64>,
}

impl ControlOutput {
    /// Zeroed outputs for `n` joints, `n_motor_velocities` desired motor velocities and
    /// `n_contacts` contacts.
    pub fn new(n: usize, n_motor_velocities: usize, n_contacts: usize) -> Self {
        Self {
            input: vec![0.0; n],
            joint_command: vec![0.0; n],
            thetadot_desired: vec![0.0; n_motor_velocities],
            wrenches: DVector::zeros(6 * n_contacts),
            qp_status: QpStatus::Solved,
            com: Vector3::zeros(),
            momentum: Vector6::zeros(),
            external_wrench: Vector6::zeros(),
        }
    }
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
    /// `b = Hdot* - m g` (6), less the generalized disturbance's wrench `w_d` when one is set.
    pub momentum_target: DVector<f64>,
    /// `world_R_contact` of each contact (the sole frames of the QP's contact constraints).
    pub contact_rotations: Vec<Matrix3<f64>>,
}

impl TaskTerms {
    /// Zeroed terms for `n` joints and `n_contacts` contacts (the identity blocks of `A` set).
    fn new(n: usize, n_contacts: usize) -> Self {
        Self {
            tau_bias: DVector::zeros(n),
            sigma: DMatrix::zeros(n, 6 * n_contacts),
            momentum_map: momentum_map_identity_blocks(n_contacts),
            momentum_target: DVector::zeros(6),
            contact_rotations: vec![Matrix3::identity(); n_contacts],
        }
    }
}

impl ControllerSettings {
    /// Checks the settings for a model with `n` joints; names the offending key.
    pub fn validate(&self, n: usize) -> Result<()> {
        if self.contacts.is_empty() || self.contacts.len() > 2 {
            return Err(Error::config(
                "controller.contacts",
                "needs one or two contact frames",
            ));
        }
        let joint_scales = &self.stiffness_estimate_joint_scales;
        if !joint_scales.is_empty() && joint_scales.len() != n {
            return Err(Error::config(
                "controller.stiffness_estimate_joint_scales",
                format!("needs {n} entries, got {}", joint_scales.len()),
            ));
        }
        let joint_scales = joint_scales
            .iter()
            .map(|&v| ("controller.stiffness_estimate_joint_scales", v));
        for (key, v) in [
            (
                "controller.damping_estimate_scale",
                self.damping_estimate_scale,
            ),
            (
                "controller.stiffness_estimate_scale",
                self.stiffness_estimate_scale,
            ),
        ]
        .into_iter()
        .chain(joint_scales)
        {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::config(key, format!("must be positive, got {v}")));
            }
        }
        let gains: [(&str, &[f64]); 4] = [
            (
                "controller.momentum_proportional",
                &self.momentum_proportional,
            ),
            ("controller.momentum_integral", &self.momentum_integral),
            ("controller.postural_stiffness", &self.postural_stiffness),
            ("controller.postural_damping", &self.postural_damping),
        ];
        for (key, values) in gains {
            if let Some(g) = values.iter().find(|g| !(g.is_finite() && **g >= 0.0)) {
                let message = format!("must be finite and non-negative, got {g}");
                return Err(Error::config(key, message));
            }
        }
        let moment = self.qp_moment_regularization;
        if !(moment.is_finite() && moment >= 0.0) {
            let message = format!("must be finite and non-negative, got {moment}");
            return Err(Error::config(
                "controller.qp_moment_regularization",
                message,
            ));
        }
        let margin = self.constraints.cop_margin;
        if !(0.0..1.0).contains(&margin) {
            let message = format!("must be in [0, 1), got {margin}");
            return Err(Error::config("controller.contact.cop_margin", message));
        }
        if self.postural_stiffness.len() != n || self.postural_damping.len() != n {
            return Err(Error::config(
                "controller.postural_stiffness",
                format!("needs {n} entries (one per joint)"),
            ));
        }
        Ok(())
    }
}

/// The contact frames named in `names` and their placements `world_H_contact` at `q0`
/// (`data` is scratch).
fn resolve_contacts(
    model: &Model,
    data: &mut Data,
    names: &[String],
    q0: &[f64],
) -> Result<(Vec<FrameId>, Vec<Pose>)> {
    sea_dyn::forward_kinematics(model, data, q0);
    let mut frames = Vec::new();
    let mut placements = Vec::new();
    for name in names {
        let id = model
            .frame_id(name)
            .map_err(|_| Error::config("controller.contacts", format!("unknown frame '{name}'")))?;
        frames.push(id);
        placements.push(sea_dyn::frame_placement(model, data, id));
    }
    Ok((frames, placements))
}

/// What the controller adds to the diagonal of its `M` (nv): the joint regularisation and, for
/// the rigid controller with `reflected_inertia`, the motor reflected inertia of each elastic
/// joint (remark1, [`ElasticParameters::reflected_inertia`]).
fn inertia_diagonal(settings: &ControllerSettings, actuation: &Actuation, diagonal: &mut [f64]) {
    for value in &mut diagonal[6..] {
        *value = settings.joint_inertia_regularization;
    }
    if settings.kind == ControllerKind::Rigid && settings.reflected_inertia {
        for (&j, p) in actuation.elastic_joints.iter().zip(&actuation.elastic) {
            diagonal[6 + j] += p.reflected_inertia();
        }
    }
}

/// The momentum controller with its own model and estimates.
pub struct MomentumController {
    model: Model,
    data: Data,
    actuation: Actuation,
    /// The controller's elastic parameters (n_e): true stiffness and damping times the
    /// settings' estimate scales.
    estimates: Vec<ElasticParameters>,
    settings: ControllerSettings,
    contact_frames: Vec<FrameId>,
    /// Reference placements `world_H_contact` (where the feet are held).
    contact_references: Vec<Pose>,
    qp: WrenchQp,
    /// Minimiser of the QP without its inequalities.
    minimizer: Minimizer,
    /// The torque map's inputs, buffers and results.
    torque_map: TorqueMap,
    /// This tick's `tau(f) = tau_bias + Sigma f` and momentum task `A f = b`.
    terms: TaskTerms,
    /// `s - s_d` (n) [rad].
    posture_error: Vec<f64>,
    /// QP Hessian `P` (k x k) and gradient `c` (k) of `0.5 f^T P f + c^T f`.
    qp_hessian: DMatrix<f64>,
    qp_gradient: DVector<f64>,
    /// The QP's minimiser without inequalities (k).
    unconstrained: DVector<f64>,
    /// `tau* = tau_bias + Sigma f*` (or `beta*`), joint side (n).
    command: DVector<f64>,
    /// `J_G^omega(s_d)` of the integral term.
    momentum_jacobian: MomentumJacobian,
    /// Total mass [kg].
    mass: f64,
    /// The relaxed momentum task's QP (no equality rows; two feet, see [`MomentumRelaxation`]).
    relaxed_qp: WrenchQp,
    /// The relaxed QP's solution (k).
    relaxed_wrenches: DVector<f64>,
    /// Ticks solved by the relaxed momentum task.
    relaxations: usize,
    /// The external wrench the dynamics take as acting on the base, about the CoM, world axes
    /// [N, Nm] ([`crate::external_wrench`]; zero unless set).
    external_wrench: Vector6<f64>,
    /// The generalized disturbance `d^` the dynamics take in every row (nv; empty: none,
    /// [`crate::generalized_disturbance`]).
    generalized_disturbance: DVector<f64>,
    /// The wrench about the CoM (world axes) of the generalized disturbance's base rows at the
    /// last tick, which the momentum task's contact wrenches carry (zero: none).
    disturbance_wrench: Vector6<f64>,
    /// The robot's CoM less the model's (world) [m] that the CoM position error takes
    /// ([`MomentumController::set_com_offset`]; zero: none).
    com_offset: Vector3<f64>,
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
        settings.validate(n)?;
        let mut data = Data::new(model);
        let (contact_frames, contact_references) =
            resolve_contacts(model, &mut data, &settings.contacts, q0)?;
        let n_contacts = contact_frames.len();
        let k = 6 * n_contacts;
        let equalities = if n_contacts > 1 { 6 } else { 0 };
        let mut torque_map = TorqueMap::new(model, k);
        inertia_diagonal(&settings, actuation, &mut torque_map.diagonal);
        let mut qp = WrenchQp::new(n_contacts, equalities, &settings.constraints);
        qp.unconstrained_first = settings.qp_unconstrained_first;
        qp.solver = settings.qp_solver;
        let mut relaxed_qp = WrenchQp::new(n_contacts, 0, &settings.constraints);
        relaxed_qp.solver = settings.qp_solver;
        Ok(Self {
            model: model.clone(),
            data,
            actuation: actuation.clone(),
            estimates: controller_estimates(
                actuation,
                settings.stiffness_estimate_scale,
                settings.damping_estimate_scale,
                &settings.stiffness_estimate_joint_scales,
            ),
            qp,
            minimizer: Minimizer::new(k, equalities),
            torque_map,
            terms: TaskTerms::new(n, n_contacts),
            posture_error: vec![0.0; n],
            qp_hessian: DMatrix::zeros(k, k),
            qp_gradient: DVector::zeros(k),
            unconstrained: DVector::zeros(k),
            command: DVector::zeros(n),
            momentum_jacobian: MomentumJacobian::new(model, k),
            mass: model.total_mass(),
            relaxed_qp,
            relaxed_wrenches: DVector::zeros(k),
            relaxations: 0,
            external_wrench: Vector6::zeros(),
            generalized_disturbance: DVector::zeros(0),
            disturbance_wrench: Vector6::zeros(),
            com_offset: Vector3::zeros(),
            settings,
            contact_frames,
            contact_references,
        })
    }

    /// QP solves that fell back to the unconstrained solution so far (the relaxed momentum
    /// task's rescues not counted).
    pub fn qp_failures(&self) -> usize {
        self.qp.counters().fallbacks - self.relaxations
    }

    /// Ticks whose momentum equality was infeasible and that the relaxed momentum task solved
    /// ([`MomentumRelaxation::WhenInfeasible`]).
    pub fn qp_relaxations(&self) -> usize {
        self.relaxations
    }

    /// QP solves so far by path: the minimiser without inequalities (feasible, hence
    /// optimal), the active set, Clarabel.
    pub fn qp_solves(&self) -> QpCounters {
        self.qp.counters()
    }

    /// Turns the QP cross-check on or off: every tick the active set solves is also solved by
    /// Clarabel, the agreement kept in [`Self::qp_agreement`] (for tests; costs a Clarabel
    /// solve per tick).
    pub fn set_qp_cross_check(&mut self, on: bool) {
        self.qp.cross_check = on;
    }

    /// Active-set solves that failed (and went to Clarabel) so far, and why the last one did.
    pub fn qp_active_set_failures(&self) -> (usize, Option<crate::active_set::ActiveSetError>) {
        (
            self.qp.counters().active_set_failures,
            self.qp.last_active_set_failure(),
        )
    }

    /// The QP cross-check's figures so far (see [`Self::set_qp_cross_check`]).
    pub fn qp_agreement(&self) -> &QpAgreement {
        &self.qp.agreement
    }

    /// The controller's actuation (the plant's, true parameters).
    pub fn actuation(&self) -> &Actuation {
        &self.actuation
    }

    /// The controller's elastic parameter estimates (n_e, order of the actuation's elastic
    /// joints): true stiffness and damping times the settings' scales.
    pub fn estimates(&self) -> &[ElasticParameters] {
        &self.estimates
    }

    /// The controller's robot model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The rigid-body workspace after the last tick: kinematics, body velocities and
    /// inertias, bias forces `h` (in `tau`, gravity included, no spring terms) and `M` at the
    /// tick's `q` and `nu` (plus the contact frames' Jacobian buffers). What a plant with an
    /// equal model can adopt instead of recomputing them at the same state.
    pub fn model_data(&self) -> &Data {
        &self.data
    }

    /// The contact terms of the last tick (factor of the controller's `M + diag`, `J`,
    /// `Jdot nu`, `J M^-1 J^T`), for a plant at the same state with the same model, diagonal
    /// and contacts.
    pub fn factored_contacts(&self) -> sea_dyn::tree_factor::FactoredContacts<'_> {
        self.torque_map.factored_contacts(&self.contact_frames)
    }

    /// The contact frames, in the order of the wrenches.
    pub fn contact_frames(&self) -> &[FrameId] {
        &self.contact_frames
    }

    /// Settings.
    pub fn settings(&self) -> &ControllerSettings {
        &self.settings
    }

    /// What the controller adds to the diagonal of its `M` (nv) [kg m^2]: zero on the base,
    /// `joint_inertia_regularization` on the joints plus, for the rigid controller with
    /// `reflected_inertia`, each elastic joint's motor reflected inertia. Its dynamics are
    /// `(M + diag) nudot + h`; an observer of what they miss uses the same.
    pub fn inertia_diagonal(&self) -> &[f64] {
        &self.torque_map.diagonal
    }

    /// The external wrench (about the CoM, world axes) [N, Nm] that the dynamics of the next
    /// ticks take as acting on the floating base, e.g. an observer's estimate
    /// ([`crate::external_wrench`]); zero: none (the paper's controller).
    pub fn set_external_wrench(&mut self, wrench: &Vector6<f64>) {
        self.external_wrench = *wrench;
    }

    /// The generalized disturbance `d^` (nv) [N, Nm] that the dynamics of the next ticks take
    /// (bias forces `h - d^`), e.g. an observer's estimate
    /// ([`crate::generalized_disturbance`]); empty or zero: none (the paper's controller).
    ///
    /// # Errors
    /// `InvalidArgument` when `disturbance` is neither empty nor of size nv.
    pub fn set_generalized_disturbance(&mut self, disturbance: &DVector<f64>) -> Result<()> {
        let nv = self.model.nv();
        if !disturbance.is_empty() && disturbance.len() != nv {
            return Err(sea_dyn::Error::InvalidArgument {
                argument: "generalized disturbance".into(),
                expected: format!("shape ({nv},)"),
                actual: format!("({},)", disturbance.len()),
            }
            .into());
        }
        self.generalized_disturbance.clone_from(disturbance);
        if disturbance.is_empty() {
            self.disturbance_wrench = Vector6::zeros();
        }
        Ok(())
    }

    /// The robot's CoM less the model's, `offset` (world) [m], that the CoM position error of
    /// the next ticks takes (the momentum task's integral term: the robot's CoM is brought to
    /// the reference, while the momentum and its map stay the model's, about its CoM), e.g. an
    /// observer's estimate ([`crate::generalized_disturbance`]); zero: none.
    pub fn set_com_offset(&mut self, offset: &Vector3<f64>) {
        self.com_offset = *offset;
    }

    /// The generalized disturbance the dynamics take (nv; empty: none).
    pub fn generalized_disturbance(&self) -> &DVector<f64> {
        &self.generalized_disturbance
    }

    /// The momentum map `A` (6 x k, paper hDot) of the last tick.
    pub fn momentum_map(&self) -> &DMatrix<f64> {
        &self.terms.momentum_map
    }

    /// The robot's mass in the controller's model [kg].
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// An output sized for this controller, for [`Self::compute_into`].
    pub fn new_output(&self) -> ControlOutput {
        let (n, n_motor_velocities, k) = self.output_sizes();
        ControlOutput::new(n, n_motor_velocities, k / 6)
    }

    /// Computes the control at plant state `x` (layout `layout`) for the CoM reference and the
    /// desired posture `s_desired` (n). Convenience wrapper of [`Self::compute_into`] that
    /// allocates the output.
    pub fn compute(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
    ) -> Result<ControlOutput> {
        let mut out = self.new_output();
        self.compute_into(x, layout, reference, s_desired, &mut out)?;
        Ok(out)
    }

    /// One controller tick (see the module doc) into `out`, which should come from
    /// [`Self::new_output`]: then it allocates nothing (except Clarabel's own work, the first
    /// Clarabel solve that builds the solver, and the message of a failed solve). Recomputes
    /// `J_G^omega(s_d)` only when `s_desired` changes.
    pub fn compute_into(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
        out: &mut ControlOutput,
    ) -> Result<()> {
        let (com, momentum) = self.task_terms(x, layout, reference, s_desired)?;
        self.fit_output(out);
        out.qp_status = self.solve_qp(&mut out.wrenches);
        copy_contiguous(&mut self.command, &self.terms.tau_bias);
        self.command
            .gemv(1.0, &self.terms.sigma, &out.wrenches, 1.0);
        self.plant_input(out);
        out.com = com;
        out.momentum = momentum;
        out.external_wrench = self.external_wrench + self.disturbance_wrench;
        Ok(())
    }

    /// Resizes `out` if it was not made by [`Self::new_output`] (allocates only then).
    fn fit_output(&self, out: &mut ControlOutput) {
        let sizes = (
            out.input.len(),
            out.thetadot_desired.len(),
            out.wrenches.len(),
        );
        if sizes != self.output_sizes() || out.joint_command.len() != sizes.0 {
            *out = self.new_output();
        }
    }

    /// `(n, n_motor_velocities, k)` of [`Self::new_output`]: desired motor velocities only for
    /// the SEA controller.
    fn output_sizes(&self) -> (usize, usize, usize) {
        let n_motor_velocities = match self.settings.kind {
            ControllerKind::Sea => self.actuation.n_elastic(),
            ControllerKind::Rigid => 0,
        };
        (
            self.model.n_joints(),
            n_motor_velocities,
            6 * self.contact_frames.len(),
        )
    }

    /// The QP of this tick (inputTorquesSOT / inputTorquesSOTu): builds the objective, the
    /// minimiser without inequalities, and solves into `wrenches` (k).
    fn solve_qp(&mut self, wrenches: &mut DVector<f64>) -> QpStatus {
        let terms = &self.terms;
        let reg = self.settings.qp_regularization;
        let (hessian, gradient) = (&mut self.qp_hessian, &mut self.qp_gradient);
        let two_feet = self.contact_frames.len() > 1;
        let found = if two_feet {
            torque_norm_objective(&terms.sigma, &terms.tau_bias, reg, hessian, gradient);
            add_moment_regularization(hessian, self.settings.qp_moment_regularization);
            self.minimizer.equality_constrained(
                hessian,
                gradient,
                &terms.momentum_map,
                &terms.momentum_target,
                &mut self.unconstrained,
            )
        } else {
            let (a, b) = (&terms.momentum_map, &terms.momentum_target);
            momentum_tracking_objective(a, b, reg, hessian, gradient);
            self.minimizer
                .unconstrained(hessian, gradient, &mut self.unconstrained)
        };
        let equality = two_feet.then_some((&terms.momentum_map, &terms.momentum_target));
        let status = self.qp.solve(
            hessian,
            gradient,
            equality,
            &terms.contact_rotations,
            found.then_some(&self.unconstrained),
            wrenches,
        );
        let relax = self.settings.momentum_relaxation == MomentumRelaxation::WhenInfeasible;
        match status {
            QpStatus::Fallback(_) if two_feet && relax => {
                self.solve_relaxed(wrenches).unwrap_or(status)
            }
            _ => status,
        }
    }

    /// The relaxed momentum task of an infeasible two-feet tick into `wrenches` (k):
    /// `MomentumRelaxed`, or `None` (wrenches untouched) when it fails too.
    fn solve_relaxed(&mut self, wrenches: &mut DVector<f64>) -> Option<QpStatus> {
        let terms = &self.terms;
        let (hessian, gradient) = (&mut self.qp_hessian, &mut self.qp_gradient);
        relaxed_momentum_objective(
            (&terms.momentum_map, &terms.momentum_target),
            (&terms.sigma, &terms.tau_bias),
            RelaxedMomentumWeights::default(),
            self.settings.qp_regularization,
            hessian,
            gradient,
        );
        let relaxed = &mut self.relaxed_wrenches;
        let status = self.relaxed_qp.solve(
            hessian,
            gradient,
            None,
            &terms.contact_rotations,
            None,
            relaxed,
        );
        let solved = status == QpStatus::Solved;
        if solved {
            wrenches.copy_from(relaxed);
            self.relaxations += 1;
        }
        solved.then_some(QpStatus::MomentumRelaxed)
    }

    /// Maps the joint-side command `self.command` to the plant input in `out`: rigid joints
    /// take it as torque; elastic joints the desired motor velocity (SEA, inputDesMotVel) or
    /// the motor torque (rigid controller, remark1).
    fn plant_input(&self, out: &mut ControlOutput) {
        let command = self.command.as_slice();
        out.joint_command.copy_from_slice(command);
        out.input.copy_from_slice(command);
        let elastic = self.actuation.elastic_joints.iter().zip(&self.estimates);
        for (e, (&j, estimate)) in elastic.enumerate() {
            match self.settings.kind {
                ControllerKind::Sea => {
                    let velocity = desired_motor_velocity(estimate, command[j]);
                    out.input[j] = velocity;
                    out.thetadot_desired[e] = velocity;
                }
                ControllerKind::Rigid => out.input[j] = rigid_motor_torque(estimate, command[j]),
            }
        }
    }

    /// Model terms, the torque map and the momentum task at the state, into `self.terms`
    /// (after `J_G^omega(s_d)`, recomputed only when `s_desired` changed); returns the CoM [m]
    /// and the centroidal momentum.
    fn task_terms(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
    ) -> Result<(Vector3<f64>, Vector6<f64>)> {
        self.momentum_jacobian.update(
            &self.model,
            &mut self.data,
            &self.contact_frames,
            &self.contact_references[0],
            s_desired,
        )?;
        let (com, momentum) = self.model_terms(x, layout);
        self.contact_terms(&com);
        let (s, sdot) = (layout.s(x), layout.sdot(x));
        for (e, value) in self.posture_error.iter_mut().enumerate() {
            *value = s[e] - s_desired[e];
        }
        let posture = PosturalTask {
            error: &self.posture_error,
            velocity: sdot,
            stiffness: &self.settings.postural_stiffness,
            damping: &self.settings.postural_damping,
        };
        let map = &mut self.torque_map;
        map.compute(&self.data.mass_matrix, &posture, self.settings.pinv_damping)?;
        copy_contiguous(&mut self.terms.tau_bias, &map.tau_bias);
        copy_contiguous(&mut self.terms.sigma, &map.sigma);
        self.momentum_target(reference, com, &momentum);
        Ok((com, momentum))
    }

    /// `M` (in `data`), `h` into the torque map (SEA controller: with hjBar in the joint rows;
    /// less the external wrench's generalized force in the base rows when one is set; less the
    /// generalized disturbance in every row when one is set, whose base rows' wrench about the
    /// CoM it keeps for the momentum target), the CoM [m, world] and the centroidal momentum
    /// at the state.
    fn model_terms(&mut self, x: &[f64], layout: &StateLayout) -> (Vector3<f64>, Vector6<f64>) {
        let model = &self.model;
        let (q, nu) = (layout.q(x), layout.nu(x));
        let data = &mut self.data;
        let map = &mut self.torque_map;
        // One kinematic pass: the bias forces leave the body velocities and inertias the
        // momentum needs; CRBA reuses the placements.
        copy_contiguous(&mut map.bias, sea_dyn::bias_forces(model, data, q, nu));
        let momentum = sea_dyn::centroidal_momentum_from_dynamics(data);
        let com = data.p_base_world + data.p_com_rel;
        if self.external_wrench != Vector6::zeros() {
            let force = base_generalized_force(&self.external_wrench, &data.p_com_rel);
            map.bias.rows_mut(0, 6).axpy(-1.0, &force, 1.0);
        }
        if !self.generalized_disturbance.is_empty() {
            map.bias -= &self.generalized_disturbance;
            let d = &self.generalized_disturbance;
            let at_base = Force::new(d.fixed_rows::<3>(0).into(), d.fixed_rows::<3>(3).into());
            self.disturbance_wrench = at_base.moment_about(&data.p_com_rel).to_vector();
        }
        sea_dyn::crba_after_rnea(model, data);
        if self.settings.kind == ControllerKind::Sea {
            subtract_spring_torque(
                &mut map.bias,
                &self.actuation.elastic_joints,
                &self.estimates,
                layout.theta(x),
                layout.s(x),
                layout.sdot(x),
            );
        }
        (com, momentum)
    }

    /// Contact Jacobians and `Jdot nu` into the torque map, the sole rotations and the contact
    /// blocks of the momentum map `A` (hDot) into `self.terms`, for the CoM `com` [m, world].
    fn contact_terms(&mut self, com: &Vector3<f64>) {
        let (model, data) = (&self.model, &mut self.data);
        let map = &mut self.torque_map;
        for (c, &frame) in self.contact_frames.iter().enumerate() {
            sea_dyn::jacobian::frame_jacobian_into_rows(
                model,
                data,
                frame,
                &mut map.jacobian,
                6 * c,
            );
            // `bias_forces` ran at this state earlier in the tick.
            let bias =
                sea_dyn::jacobian::frame_bias_acceleration_after_bias_forces(model, data, frame);
            map.jdot_nu.fixed_rows_mut::<6>(6 * c).copy_from(&bias);
            let pose = sea_dyn::frame_placement(model, data, frame);
            self.terms.contact_rotations[c] = pose.rotation;
            set_momentum_map_contact(&mut self.terms.momentum_map, c, &pose.translation, com);
        }
    }

    /// `b = Hdot* - [m g; 0] - w_d` into `self.terms.momentum_target` (hDot, eq:dotH_f,
    /// eq:IhTilde; `w_d` the generalized disturbance's wrench about the CoM, zero without one),
    /// the CoM position error taken at the robot's CoM (`set_com_offset`).
    fn momentum_target(
        &mut self,
        reference: &ComSample,
        com: Vector3<f64>,
        momentum: &Vector6<f64>,
    ) {
        let m = self.mass;
        let (desired, desired_rate) = desired_momentum(m, reference);
        // The position error is the robot's CoM's (`set_com_offset`); the momentum and its map
        // stay the model's, about its CoM.
        let integral = momentum_integral_error(
            m,
            &(com + self.com_offset),
            &reference.position,
            &self.momentum_jacobian.angular,
            &self.posture_error,
        );
        let hdot_star = momentum_rate_star(
            &desired_rate,
            &(momentum - desired),
            &integral,
            &self.settings.momentum_proportional,
            &self.settings.momentum_integral,
        );
        let mut target = momentum_equality_target(&hdot_star, m, &self.model.gravity);
        // The feet carry what the model misses (`crate::generalized_disturbance`).
        target -= self.disturbance_wrench;
        self.terms.momentum_target.copy_from(&target);
    }

    /// The torque map and momentum task at a state (what the QP of [`Self::compute`] uses).
    /// For checks: allocates the returned copy.
    pub fn torque_map(
        &mut self,
        x: &[f64],
        layout: &StateLayout,
        reference: &ComSample,
        s_desired: &[f64],
    ) -> Result<TaskTerms> {
        self.task_terms(x, layout, reference, s_desired)?;
        Ok(self.terms.clone())
    }
}
