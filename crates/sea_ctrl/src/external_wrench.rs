//! The unmodelled external wrench on the robot (a push, a hand on it), estimated from the
//! centroidal momentum and the feet's measured contact wrenches, and how the controller's
//! dynamics take it.
//!
//! Why (README, "At the robot's rate", pushes): the controller's joint torques produce its
//! planned contact wrenches only if its dynamics hold. A push it does not know is carried by
//! the feet (the joint torques are fixed over the period, so the contact constraints take the
//! push), and a 0.1 s sideways push of 75 N on the iCub's pelvis moves a sole's centre of
//! pressure past its edge while the CoM has moved 5 mm. Known, the push needs no resisting:
//! its impulse can become momentum, which the momentum task brings back afterwards with the
//! centres of pressure the QP allows (the capture-point picture).
//!
//! Estimate (a discrete momentum observer). The centroidal momentum obeys (paper hDot with an
//! external wrench `w` about the CoM, world axes) `Hdot = A f + [m g; 0] + w`. Between the
//! whole-body samples `k - 1` and `k` (period `T`), the residual
//!
//! `r_k = (H_k - H_{k-1}) / T - (A_{k-1} f_{k-1} + A_k f_k) / 2 - [m g; 0]`
//!
//! is the period's mean external wrench up to the trapezoid rule on the contact term, with `f`
//! measured by the feet's force/torque sensors (the iCub has them). The estimate is its
//! first-order low pass with bandwidth `f_c`:
//!
//! `w^_k = w^_{k-1} + a (r_k - w^_{k-1})`, `a = 1 - exp(-2 pi f_c T)`, `w^_0 = 0`.
//!
//! A model error shows as a steady estimate (a link mass error `dm`: a vertical force `dm g`
//! with the moment of where it sits), which the use below then compensates at the base.
//!
//! Use ([`base_generalized_force`]): the controller's dynamics take the estimate as a wrench on
//! the floating base, the generalized force `[F; M_com + (p_com - p_O) x F]` in the base rows
//! (world axes at the base origin `O`, the coordinates of `nu`), zero in the joint rows; the
//! momentum task is unchanged (the feet are not asked to resist it). A wrench on another link
//! is taken as if on the base: its effect on the joints between is not compensated.

use nalgebra::{DMatrix, DVectorView, Vector3, Vector6};

/// The observer of the external wrench (module doc): its estimate and the previous sample.
#[derive(Clone, Debug)]
pub struct ExternalWrenchObserver {
    /// `a = 1 - exp(-2 pi f_c T)` of the low pass.
    blend: f64,
    /// The whole-body period `T` [s].
    period: f64,
    /// `w^` [N, Nm] about the CoM, world axes.
    estimate: Vector6<f64>,
    /// `(H, A f)` of the previous sample (`None` before the first).
    previous: Option<(Vector6<f64>, Vector6<f64>)>,
}

impl ExternalWrenchObserver {
    /// An observer sampled every `period` [s] with bandwidth `bandwidth_hz` (`f_c`), both
    /// positive.
    pub fn new(period: f64, bandwidth_hz: f64) -> Self {
        Self {
            blend: 1.0 - (-2.0 * std::f64::consts::PI * bandwidth_hz * period).exp(),
            period,
            estimate: Vector6::zeros(),
            previous: None,
        }
    }

    /// The estimate `w^` (module doc) [N, Nm], about the CoM, world axes.
    pub fn estimate(&self) -> &Vector6<f64> {
        &self.estimate
    }

    /// One sample: the centroidal momentum `momentum` (`H`, world axes), the momentum map
    /// `momentum_map` (`A`, 6 x k, paper hDot) and the measured contact wrenches `wrenches`
    /// (k) at the sample, the robot's weight `weight` (`m g`, world) [N]. Returns the new
    /// estimate.
    pub fn update(
        &mut self,
        momentum: &Vector6<f64>,
        momentum_map: &DMatrix<f64>,
        wrenches: &[f64],
        weight: &Vector3<f64>,
    ) -> &Vector6<f64> {
        let mut contact_rate = Vector6::zeros();
        let wrenches = DVectorView::from_slice(wrenches, wrenches.len());
        contact_rate.gemv(1.0, momentum_map, &wrenches, 0.0);
        if let Some((previous_momentum, previous_rate)) = &self.previous {
            let mut residual =
                (momentum - previous_momentum) / self.period - 0.5 * (contact_rate + previous_rate);
            residual.fixed_rows_mut::<3>(0).axpy(-1.0, weight, 1.0);
            self.estimate += self.blend * (residual - self.estimate);
        }
        self.previous = Some((*momentum, contact_rate));
        &self.estimate
    }
}

/// The generalized force (base rows, 6) of the wrench `wrench_com` [N, Nm] about the CoM
/// (world axes) acting on the floating base: `[F; M_com + p_com_rel x F]`, with `p_com_rel`
/// the CoM relative to the base origin `O` (world axes) [m] (module doc, use).
pub fn base_generalized_force(wrench_com: &Vector6<f64>, p_com_rel: &Vector3<f64>) -> Vector6<f64> {
    let force = wrench_com.fixed_rows::<3>(0).into_owned();
    let moment = wrench_com.fixed_rows::<3>(3) + p_com_rel.cross(&force);
    Vector6::new(force.x, force.y, force.z, moment.x, moment.y, moment.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A free body pushed by a constant wrench with no contact: the estimate converges to it
    /// at the low pass's rate.
    #[test]
    fn a_constant_wrench_on_a_free_body_is_estimated_at_the_low_pass_rate() {
        let (period, mass) = (0.01, 30.0);
        let weight = Vector3::new(0.0, 0.0, -9.81 * mass);
        let push = Vector6::new(40.0, -20.0, 5.0, 1.0, 2.0, -3.0);
        let mut observer = ExternalWrenchObserver::new(period, 5.0);
        let (map, wrenches) = (DMatrix::zeros(6, 6), [0.0; 6]);
        let mut momentum = Vector6::zeros();
        let blend = 1.0 - (-2.0 * std::f64::consts::PI * 5.0 * period).exp();
        for k in 0..40 {
            let estimate = *observer.update(&momentum, &map, &wrenches, &weight);
            let expected = if k == 0 {
                0.0
            } else {
                1.0 - (1.0 - blend).powi(k)
            };
            assert!(
                (estimate - push * expected).norm() < 1e-9 * push.norm(),
                "sample {k}"
            );
            let mut rate = push;
            rate.fixed_rows_mut::<3>(0).axpy(1.0, &weight, 1.0);
            momentum += rate * period;
        }
    }

    /// Standing still, the feet carry the weight exactly: no external wrench.
    #[test]
    fn the_weight_carried_by_the_feet_is_no_external_wrench() {
        let weight = Vector3::new(0.0, 0.0, -300.0);
        let mut observer = ExternalWrenchObserver::new(0.01, 1000.0);
        let map = crate::momentum::momentum_map_identity_blocks(1);
        let wrenches = [0.0, 0.0, 300.0, 0.0, 0.0, 0.0];
        for _ in 0..3 {
            observer.update(&Vector6::zeros(), &map, &wrenches, &weight);
        }
        assert!(observer.estimate().norm() < 1e-12);
    }

    #[test]
    fn a_force_at_the_com_has_the_moment_of_its_arm_about_the_base() {
        let wrench = Vector6::new(10.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        let p_com_rel = Vector3::new(0.0, 0.0, 0.2);
        let force = base_generalized_force(&wrench, &p_com_rel);
        // (0, 0, 0.2) x (10, 0, 0) = (0, 2, 0).
        assert_eq!(force, Vector6::new(10.0, 0.0, 0.0, 0.0, 2.0, 1.0));
    }
}
