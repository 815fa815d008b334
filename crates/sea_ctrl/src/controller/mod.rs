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
//!    two feet `min |tau(f)|^2` s.t. `A f = b` (a redundant contact set, `Lambda` of lower
//!    rank than `J`: the equalities of [`crate::redundant_contacts`]); both s.t. the contact
//!    constraints
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
//!
//! The module by concern:
//! - `settings.rs`: [`ControllerKind`], [`MomentumRelaxation`], [`ControllerSettings`] and
//!   their check;
//! - `tuning.rs`: [`ControllerTuning`], the settings as a user writes them (a scenario's
//!   `[controller]` keys);
//! - `output.rs`: [`ControlOutput`], [`TaskTerms`] and step 5, the plant input
//!   (inputDesMotVel, remark1);
//! - `model_terms.rs`: steps 1 to 3, the model terms, the torque map and the momentum target
//!   (hjBar, hDot, eq:dotH_f, eq:IhTilde, eq:torques, posturalNew);
//! - `qp_solve.rs`: step 4, the QP (inputTorquesSOT / inputTorquesSOTu, frictionCones) and the
//!   relaxed momentum task;
//! - `disturbances.rs`: the external wrench, the generalized disturbance and the CoM offset
//!   that observers set, and how they enter the dynamics and the momentum task;
//! - `contact_phase.rs`, `stepping.rs`: walking's contact phases and stepping to recover a
//!   push;
//! - this file: [`MomentumController`], its construction, the tick and the accessors.

mod contact_phase;
mod disturbances;
mod model_terms;
mod output;
mod qp_solve;
mod settings;
mod step_adjustment;
mod stepping;
mod touchdown_debounce;
mod tuning;

pub use contact_phase::{
    settle_acceleration, share_penalty, swing_acceleration, LATE_TOUCHDOWN_SPEED,
    MAX_SHARE_PENALTY, TOUCHDOWN_FORCE_FRACTION,
};
pub use output::{ControlOutput, TaskTerms};
pub use settings::{ControllerKind, ControllerSettings, MomentumRelaxation};
pub use tuning::ControllerTuning;

use crate::error::{Error, Result};
use crate::momentum::MomentumJacobian;
use crate::qp::{Minimizer, QpAgreement, QpCounters, WrenchQp};
use crate::redundant_contacts::RedundantContacts;
use crate::references::ComSample;
use crate::sea::controller_estimates;
use crate::torque_map::TorqueMap;
use disturbances::Disturbances;
use model_terms::inertia_diagonal;
use nalgebra::{DMatrix, DVector};
use sea_dyn::dense::copy_contiguous;
use sea_dyn::spatial::Pose;
use sea_dyn::{Actuation, Data, ElasticParameters, FrameId, Model, StateLayout};

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
    /// The external wrench, generalized disturbance and CoM offset that observers set, and
    /// the generalized disturbance's wrench of the last tick (`disturbances.rs`).
    disturbances: Disturbances,
    /// Two feet whose `Lambda` has a lower rank than `J` (legs of 5 joints): the QP's
    /// equalities restricted to the wrenches the joints can produce
    /// ([`crate::redundant_contacts`]); `None` in the paper's case.
    redundant: Option<RedundantContacts>,
    /// Walking: the gait, the tick's foot tasks and the single-support QP
    /// ([`Self::set_walking`]; `contact_phase.rs`); `None`: the contacts are held throughout.
    walking: Option<contact_phase::ContactPhases>,
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
        let mut torque_map = TorqueMap::new(model, k);
        inertia_diagonal(&settings, actuation, &mut torque_map.diagonal);
        let redundant = (n_contacts > 1)
            .then(|| {
                RedundantContacts::at_posture(
                    model,
                    &mut data,
                    &contact_frames,
                    q0,
                    &torque_map.diagonal,
                )
            })
            .flatten();
        let equalities = match (&redundant, n_contacts > 1) {
            (Some(redundant), _) => redundant.n_rows(),
            (None, true) => 6,
            (None, false) => 0,
        };
        let mut qp = WrenchQp::new(n_contacts, equalities, &settings.constraints);
        qp.unconstrained_first = settings.tuning.qp_unconstrained_first;
        qp.solver = settings.tuning.qp_solver;
        let mut relaxed_qp = WrenchQp::new(n_contacts, 0, &settings.constraints);
        relaxed_qp.solver = settings.tuning.qp_solver;
        Ok(Self {
            model: model.clone(),
            data,
            actuation: actuation.clone(),
            estimates: controller_estimates(
                actuation,
                settings.tuning.stiffness_estimate_scale,
                settings.tuning.damping_estimate_scale,
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
            disturbances: Disturbances::new(),
            redundant,
            walking: None,
            settings,
            contact_frames,
            contact_references,
        })
    }

    /// QP solves that fell back to the unconstrained solution so far (the relaxed momentum
    /// task's rescues not counted).
    pub fn qp_failures(&self) -> usize {
        self.qp_solves().fallbacks - self.relaxations
    }

    /// Ticks whose momentum equality was infeasible and that the relaxed momentum task solved
    /// ([`MomentumRelaxation::WhenInfeasible`]).
    pub fn qp_relaxations(&self) -> usize {
        self.relaxations
    }

    /// QP solves so far by path: the minimiser without inequalities (feasible, hence
    /// optimal), the active set, Clarabel.
    pub fn qp_solves(&self) -> QpCounters {
        self.qp.counters() + self.single_support_counters()
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

    /// The momentum map `A` (6 x k, paper hDot) of the last tick.
    pub fn momentum_map(&self) -> &DMatrix<f64> {
        &self.terms.momentum_map
    }

    /// Whether the two-feet contact set is redundant (`Lambda` of lower rank than `J`, legs of
    /// 5 joints): the QP then uses [`crate::redundant_contacts`]'s equalities.
    pub fn redundant_contacts(&self) -> bool {
        self.redundant.is_some()
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
        out.external_wrench = self.disturbances.total_wrench();
        Ok(())
    }
}
