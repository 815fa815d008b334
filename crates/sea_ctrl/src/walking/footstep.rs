//! Feet and footsteps: which foot ([`Foot`]), a sole's pose on flat ground ([`SolePose`]:
//! `world_p_sole` (x, y), `world_yaw_sole`), both feet ([`Stance`]), a timed step
//! ([`Footstep`]) and the whole plan ([`FootstepPlan`]: the feet before each step and the gait
//! timing). [`check_step`] is the one reach / no-crossing / turn rule every footstep obeys.

use super::settings::WalkingSettings;
use crate::error::{Error, Result};
use nalgebra::{Rotation2, Vector2};

/// A foot; with the `serde` feature, named "left" or "right".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum Foot {
    /// The left foot (on the walking frame's +y side).
    #[default]
    Left,
    /// The right foot.
    Right,
}

impl Foot {
    /// The other foot.
    pub fn other(self) -> Foot {
        match self {
            Foot::Left => Foot::Right,
            Foot::Right => Foot::Left,
        }
    }

    /// +1 for the left foot, -1 for the right: the sign of its lateral offset from the
    /// other foot or from the walking frame.
    pub fn side(self) -> f64 {
        match self {
            Foot::Left => 1.0,
            Foot::Right => -1.0,
        }
    }
}

/// A sole's pose on flat ground: its origin's x, y in world and its yaw about world z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolePose {
    /// Sole origin in world, x and y [m].
    pub world_p_sole: Vector2<f64>,
    /// Sole yaw about world z [rad].
    pub world_yaw_sole: f64,
}

impl SolePose {
    /// The pose at `world_p_sole` with yaw `world_yaw_sole`.
    pub fn new(world_p_sole: Vector2<f64>, world_yaw_sole: f64) -> Self {
        Self {
            world_p_sole,
            world_yaw_sole,
        }
    }

    /// The rotation from the sole's ground axes to world's.
    pub fn world_r_sole(&self) -> Rotation2<f64> {
        Rotation2::new(self.world_yaw_sole)
    }

    /// A point given in this sole's ground axes (`sole_p`), in world.
    pub fn to_world(&self, sole_p: Vector2<f64>) -> Vector2<f64> {
        self.world_p_sole + self.world_r_sole() * sole_p
    }

    /// A world point in this sole's ground axes.
    pub fn to_sole(&self, world_p: Vector2<f64>) -> Vector2<f64> {
        self.world_r_sole().inverse() * (world_p - self.world_p_sole)
    }
}

/// Both feet's poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stance {
    /// The left sole.
    pub left: SolePose,
    /// The right sole.
    pub right: SolePose,
}

impl Stance {
    /// The feet side by side about `world_p_mid` (x, y), facing `world_yaw`, `width` apart.
    pub fn side_by_side(world_p_mid: Vector2<f64>, world_yaw: f64, width: f64) -> Self {
        let frame = SolePose::new(world_p_mid, world_yaw);
        let half = Vector2::new(0.0, 0.5 * width);
        Self {
            left: SolePose::new(frame.to_world(half), world_yaw),
            right: SolePose::new(frame.to_world(-half), world_yaw),
        }
    }

    /// The pose of `foot`.
    pub fn get(&self, foot: Foot) -> SolePose {
        match foot {
            Foot::Left => self.left,
            Foot::Right => self.right,
        }
    }

    /// Sets the pose of `foot`.
    pub fn set(&mut self, foot: Foot, pose: SolePose) {
        match foot {
            Foot::Left => self.left = pose,
            Foot::Right => self.right = pose,
        }
    }

    /// The walking frame: the point midway between the sole origins, with the feet's mean
    /// yaw (the mean of the two unit headings).
    pub fn mid_frame(&self) -> SolePose {
        let mid = 0.5 * (self.left.world_p_sole + self.right.world_p_sole);
        let (yl, yr) = (self.left.world_yaw_sole, self.right.world_yaw_sole);
        let yaw = (yl.sin() + yr.sin()).atan2(yl.cos() + yr.cos());
        SolePose::new(mid, yaw)
    }
}

/// A timed footstep: `foot` lifts off at `lift_off` [s] and lands at `touchdown` [s] with its
/// sole at `world_p_sole`, `world_yaw_sole`. Times count from the plan's start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footstep {
    /// The swing foot.
    pub foot: Foot,
    /// Landing pose of its sole.
    pub pose: SolePose,
    /// Lift-off time [s].
    pub lift_off: f64,
    /// Touchdown time [s].
    pub touchdown: f64,
}

impl Footstep {
    /// The middle of the swing [s]: from here on the sensors may land the foot
    /// (`controller::contact_phase`).
    pub fn mid_swing(&self) -> f64 {
        0.5 * (self.lift_off + self.touchdown)
    }

    /// How far into the swing time `t` [s] is: 0 at the lift-off, 1 at the touchdown (below
    /// 0 before, above 1 after; `walking.step_adjustment_end_phase` compares with it).
    pub fn swing_fraction(&self, t: f64) -> f64 {
        (t - self.lift_off) / (self.touchdown - self.lift_off)
    }
}

/// The footsteps of a walk with the feet before and after each.
#[derive(Clone, Debug, PartialEq)]
pub struct FootstepPlan {
    /// The steps, in order.
    pub steps: Vec<Footstep>,
    /// `stances[i]`: both feet before step `i`; `stances[steps.len()]`: the final feet.
    pub stances: Vec<Stance>,
    /// The double support from standing into the first lift-off, and from the last
    /// touchdown back to standing [s].
    pub transfer_duration: f64,
    /// The plan's start [s]: 0 for a walk, the time a push-recovery plan was made
    /// (`walking::recovery`); the first double support runs from here to the first lift-off.
    pub start_s: f64,
}

impl FootstepPlan {
    /// Times the `placements` (foot, landing pose) from the standing `initial` feet: the
    /// first lift-off after `transfer_duration`, then one step every `step_duration` with a
    /// swing of `single_support_duration`. Each step is checked with [`check_step`] against
    /// the foot it stands on; an error names `key[index]`.
    pub fn timed(
        settings: &WalkingSettings,
        initial: Stance,
        placements: &[(Foot, SolePose)],
        key: &str,
    ) -> Result<Self> {
        let mut stances = vec![initial];
        let mut steps = Vec::with_capacity(placements.len());
        let mut feet = initial;
        for (index, &(foot, pose)) in placements.iter().enumerate() {
            check_step(settings, feet.get(foot.other()), foot, pose)
                .map_err(|rule| Error::invalid(format!("{key}[{index}]"), rule.0, rule.1))?;
            let lift_off = settings.transfer_duration + index as f64 * settings.step_duration;
            steps.push(Footstep {
                foot,
                pose,
                lift_off,
                touchdown: lift_off + settings.single_support_duration(),
            });
            feet.set(foot, pose);
            stances.push(feet);
        }
        Ok(Self {
            steps,
            stances,
            transfer_duration: settings.transfer_duration,
            start_s: 0.0,
        })
    }

    /// The feet at the end (both on the ground).
    pub fn final_stance(&self) -> Stance {
        *self.stances.last().expect("a plan has its initial stance")
    }

    /// The time at which the walk ends standing: the last touchdown plus the transfer (the
    /// transfer alone without steps) [s].
    pub fn end_time(&self) -> f64 {
        self.steps.last().map_or(0.0, |step| step.touchdown) + self.transfer_duration
    }

    /// The sole the robot stands on during step `index`'s swing.
    pub fn stance_sole(&self, index: usize) -> SolePose {
        self.stances[index].get(self.steps[index].foot.other())
    }
}

/// A broken step rule: what is allowed (naming the limit's key and value) and the value.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRule(pub String, pub String);

/// Whether `foot` may land at `landing` from the `stance` sole of the other foot: in the
/// stance sole's frame, the forward distance within `max_step_length`, the lateral distance
/// (positive on the swing foot's own side) in [`min_step_width`, `max_step_width`] (the feet
/// do not cross) and the yaw within `max_step_turn`; a landing not finite is refused.
pub fn check_step(
    settings: &WalkingSettings,
    stance: SolePose,
    foot: Foot,
    landing: SolePose,
) -> std::result::Result<(), StepRule> {
    const SLACK: f64 = 1e-9;
    if !(landing.world_p_sole.iter().all(|v| v.is_finite()) && landing.world_yaw_sole.is_finite()) {
        return Err(StepRule(
            "the landing's x, y and yaw must be finite".to_string(),
            format!(
                "x = {} m, y = {} m, yaw = {} rad",
                landing.world_p_sole.x, landing.world_p_sole.y, landing.world_yaw_sole
            ),
        ));
    }
    let stance_p = stance.to_sole(landing.world_p_sole);
    let (forward, lateral) = (stance_p.x, foot.side() * stance_p.y);
    let turn = wrap_angle(landing.world_yaw_sole - stance.world_yaw_sole);
    if forward.abs() > settings.max_step_length + SLACK {
        return Err(StepRule(
            format!(
                "the forward distance from the stance sole must be at most \
                 walking.max_step_length = {} m",
                settings.max_step_length
            ),
            format!("{forward} m"),
        ));
    }
    if lateral < settings.min_step_width - SLACK || lateral > settings.max_step_width + SLACK {
        return Err(StepRule(
            format!(
                "the lateral distance from the stance sole must be in \
                 [walking.min_step_width, walking.max_step_width] = [{}, {}] m",
                settings.min_step_width, settings.max_step_width
            ),
            format!("{lateral} m"),
        ));
    }
    if turn.abs() > settings.max_step_turn + SLACK {
        return Err(StepRule(
            format!(
                "the yaw relative to the stance sole must be at most walking.max_step_turn = {} rad",
                settings.max_step_turn
            ),
            format!("{turn} rad"),
        ));
    }
    Ok(())
}

/// `angle` wrapped into (-pi, pi].
pub fn wrap_angle(angle: f64) -> f64 {
    let wrapped = angle.sin().atan2(angle.cos());
    if wrapped == -std::f64::consts::PI {
        std::f64::consts::PI
    } else {
        wrapped
    }
}
