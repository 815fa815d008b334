//! `[sensing]`'s measurement model: what the controller reads at an inner tick. The true
//! states of the inner ticks go into a ring of `delay + 1` states (filled with the initial
//! state, so that before `delay` inner periods the initial state is read); the measurement is
//! the oldest, with independent Gaussian noise on `s`, `sdot`, `theta` and `thetadot` drawn
//! from a seeded ChaCha stream (bitwise reproducible, the same on every platform). The
//! floating base's pose and velocity are read exactly. Allocation-free after
//! `Sensor::new`.
//!
//! The law evaluated at a measurement reports a measured CoM and measured errors; the run
//! records the true ones (`Sensor::observe_truth`).

use super::tick::Law;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use sea_dyn::{Data, Model, StateLayout};
use std::ops::Range;

/// `[sensing]`: what the controller measures (default: perfect sensing, the true state at the
/// tick). The whole-body controller and every joint loop tick read the state measured at their
/// inner tick: the true state `delay_inner_periods` inner periods earlier (the initial state
/// before), with independent zero-mean Gaussian noise on each joint and motor coordinate (the
/// floating base's pose and velocity are exact). The plant integrates, and the records keep,
/// the true state. Needs `controller.sampling` "multi_rate" (inner period
/// `1 / controller.inner_rate_hz`) or "zero_order_hold" (inner period: the control period)
/// unless perfect.
#[derive(
    Clone, Debug, Default, PartialEq, serde::Deserialize, serde::Serialize, schemars::JsonSchema,
)]
#[serde(default, deny_unknown_fields)]
pub struct SensingConfig {
    /// Standard deviation of the joint encoders' noise on `s` [rad].
    #[serde(deserialize_with = "sea_dyn::bounded::NonNegative::read")]
    #[schemars(with = "sea_dyn::bounded::NonNegative")]
    pub joint_position_noise_rad: f64,
    /// Standard deviation of the noise on the joint velocities `sdot` [rad/s].
    #[serde(deserialize_with = "sea_dyn::bounded::NonNegative::read")]
    #[schemars(with = "sea_dyn::bounded::NonNegative")]
    pub joint_velocity_noise_rad_s: f64,
    /// Standard deviation of the motor encoders' noise on `theta` [rad, motor side].
    #[serde(deserialize_with = "sea_dyn::bounded::NonNegative::read")]
    #[schemars(with = "sea_dyn::bounded::NonNegative")]
    pub motor_position_noise_rad: f64,
    /// Standard deviation of the noise on the motor velocities `thetadot` [rad/s, motor side].
    #[serde(deserialize_with = "sea_dyn::bounded::NonNegative::read")]
    #[schemars(with = "sea_dyn::bounded::NonNegative")]
    pub motor_velocity_noise_rad_s: f64,
    /// Measurement delay in whole inner periods, at most one whole-body period.
    pub delay_inner_periods: usize,
    /// Seed of the noise (a ChaCha stream: the same noise on every platform).
    pub seed: u64,
}

impl SensingConfig {
    /// The noise standard deviations with their keys: joint position, joint velocity, motor
    /// position, motor velocity.
    pub fn noise(&self) -> [(&'static str, f64); 4] {
        [
            ("joint_position_noise_rad", self.joint_position_noise_rad),
            (
                "joint_velocity_noise_rad_s",
                self.joint_velocity_noise_rad_s,
            ),
            ("motor_position_noise_rad", self.motor_position_noise_rad),
            (
                "motor_velocity_noise_rad_s",
                self.motor_velocity_noise_rad_s,
            ),
        ]
    }

    /// Whether the controller reads the true state (no noise, no delay; the seed is unused).
    pub fn is_perfect(&self) -> bool {
        self.delay_inner_periods == 0 && self.noise().iter().all(|&(_, std)| std == 0.0)
    }
}

/// The controller's measurements of the plant's state (one per inner tick).
pub(super) struct Sensor {
    /// Noise standard deviation of each noisy block of the state, with the block's range.
    noise: [(Range<usize>, f64); 4],
    rng: ChaCha8Rng,
    /// The last `delay + 1` true states, a ring of `nx`-long slots.
    history: Vec<f64>,
    /// Slot of the newest state.
    newest: usize,
    /// Number of slots, `delay + 1`.
    slots: usize,
    /// The last measurement (nx).
    measured: Vec<f64>,
    /// The model's workspace for the true CoM.
    data: Data,
}

impl Sensor {
    /// The sensor of `config` for states of `layout` starting at `x0`, or `None` when sensing
    /// is perfect (the controller then reads the true state itself).
    pub fn new(
        config: &SensingConfig,
        model: &Model,
        layout: StateLayout,
        x0: &[f64],
    ) -> Option<Self> {
        if config.is_perfect() {
            return None;
        }
        let (nu, theta, thetadot) = (
            layout.nu_offset(),
            layout.theta_offset(),
            layout.thetadot_offset(),
        );
        let noise = [
            (7..layout.nq, config.joint_position_noise_rad),
            (nu + 6..nu + layout.nv, config.joint_velocity_noise_rad_s),
            (theta..theta + layout.ne, config.motor_position_noise_rad),
            (
                thetadot..thetadot + layout.ne,
                config.motor_velocity_noise_rad_s,
            ),
        ];
        let slots = config.delay_inner_periods + 1;
        Some(Sensor {
            noise,
            rng: ChaCha8Rng::seed_from_u64(config.seed),
            history: x0.repeat(slots),
            newest: 0,
            slots,
            measured: x0.to_vec(),
            data: Data::new(model),
        })
    }

    /// Takes the true state `x` of an inner tick and returns the controller's measurement at
    /// this tick: the true state `delay` ticks earlier, with noise.
    pub fn measure(&mut self, x: &[f64]) -> &[f64] {
        let nx = self.measured.len();
        self.newest = (self.newest + 1) % self.slots;
        let oldest = (self.newest + 1) % self.slots;
        self.history[self.newest * nx..(self.newest + 1) * nx].copy_from_slice(x);
        self.measured
            .copy_from_slice(&self.history[oldest * nx..(oldest + 1) * nx]);
        for (range, std) in &self.noise {
            if *std == 0.0 {
                continue;
            }
            for value in &mut self.measured[range.clone()] {
                let draw: f64 = StandardNormal.sample(&mut self.rng);
                *value += std * draw;
            }
        }
        &self.measured
    }

    /// The last measurement ([`Sensor::measure`]).
    pub fn last(&self) -> &[f64] {
        &self.measured
    }

    /// After the law's tick at the last measurement: puts the true CoM (of `model` at `x`)
    /// and the true tracking errors into its observation.
    pub fn observe_truth(&mut self, law: &mut Law<'_>, model: &Model, x: &[f64]) {
        let layout = law.layout();
        let com = sea_dyn::centroidal::com(model, &mut self.data, layout.q(x));
        law.observe_truth(com, layout.s(x));
    }
}
