//! The generalized force that the controller's model misses, estimated by inverse dynamics
//! from the encoders, the sensed joint torques and the feet's force/torque sensors, taken
//! into every row of the controller's dynamics.
//!
//! Why (docs/findings/model_errors.md): the centroidal observer
//! ([`crate::external_wrench`]) sees a link mass error as a wrench and takes it at the base,
//! where it is not; the joints between keep the error of their gravity torques, which only the
//! weak postural task resists. With every link's mass off by up to 10 % (iCub, one foot, SEA at
//! 100 Hz / 1 kHz) the stance knee then bends until the joint error bound ends the run. The
//! generalized disturbance has a row per coordinate, so each joint gets its own correction.
//!
//! Estimate. With the controller's model (`M^`, `h^`) the robot's motion obeys
//!
//! `(M^(q) + D) nudot + h^(q, nu) = S^T tau + sum_c J_c(q)^T f_c + d`
//!
//! (paper eq:system with `d`, nv = 6 + n: base rows in the coordinates of `nu`; `D` the
//! diagonal the controller adds to its `M`, [`MomentumController::inertia_diagonal`], so that
//! `d` is what the controller's own dynamics miss; for the rigid controller with
//! `reflected_inertia` it holds the motors' reflected inertia, a model error of a loop whose
//! commands are the springs' torques (the multi-rate joint loops) but not of one whose commands
//! are motor torques, which the sensed spring torques do not show), where `d`
//! gathers what the model misses: mass and inertia errors, an external wrench on any link,
//! friction. Between the whole-body samples `k - 1` and `k` (period `T`), with the period's
//! mean acceleration `a_k = (nu_k - nu_{k-1}) / T`, the residual
//!
//! `r_k = (ID(q_{k-1}, nu_{k-1}, a_k) + ID(q_k, nu_k, a_k)) / 2 - (g_{k-1}^+ + g_k^-) / 2`
//!
//! (`ID(q, nu, a) = (M^(q) + D) a + h^(q, nu)`: RNEA plus `D a`) is the period's mean `d` up
//! to the trapezoid rule, with the applied generalized force `g = S^T tau + sum_c J_c(q)^T f_c` from the
//! measured joint torques `tau` and contact wrenches `f` (world axes at the contact frames'
//! origins) at the period's start, after the command of tick `k - 1` took effect (`g^+`), and
//! at its end, that command still held (`g^-`), as in [`crate::external_wrench`]. The loop
//! updates it at sample `k` once the period that starts there has shown `g_k^+` (its first
//! plant step); `g_k^-` is what the sensors read at the end of the period before. The
//! estimate is its first-order low pass with bandwidth `f_c`:
//!
//! `d^_k = d^_{k-1} + a (r_k - d^_{k-1})`, `a = 1 - exp(-2 pi f_c T)`, `d^_0 = 0`.
//!
//! Use ([`crate::controller::MomentumController::set_generalized_disturbance`]): the controller
//! takes `h^ - d^` for its bias forces in every row, so its QP plans with the dynamics that the
//! robot showed over the last periods, and the contacts carry the base rows' wrench (the
//! momentum task's equality less it: a model's weight error is the feet's to carry). A push is
//! then resisted by the feet too, which loses pushes that the centroidal observer's "go with
//! it" recovers (docs/findings/model_errors.md).
//!
//! The joint torques `tau` are what the robot senses: an SEA's deflection through the
//! stiffness estimate `K_S^` (the loop computes them, `sea_sim`'s `sense_joint_torques`). A
//! stiffness error then shows as a disturbance `(K_S / K_S^ - 1) tau` in the joint rows, and
//! taking it asks the torque loop for the difference: with `K_S^ = K_S / 2` (no
//! identification) the tracking completes where it falls without the observer; from
//! `2 K_S` the correction, a fixed-point iteration through the low pass, is too slow and the
//! identification is needed (docs/findings/robot_rate.md).

use crate::controller::MomentumController;
use crate::external_wrench::low_pass_blend;
use nalgebra::{DVector, Vector3, Vector6};
use sea_dyn::spatial::Force;
use sea_dyn::{Data, FrameId, Model};

/// The observer of the generalized disturbance (module doc): its estimate and what it keeps
/// of the previous sample. Allocation-free after [`GeneralizedDisturbanceObserver::new`].
#[derive(Clone, Debug)]
pub struct GeneralizedDisturbanceObserver {
    /// `a = 1 - exp(-2 pi f_c T)` of the low pass.
    blend: f64,
    /// The whole-body period `T` [s].
    period: f64,
    /// `d^` (nv) [N, Nm].
    estimate: DVector<f64>,
    /// The controller model's kinematics and dynamics buffers.
    data: Data,
    /// `D` (nv) [kg m^2] (module doc).
    inertia_diagonal: Vec<f64>,
    /// Whether a sample came before (the `previous` buffers hold it).
    has_previous: bool,
    /// `q_{k-1}` (nq) of the previous sample.
    q_previous: Vec<f64>,
    /// `nu_{k-1}` (nv) of the previous sample.
    nu_previous: Vec<f64>,
    /// `g_{k-1}^+` (nv) of the previous sample.
    applied_after_previous: DVector<f64>,
    /// `g_k^-` (nv) of this update.
    applied_before: DVector<f64>,
    /// `a_k` (nv) [m/s^2, rad/s^2].
    acceleration: Vec<f64>,
    /// `r_k` (nv) of this update.
    residual: DVector<f64>,
    /// The low pass's blend of the CoM offset ([`COM_OFFSET_BANDWIDTH_HZ`]).
    offset_blend: f64,
    /// The robot's CoM less the model's, horizontal, low-passed (world) [m].
    com_offset: Vector3<f64>,
}

/// The bandwidth of the CoM offset's low pass [Hz] (module doc, CoM offset): the offset is a
/// property of the posture, and the disturbance's moment is noisy with noisy encoders.
pub const COM_OFFSET_BANDWIDTH_HZ: f64 = 1.0;

/// What the sensors read at one end of a period: the joint torques (n) [Nm] and the contact
/// wrenches (6 per contact, `[force; moment]` at the contact frame's origin, world axes).
#[derive(Clone, Copy, Debug)]
pub struct AppliedForces<'a> {
    /// Joint torques `tau` (n) [Nm].
    pub joint_torques: &'a DVector<f64>,
    /// Contact wrenches `f` (6 per contact) [N, Nm].
    pub contact_wrenches: &'a DVector<f64>,
}

impl GeneralizedDisturbanceObserver {
    /// An observer of what `controller`'s dynamics miss (its model and its
    /// [`MomentumController::inertia_diagonal`]), sampled every `period` [s] with bandwidth
    /// `bandwidth_hz` (`f_c`), both positive.
    pub fn new(controller: &MomentumController, period: f64, bandwidth_hz: f64) -> Self {
        let model = controller.model();
        let nv = model.nv();
        Self {
            blend: low_pass_blend(bandwidth_hz, period),
            period,
            estimate: DVector::zeros(nv),
            data: Data::new(model),
            inertia_diagonal: controller.inertia_diagonal().to_vec(),
            has_previous: false,
            q_previous: vec![0.0; model.nq()],
            nu_previous: vec![0.0; nv],
            applied_after_previous: DVector::zeros(nv),
            applied_before: DVector::zeros(nv),
            acceleration: vec![0.0; nv],
            residual: DVector::zeros(nv),
            offset_blend: low_pass_blend(COM_OFFSET_BANDWIDTH_HZ, period),
            com_offset: Vector3::zeros(),
        }
    }

    /// The estimate `d^` (module doc) (nv) [N, Nm].
    pub fn estimate(&self) -> &DVector<f64> {
        &self.estimate
    }

    /// The robot's CoM less the model's (horizontal, world) [m] that the estimate's base rows
    /// show ([`com_offset`] at the last sample, low-passed at [`COM_OFFSET_BANDWIDTH_HZ`]).
    pub fn com_offset(&self) -> &Vector3<f64> {
        &self.com_offset
    }

    /// The update at sample `k`, once the period that starts there has shown its first forces:
    /// the measured configuration `q` (nq) and velocity `nu` (nv) at sample `k`, the contact
    /// frames `contacts` of the wrenches, the forces measured at the end of the period that
    /// ends at sample `k` (`before`: `g_k^-`, the previous command still held) and at the start
    /// of the one that begins there (`after`: `g_k^+`, after this sample's command). Returns
    /// the new estimate `d^_k` (the first update only keeps the sample).
    ///
    /// # Panics
    /// When the sizes do not match `model` and `contacts`.
    pub fn update(
        &mut self,
        (model, contacts): (&Model, &[FrameId]),
        (q, nu): (&[f64], &[f64]),
        before: AppliedForces<'_>,
        after: AppliedForces<'_>,
    ) -> &DVector<f64> {
        if self.has_previous {
            self.residual((model, contacts), (q, nu), before);
            self.estimate
                .axpy(self.blend, &self.residual, 1.0 - self.blend);
            self.update_com_offset(model);
        } else {
            sea_dyn::forward_kinematics(model, &mut self.data, q);
        }
        // The placements in `data` are at `q` now.
        let after_force = &mut self.applied_after_previous;
        applied_generalized_force(model, &mut self.data, contacts, after, after_force);
        self.q_previous.copy_from_slice(q);
        self.nu_previous.copy_from_slice(nu);
        self.has_previous = true;
        &self.estimate
    }

    /// The CoM offset's low pass with the estimate's base rows as a wrench about the model's
    /// CoM at the sample (RNEA at it just ran: the body inertias are in `data`).
    fn update_com_offset(&mut self, model: &Model) {
        sea_dyn::centroidal_momentum_from_dynamics(&mut self.data);
        let d = &self.estimate;
        let at_base = Force::new(d.fixed_rows::<3>(0).into(), d.fixed_rows::<3>(3).into());
        let about_com = at_base.moment_about(&self.data.p_com_rel).to_vector();
        let offset = com_offset(&about_com, model.total_mass(), &model.gravity);
        self.com_offset += self.offset_blend * (offset - self.com_offset);
    }

    /// `r_k` (module doc) into `self.residual` from the previous sample's buffers, the current
    /// `(q_k, nu_k)` and `g_k^-` from `before`; leaves the placements at `q_k` in `data`.
    fn residual(
        &mut self,
        (model, contacts): (&Model, &[FrameId]),
        (q, nu): (&[f64], &[f64]),
        before: AppliedForces<'_>,
    ) {
        let velocities = nu.iter().zip(&self.nu_previous);
        for (a, (now, then)) in self.acceleration.iter_mut().zip(velocities) {
            *a = (now - then) / self.period;
        }
        let (data, previous) = (&mut self.data, (&self.q_previous, &self.nu_previous));
        let start = sea_dyn::rnea(model, data, previous.0, previous.1, &self.acceleration);
        self.residual.copy_from(start);
        self.residual += sea_dyn::rnea(model, data, q, nu, &self.acceleration);
        // `D a` of both ends.
        let diagonal = self.inertia_diagonal.iter().zip(&self.acceleration);
        for (r, (d, a)) in self.residual.iter_mut().zip(diagonal) {
            *r += 2.0 * d * a;
        }
        self.residual -= &self.applied_after_previous;
        applied_generalized_force(model, data, contacts, before, &mut self.applied_before);
        self.residual -= &self.applied_before;
        self.residual *= 0.5;
    }
}

/// The horizontal offset [m] of the robot's CoM from the model's that a static disturbance
/// wrench `wrench` about the model's CoM (world axes; the base rows' wrench) shows, for the
/// model's `mass` [kg] and `gravity` [m/s^2]: the robot's weight `W = m g + F` acts at the
/// offset `r`, so `M = r x W`, and the part of `r` normal to `W` is `W x M / |W|^2` (the part
/// along gravity has no moment). Zero when `W` vanishes.
pub fn com_offset(wrench: &Vector6<f64>, mass: f64, gravity: &Vector3<f64>) -> Vector3<f64> {
    let weight = gravity * mass + wrench.fixed_rows::<3>(0);
    let moment = wrench.fixed_rows::<3>(3).into_owned();
    let norm_squared = weight.norm_squared();
    if norm_squared > 0.0 {
        weight.cross(&moment) / norm_squared
    } else {
        Vector3::zeros()
    }
}

/// `g = S^T tau + sum_c J_c^T f_c` (nv) into `force`: the generalized force of the joint
/// torques and contact wrenches `forces` (6 per contact of `contacts`) with the frame
/// Jacobians from the placements in `data` (forward kinematics done at the configuration).
fn applied_generalized_force(
    model: &Model,
    data: &mut Data,
    contacts: &[FrameId],
    forces: AppliedForces<'_>,
    force: &mut DVector<f64>,
) {
    force.fill(0.0);
    let torques = forces.joint_torques;
    force.rows_mut(6, torques.len()).copy_from(torques);
    for (c, &frame) in contacts.iter().enumerate() {
        sea_dyn::jacobian::frame_jacobian_from_kinematics(model, data, frame);
        let wrench = forces.contact_wrenches.fixed_rows::<6>(6 * c);
        force.gemv_tr(1.0, &data.frame_jacobian, &wrench, 1.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A model 2 kg light whose CoM is 4 mm beside and 3 mm below the robot's: the wrench the
    /// model misses about its CoM is the robot's weight with its moment; the offset found is
    /// the horizontal part, the vertical one does not show.
    #[test]
    fn the_com_offset_is_the_horizontal_arm_of_the_missing_weight() {
        let (gravity, model_mass, robot_mass) = (Vector3::new(0.0, 0.0, -9.81), 30.0, 32.0);
        let offset = Vector3::new(0.0, 4e-3, 3e-3);
        let robot_weight = gravity * robot_mass;
        let force = robot_weight - gravity * model_mass;
        let moment = offset.cross(&robot_weight);
        let wrench = Vector6::new(force.x, force.y, force.z, moment.x, moment.y, moment.z);
        let found = com_offset(&wrench, model_mass, &gravity);
        assert!(
            (found - Vector3::new(0.0, 4e-3, 0.0)).norm() < 1e-15,
            "{found}"
        );
        assert_eq!(
            com_offset(&Vector6::zeros(), 0.0, &gravity),
            Vector3::zeros()
        );
    }
}
