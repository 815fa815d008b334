//! The joint torque loop of the multi-rate architecture: per elastic joint, a loop at the
//! motor boards' rate (1 kHz on the iCub) that turns a desired joint torque held from the
//! whole-body controller (100 Hz) and the freshly measured spring deflection and joint velocity
//! into the desired motor velocity of the motor velocity loop (eq:tauMotors).
//!
//! Per joint, with the deflection `delta = Gamma theta - s` [rad] and the controller's
//! stiffness estimate `K_S^`:
//!
//! `Gamma thetadot_d = sdot + omega_t (tau_d - K_S^ delta) / K_S^`
//!
//! so the commanded deflection rate closes the spring torque `K_S^ delta` onto `tau_d` with
//! bandwidth `omega_t` [rad/s]. With the motor velocity loop `thetaddot = -K_m (thetadot -
//! thetadot_d)` (eq:tauMotors with its torque feed-forward) and `sdot` fed forward, the
//! deflection obeys `deltaddot + K_m deltadot + K_m omega_t delta = K_m omega_t tau_d / K_S^`:
//! poles at `-K_m/2 +- sqrt(K_m^2/4 - K_m omega_t)`. Neither estimate enters that loop (the
//! stiffness estimate only scales the torque it delivers, `K_S / K_S^` times `tau_d`, and the
//! damping estimate is not used), so its stability does not hinge on them.
//!
//! The paper's law is the special case `omega_t = K_S^ / K_D^` with `tau_d = p + beta*`
//! (labels p, inputDesMotVel): `Gamma thetadot_d = beta* / K_D^` then (see the test
//! `the_paper_law_is_the_case_omega_equal_stiffness_over_damping`). With the iCub's
//! `K_S^ / K_D^ = 350 / 0.25 = 1400 1/s`, that loop sampled with a zero-order hold over a
//! period `T` is stable only while `T` is below about 1.5 ms (the two-state model of this
//! loop: 665 Hz; the whole robot's linearisation: 673 Hz), which no 100 Hz whole-body loop
//! can hold. Here the loop runs at the inner rate with `omega_t` well below it and below
//! `K_m`, as on real SEA joints, whose torque loops reach 20 to 70 Hz
//! (docs/references.md, "Control rates of real robots").
//!
//! [`JointTorqueLoop`] runs these loops for all elastic joints between two whole-body ticks
//! (`controller.sampling = "multi_rate"` in `sea_sim`).
//!
//! [`DEFAULT_TORQUE_BANDWIDTH`] is 2 pi 20 Hz, below the closed-loop torque bandwidths reported
//! for real SEAs (30 Hz to above 70 Hz, docs/references.md): with `K_m = 200 1/s` the poles are
//! `-100 +- 123i` (damping ratio 0.63, 25 Hz natural frequency), and the loop sampled at
//! 1 kHz has a spectral radius 0.91 whatever the estimates.

use crate::controller::{ControlOutput, ControllerKind, MomentumController};
use crate::excitation::IdentificationExcitation;
use crate::sea::spring_torque_without_motor_velocity;
use sea_dyn::{ElasticParameters, StateLayout};

/// Default bandwidth `omega_t` of the joint torque loop [rad/s]: 2 pi 20 Hz (module doc).
pub const DEFAULT_TORQUE_BANDWIDTH: f64 = 2.0 * std::f64::consts::PI * 20.0;

/// Settings of the joint torque loops ([`JointTorqueLoop::from_settings`]). With the `serde`
/// feature, the keys `torque_bandwidth_hz`, `torque_loop_paper_law` and `joint_stiffness` of a
/// scenario's `[controller]`, each bounded as it is read (`sea_dyn::bounded`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct JointLoopSettings {
    /// `multi_rate`: bandwidth `omega_t / 2 pi` of the joint torque loops [Hz] (default 20 Hz,
    /// `sea_ctrl::joint_loop::DEFAULT_TORQUE_BANDWIDTH`).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::Positive::read"),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub torque_bandwidth_hz: f64,
    /// `multi_rate`: run each joint loop at the paper's bandwidth `K_S^ / K_D^` instead of
    /// `torque_bandwidth_hz` (with the SEA controller: the paper's law, inputDesMotVel, with
    /// its measurements refreshed at the inner rate).
    #[cfg_attr(feature = "serde", serde(rename = "torque_loop_paper_law"))]
    pub paper_law: bool,
    /// `multi_rate`: stiffness [Nm/rad] of a joint impedance `K_j (s_d - s)` added to the
    /// held torque at every joint loop tick (default 0: none;
    /// `sea_ctrl::joint_loop::JointTorqueLoop::with_joint_stiffness`).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub joint_stiffness: f64,
}

impl Default for JointLoopSettings {
    /// 20 Hz ([`DEFAULT_TORQUE_BANDWIDTH`]), not the paper's law, no joint impedance.
    fn default() -> Self {
        Self {
            torque_bandwidth_hz: DEFAULT_TORQUE_BANDWIDTH / (2.0 * std::f64::consts::PI),
            paper_law: false,
            joint_stiffness: 0.0,
        }
    }
}

impl JointLoopSettings {
    /// The loops' bandwidth [rad/s], `None` for the paper's `K_S^ / K_D^` per joint.
    pub fn bandwidth(&self) -> Option<f64> {
        (!self.paper_law).then_some(2.0 * std::f64::consts::PI * self.torque_bandwidth_hz)
    }
}

/// The largest bandwidth `omega_t` [rad/s] at which the joint torque loop, run every
/// `period` [s] (`1 / controller.inner_rate_hz`) on a motor velocity loop of gain
/// `motor_velocity_gain` `K_m` [1/s], is stable; every smaller positive `omega_t` is.
///
/// Derivation. Per joint with `sdot` fed forward, the deflection `delta` and its rate
/// `v = deltadot` obey `vdot = -K_m (v - u)`: the motor velocity loop tracking the commanded
/// deflection rate `u = Gamma thetadot_d - sdot = omega_t (tau_d / K_S^ - delta)`, which the
/// loop computes from `delta_k` and holds over the period `T` (zero-order hold). The hold
/// of `K_m / (s (s + K_m))` is, with `a = K_m T` and `p = exp(-a)`,
///
/// `G(z) = ((a - 1 + p) z + (1 - p - a p)) / (K_m (z - 1) (z - p))`,
///
/// and with `g = omega_t / K_m` the closed loop's poles are the roots of
/// `z^2 + b1 z + b0` with `b1 = g (a - 1 + p) - (1 + p)` and `b0 = p + g (1 - p - a p)`.
/// Jury's conditions for both inside the unit circle: `1 + b1 + b0 = g a (1 - p) > 0` always;
/// `b0 > -1` always (`1 - p - a p > 0` for `a > 0`); `b0 < 1`, the complex pair leaving the
/// circle, gives `g < (1 - p) / (1 - p - a p)`; `1 - b1 + b0 > 0`, a real pole leaving at -1,
/// gives `g < 2 (1 + p) / (a (1 + p) - 2 (1 - p))` when that denominator is positive. The
/// bound is `K_m` times the smaller. For `K_m T -> 0` it tends to `2 / T` (the forward-Euler
/// pole `1 - omega_t T` at -1), for `K_m T -> inf` too; with the iCub's `K_m = 200 1/s` at
/// 1 kHz it is 2069 rad/s (329 Hz). The estimates do not enter (module doc), nor does the
/// joint's own motion (the loop on a held link); a bandwidth near the bound rings, so useful
/// ones are far below it (the default: spectral radius 0.91).
pub fn max_stable_bandwidth(motor_velocity_gain: f64, period: f64) -> f64 {
    let k_m = motor_velocity_gain;
    let a = k_m * period;
    let p = (-a).exp();
    let complex_pair = (1.0 - p) / (1.0 - p - a * p);
    let real_pole = a * (1.0 + p) - 2.0 * (1.0 - p);
    let real_pole = if real_pole > 0.0 {
        2.0 * (1.0 + p) / real_pole
    } else {
        f64::INFINITY
    };
    k_m * complex_pair.min(real_pole)
}

/// Desired motor velocity `thetadot_d` [rad/s, motor side] of one elastic joint from the held
/// desired joint torque `torque_desired` [Nm], the measured motor angle `theta` [rad, motor
/// side], joint angle `s` [rad] and joint velocity `sdot` [rad/s], with the controller's
/// `estimate` (ratio and stiffness used) and the loop bandwidth `bandwidth` [rad/s]:
/// `Gamma thetadot_d = sdot + omega_t (tau_d - K_S^ (Gamma theta - s)) / K_S^`.
pub fn torque_loop_motor_velocity(
    estimate: &ElasticParameters,
    bandwidth: f64,
    torque_desired: f64,
    theta: f64,
    s: f64,
    sdot: f64,
) -> f64 {
    let spring_torque = estimate.stiffness * (estimate.ratio * theta - s);
    let deflection_rate = bandwidth * (torque_desired - spring_torque) / estimate.stiffness;
    (sdot + deflection_rate) / estimate.ratio
}

/// The bandwidth [rad/s] at which [`torque_loop_motor_velocity`] is the paper's law
/// (inputDesMotVel with `tau_d = p + beta*`): `K_S^ / K_D^`.
pub fn paper_law_bandwidth(estimate: &ElasticParameters) -> f64 {
    estimate.stiffness / estimate.damping
}

/// The joint loops of all elastic joints between two whole-body ticks: the desired joint
/// torques `tau_d` held from the last tick ([`JointTorqueLoop::hold`]) and, at every inner
/// tick, the plant input with each elastic joint's desired motor velocity from
/// [`torque_loop_motor_velocity`] at the freshly measured state ([`JointTorqueLoop::tick`]).
/// Rigid joints keep the tick's torque. Allocation-free after [`JointTorqueLoop::new`].
///
/// `tau_d` is the whole-body controller's joint torque: `tau*` of the rigid controller
/// (`controller.kind = "rigid"`, the rigid model's QP) or `p + beta*` of the SEA controller
/// (labels p, inputTorquesSOTu), `p` at the tick's state; with one contact both are the same
/// QP's `tau*` (the SEA QP only moves `p` from `h_j` into the unknown).
#[derive(Clone, Debug)]
pub struct JointTorqueLoop {
    kind: ControllerKind,
    /// Coordinate index (joint order) of each elastic joint (n_e).
    elastic_joints: Vec<usize>,
    /// The loop's elastic parameter estimates (n_e): the controller's, unless replaced.
    estimates: Vec<ElasticParameters>,
    /// `omega_t` of each elastic joint (n_e) [rad/s].
    bandwidths: Vec<f64>,
    /// `tau_d` of each elastic joint (n_e) [Nm].
    held: Vec<f64>,
    /// The plant input (n): rigid joints the held torque, elastic joints `thetadot_d`.
    input: Vec<f64>,
    /// Joint stiffness `K_j` [Nm/rad] of the joint impedance added to `tau_d` at every inner
    /// tick (0: none).
    joint_stiffness: f64,
    /// The held postural reference `s_d` of each elastic joint (n_e) [rad].
    s_desired: Vec<f64>,
}

impl JointTorqueLoop {
    /// The loops of `controller`'s elastic joints with its estimates and bandwidth
    /// `omega_t` [rad/s], or (`None`) each joint's [`paper_law_bandwidth`] `K_S^ / K_D^` (the
    /// paper's law with the SEA controller), holding zero torques.
    pub fn new(controller: &MomentumController, bandwidth: Option<f64>) -> Self {
        let actuation = controller.actuation();
        let estimates = controller.estimates().to_vec();
        let bandwidths = estimates
            .iter()
            .map(|estimate| bandwidth.unwrap_or_else(|| paper_law_bandwidth(estimate)))
            .collect();
        Self {
            kind: controller.settings().kind,
            elastic_joints: actuation.elastic_joints.clone(),
            estimates,
            bandwidths,
            held: vec![0.0; actuation.n_elastic()],
            input: vec![0.0; controller.model().n_joints()],
            joint_stiffness: 0.0,
            s_desired: vec![0.0; actuation.n_elastic()],
        }
    }

    /// The joint loops of `controller`'s elastic joints with `settings` (bandwidth or the
    /// paper's law, joint stiffness).
    pub fn from_settings(controller: &MomentumController, settings: &JointLoopSettings) -> Self {
        Self::new(controller, settings.bandwidth()).with_joint_stiffness(settings.joint_stiffness)
    }

    /// With a joint impedance of stiffness `stiffness` [Nm/rad] on every elastic joint: each
    /// inner tick adds `K_j (s_d - s)` (the measured `s`, the held postural reference) to
    /// `tau_d`. It stiffens the stance knee's slow mode, which the momentum task hardly sees
    /// near a straight knee, against the torque gain error `K_S / K_S^` of a stiffness
    /// estimate (docs/findings/robot_rate.md).
    pub fn with_joint_stiffness(mut self, stiffness: f64) -> Self {
        self.joint_stiffness = stiffness;
        self
    }

    /// The loop's estimates (n_e).
    pub fn estimates(&self) -> &[ElasticParameters] {
        &self.estimates
    }

    /// The loop's estimates (n_e), e.g. to give each joint its own stiffness error.
    pub fn estimates_mut(&mut self) -> &mut [ElasticParameters] {
        &mut self.estimates
    }

    /// The held desired joint torques `tau_d` (n_e) [Nm].
    pub fn held_torques(&self) -> &[f64] {
        &self.held
    }

    /// Holds the torques of a whole-body tick `output` computed at state `x`: `tau*` (rigid
    /// controller) or `p(x) + beta*` (SEA controller), and the tick's postural reference
    /// `s_desired` (n); rigid joints' inputs are kept as given.
    pub fn hold(
        &mut self,
        output: &ControlOutput,
        layout: &StateLayout,
        x: &[f64],
        s_desired: &[f64],
    ) {
        self.input.copy_from_slice(&output.input);
        let (theta, s, sdot) = (layout.theta(x), layout.s(x), layout.sdot(x));
        let joints = self.elastic_joints.iter().zip(&self.estimates);
        for (e, (&j, estimate)) in joints.enumerate() {
            let p = match self.kind {
                ControllerKind::Rigid => 0.0,
                ControllerKind::Sea => {
                    spring_torque_without_motor_velocity(estimate, theta[e], s[j], sdot[j])
                }
            };
            self.held[e] = output.joint_command[j] + p;
            self.s_desired[e] = s_desired[j];
        }
    }

    /// Adds `excitation` at time `time` [s] to the held desired torques (after
    /// [`Self::hold`], until the next hold; [`crate::excitation`]).
    pub fn excite(&mut self, excitation: &IdentificationExcitation, time: f64) {
        excitation.add_to(time, &mut self.held);
    }

    /// One inner tick at the measured state `x`: the plant input (n) with the desired motor
    /// velocity of every elastic joint.
    pub fn tick(&mut self, layout: &StateLayout, x: &[f64]) -> &[f64] {
        let (theta, s, sdot) = (layout.theta(x), layout.s(x), layout.sdot(x));
        let joints = self.elastic_joints.iter().zip(&self.estimates);
        for (e, (&j, estimate)) in joints.enumerate() {
            let impedance = self.joint_stiffness * (self.s_desired[e] - s[j]);
            self.input[j] = torque_loop_motor_velocity(
                estimate,
                self.bandwidths[e],
                self.held[e] + impedance,
                theta[e],
                s[j],
                sdot[j],
            );
        }
        &self.input
    }

    /// The plant input of the last [`Self::tick`] (n).
    pub fn input(&self) -> &[f64] {
        &self.input
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sea::{desired_motor_velocity, spring_torque_without_motor_velocity};
    use nalgebra::{Matrix2, Matrix3, Vector2};

    fn joint() -> ElasticParameters {
        ElasticParameters::paper_icub()
    }

    #[test]
    fn the_paper_law_is_the_case_omega_equal_stiffness_over_damping() {
        let estimate = ElasticParameters {
            stiffness: 400.0,
            damping: 0.3,
            ..joint()
        };
        let (theta, s, sdot, beta) = (14.0, 0.12, -0.4, 2.5);
        let p = spring_torque_without_motor_velocity(&estimate, theta, s, sdot);
        let paper = desired_motor_velocity(&estimate, beta);
        let ours = torque_loop_motor_velocity(
            &estimate,
            paper_law_bandwidth(&estimate),
            p + beta,
            theta,
            s,
            sdot,
        );
        assert!((paper - ours).abs() < 1e-12 * paper.abs(), "{paper} {ours}");
    }

    #[test]
    fn at_the_desired_torque_the_motor_follows_the_joint() {
        let estimate = joint();
        let (s, sdot, torque) = (0.3, 0.7, 5.0);
        let theta = (s + torque / estimate.stiffness) / estimate.ratio;
        let thetadot = torque_loop_motor_velocity(&estimate, 100.0, torque, theta, s, sdot);
        assert!((estimate.ratio * thetadot - sdot).abs() < 1e-12);
    }

    /// Spectral radius of the deflection loop (state `[delta, Gamma thetadot]`, motor velocity
    /// loop of gain `k_m` in continuous time, the torque loop's command held over `period`).
    fn sampled_spectral_radius(bandwidth: f64, k_m: f64, period: f64) -> f64 {
        // Exact zero-order-hold discretisation through the exponential of [[A, B], [0, 0]].
        let augmented = Matrix3::new(0.0, 1.0, 0.0, 0.0, -k_m, k_m, 0.0, 0.0, 0.0) * period;
        let exp = augmented.exp();
        let a = exp.fixed_view::<2, 2>(0, 0).into_owned();
        let b: Vector2<f64> = exp.fixed_view::<2, 1>(0, 2).into_owned();
        let closed: Matrix2<f64> = a - b * nalgebra::RowVector2::new(bandwidth, 0.0);
        closed
            .complex_eigenvalues()
            .iter()
            .map(|l| l.norm())
            .fold(0.0, f64::max)
    }

    /// The mechanism of the paper's law's rate limit: its loop sampled at 100 Hz diverges,
    /// at 1 kHz it holds; the default loop holds at 1 kHz whatever factor an estimate error
    /// puts on its bandwidth between x0.5 and x2, and even at 100 Hz.
    #[test]
    fn sampled_deflection_loop_is_stable_at_the_robot_rates() {
        let k_m = 200.0;
        let paper = paper_law_bandwidth(&joint());
        assert!(sampled_spectral_radius(paper, k_m, 1e-2) > 1.0);
        assert!(sampled_spectral_radius(paper, k_m, 1.0 / 600.0) > 1.0);
        assert!(sampled_spectral_radius(paper, k_m, 1.0 / 700.0) < 1.0);
        for factor in [0.5, 1.0, 2.0] {
            let rho = sampled_spectral_radius(factor * DEFAULT_TORQUE_BANDWIDTH, k_m, 1e-3);
            assert!(rho < 0.95, "x{factor}: {rho}");
        }
        assert!(sampled_spectral_radius(DEFAULT_TORQUE_BANDWIDTH, k_m, 1e-2) < 0.75);
    }

    /// The bound is where the sampled loop's spectral radius crosses 1, for motor loops slow
    /// and fast against the period (either of Jury's conditions binding).
    #[test]
    fn the_stability_bound_is_where_the_sampled_loop_leaves_the_unit_circle() {
        for (k_m, period) in [(200.0, 1e-3), (200.0, 1e-2), (50.0, 1e-3), (5000.0, 1e-3)] {
            let bound = max_stable_bandwidth(k_m, period);
            let below = sampled_spectral_radius(0.999 * bound, k_m, period);
            let above = sampled_spectral_radius(1.001 * bound, k_m, period);
            assert!(
                below < 1.0 && above > 1.0,
                "{k_m} {period}: {below} {above}"
            );
        }
        let icub = max_stable_bandwidth(200.0, 1e-3);
        assert!((icub - 2068.9).abs() < 0.1, "{icub}");
    }
}
