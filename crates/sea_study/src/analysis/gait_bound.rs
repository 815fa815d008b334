//! The largest sideways push a walking gait's timing and step limits can capture at all: an
//! upper bound for `sea-sim push --phase` on a walk, beside the outcomes of the closed loop.
//!
//! The linear inverted pendulum (LIP) of the walk along the stance sole's lateral axis `y`:
//! the divergent component of motion (DCM, capture point) `xi = y + ydot / omega` moves as
//!
//! ```text
//! xidot = omega (xi - p) + F / (m omega),    omega = sqrt(g / z0),
//! ```
//!
//! `p` the centre of pressure (CoP), `F` the push's lateral force (`crate::walking::lip`'s
//! pendulum, docs/references.md#walking). A push of impulse `I` over `push_duration_s` starts
//! at a fraction `phase` of a swing. From then on the best any controller can do under the
//! gait's timing is:
//!
//! - keep the CoP on the pushed side's edge of the support: the stance sole's edge in single
//!   support, the outermost sole's in double support, `half_width_m` from each sole's middle
//!   (the QP's sole: the sole's half-width times `1 - cop_margin`);
//! - land each foot that steps towards the push `max_step_width` from the other foot, and
//!   each foot on the far side `min_step_width` from it (the feet never cross), at the
//!   planned touchdowns: every landing, the swing in flight's included
//!   ([`Landings::WithinLimits`], what the gait's timing allows at all), or only those the
//!   scenario's controller moves ([`Landings::of_settings`]: with `walking.step_adjustment`
//!   the swing in flight when the push starts before `walking.step_adjustment_end_phase` of
//!   it, and every later one; without it none), the others where the plan puts them.
//!
//! The DCM at any later time decreases with the CoP at every instant and with every landing
//! on the pushed side, so these choices give the smallest excursion. The push is captured
//! when, once it has ended, the DCM is inside the outermost sole's edge at a touchdown of the
//! foot on the pushed side. [`LateralGait::bound`] bisects the impulse. No joint, no angular
//! momentum (a hip strategy could do more), no swing dynamics: an upper bound of what the
//! gait can capture with its CoP and its steps, not a prediction of a controller
//! (docs/findings/stepping.md, "the gait's own bound"; `scripts/lateral_push_bound.py` is
//! the same model written independently and checked against scipy's Radau).

use super::push::{pushed_step, PushDirection, Stance, SwingPhase};
use crate::error::{Error, Result};
use nalgebra::Vector2;
use sea_ctrl::walking::WalkingSettings;
use sea_scenario::build::contact_frames;
use sea_scenario::walking::walking_settings;
use sea_scenario::{build, Scenario, Setup};
use std::f64::consts::FRAC_1_SQRT_2;
use std::path::Path;

/// Steps after the pushed swing's lift-off within which the push must be captured.
pub const CAPTURE_STEPS: usize = 6;

/// The largest impulse [N s] the bounds try (`largest_captured`): a push captured at this
/// impulse is reported as this.
pub const BOUND_CEILING_N_S: f64 = 1000.0;

/// The resolution of the bounds' bisection (`largest_captured`) [N s].
pub const BOUND_TOLERANCE_N_S: f64 = 1e-6;

/// The side of a lateral push, seen from the pushed swing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LateralSide {
    /// Towards the stance foot's side (the stance foot then steps outwards next).
    TowardStance,
    /// Towards the swinging foot's side (the swing in flight can land outwards).
    TowardSwing,
}

impl LateralSide {
    /// +1 towards the stance foot, -1 towards the swing foot: the sign along the axis on
    /// which the stance foot is at 0 and the swing foot at `-width_m`.
    fn sign(self) -> f64 {
        match self {
            LateralSide::TowardStance => 1.0,
            LateralSide::TowardSwing => -1.0,
        }
    }
}

/// Which landings a bound may move (module doc); a landing not moved is where the plan puts
/// it, the walk's width from the other foot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Landings {
    /// Every landing, the swing in flight's included, anywhere within the step widths.
    WithinLimits,
    /// As the controller's step adjustment (`walking.step_adjustment`) moves them: the swing
    /// in flight only when the push starts before `end_phase` of it
    /// (`walking.step_adjustment_end_phase`), every later one.
    Adjusted {
        /// The fraction of a swing after which its landing is no longer moved.
        end_phase: f64,
    },
    /// Every landing where the plan puts it (`walking.step_adjustment` off).
    Planned,
}

impl Landings {
    /// The landings the controller of `settings` moves.
    pub fn of_settings(settings: &WalkingSettings) -> Self {
        if settings.step_adjustment {
            Landings::Adjusted {
                end_phase: settings.step_adjustment_end_phase,
            }
        } else {
            Landings::Planned
        }
    }

    /// Whether the `index`-th landing from the pushed swing's (0: the swing in flight) moves
    /// for a push starting at `phase` of that swing.
    fn moves(self, index: usize, phase: f64) -> bool {
        match self {
            Landings::WithinLimits => true,
            Landings::Adjusted { end_phase } => index > 0 || phase < end_phase,
            Landings::Planned => false,
        }
    }
}

/// A walk's lateral figures at a swing's lift-off (module doc), along the axis from the swing
/// foot to the stance foot: the stance foot's middle at 0, the swing foot's at `-width_m`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LateralGait {
    /// The robot's mass [kg].
    pub mass_kg: f64,
    /// The pendulum's `sqrt(g / z0)` [1/s].
    pub omega: f64,
    /// The swing (single support) [s].
    pub swing_s: f64,
    /// The double support between two swings [s].
    pub double_support_s: f64,
    /// The lateral distance between the feet at the lift-off [m] (> 0).
    pub width_m: f64,
    /// `walking.min_step_width` [m].
    pub min_width_m: f64,
    /// `walking.max_step_width` [m].
    pub max_width_m: f64,
    /// How far from a sole's middle its CoP may go sideways [m].
    pub half_width_m: f64,
    /// The push's length [s] (> 0).
    pub push_duration_s: f64,
    /// The DCM at the lift-off [m], on this axis.
    pub dcm_at_lift_off_m: f64,
}

/// The DCM after `duration` [s] from `xi` under a CoP moving linearly from `p0` to `p1`
/// (`xidot = omega (xi - p)`, exact): `p1 + r / omega + (xi - p0 - r / omega) e^(omega T)`,
/// `r` the CoP's rate.
pub fn dcm_after(xi: f64, p0: f64, p1: f64, duration: f64, omega: f64) -> f64 {
    if duration <= 0.0 {
        return xi;
    }
    let rate = (p1 - p0) / duration;
    p1 + rate / omega + (xi - p0 - rate / omega) * (omega * duration).exp()
}

/// A push's window [s] and its force as an offset of the CoP along the axis:
/// `omega (xi - p) + F / (m omega) = omega (xi - (p - cop_offset))`.
pub(crate) struct PushWindow {
    pub(crate) start: f64,
    pub(crate) end: f64,
    pub(crate) cop_offset: f64,
}

impl PushWindow {
    /// The push of `impulse` [N s] along the axis's sign `sign` over `[start, start +
    /// duration]` on a robot of `mass` [kg] and pendulum `omega` [1/s].
    pub(crate) fn new(
        impulse: f64,
        sign: f64,
        start: f64,
        duration: f64,
        mass: f64,
        omega: f64,
    ) -> Self {
        Self {
            start,
            end: start + duration,
            cop_offset: sign * impulse / duration / (mass * omega.powi(2)),
        }
    }

    /// The DCM after `[from, to]` [s] from `xi` with the CoP at `cop` and the push's force
    /// where the window overlaps.
    pub(crate) fn dcm_over(&self, xi: f64, cop: f64, from: f64, to: f64, omega: f64) -> f64 {
        let mut cuts = vec![from];
        cuts.extend(
            [self.start, self.end]
                .into_iter()
                .filter(|&t| from < t && t < to),
        );
        cuts.push(to);
        cuts.windows(2).fold(xi, |xi, piece| {
            let pushed = self.start <= piece[0] && piece[0] < self.end;
            let p = if pushed { cop - self.cop_offset } else { cop };
            dcm_after(xi, p, p, piece[1] - piece[0], omega)
        })
    }
}

impl LateralGait {
    /// The periodic walk's DCM [m] at the lift-off: the CoP at the stance sole's middle in
    /// single support and moving linearly between the soles in double support, the fixed
    /// point of one period (two steps). What a straight walk's plan converges to.
    pub fn periodic_dcm_at_lift_off(&self) -> f64 {
        let (w, ss, ds) = (self.omega, self.swing_s, self.double_support_s);
        let (stance, swing) = (0.0, -self.width_m);
        let period = |xi: f64| {
            let xi = dcm_after(xi, stance, stance, ss, w);
            let xi = dcm_after(xi, stance, swing, ds, w);
            let xi = dcm_after(xi, swing, swing, ss, w);
            dcm_after(xi, swing, stance, ds, w)
        };
        let offset = period(0.0);
        let slope = period(1.0) - offset;
        offset / (1.0 - slope)
    }

    /// Whether a lateral push of `impulse` [N s] towards `side`, starting at `phase` of the
    /// swing, is captured with the best CoP and the best of `landings` (module doc) within
    /// [`CAPTURE_STEPS`] steps.
    pub fn captured(
        &self,
        impulse: f64,
        side: LateralSide,
        phase: f64,
        landings: Landings,
    ) -> bool {
        let s = side.sign();
        let half = self.half_width_m;
        let start = phase * self.swing_s;
        let (mass, w) = (self.mass_kg, self.omega);
        let push = PushWindow::new(impulse, s, start, self.push_duration_s, mass, w);
        // [stance foot at the lift-off, swing foot]; each foot's outward direction.
        let mut feet = [0.0, -self.width_m];
        let outward = [1.0, -1.0];
        let mut xi = self.dcm_at_lift_off_m;
        let (mut t, mut stance) = (0.0, 0);
        for index in 0..CAPTURE_STEPS {
            xi = push.dcm_over(xi, feet[stance] + s * half, t, t + self.swing_s, w);
            t += self.swing_s;
            let swing = 1 - stance;
            let width = if !landings.moves(index, phase) {
                self.width_m
            } else if outward[swing] == s {
                self.max_width_m
            } else {
                self.min_width_m
            };
            feet[swing] = feet[stance] + outward[swing] * width;
            let outermost = if s * feet[0] >= s * feet[1] { 0 } else { 1 };
            let edge = feet[outermost] + s * half;
            if outermost == swing && t >= push.end && s * (xi - edge) <= 0.0 {
                return true;
            }
            xi = push.dcm_over(xi, edge, t, t + self.double_support_s, w);
            t += self.double_support_s;
            stance = swing;
        }
        false
    }

    /// The largest impulse [N s] [`Self::captured`] towards `side` at `phase` of the swing
    /// with `landings` (`largest_captured`).
    pub fn bound(&self, side: LateralSide, phase: f64, landings: Landings) -> f64 {
        largest_captured(|impulse| self.captured(impulse, side, phase, landings))
    }
}

/// The largest impulse [N s] `captured` holds, bisected to [`BOUND_TOLERANCE_N_S`] from 0 to
/// [`BOUND_CEILING_N_S`] (the ceiling when it holds there); `captured` must hold for every
/// impulse below one it holds for (the pendulum's DCM grows with the impulse).
pub(crate) fn largest_captured(captured: impl Fn(f64) -> bool) -> f64 {
    if captured(BOUND_CEILING_N_S) {
        return BOUND_CEILING_N_S;
    }
    bisect_holding(captured, (0.0, BOUND_CEILING_N_S), BOUND_TOLERANCE_N_S)
}

/// The bracket `(low, high)` (`holds` true at `low`, false at `high`) bisected until narrower
/// than `tolerance`, or until no number lies between its ends; its lower end.
pub(crate) fn bisect_holding(
    holds: impl Fn(f64) -> bool,
    (mut low, mut high): (f64, f64),
    tolerance: f64,
) -> f64 {
    while high - low > tolerance {
        let middle = 0.5 * (low + high);
        if !(low < middle && middle < high) {
            break;
        }
        if holds(middle) {
            low = middle;
        } else {
            high = middle;
        }
    }
    low
}

/// A walk's lateral figures at a pushed step ([`lateral_gait_of_walk`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkLateral {
    /// The figures along the axis.
    pub gait: LateralGait,
    /// The world (x, y) unit vector of the axis, from the swing foot towards the stance foot
    /// (the stance sole's lateral axis).
    pub world_axis: Vector2<f64>,
    /// The landings the scenario's controller moves ([`Landings::of_settings`]).
    pub landings: Landings,
}

/// The scenario at `path` with `overrides`, built, with its walking settings (`None` when it
/// does not walk).
pub(crate) fn built_walk(
    path: &Path,
    overrides: &[(String, String)],
) -> Result<(Scenario, Setup, Option<WalkingSettings>)> {
    let scenario = Scenario::from_file(path, overrides)?;
    let setup = build(&scenario)?;
    let model = &setup.model;
    let q = &setup.x0[..model.nq()];
    let soles = contact_frames(&scenario, model)?;
    let settings = walking_settings(&scenario, model, q, &soles)?;
    Ok((scenario, setup, settings))
}

/// A walk's lateral figures at the lift-off of step `step` of its plan (`None`: the
/// default, [`pushed_step`]) ([`LateralGait`]), the world (x, y) unit vector of its axis (from the swing foot
/// towards the stance foot, the stance sole's lateral axis) and the landings its controller
/// moves ([`WalkLateral`]): the scenario at `path` with
/// `overrides` built, the gait its controller plans, the robot's mass and pendulum, the swing
/// of the step and the double support after it, the feet and the plan's DCM at the lift-off
/// in the stance sole's frame, `walking.min_step_width` and `max_step_width`, the sole's
/// half-width (`controller.contact.foot_y`) shrunk by `controller.contact.cop_margin`.
///
/// Errors: a scenario without a walk or `step` beyond its plan (naming `--step`), the
/// scenario's.
pub fn lateral_gait_of_walk(
    path: &Path,
    overrides: &[(String, String)],
    step: Option<usize>,
    push_duration_s: f64,
) -> Result<WalkLateral> {
    let (_, setup, settings) = built_walk(path, overrides)?;
    let model = &setup.model;
    let (Some(gait), Some(settings)) = (setup.controller.gait(), settings) else {
        let expected = "a scenario that walks ([walking] with a command or footsteps)";
        return Err(sea_dyn::Error::invalid("--step", expected, path.display()).into());
    };
    let plan = &gait.footsteps;
    let step = pushed_step(step, plan.steps.len());
    let Some(pushed) = plan.steps.get(step) else {
        let expected = format!("a step of the plan, 0 to {}", plan.steps.len() as isize - 1);
        return Err(sea_dyn::Error::invalid("--step", expected, step).into());
    };
    let double_support_s = plan
        .steps
        .get(step + 1)
        .map_or(plan.transfer_duration, |next| {
            next.lift_off - pushed.touchdown
        });
    let stance = plan.stance_sole(step);
    let swing_foot = plan.stances[step].get(pushed.foot);
    // The axis from the swing foot towards the stance foot: the stance sole's y, signed.
    let toward_stance = -pushed.foot.side();
    let world_axis = stance.world_r_sole() * Vector2::new(0.0, toward_stance);
    let along = |world_p: Vector2<f64>| toward_stance * stance.to_sole(world_p).y;
    let dcm = gait.dcm.sample(pushed.lift_off).world_xi.xy();
    let constraints = &setup.controller.settings().constraints;
    let lateral = LateralGait {
        mass_kg: model.total_mass(),
        omega: gait.dcm.lip().omega,
        swing_s: pushed.touchdown - pushed.lift_off,
        double_support_s,
        width_m: -along(swing_foot.world_p_sole),
        min_width_m: settings.min_step_width,
        max_width_m: settings.max_step_width,
        half_width_m: half_width(constraints.cop_range(constraints.surface.foot_y)),
        push_duration_s,
        dcm_at_lift_off_m: along(dcm),
    };
    if lateral.width_m.is_nan() || lateral.width_m <= 0.0 {
        return Err(Error::config(
            "walking",
            format!("step {step}: the swing foot is not beside the stance foot"),
        ));
    }
    Ok(WalkLateral {
        gait: lateral,
        world_axis,
        landings: Landings::of_settings(&settings),
    })
}

/// Half the lateral extent `[y_min, y_max]` of the QP's sole [m]: the CoP's room on either
/// side of the sole's middle, taken at the sole's origin (the iCub's `foot_y`,
/// `[-0.025, 0.025]`, is centred on it).
fn half_width([y_min, y_max]: [f64; 2]) -> f64 {
    0.5 * (y_max - y_min)
}

/// The two bounds [N s] of a sideways push on a walk ([`gait_bounds`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaitBounds {
    /// With every landing within the step widths ([`Landings::WithinLimits`]).
    pub within_limits: f64,
    /// With the landings the scenario's controller moves ([`Landings::of_settings`]).
    pub adjusted: f64,
}

/// The bounds of [`LateralGait::bound`] for a push along each of `directions` at `at` of the
/// walk of the scenario at `path` with `overrides`, `push_duration_s` long: `None` for a
/// direction more along the walk than across it (more than 45 degrees from the stance sole's
/// lateral axis; forward and backward on a straight walk).
///
/// Errors: as [`lateral_gait_of_walk`].
pub fn gait_bounds(
    path: &Path,
    overrides: &[(String, String)],
    at: SwingPhase,
    push_duration_s: f64,
    directions: &[PushDirection],
) -> Result<Vec<Option<GaitBounds>>> {
    let walk = lateral_gait_of_walk(path, overrides, at.step, push_duration_s)?;
    let stance = Stance::of(&Scenario::from_file(path, overrides)?)?;
    Ok(directions
        .iter()
        .map(|&direction| {
            let across = stance.direction(direction).dot(&walk.world_axis);
            let side = if across >= FRAC_1_SQRT_2 {
                LateralSide::TowardStance
            } else if across <= -FRAC_1_SQRT_2 {
                LateralSide::TowardSwing
            } else {
                return None;
            };
            let bound = |landings| walk.gait.bound(side, at.phase, landings);
            Some(GaitBounds {
                within_limits: bound(Landings::WithinLimits),
                adjusted: bound(walk.landings),
            })
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// walk_push.toml's iCub as `scripts/lateral_push_bound.py`'s defaults: 33 kg, the CoM at
    /// 0.51 m, 0.3 s swings, 0.1 s double supports, feet 0.14 m apart, widths 0.09-0.25 m,
    /// the QP's sole 0.025 m x 0.7, a 0.1 s push, the periodic walk's DCM.
    fn script_gait() -> LateralGait {
        let mut gait = LateralGait {
            mass_kg: 33.0,
            omega: (9.81_f64 / 0.51).sqrt(),
            swing_s: 0.3,
            double_support_s: 0.1,
            width_m: 0.14,
            min_width_m: 0.09,
            max_width_m: 0.25,
            half_width_m: 0.025 * 0.7,
            push_duration_s: 0.1,
            dcm_at_lift_off_m: 0.0,
        };
        gait.dcm_at_lift_off_m = gait.periodic_dcm_at_lift_off();
        gait
    }

    #[test]
    fn the_bound_equals_the_independent_scripts_at_every_phase_and_side() {
        // `python3 scripts/lateral_push_bound.py`'s bound() with its Gait() at phases 0, 0.2,
        // 0.5, 0.8 and 1 (the script is checked against scipy's Radau in
        // python_tests/test_lateral_push_bound.py), whose bisection stops within 1e-4 N s.
        let gait = script_gait();
        assert!((gait.dcm_at_lift_off_m - -0.025920309635740657).abs() < 1e-12);
        let phases = [0.0, 0.2, 0.5, 0.8, 1.0];
        let script = [
            (
                LateralSide::TowardStance,
                [7.053435, 9.17666, 13.617909, 20.208609, 26.2918],
            ),
            (
                LateralSide::TowardSwing,
                [10.485315, 13.641596, 20.243764, 29.68955, 38.626671],
            ),
        ];
        for (side, expected) in script {
            for (phase, want) in phases.into_iter().zip(expected) {
                let got = gait.bound(side, phase, Landings::WithinLimits);
                assert!(
                    (got - want).abs() < 1.5e-4,
                    "{side:?} at {phase}: {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn after_the_adjustments_end_phase_the_bound_is_the_scripts_with_the_swing_not_moved() {
        // `scripts/lateral_push_bound.py`'s bound() with `landing_speed=0.0` (the swing in
        // flight lands where it lifted off, the later landings within the widths) at 0.8,
        // 0.9 and 1 of the swing.
        let gait = script_gait();
        let adjusted = Landings::Adjusted { end_phase: 0.8 };
        let script = [
            (LateralSide::TowardStance, [15.777242, 17.99587, 20.526505]),
            (LateralSide::TowardSwing, [14.573658, 16.623044, 18.960619]),
        ];
        for (side, expected) in script {
            for (phase, want) in [0.8, 0.9, 1.0].into_iter().zip(expected) {
                let got = gait.bound(side, phase, adjusted);
                assert!(
                    (got - want).abs() < 1.5e-4,
                    "{side:?} at {phase}: {got} vs {want}"
                );
                assert!(got < gait.bound(side, phase, Landings::WithinLimits));
            }
        }
    }

    #[test]
    fn before_the_end_phase_the_adjusted_bound_is_every_landings_and_the_plans_is_below() {
        let gait = script_gait();
        let adjusted = Landings::Adjusted { end_phase: 0.8 };
        for side in [LateralSide::TowardStance, LateralSide::TowardSwing] {
            for phase in [0.0, 0.2, 0.5, 0.79] {
                let within = gait.bound(side, phase, Landings::WithinLimits);
                assert_eq!(gait.bound(side, phase, adjusted), within);
                let planned = gait.bound(side, phase, Landings::Planned);
                assert!(
                    planned < within,
                    "{side:?} at {phase}: {planned} vs {within}"
                );
            }
        }
        let mut settings = WalkingSettings::default();
        assert_eq!(Landings::of_settings(&settings), Landings::Planned);
        settings.step_adjustment = true;
        settings.step_adjustment_end_phase = 0.7;
        assert_eq!(
            Landings::of_settings(&settings),
            Landings::Adjusted { end_phase: 0.7 }
        );
    }

    #[test]
    fn the_bound_grows_with_the_soles_room_and_the_step_width_and_shrinks_with_mass() {
        let gait = script_gait();
        let base = gait.bound(LateralSide::TowardStance, 0.5, Landings::WithinLimits);
        let variants = [
            (
                LateralGait {
                    half_width_m: 0.025,
                    ..gait
                },
                true,
            ),
            (
                LateralGait {
                    max_width_m: 0.3,
                    ..gait
                },
                true,
            ),
            (
                LateralGait {
                    mass_kg: 40.0,
                    ..gait
                },
                true,
            ),
            (
                LateralGait {
                    max_width_m: 0.2,
                    ..gait
                },
                false,
            ),
        ];
        for (variant, larger) in variants {
            let bound = variant.bound(LateralSide::TowardStance, 0.5, Landings::WithinLimits);
            assert_eq!(bound > base, larger, "{variant:?}: {bound} vs {base}");
        }
    }

    #[test]
    fn an_impulse_just_over_the_bound_is_not_captured_and_one_just_under_is() {
        let gait = script_gait();
        for side in [LateralSide::TowardStance, LateralSide::TowardSwing] {
            let within = Landings::WithinLimits;
            let bound = gait.bound(side, 0.2, within);
            assert!(gait.captured(bound * 0.999, side, 0.2, within));
            assert!(!gait.captured(bound * 1.001, side, 0.2, within));
        }
    }

    #[test]
    fn a_segment_of_moving_cop_matches_a_fine_explicit_integration() {
        let (omega, p0, p1, duration, xi0) = (4.4, -0.03, 0.12, 0.37, 0.05);
        let steps = 200_000;
        let dt = duration / steps as f64;
        // Midpoint rule on xidot = omega (xi - p(t)).
        let xi = (0..steps).fold(xi0, |xi, k| {
            let t = (k as f64 + 0.5) * dt;
            let p = p0 + (p1 - p0) * t / duration;
            let half = xi + 0.5 * dt * omega * (xi - (p0 + (p1 - p0) * (k as f64 * dt) / duration));
            xi + dt * omega * (half - p)
        });
        assert!((dcm_after(xi0, p0, p1, duration, omega) - xi).abs() < 1e-8);
    }
}
