//! The contact schedule of a footstep plan: at time `t`, which feet are on the ground, which
//! phase (double support, single support on the left or right foot), how far into it, the
//! next touchdown ([`FootstepPlan::phase_at`]), and the share of the load planned on the left
//! foot ([`FootstepPlan::left_load_share`]) for handing the contact wrench over between the
//! feet: 1 in left single support, 0 in right single support, 1/2 standing, and through each
//! double support the quintic `10 u^3 - 15 u^4 + 6 u^5` of the phase's fraction `u` from the
//! value before to the value after, so it is continuous with zero slope at every switch.

use super::footstep::{Foot, FootstepPlan};

/// Which feet carry the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Support {
    /// Both feet on the ground.
    Double,
    /// One foot on the ground, the other swinging.
    Single {
        /// The foot on the ground.
        stance: Foot,
    },
}

/// The phase at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaitPhase {
    /// The support.
    pub support: Support,
    /// Start of the phase [s].
    pub start: f64,
    /// End of the phase [s] (infinite once standing at the end).
    pub end: f64,
    /// How far into the phase, in [0, 1] (0 once standing at the end).
    pub fraction: f64,
    /// Index of the step swinging in single support, or landed last in double support (none
    /// before the first touchdown).
    pub step: Option<usize>,
    /// The next touchdown at or after the phase's start, if any [s].
    pub next_touchdown: Option<f64>,
}

impl GaitPhase {
    /// Whether `foot` is on the ground.
    pub fn in_contact(&self, foot: Foot) -> bool {
        match self.support {
            Support::Double => true,
            Support::Single { stance } => stance == foot,
        }
    }
}

impl FootstepPlan {
    /// The phase at `t` [s] (before the plan's start `start_s`: the initial double support).
    pub fn phase_at(&self, t: f64) -> GaitPhase {
        let t = t.max(self.start_s);
        let upcoming = self.steps.partition_point(|step| step.lift_off <= t);
        // upcoming: index of the first step not lifted off yet; the step before it (if any)
        // is swinging or has landed.
        let (support, start, end, step) = match upcoming.checked_sub(1) {
            None => (Support::Double, self.start_s, self.first_lift_off(), None),
            Some(i) if t < self.steps[i].touchdown => {
                let stance = self.steps[i].foot.other();
                let s = &self.steps[i];
                (Support::Single { stance }, s.lift_off, s.touchdown, Some(i))
            }
            Some(i) => {
                let end = self
                    .steps
                    .get(i + 1)
                    .map_or(self.end_time(), |s| s.lift_off);
                (Support::Double, self.steps[i].touchdown, end, Some(i))
            }
        };
        let (start, end, fraction) = if t < end {
            (start, end, ((t - start) / (end - start)).clamp(0.0, 1.0))
        } else {
            (self.end_time(), f64::INFINITY, 0.0)
        };
        let next_touchdown = self
            .steps
            .iter()
            .map(|s| s.touchdown)
            .find(|&touchdown| touchdown > start);
        GaitPhase {
            support,
            start,
            end,
            fraction,
            step,
            next_touchdown,
        }
    }

    /// The first lift-off, or the end of the transfer without steps [s].
    fn first_lift_off(&self) -> f64 {
        self.steps.first().map_or(self.end_time(), |s| s.lift_off)
    }

    /// The share of the load planned on the left foot at `t`, in [0, 1] (module doc).
    pub fn left_load_share(&self, t: f64) -> f64 {
        let phase = self.phase_at(t);
        let share_on = |stance: Option<Foot>| match stance {
            Some(Foot::Left) => 1.0,
            Some(Foot::Right) => 0.0,
            None => 0.5,
        };
        // The stance foot of step i's swing.
        let stance_of = |i: usize| self.steps.get(i).map(|s| s.foot.other());
        match (phase.support, phase.step) {
            (Support::Single { stance }, _) => share_on(Some(stance)),
            (Support::Double, _) if phase.end.is_infinite() => 0.5,
            (Support::Double, step) => {
                let before = step.and_then(stance_of);
                let after = stance_of(step.map_or(0, |i| i + 1));
                let blend = minimum_jerk(phase.fraction);
                share_on(before) + (share_on(after) - share_on(before)) * blend
            }
        }
    }
}

/// `10 u^3 - 15 u^4 + 6 u^5`.
fn minimum_jerk(u: f64) -> f64 {
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}
