//! Forward dynamics of the plant: one evaluation of the tangent derivative at a state, with
//! the contact wrenches as Lagrange multipliers. It fills its own [`Workspace`] stage by stage
//! (model terms, mass factor, torques, contact terms, accelerations) and writes the outputs
//! into the [`PlantOutputs`] its caller gives.

use crate::actuation::{elastic_joint_torque, motor_acceleration, motor_velocity_loop, saturate};
use crate::compliant_forces::{add_contact_forces, add_stop_torques};
use crate::contact::constraint_acceleration;
use crate::error::{Error, Result};
use crate::plant::{MotorInput, Plant};
use crate::workspace::{PlantOutputs, Workspace};
use sea_dyn::crba::crba_after_rnea;
use sea_dyn::data::Data;
use sea_dyn::dense::{
    cholesky_in_place, cholesky_solve_in_place, copy_contiguous, gemv_few_rows, gemv_tr_few_rows,
};
use sea_dyn::jacobian::{
    frame_bias_acceleration_after_bias_forces, frame_jacobian_into_rows,
    frame_velocity_from_kinematics,
};
use sea_dyn::kinematics::frame_placement;
use sea_dyn::rnea::bias_forces;
use sea_dyn::tree_factor::FactoredContacts;
use sea_dyn::StateLayout;

impl Workspace {
    /// Takes the model terms (kinematics, bias forces `h`, `M`) that another user of the same
    /// model computed at `x`'s `q` and `nu` (`data` after `bias_forces` and
    /// `crba_after_rnea`, e.g. the controller's workspace after a tick at this state), so that
    /// the next [`evaluate`] at exactly that `q` and `nu` skips kinematics, RNEA and CRBA. Any
    /// other evaluation drops them. `data` must belong to a model equal to the plant's
    /// (the caller checks, e.g. with `Model`'s `==`). Allocates nothing.
    pub fn adopt_model_terms(&mut self, data: &Data, layout: &StateLayout, x: &[f64]) {
        self.data.copy_model_terms_from(data);
        let nq = layout.nq;
        let adopted = &mut self.adopted;
        adopted.state[..nq].copy_from_slice(layout.q(x));
        adopted.state[nq..].copy_from_slice(layout.nu(x));
        adopted.model = true;
        adopted.contacts = false;
    }

    /// After [`Workspace::adopt_model_terms`] at the same state: also takes the contact terms
    /// computed there with a factored `M + diag` (`contacts`, e.g. the controller's), so the
    /// next evaluation skips the factorisation, the contact Jacobians and the Schur complement.
    /// Taken only if the contact frames and the diagonal are the plant's own (bitwise); returns
    /// whether they were. Allocates nothing.
    pub fn adopt_contact_terms(&mut self, plant: &Plant, contacts: &FactoredContacts) -> bool {
        if plant.unilateral().is_some() {
            self.adopted.contacts = false;
            return false;
        }
        plant.joint_diagonal(&mut self.diagonal);
        let frames_match = contacts.frames.len() == plant.contacts.len()
            && contacts
                .frames
                .iter()
                .zip(&plant.contacts)
                .all(|(&frame, contact)| frame == contact.frame);
        let k = 6 * plant.contacts.len();
        let own = &mut self.contact;
        let usable = self.adopted.model
            && frames_match
            && contacts.diagonal == self.diagonal.as_slice()
            && contacts.jacobian.shape() == own.jacobian.shape()
            && contacts.schur.shape() == (k, k);
        if usable {
            self.mass_factor.copy_values_from(contacts.factor);
            copy_contiguous(&mut own.jacobian, contacts.jacobian);
            copy_contiguous(&mut self.adopted.jdot_nu, contacts.jdot_nu);
            copy_contiguous(&mut own.linv_jt_t, contacts.linv_jt_t);
            copy_contiguous(&mut own.schur, contacts.schur);
        }
        self.adopted.contacts = usable;
        usable
    }

    /// Whether adopted model terms (and contact terms) are waiting for exactly this `q` and
    /// `nu` (bitwise); they are used at most once.
    fn take_adopted_terms(&mut self, q: &[f64], nu: &[f64]) -> (bool, bool) {
        let adopted = &mut self.adopted;
        let model = std::mem::replace(&mut adopted.model, false);
        let contacts = std::mem::replace(&mut adopted.contacts, false);
        let nq = q.len();
        let here = model && adopted.state[..nq] == *q && adopted.state[nq..] == *nu;
        (here, here && contacts)
    }
}

/// The failure to factorise the mass matrix at the state `x`: a state or mass matrix that is
/// not finite (a state too large for floating point, e.g. velocities of 1e300, or an implicit
/// step's stage that diverged) said as such, else the factorisation's own reason.
fn mass_factor_error(error: Error, x: &[f64], mass_matrix: &[f64]) -> Error {
    const OPERATION: &str = "factorising the mass matrix";
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        let detail = format!(
            "the state is not finite (entry {i} is {}): the state or input is too large for \
             floating point, or the step diverged",
            x[i]
        );
        return Error::numerical(OPERATION, detail);
    }
    if mass_matrix.iter().any(|m| !m.is_finite()) {
        let detail = "its entries are not finite: the state is too large for floating point";
        return Error::numerical(OPERATION, detail);
    }
    error.during(OPERATION)
}

/// Evaluates the dynamics at `x` with input `u` into `out`: the tangent derivative `xdot`,
/// the contact wrenches, joint and motor torques, saturation and drift; `ws` holds every
/// intermediate. Sizes are not checked here (see [`Plant::check_state`]); a singular mass
/// matrix or contact set is an error.
pub fn evaluate(
    plant: &Plant,
    ws: &mut Workspace,
    x: &[f64],
    u: &[f64],
    out: &mut PlantOutputs,
) -> Result<()> {
    let model = &plant.model;
    let layout = plant.layout();
    let q = layout.q(x);
    let nu = layout.nu(x);

    // h(q, nu) into `acceleration` (negated below), then M from the same kinematics (unless a
    // user of the same state already computed them: `adopt_model_terms`).
    let (adopted_model, adopted_contacts) = ws.take_adopted_terms(q, nu);
    if !adopted_model {
        bias_forces(model, &mut ws.data, q, nu);
        crba_after_rnea(model, &mut ws.data);
    }
    copy_contiguous(&mut ws.acceleration, &ws.data.tau);
    plant.joint_diagonal(&mut ws.diagonal);
    if !adopted_contacts {
        ws.mass_factor
            .factor(&ws.data.mass_matrix, &ws.diagonal)
            .map_err(|e| mass_factor_error(e, x, ws.data.mass_matrix.as_slice()))?;
    }

    joint_and_motor_torques(plant, &layout, x, u, out);

    // Unconstrained acceleration, kept as L^-T (B tau - h) until the multipliers are known:
    // nudot = L^-1 (L^-T (B tau - h) + Y f), Y = L^-T J^T, S = Y^T Y,
    // f = S^-1 (a_target - Y^T L^-T (B tau - h)).
    let acceleration = ws.acceleration.as_mut_slice();
    acceleration.iter_mut().for_each(|v| *v = -*v);
    for j in 0..model.n_joints() {
        acceleration[6 + j] += out.joint_torque[j];
    }
    crate::external::add_generalized_force(model, &mut ws.data, &ws.external, acceleration);
    add_stop_torques(plant, ws, q, nu, out);
    let unilateral = plant.unilateral();
    if let Some(unilateral) = unilateral {
        add_contact_forces(plant, unilateral, ws, out);
    }
    ws.mass_factor.solve_lt(ws.acceleration.as_mut_slice());
    if !plant.contacts.is_empty() && unilateral.is_none() {
        contact_terms(plant, ws, adopted_contacts, out);
        contact_wrenches(ws, out)?;
    }
    ws.mass_factor.solve_l(ws.acceleration.as_mut_slice());
    tangent_derivative(plant, &layout, x, ws, out);
    copy_contiguous(&mut out.step_contact_wrench, &out.contact_wrench);
    Ok(())
}

/// Spring-damper torques of elastic joints, inputs of rigid joints, and motor torques, into
/// `out`.
fn joint_and_motor_torques(
    plant: &Plant,
    layout: &StateLayout,
    x: &[f64],
    u: &[f64],
    out: &mut PlantOutputs,
) {
    let (q, theta) = (layout.q(x), layout.theta(x));
    let (nu, thetadot) = (layout.nu(x), layout.thetadot(x));
    let actuation = &plant.actuation;
    for (j, actuator) in actuation.actuators.iter().enumerate() {
        if matches!(actuator, sea_dyn::actuator::Actuator::Rigid) {
            out.joint_torque[j] = u[j];
        }
    }
    for (e, (&j, p)) in actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .enumerate()
    {
        let tau = elastic_joint_torque(p, theta[e], thetadot[e], q[7 + j], nu[6 + j]);
        out.joint_torque[j] = tau;
        let demanded = match plant.motor_input {
            MotorInput::Torque => u[j],
            MotorInput::VelocityLoop { gain } => {
                motor_velocity_loop(p, gain, thetadot[e], u[j], tau)
            }
        };
        let (torque, saturated) = saturate(p, demanded);
        out.motor_torque[e] = torque;
        out.saturated[e] = saturated;
    }
}

/// Stage 3: contact Jacobian, `L^-T J^T`, Schur complement and the Baumgarte acceleration
/// target `-(Jdot nu + K_d J nu + K_p e)` (paper eq:constraints_acc, into the workspace's
/// contact target), plus the drift (into `out`). With `adopted`, `J`, `L^-T J^T`, the Schur
/// complement and `Jdot nu` are already in `ws` ([`Workspace::adopt_contact_terms`]); only
/// the pose errors and the target are computed.
fn contact_terms(plant: &Plant, ws: &mut Workspace, adopted: bool, out: &mut PlantOutputs) {
    let model = &plant.model;
    out.drift_position = 0.0;
    out.drift_rotation = 0.0;
    let terms = &mut ws.contact;
    for (c, contact) in plant.contacts.iter().enumerate() {
        let bias = if adopted {
            ws.adopted.jdot_nu.fixed_rows::<6>(6 * c).into_owned()
        } else {
            frame_jacobian_into_rows(model, &ws.data, contact.frame, &mut terms.jacobian, 6 * c);
            // `evaluate` ran `bias_forces` at this state just before.
            frame_bias_acceleration_after_bias_forces(model, &ws.data, contact.frame)
        };
        let pose = frame_placement(model, &ws.data, contact.frame);
        let (position_error, rotation_err) = contact.pose_error(&pose);
        out.drift_position = out.drift_position.max(position_error.norm());
        out.drift_rotation = out.drift_rotation.max(rotation_err.norm());
        // J nu from the body velocities that RNEA's forward pass left (or that were adopted
        // with the model terms) at this state.
        let frame_velocity = frame_velocity_from_kinematics(model, &ws.data, contact.frame);
        for r in 0..6 {
            let error = if r < 3 {
                position_error[r]
            } else {
                rotation_err[r - 3]
            };
            terms.target[6 * c + r] = constraint_acceleration(
                bias[r],
                frame_velocity[r],
                error,
                plant.baumgarte_kd,
                plant.baumgarte_kp,
            );
        }
    }
    if !adopted {
        ws.mass_factor
            .schur_complement(&terms.jacobian, &mut terms.linv_jt_t, &mut terms.schur);
    }
}

/// The multipliers `f = S^-1 (a_target - Y^T L^-T (B tau - h))` (into `out`), and
/// `L^-T (B tau - h) + Y f` in the workspace's accelerations.
fn contact_wrenches(ws: &mut Workspace, out: &mut PlantOutputs) -> Result<()> {
    let terms = &mut ws.contact;
    gemv_few_rows(
        terms.target.as_mut_slice(),
        -1.0,
        &terms.linv_jt_t,
        ws.acceleration.as_slice(),
        1.0,
    );
    cholesky_in_place(&mut terms.schur).map_err(|i| {
        Error::numerical(
            "solving for the contact wrenches",
            format!("contact constraints are degenerate (Schur complement pivot {i})"),
        )
    })?;
    cholesky_solve_in_place(&terms.schur, terms.target.as_mut_slice());
    gemv_tr_few_rows(
        ws.acceleration.as_mut_slice(),
        1.0,
        &terms.linv_jt_t,
        terms.target.as_slice(),
        1.0,
    );
    copy_contiguous(&mut out.contact_wrench, &terms.target);
    Ok(())
}

/// Stage 4's result into `out.xdot = [nu; thetadot; nudot; thetaddot]`, the motor
/// accelerations from paper eq:motors.
fn tangent_derivative(
    plant: &Plant,
    layout: &StateLayout,
    x: &[f64],
    ws: &Workspace,
    out: &mut PlantOutputs,
) {
    // Slice copies: nalgebra's row views copy entry by entry (see `dense::copy_contiguous`).
    let xdot = layout.tangent().split_mut(out.xdot.as_mut_slice());
    xdot.dq.copy_from_slice(layout.nu(x));
    xdot.dtheta.copy_from_slice(layout.thetadot(x));
    xdot.dnu.copy_from_slice(ws.acceleration.as_slice());
    let actuation = &plant.actuation;
    for (e, (thetaddot, p)) in xdot
        .dthetadot
        .iter_mut()
        .zip(&actuation.elastic)
        .enumerate()
    {
        let j = actuation.elastic_joints[e];
        *thetaddot = motor_acceleration(p, out.motor_torque[e], out.joint_torque[j]);
    }
}
