//! The model terms of a tick at the plant state, into the torque map and [`TaskTerms`]: `M`
//! and `h` (SEA controller: hjBar, `h_j - p`, [`crate::sea`]; the observers' corrections of
//! `disturbances.rs`), the contact Jacobians and `Jdot nu` (eq:constraints_acc), the CoM
//! and the centroidal momentum `H`; the contact blocks of the momentum map `A` (hDot); the
//! torque map `tau(f) = tau_bias + Sigma f` ([`crate::torque_map`], eq:torques with
//! posturalNew); the momentum target `b = Hdot* - [m g; 0]` ([`crate::momentum`], eq:dotH_f
//! with the integral term of eq:IhTilde). Also the diagonal the controller adds to its `M`
//! (remark1, eq:equivRigidSystem).

use super::output::TaskTerms;
use super::settings::{ControllerKind, ControllerSettings};
use super::MomentumController;
use crate::error::Result;
use crate::momentum::{
    desired_momentum, momentum_equality_target, momentum_integral_error, momentum_rate_star,
    set_momentum_map_contact,
};
use crate::references::ComSample;
use crate::sea::subtract_spring_torque;
use crate::torque_map::PosturalTask;
use nalgebra::{Vector3, Vector6};
use sea_dyn::dense::copy_contiguous;
use sea_dyn::{Actuation, StateLayout};
// Named by the doc comments only.
#[cfg(doc)]
use sea_dyn::ElasticParameters;

/// What the controller adds to the diagonal of its `M` (nv): the joint regularisation and, for
/// the rigid controller with `reflected_inertia`, the motor reflected inertia of each elastic
/// joint (remark1, [`ElasticParameters::reflected_inertia`]).
pub(super) fn inertia_diagonal(
    settings: &ControllerSettings,
    actuation: &Actuation,
    diagonal: &mut [f64],
) {
    for value in &mut diagonal[6..] {
        *value = settings.tuning.joint_inertia_regularization;
    }
    if settings.kind == ControllerKind::Rigid && settings.tuning.reflected_inertia {
        for (&j, p) in actuation.elastic_joints.iter().zip(&actuation.elastic) {
            diagonal[6 + j] += p.reflected_inertia();
        }
    }
}

impl MomentumController {
    /// Model terms, the torque map and the momentum task at the state, into `self.terms`
    /// (after `J_G^omega(s_d)`, recomputed only when `s_desired` changed); returns the CoM [m]
    /// and the centroidal momentum.
    pub(super) fn task_terms(
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
        if self.walking.is_some() {
            self.contact_accelerations(layout.nu(x));
        }
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
        map.compute(
            &self.data.mass_matrix,
            &posture,
            self.settings.tuning.pinv_damping,
        )?;
        copy_contiguous(&mut self.terms.tau_bias, &map.tau_bias);
        copy_contiguous(&mut self.terms.sigma, &map.sigma);
        self.momentum_target(reference, com, &momentum);
        if let Some(redundant) = &mut self.redundant {
            let map = &self.torque_map;
            redundant.update(
                map.lambda_t(),
                map.contact_schur(),
                map.task_bias(),
                &self.terms.momentum_map,
                &self.terms.momentum_target,
            );
        }
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
        self.disturbances
            .correct_bias(&mut map.bias, &data.p_com_rel);
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

    /// Walking: each contact's desired acceleration into the torque map at the tick's
    /// placements (`contact_phase.rs`), with the generalized velocity `nu`.
    fn contact_accelerations(&mut self, nu: &[f64]) {
        for c in 0..self.contact_frames.len() {
            let frame = self.contact_frames[c];
            let pose = sea_dyn::frame_placement(&self.model, &self.data, frame);
            self.set_contact_acceleration(c, &pose, nu);
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
            &self.disturbances.robot_com(com),
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
        self.disturbances.carry(&mut target);
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
