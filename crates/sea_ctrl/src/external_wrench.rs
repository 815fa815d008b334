//! The unmodelled external wrench on the robot (a push, a hand on it), estimated from the
//! centroidal momentum and the feet's measured contact wrenches, and how the controller's
//! dynamics take it.
//!
//! Why (docs/findings/pushes.md): the controller's joint torques produce its
//! planned contact wrenches only if its dynamics hold. A push it does not know is carried by
//! the feet (the joint torques are fixed over the period, so the contact constraints take the
//! push): on the iCub standing on two feet (the push scenario, SEA at 100 Hz / 1 kHz) a 0.1 s
//! sideways push of 85 N on the pelvis tips the lightly loaded sole during the push; told the
//! push, the feet carry the planned wrenches (to 1e-5 at the initial state), its impulse
//! becomes momentum, which the momentum task brings back afterwards with the centres of
//! pressure the QP allows (the capture-point picture), and the same push is recovered.
//!
//! Estimate (a discrete momentum observer). The centroidal momentum obeys (paper hDot with an
//! external wrench `w` about the CoM, world axes) `Hdot = A f + [m g; 0] + w`. Between the
//! whole-body samples `k - 1` and `k` (period `T`), the residual
//!
//! `r_k = (H_k - H_{k-1}) / T - (Hdot(f_{k-1}^+) + Hdot(f_k^-)) / 2`
//!
//! (`Hdot(f)` of paper hDot, [`crate::momentum::momentum_rate`], with that sample's `A`) is the
//! period's mean external wrench up to the trapezoid rule on the contact term, with the
//! contact wrenches `f` measured by the feet's force/torque sensors (the iCub has them) over
//! the period: `f_{k-1}^+` at its start, after the command of tick `k - 1` took effect, and
//! `f_k^-` at its end, with that command still held (the two differ at a sample when the
//! contact forces follow the command at once: rigid joints under torque control). When the
//! stack reads the sensors through the period and averages them
//! ([`crate::robot::PeriodSensors::mean_contact_wrench`]; the simulated loop does, over its
//! plant steps), that mean `f_bar` takes the place of both, and the residual is the period's
//! mean external wrench exactly (the contact term is linear in `f`). The two instants alone
//! alias a contact that bounces within the period: a landed foot whose force alternates
//! between 0 and 130 N from one 10 ms sample to the next makes the trapezoid miss the contact
//! impulse, and walk_push.toml with the observer and no push then ends on its CoM error at
//! 4.2 s; with the mean it walks its ten steps (docs/findings/walking.md). The estimate is its
//! first-order low pass with bandwidth `f_c`:
//!
//! `w^_k = w^_{k-1} + a (r_k - w^_{k-1})`, `a = 1 - exp(-2 pi f_c T)`, `w^_0 = 0`.
//!
//! The loop updates it after the period that starts at sample `k` (once `f_{k+1}^-` is
//! measured) and the controller takes it from tick `k + 1` on: the push of a period acts on
//! the controller two ticks later, before the low pass's own lag (`1 / (2 pi f_c)`, 32 ms at
//! the push scenario's 5 Hz). A model error shows as a steady estimate (a link mass error
//! `dm`: a vertical force `dm g` with the moment of where it sits), taken at the base where it
//! is not (docs/findings/model_errors.md: per-link mass errors fare worse with the observer).
//!
//! Use ([`base_generalized_force`]): the controller's dynamics take the estimate as a wrench on
//! the floating base, the generalized force `[F; M_com + (p_com - p_O) x F]` in the base rows
//! (world axes at the base origin `O`, the coordinates of `nu`), zero in the joint rows; the
//! momentum task is unchanged (the feet are not asked to resist it). A wrench on another link
//! is taken as if on the base: its effect on the joints between is not compensated.

use crate::momentum::momentum_rate;
use nalgebra::{DMatrix, DVector, Vector3, Vector6};
use sea_dyn::spatial::Force;

/// The default bandwidth `f_c` of the estimate's low pass [Hz]: the best of 2, 3, 5, 8 and
/// 12 Hz for pushes on the iCub (docs/references.md, "External wrench observer").
pub const DEFAULT_BANDWIDTH_HZ: f64 = 5.0;

/// What the controller knows of an unmodelled external wrench; with the `serde` feature,
/// named "none", "observed" or "generalized".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum ExternalWrench {
    /// Nothing: its dynamics have no external wrench (the paper's controller; the default).
    #[default]
    None,
    /// Estimated from the centroidal momentum and the feet's force/torque sensors (in
    /// simulation: the plant's contact wrenches at the sample), taken as acting on the base
    /// ([`ExternalWrenchObserver`]).
    Observed,
    /// The generalized force the controller's model misses (link mass errors, a wrench on any
    /// link), estimated by inverse dynamics from the encoders, the joint torque sensors and the
    /// feet's force/torque sensors (`crate::generalized_disturbance`), taken into every row
    /// of the dynamics.
    Generalized,
}

/// The observer of the unmodelled external wrench as a user sets it. With the `serde`
/// feature, the keys `external_wrench` and `external_wrench_bandwidth_hz` of a scenario's
/// `[controller]`, each checked as it is read (`sea_dyn::bounded`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct ExternalWrenchSettings {
    /// The unmodelled external wrench (a push): "none" (the paper's controller; the default)
    /// or "observed" (estimated each whole-body period from the centroidal momentum and the
    /// feet's measured contact wrenches, and taken into the controller's dynamics as a wrench
    /// on the base; `sea_ctrl::external_wrench`) or "generalized" (the generalized force the
    /// model misses, link mass errors included, estimated by inverse dynamics and taken into
    /// every row of the dynamics; `sea_ctrl::generalized_disturbance`). Needs sampling
    /// "zero_order_hold" or "multi_rate".
    #[cfg_attr(feature = "serde", serde(rename = "external_wrench"))]
    pub kind: ExternalWrench,
    /// `external_wrench` "observed" or "generalized": bandwidth `f_c` of the estimate's low
    /// pass [Hz] (default `sea_ctrl::external_wrench::DEFAULT_BANDWIDTH_HZ`, 5 Hz).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "external_wrench_bandwidth_hz",
            deserialize_with = "sea_dyn::bounded::Positive::read"
        ),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub bandwidth_hz: f64,
}

impl Default for ExternalWrenchSettings {
    /// No observer; when one is set, [`DEFAULT_BANDWIDTH_HZ`].
    fn default() -> Self {
        Self {
            kind: ExternalWrench::None,
            bandwidth_hz: DEFAULT_BANDWIDTH_HZ,
        }
    }
}

/// The observer of the external wrench (module doc): its estimate and what it keeps of the
/// previous sample.
#[derive(Clone, Debug)]
pub struct ExternalWrenchObserver {
    /// `a = 1 - exp(-2 pi f_c T)` of the low pass.
    blend: f64,
    /// The whole-body period `T` [s].
    period: f64,
    /// `w^` [N, Nm] about the CoM, world axes.
    estimate: Vector6<f64>,
    /// `(H_{k-1}, Hdot(f_{k-1}^+))` of the previous sample (`None` before the first).
    previous: Option<(Vector6<f64>, Vector6<f64>)>,
    /// `f_k^-`: the wrenches at the end of the period that ends at the next sample (6 per
    /// contact; empty before the first update).
    period_end_wrenches: DVector<f64>,
}

impl ExternalWrenchObserver {
    /// An observer sampled every `period` [s] with bandwidth `bandwidth_hz` (`f_c`), both
    /// positive.
    pub fn new(period: f64, bandwidth_hz: f64) -> Self {
        Self {
            blend: low_pass_blend(bandwidth_hz, period),
            period,
            estimate: Vector6::zeros(),
            previous: None,
            period_end_wrenches: DVector::zeros(0),
        }
    }

    /// The estimate `w^` (module doc) [N, Nm], about the CoM, world axes.
    pub fn estimate(&self) -> &Vector6<f64> {
        &self.estimate
    }

    /// The update after the period that starts at sample `k`: the centroidal momentum
    /// `momentum` (`H_k`, world axes) and the momentum map `momentum_map` (`A` at sample `k`, 6
    /// x 6 n_c, paper hDot) of its tick, the measured contact wrenches `at_sample` (`f_k^+`,
    /// 6 n_c) at its start and `at_period_end` (`f_{k+1}^-`) at its end, the mass [kg] and
    /// gravity (world) [m/s^2] of the model. Returns the new estimate `w^_k`.
    ///
    /// # Panics
    /// When the wrenches' sizes are not `momentum_map`'s columns.
    pub fn update(
        &mut self,
        (momentum, momentum_map): (&Vector6<f64>, &DMatrix<f64>),
        at_sample: &DVector<f64>,
        at_period_end: &DVector<f64>,
        (mass, gravity): (f64, &Vector3<f64>),
    ) -> &Vector6<f64> {
        let rate = |wrenches: &DVector<f64>| momentum_rate(momentum_map, wrenches, mass, gravity);
        let rate_after = rate(at_sample);
        if let Some((previous_momentum, previous_rate_after)) = &self.previous {
            let rate_before = rate(&self.period_end_wrenches);
            let residual = (momentum - previous_momentum) / self.period
                - 0.5 * (previous_rate_after + rate_before);
            self.estimate += self.blend * (residual - self.estimate);
        }
        self.previous = Some((*momentum, rate_after));
        self.period_end_wrenches.clone_from(at_period_end);
        &self.estimate
    }
}

/// The blend `a = 1 - exp(-2 pi f_c T)` of a first-order low pass with bandwidth
/// `bandwidth_hz` (`f_c`) sampled every `period` (`T`) [s]: `y_k = y_{k-1} + a (u_k - y_{k-1})`.
pub fn low_pass_blend(bandwidth_hz: f64, period: f64) -> f64 {
    1.0 - (-2.0 * std::f64::consts::PI * bandwidth_hz * period).exp()
}

/// The generalized force (base rows, 6) of the wrench `wrench_com` [N, Nm] about the CoM
/// (world axes) acting on the floating base: `[F; M_com + p_com_rel x F]`, with `p_com_rel`
/// the CoM relative to the base origin `O` (world axes) [m] (module doc, use).
pub fn base_generalized_force(wrench_com: &Vector6<f64>, p_com_rel: &Vector3<f64>) -> Vector6<f64> {
    let force = wrench_com.fixed_rows::<3>(0).into_owned();
    let about_com = Force::new(force, wrench_com.fixed_rows::<3>(3).into_owned());
    // `O` is at `-p_com_rel` from the CoM.
    about_com.moment_about(&-p_com_rel).to_vector()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::momentum::{momentum_map_identity_blocks, set_momentum_map_contact};

    const GRAVITY: Vector3<f64> = Vector3::new(0.0, 0.0, -9.81);

    /// A free body pushed by a constant wrench with no contact: the estimate converges to it
    /// at the low pass's rate.
    #[test]
    fn a_constant_wrench_on_a_free_body_is_estimated_at_the_low_pass_rate() {
        let (period, mass) = (0.01, 30.0);
        let push = Vector6::new(40.0, -20.0, 5.0, 1.0, 2.0, -3.0);
        let mut observer = ExternalWrenchObserver::new(period, 5.0);
        let (map, wrenches) = (DMatrix::zeros(6, 6), DVector::zeros(6));
        let mut momentum = Vector6::zeros();
        let blend = 1.0 - (-2.0 * std::f64::consts::PI * 5.0 * period).exp();
        for k in 0..40 {
            let estimate =
                *observer.update((&momentum, &map), &wrenches, &wrenches, (mass, &GRAVITY));
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
            rate.fixed_rows_mut::<3>(0).axpy(mass, &GRAVITY, 1.0);
            momentum += rate * period;
        }
    }

    /// A foot 0.1 m beside and 0.5 m below the CoM whose wrench ramps within each period and
    /// jumps at each sample (a new command), beside a constant push: with the period's start
    /// and end wrenches paired as measured the residual is the push exactly (the trapezoid is
    /// exact for a ramp); the wrench after the jump in place of the one before it is not.
    #[test]
    fn the_period_ends_pair_with_the_wrenches_measured_there() {
        let (period, mass) = (0.01, 30.0);
        let push = Vector6::new(25.0, 0.0, 0.0, 0.0, 3.0, 0.0);
        let mut map = momentum_map_identity_blocks(1);
        set_momentum_map_contact(
            &mut map,
            0,
            &Vector3::new(0.0, 0.1, 0.0),
            &Vector3::new(0.0, 0.0, 0.5),
        );
        // The foot's wrench: after sample k it starts at `start(k)` and ramps by `slope`.
        let start = |k: usize| {
            DVector::from_vec(vec![
                -20.0 + k as f64,
                2.0,
                300.0 + 5.0 * k as f64,
                1.0,
                -2.0,
                0.5,
            ])
        };
        let slope = DVector::from_vec(vec![0.0, 0.5, -4.0, 0.2, 0.0, 0.0]);
        let mut observer = ExternalWrenchObserver::new(period, 1e9);
        let mut momentum = Vector6::zeros();
        for k in 0..5 {
            let end = start(k) + &slope;
            let estimate = *observer.update((&momentum, &map), &start(k), &end, (mass, &GRAVITY));
            if k > 0 {
                assert!((estimate - push).norm() < 1e-9, "sample {k}: {estimate:?}");
            }
            let mean = momentum_rate(&map, &(0.5 * (start(k) + &end)), mass, &GRAVITY);
            momentum += (mean + push) * period;
        }
        let mut mixed = ExternalWrenchObserver::new(period, 1e9);
        let mut momentum = Vector6::zeros();
        let mut error: f64 = 0.0;
        for k in 0..5 {
            let end = start(k) + &slope;
            // The next sample's wrench, after its jump, for the period's end.
            let estimate = *mixed.update(
                (&momentum, &map),
                &start(k),
                &start(k + 1),
                (mass, &GRAVITY),
            );
            error = error.max((estimate - push).norm());
            let mean = momentum_rate(&map, &(0.5 * (start(k) + &end)), mass, &GRAVITY);
            momentum += (mean + push) * period;
        }
        assert!(error > 1.0, "{error}");
    }

    /// Standing still, the feet carry the weight exactly: no external wrench.
    #[test]
    fn the_weight_carried_by_the_feet_is_no_external_wrench() {
        let mut observer = ExternalWrenchObserver::new(0.01, 1000.0);
        let map = momentum_map_identity_blocks(1);
        let wrenches = DVector::from_vec(vec![0.0, 0.0, 300.0, 0.0, 0.0, 0.0]);
        for _ in 0..3 {
            let momentum = Vector6::zeros();
            observer.update(
                (&momentum, &map),
                &wrenches,
                &wrenches,
                (300.0 / 9.81, &GRAVITY),
            );
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
