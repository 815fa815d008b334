//! Footsteps from a walking command ([`footsteps_from_command`]) or from an explicit list
//! ([`footsteps_from_list`]).
//!
//! The command moves the walking frame (midway between the feet) once per step by the
//! command's velocities times `step_duration`, expressed in the frame before the step:
//! `dx = clamp(v_x T, +-max_step_length)`, `dy = clamp(v_y T, +-(room))`,
//! `dtheta = clamp(omega_z T, +-max_step_turn)`, where the lateral room keeps the feet
//! `nominal_width +- dy` within [`min_step_width`, `max_step_width`]. The swing foot lands
//! at its side of the moved frame, `nominal_width / 2` off its x axis, with the frame's yaw:
//! the stance width is kept in the turned frame. After the command's steps one more step puts
//! the other foot beside the last one (the stop: feet side by side, same yaw). Each landing
//! is then moved into the step limits in the frame of the sole it stands on (a turn of
//! `dtheta` moves the landing about `nominal_width / 2 sin(dtheta)` forward or back there),
//! and the walking frame follows the landing. A simpler
//! per-step integration than the unicycle planner of bipedal-locomotion-framework
//! (docs/references.md#walking), which optimises the path of the frame between steps.

use super::footstep::{wrap_angle, Foot, FootstepPlan, SolePose, Stance};
use super::settings::WalkingSettings;
use crate::error::{Error, Result};
use nalgebra::Vector2;

/// The footsteps of `settings.command` from the standing `initial` feet: the command's
/// steps (`steps`, or as many as fit in `duration`), alternating from `first_foot`, then the
/// stop step. Every step is checked (footstep::check_step); an error names
/// `walking.command[index]`.
pub fn footsteps_from_command(settings: &WalkingSettings, initial: Stance) -> Result<FootstepPlan> {
    let steps = settings.command_steps().ok_or_else(|| {
        Error::config(
            "walking.command.steps",
            "set exactly one of walking.command.steps and walking.command.duration",
        )
    })?;
    let increment = frame_increment(settings);
    let width = settings.nominal_width;
    let (mut frame, mut feet) = (initial.mid_frame(), initial);
    let mut foot = settings.command.first_foot;
    let mut placements = Vec::with_capacity(steps + 1);
    for _ in 0..steps {
        let wished = beside_frame(advance(frame, increment), foot, width);
        let landing = within_limits(settings, feet.get(foot.other()), foot, wished);
        // The walking frame: half the width inwards of the landing, with its yaw.
        frame = beside_frame(landing, foot.other(), width);
        feet.set(foot, landing);
        placements.push((foot, landing));
        foot = foot.other();
    }
    placements.push((foot, beside_frame(frame, foot, width)));
    FootstepPlan::timed(settings, initial, &placements, "walking.command")
}

/// The footsteps of an explicit list (`settings.footsteps`, or `list` when given) from the
/// standing `initial` feet; a step the feet cannot take is an error naming
/// `walking.footsteps[index]` and the limit.
pub fn footsteps_from_list(
    settings: &WalkingSettings,
    initial: Stance,
    list: &[(Foot, SolePose)],
) -> Result<FootstepPlan> {
    FootstepPlan::timed(settings, initial, list, "walking.footsteps")
}

/// The footsteps the settings ask for: the explicit list when `settings.footsteps` is not
/// empty, else the command's.
pub fn footsteps_from_settings(
    settings: &WalkingSettings,
    initial: Stance,
) -> Result<FootstepPlan> {
    if settings.stepping {
        // Standing: no planned step; pushes add the recovery steps (`walking::recovery`).
        FootstepPlan::timed(settings, initial, &[], "walking")
    } else if settings.footsteps.is_empty() {
        footsteps_from_command(settings, initial)
    } else {
        let list: Vec<_> = settings
            .footsteps
            .iter()
            .map(|s| (s.foot, s.pose()))
            .collect();
        footsteps_from_list(settings, initial, &list)
    }
}

/// Stop on command: `plan`'s steps up to `last` (inclusive; the step under way, or any later
/// one), then one step of the other foot to the side of the sole landed last, the nominal
/// width apart with its yaw (feet side by side), unless it is there already. The kept steps
/// keep their timing.
pub fn stop_after(
    settings: &WalkingSettings,
    plan: &FootstepPlan,
    last: usize,
) -> Result<FootstepPlan> {
    let kept = plan.steps.len().min(last + 1);
    let mut placements: Vec<_> = plan.steps[..kept]
        .iter()
        .map(|step| (step.foot, step.pose))
        .collect();
    if let Some(&(foot, landed)) = placements.last() {
        let offset = Vector2::new(0.0, -foot.side() * settings.nominal_width);
        let beside = SolePose::new(landed.to_world(offset), landed.world_yaw_sole);
        let other = plan.stances[kept].get(foot.other());
        let already = (other.world_p_sole - beside.world_p_sole).norm() < 1e-9
            && wrap_angle(other.world_yaw_sole - beside.world_yaw_sole).abs() < 1e-9;
        if !already {
            placements.push((foot.other(), beside));
        }
    }
    FootstepPlan::timed(settings, plan.stances[0], &placements, "walking.command")
}

/// The walking frame's motion per step in its own axes: (dx, dy, dtheta), clipped to the
/// step limits (module doc).
fn frame_increment(settings: &WalkingSettings) -> (f64, f64, f64) {
    let [dx, dy, dtheta] = command_increments(settings).map(|axis| axis.allowed);
    (dx, dy, dtheta)
}

/// One axis of the command per step: what the velocity asks and what the step limit allows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommandClip {
    /// The command's key, e.g. `walking.command.forward_velocity`.
    pub key: &'static str,
    /// The velocity the command gives [m/s or rad/s].
    pub velocity: f64,
    /// The motion per step it asks, `velocity * step_duration` [m or rad].
    pub asked: f64,
    /// The motion per step the limit allows, `asked` clamped to +-`limit` [m or rad].
    pub allowed: f64,
    /// The settings that bound the axis, e.g. `walking.max_step_length`, or
    /// `walking.max_step_width - walking.nominal_width` sideways.
    pub limit_rule: &'static str,
    /// The bound on the motion per step [m or rad].
    pub limit: f64,
    /// The step duration [s].
    pub step_duration: f64,
    /// The unit of the motion per step (`m` or `rad`).
    pub unit: &'static str,
}

impl std::fmt::Display for CommandClip {
    /// E.g. `walking.command.forward_velocity = 0.5 m/s asks 0.250 m per 0.5 s step;
    /// walking.max_step_length allows 0.170 m: the walk goes at 0.340 m/s`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (unit, period) = (self.unit, self.step_duration);
        write!(
            f,
            "{} = {} {unit}/s asks {:.3} {unit} per {period} s step; {} allows {:.3} {unit}: \
             the walk goes at {:.3} {unit}/s",
            self.key,
            self.velocity,
            self.asked,
            self.limit_rule,
            self.limit,
            self.allowed / period,
        )
    }
}

/// The command's three axes per step (forward, sideways, turning), each with the limit
/// that bounds it: `max_step_length`; the lateral room that keeps the feet
/// `min_step_width`..`max_step_width` apart around `nominal_width`; `max_step_turn`.
pub fn command_increments(settings: &WalkingSettings) -> [CommandClip; 3] {
    let period = settings.step_duration;
    let command = &settings.command;
    let width = settings.nominal_width;
    let (to_max, to_min) = (
        settings.max_step_width - width,
        width - settings.min_step_width,
    );
    let (lateral_key, lateral_room) = if to_max <= to_min {
        ("walking.max_step_width - walking.nominal_width", to_max)
    } else {
        ("walking.nominal_width - walking.min_step_width", to_min)
    };
    let axis = |key, velocity: f64, limit_rule, limit: f64, unit| CommandClip {
        key,
        velocity,
        asked: velocity * period,
        allowed: (velocity * period).clamp(-limit, limit),
        limit_rule,
        limit,
        step_duration: period,
        unit,
    };
    [
        axis(
            "walking.command.forward_velocity",
            command.forward_velocity,
            "walking.max_step_length",
            settings.max_step_length,
            "m",
        ),
        axis(
            "walking.command.sideways_velocity",
            command.sideways_velocity,
            lateral_key,
            lateral_room,
            "m",
        ),
        axis(
            "walking.command.turning_velocity",
            command.turning_velocity,
            "walking.max_step_turn",
            settings.max_step_turn,
            "rad",
        ),
    ]
}

/// The command's axes that the step limits clip ([`command_increments`] whose `allowed`
/// differs from `asked`): the walk then goes slower than commanded. Empty when the robot
/// walks a list of footsteps or stands stepping (no command is walked).
pub fn command_clips(settings: &WalkingSettings) -> Vec<CommandClip> {
    if settings.stepping || !settings.footsteps.is_empty() {
        return Vec::new();
    }
    command_increments(settings)
        .into_iter()
        .filter(|axis| (axis.allowed - axis.asked).abs() > 1e-12)
        .collect()
}

/// `frame` moved by `(dx, dy, dtheta)` given in its own axes.
fn advance(frame: SolePose, (dx, dy, dtheta): (f64, f64, f64)) -> SolePose {
    SolePose::new(
        frame.to_world(Vector2::new(dx, dy)),
        frame.world_yaw_sole + dtheta,
    )
}

/// `wished` for `foot` moved into the step limits in the `stance` sole's frame: forward
/// distance within the reach, lateral distance in [`min_step_width`, `max_step_width`] on
/// the foot's own side, turn within `max_step_turn` (footstep::check_step's rule).
fn within_limits(
    settings: &WalkingSettings,
    stance: SolePose,
    foot: Foot,
    wished: SolePose,
) -> SolePose {
    let stance_p = stance.to_sole(wished.world_p_sole);
    let reach = settings.max_step_length;
    let lateral =
        (foot.side() * stance_p.y).clamp(settings.min_step_width, settings.max_step_width);
    let turn = wrap_angle(wished.world_yaw_sole - stance.world_yaw_sole)
        .clamp(-settings.max_step_turn, settings.max_step_turn);
    SolePose::new(
        stance.to_world(Vector2::new(
            stance_p.x.clamp(-reach, reach),
            foot.side() * lateral,
        )),
        stance.world_yaw_sole + turn,
    )
}

/// `foot`'s sole on its side of the walking `frame`, `width / 2` off its x axis.
fn beside_frame(frame: SolePose, foot: Foot, width: f64) -> SolePose {
    SolePose::new(
        frame.to_world(Vector2::new(0.0, foot.side() * 0.5 * width)),
        frame.world_yaw_sole,
    )
}
