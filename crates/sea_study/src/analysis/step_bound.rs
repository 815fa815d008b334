//! The largest push a standing robot could capture at all by stepping under its stepping
//! settings: an upper bound for `sea-sim push` on a scenario with `walking.stepping`, beside
//! the stance's capture-point bound (no step) and the closed loop's outcomes.
//!
//! The linear inverted pendulum (LIP) along the push's axis `u`, the DCM
//! `xi = x + xdot / omega` moving as
//!
//! ```text
//! xidot = omega (xi - p) + F / (m omega),    omega = sqrt(g / z_com),
//! ```
//!
//! from rest over the CoM, `p` the centre of pressure (CoP) and `F` the push's force, a
//! constant `I / push_duration` from the push's start. The best a controller can do under
//! the settings:
//!
//! - the CoP always at the support's farthest point along `u`: the QP's sole (the sole's
//!   rectangle shrunk by `controller.contact.cop_margin` about its middle) of the stance
//!   foot in single support, of the foot farthest along `u` in double support;
//! - the first lift-off at any time from the push's start on (before the DCM says a step is
//!   needed, and with no transfer of the load: an instant hand-over), every swing
//!   `walking.min_swing_duration`, a double support of `walking.recovery_transfer_duration`
//!   between two steps, at most `walking.max_recovery_steps` steps, the feet alternating;
//! - each landing as far along `u` as the step limits allow from the stance foot: up to
//!   `walking.max_step_length` ahead for a push along the soles; sideways on the stepping
//!   foot's own side (the feet never cross), `walking.max_step_width` out for the foot on the
//!   pushed side, `walking.min_step_width` in for the other.
//!
//! The DCM at every later time grows with the CoP's distance and shrinks with each landing
//! along `u`, so for a given first foot and lift-off these choices give the smallest
//! excursion; [`StandingStep::bound`] takes the best first foot and lift-off (a grid of
//! [`LIFT_OFF_STEP_S`]) and bisects the impulse. The push is captured when, once it has
//! ended, the DCM is inside the support's farthest edge along `u` at a touchdown (or without
//! a step). No joint, no angular momentum (a hip strategy could do more), no swing dynamics:
//! an upper bound of what the settings allow, not a prediction of a controller
//! (docs/findings/stepping.md, "What stepping can capture at all").
//!
//! Sideways, lifting the loaded foot (the one on the pushed side) moves the CoP to the other
//! foot: with the DCM at the loaded sole's outer edge (the no-step bound) and the feet `w`
//! apart, the DCM is then at least `w` beyond the CoP's reach and `w e^(omega T)` after a
//! swing `T`, while the landing is at most `max_step_width` from the stance: a step captures
//! more than the stance alone only if `w e^(omega T) < max_step_width`, `w` at least
//! `min_step_width` (the far foot stepped in first).

use super::gait_bound::{largest_captured, PushWindow};
use super::push::{PushDirection, Stance};
use crate::error::{Error, Result};
use nalgebra::Vector2;
use sea_ctrl::qp::ContactConstraints;
use sea_scenario::build::contact_frames;
use sea_scenario::walking::walking_settings;
use sea_scenario::{build, Scenario};
use std::path::Path;

/// The grid of first lift-off times [s] from the push's start that [`StandingStep::bound`]
/// tries.
pub const LIFT_OFF_STEP_S: f64 = 0.005;

/// How long after the push's end [`StandingStep::bound`] tries first lift-offs [s].
pub const LIFT_OFF_HORIZON_S: f64 = 0.5;

/// Where a foot may land along the push's axis, from the foot it stands on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepReach {
    /// A push along the soles (forward or backward): up to `max_length` [m] ahead of the
    /// stance sole's origin along the push (`walking.max_step_length`).
    Along {
        /// The longest step [m].
        max_length: f64,
    },
    /// A sideways push: on the stepping foot's own side of the stance foot, `max_width` [m]
    /// from it for the foot on the pushed side, `min_width` [m] for the other
    /// (`walking.max_step_width`, `min_step_width`).
    Across {
        /// The closest the feet may be [m].
        min_width: f64,
        /// The farthest [m].
        max_width: f64,
    },
}

/// A standing robot along a push's axis `u` (module doc): positions are along `u` [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StandingStep {
    /// The robot's mass [kg].
    pub mass_kg: f64,
    /// The pendulum's `sqrt(g / z_com)` [1/s].
    pub omega: f64,
    /// The push's length [s] (> 0).
    pub push_duration_s: f64,
    /// The CoM, and the DCM at rest [m].
    pub com_m: f64,
    /// The two soles' origins [m].
    pub feet_m: [f64; 2],
    /// The CoP's farthest point along `u` from a sole's origin [m].
    pub cop_reach_m: f64,
    /// The step limits.
    pub reach: StepReach,
    /// Each swing [s] (`walking.min_swing_duration`).
    pub swing_s: f64,
    /// The double support between two steps [s] (`walking.recovery_transfer_duration`).
    pub transfer_s: f64,
    /// The most steps (`walking.max_recovery_steps`).
    pub max_steps: usize,
}

/// A recovery: which foot steps first and when [s from the push's start]; `None`: no step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstStep {
    /// The index of the first stepping foot in [`StandingStep::feet_m`].
    pub foot: usize,
    /// Its lift-off [s] after the push's start.
    pub lift_off_s: f64,
}

/// The bound and the recovery that reaches it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepBound {
    /// The largest impulse captured [N s].
    pub impulse_n_s: f64,
    /// The first step of the best recovery; `None`: standing captures the most.
    pub first_step: Option<FirstStep>,
}

impl StandingStep {
    /// The support's farthest CoP along `u` on `feet`.
    fn edge(&self, feet: [f64; 2]) -> f64 {
        feet[0].max(feet[1]) + self.cop_reach_m
    }

    /// Where `foot` lands from the other foot, as far along `u` as the limits allow.
    fn landing(&self, foot: usize, feet: [f64; 2]) -> f64 {
        let stance = feet[1 - foot];
        match self.reach {
            StepReach::Along { max_length } => stance + max_length,
            StepReach::Across { max_width, .. } if feet[foot] > stance => stance + max_width,
            StepReach::Across { min_width, .. } => stance - min_width,
        }
    }

    /// Whether, from `xi` at `t` on `feet`, standing holds: the CoP on the edge until the
    /// push's end, the DCM then inside it.
    fn stands(&self, xi: f64, t: f64, feet: [f64; 2], push: &PushWindow) -> bool {
        let edge = self.edge(feet);
        let xi = if t < push.end {
            push.dcm_over(xi, edge, t, push.end, self.omega)
        } else {
            xi
        };
        xi <= edge
    }

    /// Whether a push of `impulse` [N s] along `u` is captured by standing (`first` `None`)
    /// or by steps from `first` on (module doc).
    pub fn captured(&self, impulse: f64, first: Option<FirstStep>) -> bool {
        let w = self.omega;
        let (mass, duration) = (self.mass_kg, self.push_duration_s);
        let push = PushWindow::new(impulse, 1.0, 0.0, duration, mass, w);
        let mut feet = self.feet_m;
        let Some(first) = first else {
            return self.stands(self.com_m, 0.0, feet, &push);
        };
        let mut xi = push.dcm_over(self.com_m, self.edge(feet), 0.0, first.lift_off_s, w);
        let (mut t, mut foot) = (first.lift_off_s, first.foot);
        for step in 0..self.max_steps {
            if step > 0 {
                xi = push.dcm_over(xi, self.edge(feet), t, t + self.transfer_s, w);
                t += self.transfer_s;
            }
            let stance_cop = feet[1 - foot] + self.cop_reach_m;
            xi = push.dcm_over(xi, stance_cop, t, t + self.swing_s, w);
            t += self.swing_s;
            feet[foot] = self.landing(foot, feet);
            if self.stands(xi, t, feet, &push) {
                return true;
            }
            foot = 1 - foot;
        }
        false
    }

    /// The largest impulse [N s] `first` captures (`largest_captured`): standing
    /// (`None`), or the recovery whose first step is `first`.
    pub fn bound_of(&self, first: Option<FirstStep>) -> f64 {
        largest_captured(|impulse| self.captured(impulse, first))
    }

    /// The largest impulse [N s] standing captures (no step).
    pub fn bound_without_steps(&self) -> f64 {
        self.bound_of(None)
    }

    /// The best of standing and of every first foot and lift-off on the grid (module doc).
    pub fn bound(&self) -> StepBound {
        let lift_offs = ((self.push_duration_s + LIFT_OFF_HORIZON_S) / LIFT_OFF_STEP_S) as usize;
        let steps = (0..2).flat_map(|foot| {
            (0..=lift_offs).map(move |k| {
                Some(FirstStep {
                    foot,
                    lift_off_s: k as f64 * LIFT_OFF_STEP_S,
                })
            })
        });
        let candidates = std::iter::once(None)
            .chain((self.max_steps > 0).then_some(steps).into_iter().flatten());
        candidates
            .map(|first| StepBound {
                impulse_n_s: self.bound_of(first),
                first_step: first,
            })
            .reduce(|best, this| {
                if this.impulse_n_s > best.impulse_n_s {
                    this
                } else {
                    best
                }
            })
            .expect("standing is always a candidate")
    }
}

/// The standing robot of the scenario at `path` with `overrides` along `direction`
/// ([`StandingStep`]): the stance's mass, pendulum and CoM ([`Stance::of`]), the soles'
/// origins, the QP's sole (`controller.contact.foot_x`, `foot_y` shrunk by `cop_margin`), the
/// walking settings' step limits, recovery swing and transfer and most steps, a push of
/// `push_duration_s`.
///
/// Errors: a scenario without `[walking]` with `stepping = true` (naming `walking.stepping`),
/// the scenario's.
pub fn standing_step_of(
    path: &Path,
    overrides: &[(String, String)],
    direction: PushDirection,
    push_duration_s: f64,
) -> Result<StandingStep> {
    let scenario = Scenario::from_file(path, overrides)?;
    let setup = build(&scenario)?;
    let model = &setup.model;
    let soles = contact_frames(&scenario, model)?;
    let settings = walking_settings(&scenario, model, &setup.x0[..model.nq()], &soles)?;
    let Some(settings) = settings.filter(|settings| settings.stepping) else {
        return Err(Error::config(
            "walking.stepping",
            "the stepping bound needs a scenario that steps to recover a push",
        ));
    };
    let stance = Stance::of(&scenario)?;
    let u = stance.direction(direction);
    let in_sole = direction.in_sole();
    let feet: Vec<f64> = setup
        .plant
        .contacts
        .iter()
        .map(|contact| contact.world_h_frame_desired.translation.xy().dot(&u))
        .collect();
    let [left, right] = feet[..] else {
        return Err(Error::config(
            "robot.contacts",
            "the stepping bound needs two feet",
        ));
    };
    let constraints = &setup.controller.settings().constraints;
    let reach = if in_sole.x.abs() > 0.5 {
        StepReach::Along {
            max_length: settings.max_step_length,
        }
    } else {
        StepReach::Across {
            min_width: settings.min_step_width,
            max_width: settings.max_step_width,
        }
    };
    Ok(StandingStep {
        mass_kg: stance.mass_kg,
        omega: stance.omega0,
        push_duration_s,
        com_m: stance.com_xy.dot(&u),
        feet_m: [left, right],
        cop_reach_m: cop_reach(constraints, in_sole),
        reach,
        swing_s: settings.min_swing_duration,
        transfer_s: settings.recovery_transfer_duration,
        max_steps: settings.max_recovery_steps,
    })
}

/// The farthest point along `in_sole` (a unit vector in the sole's x, y) of the QP's sole:
/// the rectangle `foot_x` x `foot_y` of `constraints`, each side its
/// [`ContactConstraints::cop_range`] [m].
fn cop_reach(constraints: &ContactConstraints, in_sole: Vector2<f64>) -> f64 {
    let [x, y] = [constraints.surface.foot_x, constraints.surface.foot_y];
    let ([x_min, x_max], [y_min, y_max]) = (constraints.cop_range(x), constraints.cop_range(y));
    [x_min, x_max]
        .into_iter()
        .flat_map(|x| [y_min, y_max].map(|y| Vector2::new(x, y).dot(&in_sole)))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// [`StandingStep::bound`] along each of `directions` for the scenario at `path` with
/// `overrides` and a push of `push_duration_s`, as JSON: `impulse_n_s` and, when a step
/// captures the most, `first_step` (`contact`, its name in `robot.contacts`, and
/// `lift_off_s` after the push's start); `None` when the scenario does not step (no
/// `[walking]` with `stepping = true`).
///
/// Errors: the scenario's.
pub fn stepping_bounds_json(
    path: &Path,
    overrides: &[(String, String)],
    push_duration_s: f64,
    directions: &[PushDirection],
) -> Result<Option<Vec<serde_json::Value>>> {
    let scenario = Scenario::from_file(path, overrides)?;
    if !scenario
        .walking
        .as_ref()
        .is_some_and(|walking| walking.stepping)
    {
        return Ok(None);
    }
    let contacts = &scenario.robot.contacts;
    directions
        .iter()
        .map(|&direction| {
            let bound = standing_step_of(path, overrides, direction, push_duration_s)?.bound();
            let first_step = bound.first_step.map(|first| {
                serde_json::json!({
                    "contact": contacts[first.foot],
                    "lift_off_s": first.lift_off_s,
                })
            });
            Ok(serde_json::json!({
                "impulse_n_s": bound.impulse_n_s,
                "first_step": first_step,
            }))
        })
        .collect::<Result<Vec<_>>>()
        .map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The iCub standing on two soles 0.14 m apart, pushed sideways to the left (`u` = +y):
    /// 33 kg, omega 4.3, the QP's sole reaching 0.0225 m out, 0.3 s swings.
    fn sideways() -> StandingStep {
        StandingStep {
            mass_kg: 33.0,
            omega: 4.3,
            push_duration_s: 0.1,
            com_m: 0.0,
            feet_m: [0.07, -0.07],
            cop_reach_m: 0.0225,
            reach: StepReach::Across {
                min_width: 0.09,
                max_width: 0.25,
            },
            swing_s: 0.3,
            transfer_s: 0.1,
            max_steps: 2,
        }
    }

    /// The same robot pushed forward (`u` = +x): the toes' CoP 0.085 m ahead of the soles'
    /// origins, steps up to 0.17 m.
    fn forward() -> StandingStep {
        StandingStep {
            feet_m: [0.0, 0.0],
            com_m: 0.01,
            cop_reach_m: 0.085,
            reach: StepReach::Along { max_length: 0.17 },
            ..sideways()
        }
    }

    /// Standing: `xi(tau) = e + (c - e) e^(w tau) + I / (tau m w^2) (e^(w tau) - 1) <= e`.
    fn standing_closed_form(robot: &StandingStep) -> f64 {
        let (w, tau) = (robot.omega, robot.push_duration_s);
        let d = robot.feet_m[0].max(robot.feet_m[1]) + robot.cop_reach_m - robot.com_m;
        let growth = (w * tau).exp();
        robot.mass_kg * w * w * tau * d * growth / (growth - 1.0)
    }

    #[test]
    fn without_steps_the_bound_is_the_pendulums_closed_form() {
        for robot in [sideways(), forward()] {
            let standing = StandingStep {
                max_steps: 0,
                ..robot
            };
            let bound = standing.bound();
            assert_eq!(bound.first_step, None);
            let want = standing_closed_form(&standing);
            assert!(
                (bound.impulse_n_s - want).abs() < 1e-5,
                "{bound:?} vs {want}"
            );
        }
    }

    #[test]
    fn one_step_forward_at_the_push_matches_the_closed_form_of_a_short_push() {
        // A push of 1e-5 s is an impulse: xi0 = c + I / (m w); stepping at once, the DCM
        // after the swing T is e + (xi0 - e) e^(w T) with the CoP on the stance toe `e`,
        // captured while it is inside the landed toe e + L: I <= m w (e - c + L e^(-w T)).
        let robot = StandingStep {
            push_duration_s: 1e-5,
            max_steps: 1,
            ..forward()
        };
        let first = Some(FirstStep {
            foot: 0,
            lift_off_s: 0.0,
        });
        let (w, t, e, c, l) = (robot.omega, robot.swing_s, 0.085, 0.01, 0.17);
        let want = robot.mass_kg * w * (e - c + l * (-w * t).exp());
        let got = robot.bound_of(first);
        assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
        // Stepping at once is the best forward: the grid's bound is this one.
        let best = robot.bound();
        assert!((best.impulse_n_s - got).abs() < 1e-9, "{best:?} vs {got}");
    }

    #[test]
    fn two_steps_forward_match_the_closed_form_with_the_transfer_between() {
        // An impulse, stepping at once, the DCM `a = xi0 - e` past the toe: after the first
        // swing `a E - L` past the landed toe (E = e^(w T)), after the transfer D and the
        // second swing `(a E - L) e^(w D) E`, captured within the second landing's L:
        // a <= L e^(-w T) (1 + e^(-w (D + T))).
        let robot = StandingStep {
            push_duration_s: 1e-5,
            // The first landing too short to capture: the second step is needed.
            reach: StepReach::Along { max_length: 0.05 },
            ..forward()
        };
        let first = Some(FirstStep {
            foot: 1,
            lift_off_s: 0.0,
        });
        let (w, t, d, l) = (robot.omega, robot.swing_s, robot.transfer_s, 0.05);
        let a = l * (-w * t).exp() * (1.0 + (-w * (d + t)).exp());
        let want = robot.mass_kg * w * (0.085 - 0.01 + a);
        let got = robot.bound_of(first);
        assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
        let one = StandingStep {
            max_steps: 1,
            ..robot
        };
        assert!(
            one.bound_of(first) < got - 0.1,
            "{} vs {got}",
            one.bound_of(first)
        );
    }

    #[test]
    fn sideways_a_step_adds_nothing_while_the_feet_width_grows_past_the_reach_in_a_swing() {
        // Even with the far foot in to 0.09 m first, 0.09 e^(4.3 x 0.3) = 0.33 m > 0.25 m: no
        // step captures more than standing.
        let robot = sideways();
        assert!(0.09 * (robot.omega * robot.swing_s).exp() > 0.25);
        let bound = robot.bound();
        assert_eq!(bound.first_step, None, "{bound:?}");
        let standing = standing_closed_form(&robot);
        assert!((bound.impulse_n_s - standing).abs() < 1e-5, "{bound:?}");
        // 0.09 e^(4.3 x 0.15) = 0.17 m < 0.25 m: stepping captures more (the best: the far
        // foot in first, then the loaded foot out).
        let quick = StandingStep {
            swing_s: 0.15,
            ..robot
        };
        assert!(0.09 * (quick.omega * quick.swing_s).exp() < 0.25);
        let bound = quick.bound();
        assert!(
            bound.impulse_n_s > standing + 0.1,
            "{bound:?} vs {standing}"
        );
        assert!(bound.first_step.is_some(), "{bound:?}");
    }

    #[test]
    fn forward_the_step_raises_the_bound_and_later_lift_offs_capture_less() {
        let robot = forward();
        let bound = robot.bound();
        assert!(
            bound.impulse_n_s > 1.3 * standing_closed_form(&robot),
            "{bound:?}"
        );
        let at = |lift_off_s| {
            robot.bound_of(Some(FirstStep {
                foot: 1,
                lift_off_s,
            }))
        };
        assert!(
            at(0.0) > at(0.1) && at(0.1) > at(0.2),
            "{} {} {}",
            at(0.0),
            at(0.1),
            at(0.2)
        );
    }

    #[test]
    fn the_cop_reach_is_the_shrunk_soles_farthest_point() {
        let mut constraints = ContactConstraints {
            cop_margin: 0.1,
            ..Default::default()
        };
        constraints.surface.foot_x = [-0.05, 0.10];
        constraints.surface.foot_y = [-0.025, 0.025];
        let cases = [
            (Vector2::new(1.0, 0.0), 0.025 + 0.075 * 0.9),
            (Vector2::new(-1.0, 0.0), -0.025 + 0.075 * 0.9),
            (Vector2::new(0.0, 1.0), 0.025 * 0.9),
            (Vector2::new(0.0, -1.0), 0.025 * 0.9),
        ];
        for (direction, want) in cases {
            let got = cop_reach(&constraints, direction);
            assert!((got - want).abs() < 1e-15, "{direction}: {got} vs {want}");
        }
    }
}
