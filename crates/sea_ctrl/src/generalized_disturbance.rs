//! The generalized force that the controller's model misses, estimated by inverse dynamics
//! from the encoders, the sensed joint torques and the feet's force/torque sensors, taken
//! into every row of the controller's dynamics.
//!
//! Why (README, "At the robot's rate", model errors): the centroidal observer
//! ([`crate::external_wrench`]) sees a link mass error as a wrench and takes it at the base,
//! where it is not; the joints between keep the error of their gravity torques, which only the
//! weak postural task resists. With every link's mass off by up to 10 % (iCub, one foot, SEA at
//! 100 Hz / 1 kHz) the stance knee then bends until the joint error bound ends the run. The
//! generalized disturbance has a row per coordinate, so each joint gets its own correction.
//!
//! Estimate. With the controller's model (`M^`, `h^`) the robot's motion obeys
//!
//! `M^(q) nudot + h^(q, nu) = S^T tau + sum_c J_c(q)^T f_c + d`
//!
//! (paper eq:system with `d`, nv = 6 + n: base rows in the coordinates of `nu`), where `d`
//! gathers what the model misses: mass and inertia errors, an external wrench on any link,
//! friction. Between the whole-body samples `k - 1` and `k` (period `T`), with the period's
//! mean acceleration `a_k = (nu_k - nu_{k-1}) / T`, the residual
//!
//! `r_k = (ID(q_{k-1}, nu_{k-1}, a_k) + ID(q_k, nu_k, a_k)) / 2 - (g_{k-1}^+ + g_k^-) / 2`
//!
//! (`ID(q, nu, a) = M^(q) a + h^(q, nu)`, RNEA) is the period's mean `d` up to the trapezoid
//! rule, with the applied generalized force `g = S^T tau + sum_c J_c(q)^T f_c` from the
//! measured joint torques `tau` and contact wrenches `f` (world axes at the contact frames'
//! origins) at the period's start, after the command of tick `k - 1` took effect (`g^+`), and
//! at its end, that command still held (`g^-`), as in [`crate::external_wrench`]. The estimate
//! is its first-order low pass with bandwidth `f_c`:
//!
//! `d^_k = d^_{k-1} + a (r_k - d^_{k-1})`, `a = 1 - exp(-2 pi f_c T)`, `d^_0 = 0`.
//!
//! Use ([`crate::controller::MomentumController::set_generalized_disturbance`]): the controller
//! takes `h^ - d^` for its bias forces in every row, so its QP plans with the dynamics that the
//! robot showed over the last periods, and the contacts carry the base rows' wrench (the
//! momentum task's equality less it: a model's weight error is the feet's to carry). A push is
//! then resisted by the feet too, which loses pushes that the centroidal observer's "go with
//! it" recovers (README, model errors).
//!
//! The joint torques `tau` are what the robot senses: an SEA's deflection through the
//! stiffness estimate `K_S^` (the loop computes them, `sea_sim`'s `sense_joint_torques`). A
//! stiffness error then shows as a disturbance `(K_S / K_S^ - 1) tau` in the joint rows, and
//! taking it asks the torque loop for the difference: with `K_S^ = K_S / 2` (no
//! identification) the tracking completes where it falls without the observer; from
//! `2 K_S` the correction, a fixed-point iteration through the low pass, is too slow and the
//! identification is needed (README, "At the robot's rate").

use crate::external_wrench::low_pass_blend;
use nalgebra::DVector;
use sea_dyn::{Data, FrameId, Model};

/// The observer of the generalized disturbance (module doc): its estimate and what it keeps
/// of the previous sample.
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
    /// `(q_{k-1}, nu_{k-1}, g_{k-1}^+)` of the previous sample (`None` before the first).
    previous: Option<(Vec<f64>, Vec<f64>, DVector<f64>)>,
    /// `(tau_k^-, f_k^-)`: the torques (n) and wrenches (6 per contact) at the end of the
    /// period that ends at the next sample.
    period_end: (DVector<f64>, DVector<f64>),
    /// `a_k` (nv) [m/s^2, rad/s^2].
    acceleration: Vec<f64>,
}

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
    /// An observer for the controller's `model`, sampled every `period` [s] with bandwidth
    /// `bandwidth_hz` (`f_c`), both positive.
    pub fn new(model: &Model, period: f64, bandwidth_hz: f64) -> Self {
        let nv = model.nv();
        Self {
            blend: low_pass_blend(bandwidth_hz, period),
            period,
            estimate: DVector::zeros(nv),
            data: Data::new(model),
            previous: None,
            period_end: (DVector::zeros(0), DVector::zeros(0)),
            acceleration: vec![0.0; nv],
        }
    }

    /// The estimate `d^` (module doc) (nv) [N, Nm].
    pub fn estimate(&self) -> &DVector<f64> {
        &self.estimate
    }

    /// The update after the period that starts at sample `k`: the measured configuration `q`
    /// (nq) and velocity `nu` (nv) at sample `k`, the contact frames `contacts` of the
    /// wrenches, the forces measured at the period's start (`at_sample`, after the command)
    /// and end (`at_period_end`, the command still held). Returns the new estimate `d^_k`.
    ///
    /// # Panics
    /// When the sizes do not match `model` and `contacts`.
    pub fn update(
        &mut self,
        (model, contacts): (&Model, &[FrameId]),
        (q, nu): (&[f64], &[f64]),
        at_sample: AppliedForces<'_>,
        at_period_end: AppliedForces<'_>,
    ) -> &DVector<f64> {
        match self.previous.take() {
            Some(previous) => {
                let residual = self.residual((model, contacts), &previous, (q, nu));
                self.estimate += self.blend * (residual - &self.estimate);
            }
            None => sea_dyn::forward_kinematics(model, &mut self.data, q),
        }
        // The placements in `data` are at `q` now.
        let applied_after = applied_generalized_force(
            model,
            &mut self.data,
            contacts,
            at_sample.joint_torques,
            at_sample.contact_wrenches,
        );
        self.previous = Some((q.to_vec(), nu.to_vec(), applied_after));
        self.period_end.0.clone_from(at_period_end.joint_torques);
        self.period_end.1.clone_from(at_period_end.contact_wrenches);
        &self.estimate
    }

    /// `r_k` (module doc) for the previous sample `(q_{k-1}, nu_{k-1}, g_{k-1}^+)` and the
    /// current `(q_k, nu_k)`; leaves the placements at `q_k` in `data`.
    fn residual(
        &mut self,
        (model, contacts): (&Model, &[FrameId]),
        (q_previous, nu_previous, applied_after): &(Vec<f64>, Vec<f64>, DVector<f64>),
        (q, nu): (&[f64], &[f64]),
    ) -> DVector<f64> {
        for ((a, now), before) in self.acceleration.iter_mut().zip(nu).zip(nu_previous) {
            *a = (now - before) / self.period;
        }
        let data = &mut self.data;
        let mut residual =
            sea_dyn::rnea(model, data, q_previous, nu_previous, &self.acceleration).clone();
        residual += sea_dyn::rnea(model, data, q, nu, &self.acceleration);
        residual -= applied_after;
        let (torques, wrenches) = &self.period_end;
        residual -= applied_generalized_force(model, data, contacts, torques, wrenches);
        residual * 0.5
    }
}

/// `g = S^T tau + sum_c J_c^T f_c` (nv): the generalized force of the joint torques `torques`
/// (n) and the contact wrenches `wrenches` (6 per contact of `contacts`) with the frame
/// Jacobians from the placements in `data` (forward kinematics done at the configuration).
fn applied_generalized_force(
    model: &Model,
    data: &mut Data,
    contacts: &[FrameId],
    torques: &DVector<f64>,
    wrenches: &DVector<f64>,
) -> DVector<f64> {
    let mut force = DVector::zeros(model.nv());
    force.rows_mut(6, torques.len()).copy_from(torques);
    for (c, &frame) in contacts.iter().enumerate() {
        sea_dyn::jacobian::frame_jacobian_from_kinematics(model, data, frame);
        let wrench = wrenches.fixed_rows::<6>(6 * c);
        force.gemv_tr(1.0, &data.frame_jacobian, &wrench, 1.0);
    }
    force
}
