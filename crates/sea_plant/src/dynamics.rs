//! Forward dynamics of the plant: one evaluation of the tangent derivative at a state, with
//! the contact wrenches as Lagrange multipliers, and the workspace holding every buffer.

use crate::actuation::{elastic_joint_torque, motor_acceleration, motor_velocity_loop, saturate};
use crate::contact::{contact_terms, sole_margins, WrenchMargins};
use crate::error::{Error, Result};
use crate::plant::{MotorInput, Plant};
use nalgebra::{DMatrix, DVector, Vector3};
use sea_dyn::crba::crba_after_rnea;
use sea_dyn::data::Data;
use sea_dyn::dense::{
    cholesky_in_place, cholesky_solve_in_place, copy_contiguous, gemv_few_rows, gemv_tr_few_rows,
};
use sea_dyn::kinematics::frame_placement;
use sea_dyn::rnea::bias_forces;
use sea_dyn::tree_factor::{FactoredContacts, TreeFactor};
use sea_dyn::StateLayout;

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
    pub(crate) mass_factor: TreeFactor,
    /// Diagonal added to `M` (joint inertia regularisation), then to `M~` (nv).
    pub(crate) diagonal: Vec<f64>,
    /// Stacked contact Jacobian (k x nv).
    pub(crate) contact_jacobian: DMatrix<f64>,
    /// `Y^T = (L^-T J^T)^T` with `M = L^T L` (k x nv: one contiguous k-column per velocity).
    pub(crate) linv_jt_t: DMatrix<f64>,
    /// `J M^-1 J^T`, then its factor (k x k).
    pub(crate) schur: DMatrix<f64>,
    /// Constraint acceleration target, then multipliers (k).
    pub(crate) constraint_rhs: DVector<f64>,
    /// Velocity-sized scratch (nv).
    pub(crate) scratch_v: DVector<f64>,
    /// A second velocity-sized scratch (nv), for the implicit solve's constraint target.
    pub(crate) scratch_v2: DVector<f64>,
    /// Implicit step: factor of `M~` (nv x nv), `J` at the step start (k x nv), `(L~^-T J^T)^T`
    /// (k x nv), Schur factor (k x k), per elastic joint the coefficients of the motor
    /// elimination (n_e).
    pub(crate) w_factor: TreeFactor,
    pub(crate) w_jacobian: DMatrix<f64>,
    pub(crate) w_linv_jt_t: DMatrix<f64>,
    pub(crate) w_schur: DMatrix<f64>,
    pub(crate) w_motor: Vec<crate::integrator::MotorElimination>,
    pub(crate) w_g: f64,
    /// Stage buffers of the integrators (nd each) and a state buffer (nx).
    pub(crate) stage: [DVector<f64>; 4],
    pub(crate) x_stage: Vec<f64>,
    /// Outputs of the step-start evaluation, kept while later stages evaluate elsewhere.
    pub(crate) saved: SavedOutputs,
    /// `[q; nu]` (nq + nv) at which [`PlantData::adopt_model_terms`] gave the model terms in
    /// `data`, and whether they are still unused.
    adopted_state: Vec<f64>,
    adopted: bool,
    /// Whether the factor, `J`, `L^-T J^T` and `J M^-1 J^T` were adopted too
    /// ([`PlantData::adopt_contact_terms`]), with `Jdot nu` here (k).
    adopted_contacts: bool,
    pub(crate) adopted_jdot_nu: DVector<f64>,
}

/// Copies of the evaluation outputs (same sizes as in [`PlantData`]).
#[derive(Clone, Debug)]
pub(crate) struct SavedOutputs {
    pub(crate) xdot: DVector<f64>,
    pub(crate) contact_wrench: DVector<f64>,
    pub(crate) joint_torque: DVector<f64>,
    pub(crate) motor_torque: DVector<f64>,
    pub(crate) saturated: Vec<bool>,
    pub(crate) drift: (f64, f64),
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
            linv_jt_t: DMatrix::zeros(k, nv),
            schur: DMatrix::zeros(k, k),
            constraint_rhs: DVector::zeros(k),
            scratch_v: DVector::zeros(nv),
            scratch_v2: DVector::zeros(nv),
            w_factor: TreeFactor::new(&plant.model),
            w_jacobian: DMatrix::zeros(k, nv),
            w_linv_jt_t: DMatrix::zeros(k, nv),
            w_schur: DMatrix::zeros(k, k),
            w_motor: vec![Default::default(); ne],
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
            adopted_state: vec![0.0; layout.nq + nv],
            adopted: false,
            adopted_contacts: false,
            adopted_jdot_nu: DVector::zeros(k),
        }
    }

    /// Takes the model terms (kinematics, bias forces `h`, `M`) that another user of the same
    /// model computed at `x`'s `q` and `nu` (`data` after `bias_forces` and
    /// `crba_after_rnea`, e.g. the controller's workspace after a tick at this state), so that
    /// the next [`evaluate`] at exactly that `q` and `nu` skips kinematics, RNEA and CRBA. Any
    /// other evaluation drops them. `data` must belong to a model equal to the plant's
    /// (the caller checks, e.g. with `Model`'s `==`). Allocates nothing.
    pub fn adopt_model_terms(&mut self, data: &Data, layout: &StateLayout, x: &[f64]) {
        self.data.copy_model_terms_from(data);
        let nq = layout.nq;
        self.adopted_state[..nq].copy_from_slice(layout.q(x));
        self.adopted_state[nq..].copy_from_slice(layout.nu(x));
        self.adopted = true;
        self.adopted_contacts = false;
    }

    /// After [`PlantData::adopt_model_terms`] at the same state: also takes the contact terms
    /// computed there with a factored `M + diag` (`contacts`, e.g. the controller's), so the
    /// next evaluation skips the factorisation, the contact Jacobians and the Schur complement.
    /// Taken only if the contact frames and the diagonal are the plant's own (bitwise); returns
    /// whether they were. Allocates nothing.
    pub fn adopt_contact_terms(&mut self, plant: &Plant, contacts: &FactoredContacts) -> bool {
        joint_diagonal(plant, &mut self.diagonal);
        let frames_match = contacts.frames.len() == plant.contacts.len()
            && contacts
                .frames
                .iter()
                .zip(&plant.contacts)
                .all(|(&frame, contact)| frame == contact.frame);
        let k = 6 * plant.contacts.len();
        let usable = self.adopted
            && frames_match
            && contacts.diagonal == self.diagonal.as_slice()
            && contacts.jacobian.shape() == self.contact_jacobian.shape()
            && contacts.schur.shape() == (k, k);
        if usable {
            self.mass_factor.copy_values_from(contacts.factor);
            copy_contiguous(&mut self.contact_jacobian, contacts.jacobian);
            copy_contiguous(&mut self.adopted_jdot_nu, contacts.jdot_nu);
            copy_contiguous(&mut self.linv_jt_t, contacts.linv_jt_t);
            copy_contiguous(&mut self.schur, contacts.schur);
        }
        self.adopted_contacts = usable;
        usable
    }

    /// Whether adopted model terms (and contact terms) are waiting for exactly this `q` and
    /// `nu` (bitwise); they are used at most once.
    fn take_adopted_terms(&mut self, q: &[f64], nu: &[f64]) -> (bool, bool) {
        let adopted = std::mem::replace(&mut self.adopted, false);
        let contacts = std::mem::replace(&mut self.adopted_contacts, false);
        let nq = q.len();
        let here = adopted && self.adopted_state[..nq] == *q && self.adopted_state[nq..] == *nu;
        (here, here && contacts)
    }

    /// Saves the outputs of the last evaluation (no allocation).
    pub(crate) fn save_outputs(&mut self) {
        let s = &mut self.saved;
        copy_contiguous(&mut s.xdot, &self.xdot);
        copy_contiguous(&mut s.contact_wrench, &self.contact_wrench);
        copy_contiguous(&mut s.joint_torque, &self.joint_torque);
        copy_contiguous(&mut s.motor_torque, &self.motor_torque);
        s.saturated.copy_from_slice(&self.saturated);
        s.drift = (self.drift_position, self.drift_rotation);
    }

    /// Restores the outputs saved by [`PlantData::save_outputs`].
    pub(crate) fn restore_outputs(&mut self) {
        let s = &self.saved;
        copy_contiguous(&mut self.xdot, &s.xdot);
        copy_contiguous(&mut self.contact_wrench, &s.contact_wrench);
        copy_contiguous(&mut self.joint_torque, &s.joint_torque);
        copy_contiguous(&mut self.motor_torque, &s.motor_torque);
        self.saturated.copy_from_slice(&s.saturated);
        (self.drift_position, self.drift_rotation) = s.drift;
    }

    /// Margins of each contact's last simulated wrench, in its sole frame.
    pub fn wrench_margins(&self, plant: &Plant, x: &[f64]) -> Vec<WrenchMargins> {
        let limits = &plant.contact_limits;
        let mut data = self.data.clone();
        sea_dyn::kinematics::forward_kinematics(&plant.model, &mut data, &x[..plant.model.nq()]);
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

/// Evaluates the dynamics at `x` with input `u`: fills `pd.xdot` (tangent derivative),
/// the contact wrenches, joint and motor torques and the drift. Sizes are not checked here
/// (see [`Plant::check_state`]); a singular mass matrix or contact set is an error.
pub fn evaluate(plant: &Plant, pd: &mut PlantData, x: &[f64], u: &[f64]) -> Result<()> {
    let model = &plant.model;
    let layout = plant.layout();
    let (nq, nv, ne) = (layout.nq, layout.nv, layout.ne);
    let q = &x[..nq];
    let theta = layout.theta(x);
    let nu = layout.nu(x);
    let thetadot = layout.thetadot(x);

    // h(q, nu) into scratch_v (negated below), then M from the same kinematics (unless a
    // user of the same state already computed them: `adopt_model_terms`).
    let (adopted_model, adopted_contacts) = pd.take_adopted_terms(q, nu);
    if !adopted_model {
        bias_forces(model, &mut pd.data, q, nu);
        crba_after_rnea(model, &mut pd.data);
    }
    copy_contiguous(&mut pd.scratch_v, &pd.data.tau);
    joint_diagonal(plant, &mut pd.diagonal);
    if !adopted_contacts {
        pd.mass_factor
            .factor(&pd.data.mass_matrix, &pd.diagonal)
            .map_err(|e| e.during("factorising the mass matrix"))?;
    }

    joint_and_motor_torques(plant, pd, q, theta, nu, thetadot, u);

    // Unconstrained acceleration, kept as L^-T (B tau - h) until the multipliers are known:
    // nudot = L^-1 (L^-T (B tau - h) + Y f), Y = L^-T J^T, S = Y^T Y,
    // f = S^-1 (a_target - Y^T L^-T (B tau - h)).
    pd.scratch_v
        .as_mut_slice()
        .iter_mut()
        .for_each(|v| *v = -*v);
    for j in 0..model.n_joints() {
        pd.scratch_v[6 + j] += pd.joint_torque[j];
    }
    pd.mass_factor.solve_lt(pd.scratch_v.as_mut_slice());
    if !plant.contacts.is_empty() {
        contact_terms(plant, pd, nu, adopted_contacts);
        gemv_few_rows(
            pd.constraint_rhs.as_mut_slice(),
            -1.0,
            &pd.linv_jt_t,
            pd.scratch_v.as_slice(),
            1.0,
        );
        cholesky_in_place(&mut pd.schur).map_err(|i| {
            Error::numerical(
                "solving for the contact wrenches",
                format!("contact constraints are degenerate (Schur complement pivot {i})"),
            )
        })?;
        cholesky_solve_in_place(&pd.schur, pd.constraint_rhs.as_mut_slice());
        gemv_tr_few_rows(
            pd.scratch_v.as_mut_slice(),
            1.0,
            &pd.linv_jt_t,
            pd.constraint_rhs.as_slice(),
            1.0,
        );
        copy_contiguous(&mut pd.contact_wrench, &pd.constraint_rhs);
    }
    pd.mass_factor.solve_l(pd.scratch_v.as_mut_slice());

    let nd = layout.nd();
    // Slice copies: nalgebra's row views copy entry by entry (see `dense::copy_contiguous`).
    let xdot = pd.xdot.as_mut_slice();
    xdot[..nv].copy_from_slice(nu);
    xdot[nv..nv + ne].copy_from_slice(thetadot);
    xdot[nv + ne..2 * nv + ne].copy_from_slice(pd.scratch_v.as_slice());
    for e in 0..ne {
        let p = &plant.actuation.elastic[e];
        let j = plant.actuation.elastic_joints[e];
        xdot[2 * nv + ne + e] = motor_acceleration(p, pd.motor_torque[e], pd.joint_torque[j]);
    }
    debug_assert_eq!(2 * nv + 2 * ne, nd);
    Ok(())
}

/// The joint inertia regularisation on the joint diagonal (nv; base entries zero).
pub(crate) fn joint_diagonal(plant: &Plant, diagonal: &mut [f64]) {
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
        if matches!(actuator, sea_dyn::actuator::Actuator::Rigid) {
            pd.joint_torque[j] = u[j];
        }
    }
    for (e, (&j, p)) in actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .enumerate()
    {
        let tau = elastic_joint_torque(p, theta[e], thetadot[e], q[7 + j], nu[6 + j]);
        pd.joint_torque[j] = tau;
        let demanded = match plant.motor_input {
            MotorInput::Torque => u[j],
            MotorInput::VelocityLoop { gain } => {
                motor_velocity_loop(p, gain, thetadot[e], u[j], tau)
            }
        };
        let (torque, saturated) = saturate(p, demanded);
        pd.motor_torque[e] = torque;
        pd.saturated[e] = saturated;
    }
}
