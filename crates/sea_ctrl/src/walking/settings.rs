//! The walking settings ([`WalkingSettings`]): the gait's timing, the linear inverted
//! pendulum's height, the step limits, the swing clearance, the push-recovery step's bounds,
//! and the walking command ([`WalkCommand`]) or an explicit list of footsteps
//! ([`FootstepSpec`]). With the `serde` feature each is a table whose missing keys take the
//! defaults and whose unknown keys are errors, ready for a `[walking]` scenario table.
//! [`WalkingSettings::validate`] names the offending key (`walking.step_duration`, ...).

use super::footstep::{Foot, SolePose};
use super::lip::Lip;
use super::step_timing::StepTiming;
use crate::error::{require_positive, Result};
use nalgebra::Vector2;

/// The walking command: velocities of the walking frame (the frame midway between the feet)
/// and how long to walk. With the `serde` feature, the table `[walking.command]`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct WalkCommand {
    /// Forward velocity along the walking frame's x axis [m/s]; the step's forward length
    /// `forward_velocity * step_duration` is clipped to `max_step_length` (a warning at the
    /// run's start names both keys and the speed walked).
    pub forward_velocity: f64,
    /// Sideways velocity along the walking frame's y axis (left positive) [m/s]; the step's
    /// lateral shift is clipped so that the feet stay `min_step_width`..`max_step_width` apart
    /// (with a warning, as `forward_velocity`).
    pub sideways_velocity: f64,
    /// Turning velocity about the vertical (counter-clockwise positive) [rad/s]; the turn per
    /// step is clipped to `max_step_turn` (with a warning, as `forward_velocity`).
    pub turning_velocity: f64,
    /// The foot that takes the first step ("left" or "right").
    pub first_foot: Foot,
    /// The number of steps of the command (1 to 100000, [`MAX_COMMAND_STEPS`]), after which
    /// one more step brings the feet side by side; set this or `duration`.
    #[cfg_attr(feature = "serde", schemars(range(min = 1, max = 100000)))]
    pub steps: Option<usize>,
    /// How long to walk [s] (> 0, below `MAX_COMMAND_STEPS` steps): `floor(duration /
    /// step_duration)` steps (at least one), then the stop step; set this or `steps`.
    pub duration: Option<f64>,
}

impl Default for WalkCommand {
    /// Standing still: zero velocities, the left foot first, no length set.
    fn default() -> Self {
        Self {
            forward_velocity: 0.0,
            sideways_velocity: 0.0,
            turning_velocity: 0.0,
            first_foot: Foot::Left,
            steps: None,
            duration: None,
        }
    }
}

/// One footstep of an explicit list: which foot lands where (world, on the ground). With the
/// `serde` feature, an entry of `[[walking.footsteps]]`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(deny_unknown_fields)
)]
pub struct FootstepSpec {
    /// The foot that steps ("left" or "right").
    pub foot: Foot,
    /// Sole origin x in world [m].
    pub x: f64,
    /// Sole origin y in world [m].
    pub y: f64,
    /// Sole yaw about world z [rad].
    pub yaw: f64,
}

impl FootstepSpec {
    /// The sole pose this entry names.
    pub fn pose(&self) -> SolePose {
        SolePose::new(Vector2::new(self.x, self.y), self.yaw)
    }
}

/// Settings of the walking planner. Defaults: an iCub-sized robot (LIP height 0.53 m, so
/// `omega` about 4.3 1/s, docs/references.md#walking), to be scaled to the robot by the caller.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct WalkingSettings {
    /// Height of the linear inverted pendulum's CoM above the soles `z0` [m], > 0;
    /// `omega = sqrt(g / z0)`.
    pub com_height: f64,
    /// Duration of one step [s]: its single support (the swing) and the double support that
    /// follows; at least one whole-body period.
    pub step_duration: f64,
    /// Double support within each step [s], in [one whole-body period, `step_duration` - one
    /// whole-body period].
    pub double_support_duration: f64,
    /// The double support from standing into the first step and from the last step back to
    /// standing over the mid-feet point [s], at least one whole-body period.
    pub transfer_duration: f64,
    /// With `controller.stiffness_identification`: the identification updates the stiffness
    /// estimates only while both feet are on the ground and have been for at least this
    /// long [s] (a lift-off, a planned or sensed touchdown, and the run's start reopen the
    /// window), and holds them otherwise, keeping only the measured velocity for its next
    /// finite difference (`sea_ctrl::robot`, `StiffnessIdentifier::hold_sample`); >= 0,
    /// default 0.2 s. Above `double_support_duration` (the iCub's gaits: 0.1 and 0.15 s) the
    /// estimates are held from the first lift-off to the walk's end: they are learnt in the
    /// initial transfer (whose sideways CoM shift loads the hips' and ankles' roll joints)
    /// and standing after the walk. At 0 the first sample, in the feet's settling on the
    /// ground, moves the estimates by up to 16 % and the walks fall (docs/findings/walking.md,
    /// "The stiffness identification while walking").
    pub identification_settle: f64,
    /// With `controller.stiffness_identification`: also update in single support once the
    /// stance foot has stood alone for at least this long [s] (unset, the default: hold the
    /// estimates through every single support). With the central difference
    /// (`controller.identification_acceleration = "central"`) 0.1 s keeps the iCub's walks
    /// complete and their legs' estimates within 2 % under x0.7 / x1.4, and lets MuJoCo's SEA
    /// iCub walk walk_fast from x0.7 with the shipped 0.6 s transfer; with the backward
    /// difference the same learning loses walk_fast (docs/findings/walking.md, "Learning in
    /// single support"). Finite and >= 0.
    #[cfg_attr(feature = "serde", serde(skip_serializing_if = "Option::is_none"))]
    pub identification_single_support: Option<f64>,
    /// Apex height of the swing sole above the ground [m], >= 0.
    pub swing_height: f64,
    /// The swing sole's toe-off: its largest pitch, toe down about the toe (the front edge
    /// of the sole's contact rectangle), reached at half of `swing_toe_off_end` and gone by
    /// it [rad], in [0, 0.5] (default 0: the sole swings flat; `walking::ToeOff`). On the
    /// iCub at 0.4 m/s, 0.1 rad completes 20 of 72 gaits under the true stiffness estimate
    /// and x0.7 / x1.4 identified alike, against 4 flat; at 0.35 m/s it loses (with the end
    /// at 0.55, 44 of 72 against 69 under the true estimate), so walk_04.toml sets it and the
    /// default stays flat (docs/findings/walking.md, "0.4 m/s: a toe-off").
    pub swing_toe_off_pitch: f64,
    /// The fraction of the swing by which a toe-off's sole is flat again, in (0, 1]
    /// (default 0.5).
    pub swing_toe_off_end: f64,
    /// Nominal lateral distance between the sole origins [m], in (`min_step_width`,
    /// `max_step_width`).
    pub nominal_width: f64,
    /// Largest forward or backward distance of the landing sole from the stance sole, in the
    /// stance sole's frame [m], > 0 (the reach; default 0.17, the iCub's: a step adjusted to
    /// 0.2 m at a CoM height of 0.51 m straightens the swing knee onto its stop with the sole
    /// still 16-18 mm above the ground, and the foot lands on its toe; docs/findings/stepping.md).
    pub max_step_length: f64,
    /// Smallest lateral distance of the landing sole from the stance sole, on its own side, in
    /// the stance sole's frame [m], > 0 (the feet do not collide or cross).
    pub min_step_width: f64,
    /// Largest lateral distance of the landing sole from the stance sole in the stance sole's
    /// frame [m] (the lateral reach).
    pub max_step_width: f64,
    /// Largest yaw of the landing sole relative to the stance sole [rad], in (0, pi/2].
    pub max_step_turn: f64,
    /// Shortest swing of a push-recovery step [s], at least one whole-body period.
    pub min_swing_duration: f64,
    /// A step is needed when the measured capture point is outside the support polygon or
    /// closer to its edge than this margin [m], taken by the DCM's direction from the mid-feet
    /// point ([`CaptureMargin`]): a number (the same margin in every direction) or a table
    /// `{ forward, backward, sideways }` (a key left out: its default). Default: 0.01 m
    /// forward, 0 backward and sideways.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "CaptureMargin::read"),
        schemars(with = "CaptureMarginInput")
    )]
    pub capture_margin: CaptureMargin,
    /// Position gain of the swing sole's tracking (the PD on its pose error added to the swing
    /// trajectory's acceleration) [1/s^2], >= 0.
    pub swing_position_gain: f64,
    /// Velocity gain of the swing sole's tracking [1/s], >= 0.
    pub swing_velocity_gain: f64,
    /// Position gain of the PD that settles a foot on the ground flat on it (its height to
    /// the ground, its roll and pitch to zero; `controller::contact_phase::settle_acceleration`)
    /// [1/s^2], >= 0 (default 100: with 20 below, critically damped at 10 rad/s); 0 with
    /// `settle_velocity_gain` 0: the foot is held where it is (the paper's contact, zero
    /// acceleration; then landing soles that bounce or rock stay in the air, and 50 steps at
    /// 0.3 m/s end early, docs/findings/walking.md).
    pub settle_position_gain: f64,
    /// Velocity gain of the PD that settles a foot on the ground [1/s], >= 0 (default 20).
    pub settle_velocity_gain: f64,
    /// Double support: the momentum task in least squares with this weight (times the
    /// torque objective's mean diagonal) instead of the paper's equality `A f = b`, >= 0
    /// (default 0: the equality, which at a touchdown loads the landing foot at once with
    /// the momentum rate the stance foot could not produce).
    pub double_support_momentum_weight: f64,
    /// Whether the feet's force/torque sensors move the touchdowns (an early touchdown holds
    /// the foot, a late foot keeps descending; `controller::contact_phase`), default `true`
    /// (every shipped walk completes either way, the iCub's feet touch down early at every
    /// step, and a robot's touchdowns do not keep to a plan's time; docs/findings/walking.md);
    /// `false`: the plan's timing alone.
    pub sensed_touchdown: bool,
    /// With `sensed_touchdown`: how long a foot's sensor must read it loaded (or unloaded)
    /// before the controller takes the foot as landed (or lifted) [s], >= 0 (default 0.01:
    /// one period of a 100 Hz whole-body loop, so there every reading counts at once); each
    /// reading stands for the period before it (`controller::touchdown_debounce`,
    /// `DebouncedLoad`). At a 1 kHz whole-body loop the feet's forces chatter at every
    /// touchdown, and without it 14 of 72 gaits at 0.3 m/s complete against 45 with it
    /// (docs/findings/walking.md, "Touchdowns at a 1 kHz whole-body loop").
    pub touchdown_debounce: f64,
    /// Stepping to recover a push while standing (`controller::stepping`): each whole-body
    /// tick the measured DCM is checked against the support polygon (`capture_margin`); when
    /// it needs a step, a recovery step is planned from it ([`super::recovery_step`]) and
    /// walked, then the robot stands over its new feet. Only standing: with `true`, leave
    /// `command` and `footsteps` unset (pushes while walking are not handled).
    pub stepping: bool,
    /// Stepping: the most recovery steps taken one after the other after a push (a second
    /// step when the first does not capture the DCM), >= 1.
    #[cfg_attr(feature = "serde", schemars(range(min = 1)))]
    pub max_recovery_steps: usize,
    /// Stepping: the double support that moves the load off the swing foot before a
    /// recovery step lifts off [s], at least one whole-body period.
    pub recovery_transfer_duration: f64,
    /// Stepping: how far beyond the DCM predicted at touchdown the swing sole is aimed, along
    /// the DCM's motion away from the stance's centre of pressure [m], >= 0
    /// ([`super::recovery_step_beyond`]).
    pub recovery_step_offset: f64,
    /// Step adjustment while walking (`controller::step_adjustment`, [`super::adjust_step`]):
    /// at each whole-body tick of a swing whose measured DCM is more than
    /// `step_adjustment_threshold` from the plan's, the swing's landing (and every later
    /// footstep with it) is moved by that error grown to touchdown,
    /// `(xi_measured - xi_planned) e^(omega t_remaining)`, clipped to the step limits
    /// (`max_step_length`, `min_step_width`..`max_step_width`: the feet never cross); the DCM
    /// plan is made again from the measured state over the moved footsteps (the stance's
    /// centre of pressure, within its sole, taking what the clipping leaves) and the swing
    /// re-aimed in flight, until `step_adjustment_end_phase` of the swing. `false`: the plan
    /// as made at the start.
    pub step_adjustment: bool,
    /// Step adjustment: the DCM error [m] (measured minus planned, now) above which a
    /// swing's landing is moved, >= 0 (default 0.005, within the iCub's tracking errors of an
    /// unpushed walk, up to 0.7 cm, which are then adjusted by 1-2 cm: with 0.03 a push of
    /// 4 N s to the side does not reach the threshold in its own swing, and the walk falls;
    /// docs/findings/stepping.md).
    pub step_adjustment_threshold: f64,
    /// Step adjustment: the fraction of a swing after which its landing is no longer moved,
    /// in (0, 1] (default 0.8). In the last ticks of each unpushed iCub swing the measured DCM
    /// error jumps to 1.1-1.6 cm as the foot meets the ground; a landing moved then has one
    /// or two periods to get there, and walk_fast.toml adjusted there falls (with
    /// `step_adjustment_threshold` 0.01; docs/findings/stepping.md).
    pub step_adjustment_end_phase: f64,
    /// Step adjustment: whether a swing whose adjusted landing lies beyond the step limits
    /// lands earlier ([`super::step_timing`], after Khadiv et al. 2016): `"fixed"` (default,
    /// the plan's timing), `"sideways"` (a landing clipped to
    /// `min_step_width`..`max_step_width`) or `"any"` (clipped in any direction, the reach
    /// too). On walk_push.toml's template `"sideways"` with 0.15 s swings clears 8.3 N s in
    /// every sideways push cell; on the iCub the ideal controller then recovers 84 of 108
    /// pushes against 73, the design 75, and `"any"` loses forward pushes
    /// (docs/findings/walking_template.md).
    pub step_timing: StepTiming,
    /// Step timing: the shortest swing a timing adaptation makes [s], at least one whole-body
    /// period and, with `step_timing` other than `"fixed"`, at most the single support and,
    /// with a toe-off, at least its end (`swing_toe_off_end` of the single support) (default
    /// 0.2).
    pub min_adjusted_swing_duration: f64,
    /// The walking command, used when `footsteps` is empty (refused with `footsteps`).
    pub command: WalkCommand,
    /// Explicit footsteps, in order (empty: footsteps from `command`; refused with a
    /// `command` that sets a velocity, `steps` or `duration`).
    pub footsteps: Vec<FootstepSpec>,
}

impl Default for WalkingSettings {
    fn default() -> Self {
        Self {
            com_height: 0.53,
            step_duration: 0.6,
            double_support_duration: 0.15,
            transfer_duration: 0.6,
            identification_settle: 0.2,
            identification_single_support: None,
            swing_height: 0.03,
            swing_toe_off_pitch: 0.0,
            swing_toe_off_end: 0.5,
            nominal_width: 0.14,
            max_step_length: 0.17,
            min_step_width: 0.09,
            max_step_width: 0.25,
            max_step_turn: 0.35,
            min_swing_duration: 0.3,
            capture_margin: CaptureMargin::default(),
            swing_position_gain: 400.0,
            swing_velocity_gain: 40.0,
            settle_position_gain: 100.0,
            settle_velocity_gain: 20.0,
            double_support_momentum_weight: 0.0,
            sensed_touchdown: true,
            touchdown_debounce: 0.01,
            stepping: false,
            max_recovery_steps: 2,
            recovery_transfer_duration: 0.1,
            recovery_step_offset: 0.03,
            step_adjustment: false,
            step_adjustment_threshold: 0.005,
            step_adjustment_end_phase: 0.8,
            step_timing: StepTiming::Fixed,
            min_adjusted_swing_duration: 0.2,
            command: WalkCommand::default(),
            footsteps: Vec::new(),
        }
    }
}

/// How close the measured DCM may come to the support polygon's edge before a recovery step
/// is taken [m], each >= 0, by the DCM's direction from the mid-feet point in the mid-feet
/// frame, `u` (unit; x forward): `forward max(u_x, 0)^2 + backward max(-u_x, 0)^2 + sideways
/// u_y^2`, so equal margins are that margin in every direction (the direction is the DCM's,
/// not the nearest edge's normal: near a front corner the forward margin is blended with the
/// sideways one). A margin steps before the DCM reaches the edge, which buys the swing time;
/// it pays forward, where a step captures far beyond the stance. Sideways a step of the loaded
/// foot captures no more than standing, and a small step backward drifts sideways and falls,
/// so both step at the edge by default (docs/findings/stepping.md, "Where a step is needed").
/// A key left out of the table takes its default.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct CaptureMargin {
    /// The margin ahead of the feet [m].
    pub forward: f64,
    /// The margin behind the feet [m].
    pub backward: f64,
    /// The margin on either side [m].
    pub sideways: f64,
}

/// A scenario's `walking.capture_margin`: a number or a table.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
enum CaptureMarginInput {
    /// The same margin in every direction [m].
    Uniform(f64),
    /// A margin per direction.
    Directions(CaptureMargin),
}

impl Default for CaptureMargin {
    /// 0.01 m forward, 0 backward and sideways.
    fn default() -> Self {
        Self {
            forward: 0.01,
            backward: 0.0,
            sideways: 0.0,
        }
    }
}

impl CaptureMargin {
    /// The same margin `margin` [m] in every direction.
    pub fn uniform(margin: f64) -> Self {
        Self {
            forward: margin,
            backward: margin,
            sideways: margin,
        }
    }

    /// The margin [m] for a DCM in the direction `direction` from the mid-feet point (mid-feet
    /// frame; any length, zero: 0).
    pub fn toward(&self, direction: Vector2<f64>) -> f64 {
        let norm = direction.norm();
        if norm <= 0.0 {
            return 0.0;
        }
        let u = direction / norm;
        self.forward * u.x.max(0.0).powi(2)
            + self.backward * (-u.x).max(0.0).powi(2)
            + self.sideways * u.y * u.y
    }

    /// Every margin times `scale`.
    pub fn scaled(&self, scale: f64) -> Self {
        Self {
            forward: self.forward * scale,
            backward: self.backward * scale,
            sideways: self.sideways * scale,
        }
    }

    /// Reads a number (every direction) or a table (a key left out: its default).
    #[cfg(feature = "serde")]
    fn read<'de, D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Self, D::Error> {
        use serde::de::Error as _;
        let input = <CaptureMarginInput as serde::Deserialize>::deserialize(deserializer).map_err(
            |_| {
                D::Error::custom(
                    "expected a number or a table with numbers among forward, backward, sideways",
                )
            },
        )?;
        Ok(match input {
            CaptureMarginInput::Uniform(margin) if !(margin.is_finite() && margin >= 0.0) => {
                return Err(D::Error::custom(format!(
                    "must be non-negative and finite, got {margin}"
                )));
            }
            CaptureMarginInput::Uniform(margin) => Self::uniform(margin),
            CaptureMarginInput::Directions(margins) => margins,
        })
    }
}

/// The figures of a robot standing that the walking settings scale with
/// ([`WalkingSettings::scaled_to`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotWalkingFigures {
    /// The CoM's height above the soles, standing [m].
    pub com_height: f64,
    /// The horizontal distance between the two sole origins, standing [m].
    pub feet_distance: f64,
    /// The straight leg's length [m]: the sum of the distances between the leg's joint
    /// origins from the hip down to the sole (the shorter leg's).
    pub leg_length: f64,
    /// The longest step the legs reach from the standing posture, `2 sqrt(L^2 - h^2)` (straight
    /// leg `L`, hip height `h`) [m].
    pub reach: f64,
}

/// The iCub's straight leg length [m] (urdf/icub25.urdf, hip yaw origin to sole: 0.5436 m), the
/// length the defaults are sized for and [`WalkingSettings::scaled_to`] scales from.
pub const ICUB_LEG_LENGTH: f64 = 0.5436;

/// `max_step_length` of [`WalkingSettings::scaled_to`] as a fraction of the legs' reach (the
/// iCub's 0.17 m, measured walking, is 0.37 of its 0.459 m; the robots set up by `init` take
/// 0.6, not measured that way).
pub const STEP_LENGTH_PER_REACH: f64 = 0.6;

/// The most steps a walking command may ask for (`walking.command.steps`, or
/// `walking.command.duration / walking.step_duration`): the plan holds every step, its
/// swing and its DCM segments from the start (about 11 hours of 0.4 s steps).
pub const MAX_COMMAND_STEPS: usize = 100_000;

impl WalkingSettings {
    /// The defaults scaled to a robot of `figures` (the rule `sea-sim init` writes,
    /// docs/explanation/walking.md#settings): `com_height` the CoM's standing height,
    /// `nominal_width` the feet's distance, `min_step_width` and `max_step_width` the defaults'
    /// in proportion to it, `max_step_length` [`STEP_LENGTH_PER_REACH`] of the reach; with the
    /// length ratio `k = leg_length / ICUB_LEG_LENGTH`, `swing_height`, `capture_margin` and
    /// `step_adjustment_threshold` times `k` and every duration (step, double support, transfer, shortest swings) times
    /// `sqrt(k)` (a pendulum's time scale); the swing gains, the command and the footsteps as
    /// the defaults'. An error names the figure that is not positive and finite.
    pub fn scaled_to(figures: &RobotWalkingFigures) -> Result<Self> {
        for (name, value) in [
            ("com_height", figures.com_height),
            ("feet_distance", figures.feet_distance),
            ("leg_length", figures.leg_length),
            ("reach", figures.reach),
        ] {
            require_positive(format!("walking figures: {name}"), value)?;
        }
        let icub = Self::default();
        let length_scale = figures.leg_length / ICUB_LEG_LENGTH;
        let time_scale = length_scale.sqrt();
        let width_scale = figures.feet_distance / icub.nominal_width;
        Ok(Self {
            com_height: figures.com_height,
            step_duration: icub.step_duration * time_scale,
            double_support_duration: icub.double_support_duration * time_scale,
            transfer_duration: icub.transfer_duration * time_scale,
            swing_height: icub.swing_height * length_scale,
            nominal_width: figures.feet_distance,
            max_step_length: STEP_LENGTH_PER_REACH * figures.reach,
            min_step_width: icub.min_step_width * width_scale,
            max_step_width: icub.max_step_width * width_scale,
            min_swing_duration: icub.min_swing_duration * time_scale,
            min_adjusted_swing_duration: icub.min_adjusted_swing_duration * time_scale,
            capture_margin: icub.capture_margin.scaled(length_scale),
            step_adjustment_threshold: icub.step_adjustment_threshold * length_scale,
            ..icub
        })
    }

    /// The pendulum of `com_height` under gravity of magnitude `gravity` [m/s^2] (the
    /// model's); an error names `walking.com_height` when it is not positive.
    pub fn lip(&self, gravity: f64) -> Result<Lip> {
        Lip::new(gravity, self.com_height)
    }

    /// The swing of each step (single support) [s]: `step_duration - double_support_duration`.
    pub fn single_support_duration(&self) -> f64 {
        self.step_duration - self.double_support_duration
    }

    /// The number of command steps (before the stop step): `steps`, or
    /// `floor(duration / step_duration)` at least 1. `None` when neither is set.
    pub fn command_steps(&self) -> Option<usize> {
        match (self.command.steps, self.command.duration) {
            (Some(steps), _) => Some(steps),
            (None, Some(duration)) => {
                Some(((duration / self.step_duration).floor() as usize).max(1))
            }
            (None, None) => None,
        }
    }
}
