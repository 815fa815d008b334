//! Online identification of the spring stiffness of every elastic joint from the encoders and
//! the rigid-body model: the joint torque the model says the joint carries, against the
//! spring deflection the encoders measure.
//!
//! Why (docs/findings/robot_rate.md): the joint torque loop ([`crate::joint_loop`]) measures
//! the torque as `K_S^ delta`, so it delivers `g tau_d` with the gain `g = K_S / K_S^`. With
//! `g != 1` the whole-body controller's cancellation of the gravity torques' change with
//! posture (a negative stiffness of the loaded stance leg) misses a fraction `1 - g`, and the
//! slow mode of the stance knee turns unstable at a 1 to 2 % error. Identifying `K_S` turns
//! the torque loop's gain back to 1; what remains is the model's own error, which scales the
//! identified stiffness and the model's torques alike (a link mass error of `eps` identifies
//! `(1 + eps) K_S` and asks for `(1 + eps)` times the torque, so the delivered torque is the
//! one the real robot needs).
//!
//! The model's joint torques at the measured state, with `nudot` the finite difference of the
//! measured `nu` over the update period (zero at the first update):
//!
//! `tau_model = S ((M + D) nudot + h - J^T f)` (the joint rows of the floating-base dynamics,
//! `D` the joints' inertia regularisation: the controller's `joint_inertia_regularization` on
//! every joint, zero on the base), where
//! the contact wrenches `f` are the given ones `f_0` (measured by the feet's force/torque
//! sensors, or the commanded `f*`) corrected to satisfy the base rows `J_b^T f = (M nudot +
//! h)_b` with the least change (`f = f_0 + J_b (J_b^T J_b)^-1 r`, `r = (M nudot + h)_b - J_b^T
//! f_0`, `J_b` the base columns of the stacked contact Jacobians): on one foot this is the
//! contact wrench exactly (six equations, six unknowns) whatever `f_0`; on two feet the internal
//! force between the feet is `f_0`'s, so the commanded `f*` biases the legs' estimates where
//! sensors do not.
//!
//! `D` is what the link side of each joint carries beyond `M`: the plant's
//! `joint_inertia_regularization` (0.1 kg m^2 per joint on the iCub), of which the identifier
//! knows the controller's setting (a scenario's `plant.` and `controller.` keys of that name are
//! separate and equal by default; with different values the identified stiffness absorbs the
//! difference as it does a mass error). The motor's reflected
//! inertia that the rigid controller may add to its own diagonal is on the motor side of the
//! spring and is not in it. Without `D` the model's torques miss `D nudot` wherever a joint
//! accelerates, and a joint whose torque is mostly inertial is identified soft: from the true
//! stiffness, a 0.25 Nm excitation of the iCub's torso roll at 1 Hz (two feet) identified the
//! torso roll at x0.88 and the torso yaw at x0.53 after 3 s; with `D`, both within 0.1 %.
//!
//! With measured wrenches the base rows check them: their residual `r` is the model's error
//! (steady: a wrong mass) plus the robot's unmodelled external wrench (a push, a hand on the
//! robot), which the correction would put on the feet and so into the legs' torques. An
//! update whose force residual departs from its running mean (the steady part, averaged with
//! the same forgetting over the accepted updates) by more than
//! `IdentificationSettings::max_external_force` times the robot's weight, or whose moment
//! residual (about the CoM, where a uniform mass error has none) departs by more than that
//! force times `IdentificationSettings::external_moment_arm`, is skipped: the estimates are
//! held through a push. The moment matters at a push's first sample: the measured wrenches
//! have already moved load between the feet while the finite-difference `nudot` (one period
//! late) has not seen the push, so the force residual is small (1.6 N for a 65 N sideways push
//! on the iCub's pelvis) but the moment's is not (2.2 Nm), and that one sample put the
//! mismatch into the lightly loaded legs' joints (their estimates moved by up to 50 %). Once
//! the identification has run `3 T_id` (its estimates within 5 % of their fixed point), they
//! are also held for
//! `IdentificationSettings::hold_after_external_force` after the last skipped update: the
//! recovery from a push moves the robot fast, where the finite-difference `nudot` makes the
//! model's torques poorer. (Measured before `D` was in the model's torques: a 5.5 N s push on
//! the converged iCub was recovered with the hold, not without, the recovery's `D nudot` going
//! into the estimates; with `D` both recover it, and the hold stays as a guard.) Before that
//! the estimates are still far from the robot's and learning through the recovery is worth
//! more than holding a wrong value.
//!
//! Walking (`crate::robot`, `walking.identification_settle`): the stack updates only when
//! both feet have been on the ground for a while and calls [`StiffnessIdentifier::hold_sample`]
//! otherwise. Measured on the iCub's walks (docs/findings/walking.md): the first period of a
//! run, while the feet settle on unilateral contacts, has a base-row force residual of 22 N
//! (nudot zero at the first update, then -8 N at the second); learnt from, that one sample
//! moved the legs' estimates by up to 16 %, and it set the external force check's running
//! mean, from which every later residual departed by about 22 N (past the 6.5 N bound): 1 of
//! 400 updates was accepted over a 50-step walk. In the walking double supports the departures
//! are 13 to 290 N (median 39 N: impacts and rocking soles within the period), so the check
//! rejects those anyway; the initial transfer (the CoM moving over to the first stance foot)
//! and the standing after the walk are where the model holds. With
//! `walking.identification_single_support` the stack also updates once the stance foot has
//! stood alone that long; with the central difference (below) that keeps the walks' leg
//! estimates within 2 %, with the backward one it loses the 0.3 m/s walk (the same findings,
//! "Learning in single support").
//!
//! The acceleration ([`IdentificationAcceleration`]): the backward difference
//! `nudot_k = (nu_k - nu_(k-1)) / T` is the mean acceleration of the last period, half a
//! period behind the state `x_k` whose torques and deflections it is paired with; where the
//! acceleration changes within a period (a stance leg's rocking sole, the springs' modes) that
//! lag is a torque error. The central difference `(nu_(k+1) - nu_(k-1)) / 2T` is the acceleration at `x_k` to
//! second order; each update then learns from the previous update's sample (state and
//! wrenches kept), one period late, and a hold ([`StiffnessIdentifier::hold_sample`]) drops the
//! pending sample, so no sample with a held neighbour is learnt from. Measured on the iCub's
//! walk_fast 3 s in (x0.7 / x1.4, the estimates held while stepping): the legs' worst estimate
//! error 5.4 / 5.9 % backward, 2.8 / 6.8 % central, the median leg joint's 1.6 / 0.9 % and
//! 0.1 / 0.1 %.
//!
//! Per joint, recursive least squares with exponential forgetting on
//! `tau_model - K_D^ deltadot = K_S delta` (the spring's damping term removed with the damping
//! estimate): `S_dd <- lambda S_dd + delta^2`, `S_td <- lambda S_td + (tau_model - K_D^
//! deltadot) delta`, `K_S^ = S_td / S_dd`, `lambda = exp(-T / T_id)`, started from the prior
//! `K_S^0` with the weight of a deflection `delta_0` (`S_dd = delta_0^2`, `S_td = K_S^0
//! delta_0^2`). A joint whose torque stays below `K_S^0 delta_0` keeps (nearly) its prior: its
//! stiffness is not observable, and its torque gain error acts on torques that small.
//! Estimates are kept within `[K_S^0 / c, c K_S^0]`, `c = IdentificationSettings::range_factor`
//! (default 3: the prior is trusted to a factor of 3, beyond the x0.5 to x2 that the loop is
//! asked to hold). Few samples can carry a large torque error on a lightly loaded joint (the
//! model's own error, or noise through the finite-difference `nudot`: velocity noise of 1e-2
//! rad/s puts several Nm into the legs' model torques), and one such update took the stance
//! ankle roll to the old bound `K_S^0 / 10`, whose tenfold torque gain tipped the sole (one
//! noisy run in twelve, seed 0; with 3 it completes; the samples' filter, below, now also keeps
//! such updates out).
//!
//! Encoder noise: a deflection measured with noise of variance `sigma^2` makes `S_dd` larger
//! by `sigma^2 W` on average (`W <- lambda W + 1`, the samples' forgetting weight) while
//! `S_td` stays unbiased, so plain least squares identifies `K_S var(delta) / (var(delta) +
//! sigma^2)`: a joint whose deflection is near the noise is identified soft (x0.5 on the
//! iCub's lightly loaded joints at 1e-4 rad) and then gets twice its torque. With
//! `IdentificationSettings::deflection_noise` the bias is removed (bias-compensated least
//! squares, errors-in-variables with a known noise variance): `K_S^ = S_td / (S_dd - sigma^2
//! W)`, updated only while the compensated `S_dd` is at least `sigma^2 W` (a signal at least
//! as strong as the noise; otherwise the estimate is held), with `sigma^2` the variance that
//! the samples' filter leaves (`sigma^2 a / (2 - a)`, "Filtering" below). The noise reaches the external
//! force check too: with velocity noise of 1e-2 rad/s the finite-difference `nudot` puts
//! departures of several N and Nm into the base rows' residual, past the bounds at nearly every
//! update, and the identification then stops learning (measured: 0 of 12 noisy tracking runs
//! complete, 11 of 12 with the check off). The bounds are therefore at least
//! [`NOISE_BOUND_FACTOR`] times the rms of the departures when the encoders are declared noisy
//! (`deflection_noise > 0`): a running mean square with the same forgetting over every update,
//! each departure capped at the bound it is checked against (capped at the fixed bound
//! instead, the bounds cannot rise to the noise and 3 of 12 noisy runs complete). The price: a
//! steady force held long raises the bounds by about 8 % per update once they follow it (a
//! 50 N force passes after about 0.7 s, and after the hold the identification learns from the
//! pushed samples); the pushes of 0.1 s in the push tables stay detected. With exact encoders
//! (no noise declared) the bounds are the fixed ones and a steady push stays detected however
//! long it lasts.
//!
//! Filtering: the finite-difference `nudot` turns velocity noise into acceleration noise
//! (1e-2 rad/s over 10 ms: 1.4 rad/s^2 per coordinate), which the model's torques carry into
//! every row; on the stance leg, where the whole robot's inertia sits, that is several Nm per
//! sample, as large as the torques the identification learns from, so in its first fraction
//! of a second a loaded joint's estimate could wander (measured: the stance ankle pitch at
//! x0.23 after 0.44 s from x0.5, and the sole tipped). Each joint's spring torque and
//! deflection are therefore low-passed alike before the sums,
//! `y_f <- y_f + a (y - y_f)`, `a = 1 - exp(-2 pi f_r T)` (`f_r`:
//! `IdentificationSettings::filter_bandwidth`, 5 Hz), started at the first sample and
//! fed only the updates that are made (not those the external force check skips). The
//! relation `spring = K_S delta` is linear and static, so it holds between the filtered
//! signals as between the raw ones (the same filter on both sides), while the noise above
//! `f_r` is removed; white deflection noise keeps the variance `sigma^2 a / (2 - a)`, which is
//! what the bias compensation removes. Measured on the tracking with noisy encoders (1e-4 rad,
//! 1e-2 rad/s), seeds 0-15 from x0.5 / x1 / x2 (the robust design, docs/findings/model_errors.md):
//! 48 of 48 complete with the final joint error at most 0.17 rad (unfiltered: 45 of 48, three
//! falls at 0.43-0.45 s from x0.5, at most 0.23 rad); the identification alone, seeds 0-7:
//! 23 of 24, at most 0.18 rad, CoM rms at most 2.9 mm (unfiltered: 20 of 24, and up to
//! 0.52 rad and 4.8 mm among the completed).

use crate::controller::MomentumController;
use crate::external_wrench::low_pass_blend;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};
use sea_dyn::jacobian::frame_jacobian_from_kinematics;
use sea_dyn::rnea;
use sea_dyn::spatial::{Force, SpatialInertia};
use sea_dyn::{Data, ElasticParameters, FrameId, Model, StateLayout};

/// The external force check's bounds are at least this many times the rms of the residual's
/// departures (module doc, "Encoder noise").
pub const NOISE_BOUND_FACTOR: f64 = 3.0;

#[cfg(feature = "serde")]
sea_dyn::number_bound!(
    /// [`IdentificationSettings::prior_deflection`]: a deflection in `(0, 0.1]` rad.
    PriorDeflection,
    "must be positive and at most 0.1 rad",
    |v| v > 0.0 && v <= 0.1,
    { "type": "number", "exclusiveMinimum": 0.0, "maximum": 0.1 }
);

/// Settings of [`StiffnessIdentifier`]. With the `serde` feature, the keys
/// `identification_*` of a scenario's `[controller]` (the tuning fields; the external force
/// check's bounds are the defaults'), each bounded as it is read (`sea_dyn::bounded`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct IdentificationSettings {
    /// `multi_rate` with `stiffness_identification`: forgetting time constant `T_id` of the
    /// identification [s]: older samples weigh `exp(-age / T_id)` (default 1 s).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_time_s",
            deserialize_with = "sea_dyn::bounded::Positive::read"
        ),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub time_constant: f64,
    /// `multi_rate` with `stiffness_identification`: the standard deviation of the noise on a
    /// measured spring deflection `delta` [rad] that the identification removes from its sums
    /// `S_dd` (bias-compensated least squares; module doc, "Encoder noise"); the encoders'
    /// specification, e.g. `sqrt(sigma_s^2 + (ratio sigma_theta)^2)`. Default 0 (noise-free
    /// encoders).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_deflection_noise_rad",
            deserialize_with = "sea_dyn::bounded::NonNegative::read"
        ),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub deflection_noise: f64,
    /// `multi_rate` with `stiffness_identification` and measured wrenches: how long the
    /// converged estimates stay held after a push was detected (the last update the external
    /// force check skipped) [s] (`sea_ctrl::stiffness_id`; default 1 s).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_hold_s",
            deserialize_with = "sea_dyn::bounded::NonNegative::read"
        ),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub hold_after_external_force: f64,
    /// `multi_rate` with `stiffness_identification`: the weight of the prior estimate, as
    /// the spring deflection `delta_0` [rad] of one sample (`sea_ctrl::stiffness_id`; default 1e-3 rad,
    /// 0.35 Nm on the iCub). A joint carrying less torque than `K_S^0 delta_0` keeps its
    /// prior: with `external_wrench = "generalized"`, 5e-3 keeps the model's own torque errors
    /// on lightly loaded joints (the stance ankle roll) out of the estimates
    /// (docs/findings/model_errors.md). At most 0.1 rad.
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_prior_deflection_rad",
            deserialize_with = "PriorDeflection::read"
        ),
        schemars(with = "PriorDeflection")
    )]
    pub prior_deflection: f64,
    /// `multi_rate` with `stiffness_identification`: the bandwidth `f_r` [Hz] of the
    /// first-order low pass that filters each joint's spring torque and deflection alike
    /// before the least squares (`sea_ctrl::stiffness_id`, "Filtering"; default 5 Hz); positive, and a
    /// bandwidth far above the update rate (e.g. 1e9) leaves the samples unfiltered.
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_filter_hz",
            deserialize_with = "sea_dyn::bounded::Positive::read"
        ),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub filter_bandwidth: f64,
    /// `multi_rate` with `stiffness_identification`: the estimates stay within this factor
    /// `c` of the prior, `[K_S^0 / c, c K_S^0]` (`sea_ctrl::stiffness_id`; default 3, more than 1): how far
    /// from the prior the robot's stiffness may be.
    #[cfg_attr(
        feature = "serde",
        serde(
            rename = "identification_range_factor",
            deserialize_with = "sea_dyn::bounded::MoreThanOne::read"
        ),
        schemars(with = "sea_dyn::bounded::MoreThanOne")
    )]
    pub range_factor: f64,
    /// `multi_rate` with `stiffness_identification`: how `nudot` of the model's torques is
    /// taken from the measured velocities (`sea_ctrl::stiffness_id`, "The acceleration";
    /// default `backward`).
    #[cfg_attr(feature = "serde", serde(rename = "identification_acceleration"))]
    pub acceleration: IdentificationAcceleration,
    /// With measured wrenches: the largest force residual of the base rows, as a fraction of
    /// the robot's weight, at which an update is made (module doc); `None` (commanded
    /// wrenches, whose residual is the momentum error) for no check.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub max_external_force: Option<f64>,
    /// With the external force check: the moment residual's bound is the force bound times
    /// this arm [m] (module doc).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub external_moment_arm: f64,
}

impl Default for IdentificationSettings {
    /// `T_id` 1 s, `delta_0` 1e-3 rad (0.35 Nm at the iCub's 350 Nm/rad), external force
    /// check at 2 % of the weight (6.5 N on the iCub) and its moment at 0.1 m (0.65 Nm, a
    /// force at the sole's half-length), held 1 s after it once converged; estimates within a
    /// factor 3 of the prior; the samples low-passed at 5 Hz.
    fn default() -> Self {
        Self {
            time_constant: 1.0,
            prior_deflection: 1e-3,
            max_external_force: Some(0.02),
            deflection_noise: 0.0,
            hold_after_external_force: 1.0,
            external_moment_arm: 0.1,
            range_factor: 3.0,
            filter_bandwidth: 5.0,
            acceleration: IdentificationAcceleration::Backward,
        }
    }
}

/// `controller.identification_acceleration`: the finite difference of the measured velocities
/// that gives the model's torques their `nudot` (with the `serde` feature, named "backward" or
/// "central").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum IdentificationAcceleration {
    /// `(nu_k - nu_(k-1)) / T` at sample `k`: the mean acceleration of the last period, half a
    /// period behind the sample's state (the default).
    #[default]
    Backward,
    /// `(nu_(k+1) - nu_(k-1)) / 2T` at sample `k`, which is learnt from one period late: the
    /// acceleration at the sample's state to second order.
    Central,
}

/// `controller.identification_wrenches`: the contact wrenches the stiffness identification
/// takes (with the `serde` feature, named "measured" or "commanded").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum IdentificationWrenches {
    /// Measured by force/torque sensors at the feet, as on the iCub (docs/references.md; in
    /// simulation: the plant's contact wrenches at the sample; the default).
    #[default]
    Measured,
    /// The whole-body controller's commanded `f*` (no sensors): on two feet the internal
    /// force between the feet is then the commanded one, which biases the legs' estimates.
    Commanded,
}

/// The identifier of the stiffness of every elastic joint (module doc). Allocation-free after
/// [`StiffnessIdentifier::new`] (with the central difference, after the first update, which
/// sizes the pending sample's state).
#[derive(Clone, Debug)]
pub struct StiffnessIdentifier {
    model: Model,
    data: Data,
    settings: IdentificationSettings,
    contact_frames: Vec<FrameId>,
    /// Coordinate index of each elastic joint (n_e).
    elastic_joints: Vec<usize>,
    /// The prior `K_S^0` of each elastic joint (n_e) [Nm/rad].
    prior: Vec<f64>,
    /// `D` of each joint (module doc) [kg m^2].
    joint_inertia_regularization: f64,
    /// The low-passed spring torque `tau_model - K_D^ deltadot` (n_e) [Nm] (module doc,
    /// "Filtering"), valid when `has_filtered`.
    filtered_spring: Vec<f64>,
    /// The low-passed deflection `delta` (n_e) [rad], valid when `has_filtered`.
    filtered_deflection: Vec<f64>,
    /// Whether an update has set the filters.
    has_filtered: bool,
    /// `S_dd` (n_e) [rad^2] and `S_td` (n_e) [Nm rad].
    sum_deflection_squared: Vec<f64>,
    sum_torque_deflection: Vec<f64>,
    /// `W`, the forgetting weight of the samples so far (`W <- lambda W + 1`).
    sample_weight: f64,
    /// Time since the first update [s].
    elapsed: f64,
    /// Time left of the hold after an external force [s].
    hold_left: f64,
    /// `nu` of the previous update (nv), valid when `has_previous`.
    nu_previous: Vec<f64>,
    /// Whether an update came before (`nu_previous` holds its `nu`).
    has_previous: bool,
    /// `nudot` (nv) of this update.
    nudot: Vec<f64>,
    /// The central difference's pending sample: the previous update's state (nx, sized at
    /// the first update) and contact wrenches (6 k), valid when `has_delayed`.
    delayed_state: Vec<f64>,
    delayed_wrenches: DVector<f64>,
    has_delayed: bool,
    /// `nu` one period before the pending sample (nv), valid when `has_nu_before_delayed`.
    nu_before_delayed: Vec<f64>,
    has_nu_before_delayed: bool,
    /// `(M + D) nudot + h - J^T f` (nv) of this update: its joint rows are `tau_model`.
    generalized_force: DVector<f64>,
    /// Stacked contact Jacobians (6 k x nv).
    contact_jacobian: DMatrix<f64>,
    /// Which contacts carry load (k / 6; all by default): a walking foot in the air gets no
    /// share of the base rows' correction ([`Self::set_loaded_contacts`]).
    loaded: Vec<bool>,
    /// The base columns of the loaded contacts' rows, the others zero (6 k x 6).
    loaded_base: DMatrix<f64>,
    /// The contact wrenches `f` of this update (6 k).
    wrenches: DVector<f64>,
    /// The base rows' residual `r` of the last update (force; moment about the CoM) [N, Nm].
    residual: Vector6<f64>,
    /// Running mean of `r` over the accepted updates (the model's steady error), once set.
    residual_mean: Option<Vector6<f64>>,
    /// Running mean squares of the force and moment departures, each capped at its bound:
    /// the noise level of the external force check (module doc).
    departure_mean_square: (f64, f64),
    /// The robot's weight `m |g|` [N].
    weight: f64,
}

impl StiffnessIdentifier {
    /// The identifier of `controller`'s elastic joints, starting from the estimates `prior`
    /// (n_e, the loop's), with `controller`'s model and contacts.
    ///
    /// # Panics
    /// When `settings.range_factor` is not a number above 1 (the scenario's validation
    /// refuses such a `controller.identification_range_factor`).
    pub fn new(
        controller: &MomentumController,
        prior: &[ElasticParameters],
        settings: IdentificationSettings,
    ) -> Self {
        assert!(
            settings.range_factor > 1.0,
            "range_factor must be above 1, got {}",
            settings.range_factor
        );
        let model = controller.model().clone();
        let nv = model.nv();
        let contact_frames = controller.contact_frames().to_vec();
        let k = 6 * contact_frames.len();
        let prior: Vec<f64> = prior.iter().map(|p| p.stiffness).collect();
        let n_e = prior.len();
        let prior_weight = settings.prior_deflection.powi(2);
        Self {
            data: Data::new(&model),
            settings,
            contact_frames,
            elastic_joints: controller.actuation().elastic_joints.clone(),
            sum_deflection_squared: vec![prior_weight; prior.len()],
            sum_torque_deflection: prior.iter().map(|k_s| k_s * prior_weight).collect(),
            sample_weight: 0.0,
            elapsed: 0.0,
            hold_left: 0.0,
            prior,
            joint_inertia_regularization: controller.settings().tuning.joint_inertia_regularization,
            filtered_spring: vec![0.0; n_e],
            filtered_deflection: vec![0.0; n_e],
            has_filtered: false,
            nu_previous: vec![0.0; nv],
            has_previous: false,
            nudot: vec![0.0; nv],
            delayed_state: Vec::new(),
            delayed_wrenches: DVector::zeros(k),
            has_delayed: false,
            nu_before_delayed: vec![0.0; nv],
            has_nu_before_delayed: false,
            generalized_force: DVector::zeros(nv),
            contact_jacobian: DMatrix::zeros(k, nv),
            loaded: vec![true; k / 6],
            loaded_base: DMatrix::zeros(k, 6),
            wrenches: DVector::zeros(k),
            residual: Vector6::zeros(),
            residual_mean: None,
            departure_mean_square: (0.0, 0.0),
            weight: model.total_mass() * model.gravity.norm(),
            model,
        }
    }

    /// The departure of the base rows' force residual from its running mean at the last
    /// update [N]: with measured wrenches, the unmodelled external force on the robot.
    pub fn external_force(&self) -> f64 {
        let mean = self.residual_mean.unwrap_or(self.residual);
        (self.residual - mean).fixed_rows::<3>(0).norm()
    }

    /// The departure of the base rows' moment residual from its running mean at the last
    /// update [Nm] (about the CoM, world axes): with measured wrenches, the moment of the
    /// unmodelled external wrench and the first sample of a push (module doc).
    pub fn external_moment(&self) -> f64 {
        let mean = self.residual_mean.unwrap_or(self.residual);
        (self.residual - mean).fixed_rows::<3>(3).norm()
    }

    /// The joint torques `tau_model` (nv; joint rows from 6) of the last update [Nm].
    pub fn model_torques(&self) -> &[f64] {
        self.generalized_force.as_slice()
    }

    /// Which contacts carry load from the next update on (one flag per contact, the
    /// controller's order): the base rows' correction of the wrenches (module doc) is spread
    /// over the loaded ones only, so a walking foot in the air keeps its zero wrench. All
    /// loaded: the correction of the module doc.
    pub fn set_loaded_contacts(&mut self, loaded: &[bool]) {
        for (flag, &value) in self.loaded.iter_mut().zip(loaded) {
            *flag = value;
        }
    }

    /// A period the identification does not learn from (walking: a foot in the air or a
    /// contact change within `walking.identification_settle`, `crate::robot`): the estimates,
    /// sums, filters and external force check stay as they are; only the measured velocity
    /// of `x` (layout `layout`) is kept, so that the next update's finite-difference `nudot`
    /// spans one period (the first update after a hold has its acceleration, not zero).
    pub fn hold_sample(&mut self, layout: &StateLayout, x: &[f64]) {
        self.nu_previous.copy_from_slice(layout.nu(x));
        self.has_previous = true;
        // The central difference: no pending sample; `x`'s velocity is the next one's before.
        self.has_delayed = false;
        self.nu_before_delayed.copy_from_slice(layout.nu(x));
        self.has_nu_before_delayed = true;
    }

    /// One update at the measured state `x` (layout `layout`), `period` [s] after the
    /// previous one, with the contact wrenches `wrenches` (6 k, measured or commanded, at the
    /// contact frames' origins, world axes): refines the stiffness in `estimates` (n_e, e.g.
    /// the joint loop's). Returns false when the update was skipped (external force check,
    /// module doc), or, with the central difference, when no sample was ready to learn from
    /// (the first two updates, and the first after a hold).
    pub fn update(
        &mut self,
        layout: &StateLayout,
        x: &[f64],
        period: f64,
        wrenches: &DVector<f64>,
        estimates: &mut [ElasticParameters],
    ) -> bool {
        match self.settings.acceleration {
            IdentificationAcceleration::Backward => {
                self.backward_acceleration(layout.nu(x), period);
                self.learn(layout, x, period, wrenches, estimates)
            }
            IdentificationAcceleration::Central => {
                self.update_central(layout, x, period, wrenches, estimates)
            }
        }
    }

    /// [`Self::update`] with the central difference: the previous update's sample is learnt
    /// from, its `nudot` the difference of the velocities either side over `2 period`; `x`
    /// and `wrenches` become the pending sample.
    fn update_central(
        &mut self,
        layout: &StateLayout,
        x: &[f64],
        period: f64,
        wrenches: &DVector<f64>,
        estimates: &mut [ElasticParameters],
    ) -> bool {
        let mut made = false;
        if self.has_delayed && self.has_nu_before_delayed {
            let velocities = layout.nu(x).iter().zip(&self.nu_before_delayed);
            for (a, (after, before)) in self.nudot.iter_mut().zip(velocities) {
                *a = (after - before) / (2.0 * period);
            }
            // Taken out while `learn` borrows `self`, and put back (no allocation).
            let sample = std::mem::take(&mut self.delayed_state);
            let sample_wrenches = std::mem::replace(&mut self.delayed_wrenches, DVector::zeros(0));
            made = self.learn(layout, &sample, period, &sample_wrenches, estimates);
            (self.delayed_state, self.delayed_wrenches) = (sample, sample_wrenches);
        }
        if self.has_delayed {
            self.nu_before_delayed
                .copy_from_slice(layout.nu(&self.delayed_state));
            self.has_nu_before_delayed = true;
        }
        self.delayed_state.clear();
        self.delayed_state.extend_from_slice(x);
        self.delayed_wrenches.copy_from(wrenches);
        self.has_delayed = true;
        made
    }

    /// `nudot` of the backward difference from the previous update's `nu` (zero without
    /// one); `nu` becomes the previous.
    fn backward_acceleration(&mut self, nu: &[f64], period: f64) {
        if self.has_previous {
            for ((a, v), v0) in self.nudot.iter_mut().zip(nu).zip(&self.nu_previous) {
                *a = (v - v0) / period;
            }
        } else {
            self.nudot.fill(0.0);
        }
        self.nu_previous.copy_from_slice(nu);
        self.has_previous = true;
    }

    /// One least-squares update from the sample at `x` with `nudot` set (module doc).
    fn learn(
        &mut self,
        layout: &StateLayout,
        x: &[f64],
        period: f64,
        wrenches: &DVector<f64>,
        estimates: &mut [ElasticParameters],
    ) -> bool {
        self.model_joint_torques(layout, x, wrenches);
        let lambda = (-period / self.settings.time_constant).exp();
        if self.external_force_hold(period, lambda) {
            return false;
        }
        let mean = self.residual_mean.get_or_insert(self.residual);
        *mean = lambda * *mean + (1.0 - lambda) * self.residual;
        self.sample_weight = lambda * self.sample_weight + 1.0;
        let filter_blend = low_pass_blend(self.settings.filter_bandwidth, period);
        let noise_weight = self.noise_variance(filter_blend) * self.sample_weight;
        let blend = self.next_filter_blend(filter_blend);
        let (theta, s) = (layout.theta(x), layout.s(x));
        let (thetadot, sdot) = (layout.thetadot(x), layout.sdot(x));
        let joints = self.elastic_joints.iter().zip(estimates.iter_mut());
        for (e, (&j, estimate)) in joints.enumerate() {
            let deflection_rate = estimate.ratio * thetadot[e] - sdot[j];
            let spring = self.generalized_force[6 + j] - estimate.damping * deflection_rate;
            let deflection = estimate.ratio * theta[e] - s[j];
            let spring = low_pass(&mut self.filtered_spring[e], blend, spring);
            let deflection = low_pass(&mut self.filtered_deflection[e], blend, deflection);
            let sum_dd = &mut self.sum_deflection_squared[e];
            let sum_td = &mut self.sum_torque_deflection[e];
            *sum_dd = lambda * *sum_dd + deflection * deflection;
            *sum_td = lambda * *sum_td + spring * deflection;
            let compensated = *sum_dd - noise_weight;
            if noise_weight == 0.0 || compensated >= noise_weight {
                let (prior, range) = (self.prior[e], self.settings.range_factor);
                estimate.stiffness = (*sum_td / compensated).clamp(prior / range, range * prior);
            }
        }
        true
    }

    /// The blend of the samples' low pass for this update: `filter_blend` (`a = 1 - exp(-2 pi
    /// f_r T)` of the update's period), or 1 at the first update, which sets the filters.
    fn next_filter_blend(&mut self, filter_blend: f64) -> f64 {
        let first = !std::mem::replace(&mut self.has_filtered, true);
        if first {
            1.0
        } else {
            filter_blend
        }
    }

    /// The variance [rad^2] of the filtered deflection's noise for the filter's blend `a`:
    /// `sigma^2 a / (2 - a)` (module doc, "Filtering").
    fn noise_variance(&self, filter_blend: f64) -> f64 {
        self.settings.deflection_noise.powi(2) * filter_blend / (2.0 - filter_blend)
    }

    /// Whether this update is skipped by the external force check or the hold after it (module
    /// doc), `period` [s] after the previous update, with the forgetting factor `lambda` of
    /// that period.
    fn external_force_hold(&mut self, period: f64, lambda: f64) -> bool {
        self.elapsed += period;
        let Some(fraction) = self.settings.max_external_force else {
            return false;
        };
        let (force_bound, moment_bound) = self.external_bounds(fraction);
        let (force, moment) = (self.external_force(), self.external_moment());
        if self.settings.deflection_noise > 0.0 {
            // Noisy encoders declared: the noise level, each departure capped at its bound.
            let capped = (force.min(force_bound), moment.min(moment_bound));
            let (force_square, moment_square) = &mut self.departure_mean_square;
            *force_square = lambda * *force_square + (1.0 - lambda) * capped.0.powi(2);
            *moment_square = lambda * *moment_square + (1.0 - lambda) * capped.1.powi(2);
        }
        if force > force_bound || moment > moment_bound {
            let converged = self.elapsed >= 3.0 * self.settings.time_constant;
            if converged {
                self.hold_left = self.settings.hold_after_external_force;
            }
            return true;
        }
        self.hold_left -= period;
        self.hold_left > 0.0
    }

    /// The external force check's bounds `(force [N], moment [Nm])` for the force bound
    /// `fraction` of the weight (module doc): that force and its moment at
    /// `external_moment_arm`, or [`NOISE_BOUND_FACTOR`] times the departures' rms when the
    /// measurements are noisier.
    fn external_bounds(&self, fraction: f64) -> (f64, f64) {
        let force = fraction * self.weight;
        let moment = force * self.settings.external_moment_arm;
        let (force_square, moment_square) = self.departure_mean_square;
        (
            force.max(NOISE_BOUND_FACTOR * force_square.sqrt()),
            moment.max(NOISE_BOUND_FACTOR * moment_square.sqrt()),
        )
    }

    /// The identification's fixed point at a state `x` held still (an equilibrium, where
    /// `nudot = 0` and `deltadot = 0`): every sample the same, the prior forgotten, each
    /// joint's estimate is `tau_model / delta` (kept as it is where `|delta| < 1e-9` rad), with
    /// the contact wrenches `wrenches` (6 k). For the linearisation with the identification
    /// converged; the identifier's own state is left as it was.
    pub fn converged_at(
        &mut self,
        layout: &StateLayout,
        x: &[f64],
        wrenches: &DVector<f64>,
        estimates: &mut [ElasticParameters],
    ) {
        self.nudot.fill(0.0);
        self.model_joint_torques(layout, x, wrenches);
        let (theta, s) = (layout.theta(x), layout.s(x));
        let joints = self.elastic_joints.iter().zip(estimates.iter_mut());
        for (e, (&j, estimate)) in joints.enumerate() {
            let deflection = estimate.ratio * theta[e] - s[j];
            if deflection.abs() >= 1e-9 {
                let prior = self.prior[e];
                let stiffness = self.generalized_force[6 + j] / deflection;
                let range = self.settings.range_factor;
                estimate.stiffness = stiffness.clamp(prior / range, range * prior);
            }
        }
    }

    /// `(M + D) nudot + h - J^T f` at `x` into `generalized_force` (module doc), with the
    /// `nudot` set.
    fn model_joint_torques(&mut self, layout: &StateLayout, x: &[f64], wrenches: &DVector<f64>) {
        let (q, nu) = (layout.q(x), layout.nu(x));
        let inverse_dynamics = rnea(&self.model, &mut self.data, q, nu, &self.nudot);
        self.generalized_force.copy_from(inverse_dynamics);
        let joint_rows = self.generalized_force.iter_mut().zip(&self.nudot).skip(6);
        for (force, acceleration) in joint_rows {
            *force += self.joint_inertia_regularization * acceleration;
        }
        for (c, &frame) in self.contact_frames.iter().enumerate() {
            frame_jacobian_from_kinematics(&self.model, &mut self.data, frame);
            let mut rows = self.contact_jacobian.rows_mut(6 * c, 6);
            rows.copy_from(&self.data.frame_jacobian);
        }
        self.base_consistent_wrenches(wrenches);
        let jacobian = &self.contact_jacobian;
        self.generalized_force
            .gemv_tr(-1.0, jacobian, &self.wrenches, 1.0);
    }

    /// `f = f_0 + J_b (J_b^T J_b)^-1 (tau_b - J_b^T f_0)` into `self.wrenches` from the given
    /// `wrenches` `f_0`, with the base rows `tau_b` of `generalized_force` (before the contact
    /// term).
    fn base_consistent_wrenches(&mut self, wrenches: &DVector<f64>) {
        self.wrenches.copy_from(wrenches);
        if self.contact_frames.is_empty() {
            return;
        }
        let base = self.contact_jacobian.fixed_columns::<6>(0);
        let residual: Vector6<f64> =
            self.generalized_force.fixed_rows::<6>(0) - base.tr_mul(&self.wrenches);
        self.residual = about_the_com(&residual, &self.data);
        if self.loaded.iter().all(|&loaded| loaded) {
            let normal: Matrix6<f64> = base.tr_mul(&base);
            if let Some(solution) = normal.cholesky().map(|c| c.solve(&residual)) {
                self.wrenches.gemv(1.0, &base, &solution, 1.0);
            }
            return;
        }
        // Only the loaded contacts' rows take the correction.
        self.loaded_base.copy_from(&base);
        for (c, &loaded) in self.loaded.iter().enumerate() {
            if !loaded {
                self.loaded_base.rows_mut(6 * c, 6).fill(0.0);
            }
        }
        let loaded_base = &self.loaded_base;
        let normal = loaded_base.tr_mul(loaded_base);
        if let Some(solution) = normal.cholesky().map(|c| c.solve(&residual)) {
            self.wrenches.gemv(1.0, loaded_base, &solution, 1.0);
        }
    }
}

/// One step of a first-order low pass: `state <- state + blend (sample - state)`; returns the
/// new state.
fn low_pass(state: &mut f64, blend: f64, sample: f64) -> f64 {
    *state += blend * (sample - *state);
    *state
}

/// The base rows' wrench `wrench_o` (force; moment about the base origin `O`, world axes) as
/// force and moment about the CoM, with the body inertias at `O` that `rnea` left in `data`:
/// a model's mass error then shows as a force only, whatever the posture (its moment about the
/// CoM is that of the error's own centre of mass, not the moving arm from `O`).
fn about_the_com(wrench_o: &Vector6<f64>, data: &Data) -> Vector6<f64> {
    let mut whole = SpatialInertia::zero();
    for body in &data.body_inertia {
        whole += *body;
    }
    let force = wrench_o.fixed_rows::<3>(0).into_owned();
    let about_o = Force::new(force, wrench_o.fixed_rows::<3>(3).into_owned());
    about_o.moment_about(&whole.com()).to_vector()
}
