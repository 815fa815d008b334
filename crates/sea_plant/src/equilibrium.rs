//! Static equilibrium of the plant: the joint torques that hold a configuration at rest with
//! the contacts carrying the base, and the motor angles whose springs transmit them (so that a
//! run starts in equilibrium).

use crate::error::Result;
use crate::plant::Plant;
use sea_dyn::data::Data;
use sea_dyn::model::{FrameId, Model};

/// Static joint torques (n) holding `q` at rest with the contact frames `contacts` taking the
/// base wrench: with `g(q)` the gravity forces and `J` the stacked contact Jacobians, the
/// least-norm contact wrenches `f = (J_b^T)^+ g_b` balance the base and the joints supply
/// `tau = g_s - J_s^T f` (zero wrenches if the pseudo-inverse fails).
pub fn static_torques(model: &Model, q: &[f64], contacts: &[FrameId]) -> Vec<f64> {
    let mut data = Data::new(model);
    let gravity = sea_dyn::gravity_forces(model, &mut data, q).clone();
    let n = model.n_joints();
    let mut jacobian = nalgebra::DMatrix::zeros(6 * contacts.len(), model.nv());
    for (c, &frame) in contacts.iter().enumerate() {
        jacobian
            .rows_mut(6 * c, 6)
            .copy_from(sea_dyn::frame_jacobian(model, &mut data, q, frame));
    }
    let jb_t = jacobian.columns(0, 6).transpose();
    let f = jb_t
        .clone()
        .pseudo_inverse(1e-12)
        .map(|p| p * gravity.rows(0, 6))
        .unwrap_or_else(|_| nalgebra::DVector::zeros(6 * contacts.len()));
    let torques = gravity.rows(6, n) - jacobian.columns(6, n).transpose() * f;
    torques.as_slice().to_vec()
}

/// The motor angles (n_e) that make `plant`'s springs hold `q` at rest on its contacts:
/// [`static_torques`] of the plant's contact frames, transmitted by preloaded springs
/// ([`Plant::preloaded_motor_angles`]).
pub fn static_motor_angles(plant: &Plant, q: &[f64]) -> Result<Vec<f64>> {
    plant.model.check_configuration(q)?;
    let frames: Vec<FrameId> = plant.contacts.iter().map(|c| c.frame).collect();
    let torques = static_torques(&plant.model, q, &frames);
    plant.preloaded_motor_angles(q, &torques)
}
