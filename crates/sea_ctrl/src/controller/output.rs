//! A tick's outputs and how the tick fills them: [`ControlOutput`] (the plant input, the QP
//! wrenches, the CoM, the momentum), [`TaskTerms`] (`tau(f) = tau_bias + Sigma f`, eq:torques
//! with posturalNew, and the momentum task `A f = b`, hDot with eq:dotH_f), and the map of the
//! joint-side command to the plant input: rigid joints `tau*`, elastic joints the desired motor
//! velocity (SEA controller, inputDesMotVel) or the motor torque `Gamma tau*` (rigid
//! controller, remark1).

use super::settings::ControllerKind;
use super::MomentumController;
use crate::momentum::momentum_map_identity_blocks;
use crate::qp::QpStatus;
use crate::sea::{desired_motor_velocity, rigid_motor_torque};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

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
    pub(super) fn new(n: usize, n_contacts: usize) -> Self {
        Self {
            tau_bias: DVector::zeros(n),
            sigma: DMatrix::zeros(n, 6 * n_contacts),
            momentum_map: momentum_map_identity_blocks(n_contacts),
            momentum_target: DVector::zeros(6),
            contact_rotations: vec![Matrix3::identity(); n_contacts],
        }
    }
}

impl MomentumController {
    /// Resizes `out` if it was not made by [`Self::new_output`] (allocates only then).
    pub(super) fn fit_output(&self, out: &mut ControlOutput) {
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
    pub(super) fn output_sizes(&self) -> (usize, usize, usize) {
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

    /// Maps the joint-side command `self.command` to the plant input in `out`: rigid joints
    /// take it as torque; elastic joints the desired motor velocity (SEA, inputDesMotVel) or
    /// the motor torque (rigid controller, remark1).
    pub(super) fn plant_input(&self, out: &mut ControlOutput) {
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
}
