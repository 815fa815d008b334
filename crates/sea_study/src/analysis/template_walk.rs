//! A walk's planner and momentum law on the linear inverted pendulum (LIP), the robot left
//! out: what the gait, its step adjustment and the momentum task's linear rows recover of a
//! push when every wrench they ask for within the soles is delivered. Between the pendulum's
//! bounds ([`super::gait_bound`], the best any controller could do with the gait's timing)
//! and the whole robot's closed loop (`sea-sim push`), it tells which of the two a shortfall
//! belongs to: the planner and the law, or the robot realising them.
//!
//! The template: the CoM `c` (world x, y) at the pendulum's height moves as
//!
//! ```text
//! cddot = omega^2 (c - p) + F / m,
//! ```
//!
//! `p` the centre of pressure, `F` the push. At each whole-body tick (`controller.rate_hz`) the
//! controller's own planner (`sea_ctrl::walking::Gait`, with `walking.step_adjustment` when
//! the scenario has it, `adjust_step` fed the template's CoM) gives the CoM reference, and the
//! momentum task's linear rows (paper eq:dotH_f with eq:IhTilde, `controller.
//! momentum_proportional` and `momentum_integral`, x and y) the CoM acceleration they ask
//! for:
//!
//! ```text
//! cddot* = cddot_d - K_p (cdot - cdot_d) - K_i (c - c_d).
//! ```
//!
//! The centre of pressure that gives it, `c - cddot* / omega^2`, is moved to the closest point
//! of the support the plan has at that tick (the QP's soles, shrunk by `controller.contact.
//! cop_margin`; their convex hull in double support) and held over the tick. Feet land where
//! and when the plan says, at once, and carry any share of the load; there is no angular
//! momentum (no hip strategy), no joint, no swing dynamics; a push acts at the CoM (the
//! robot's on a link, which turns it too), and the observer of external wrenches
//! (`controller.external_wrench`) is not modelled: the law knows no push. The walk is lost
//! when the CoM leaves its reference by more than `simulation.divergence_com_error_m` within
//! the run (`simulation.duration_s`), or when it has ended by then with the DCM outside the
//! final stance.

use super::gait_bound::{bisect_holding, built_walk};
use super::push::{PushDirection, Stance};
use crate::error::{Error, Result};
use nalgebra::Vector2;
use sea_ctrl::walking::{adjust_step, Gait, MeasuredCom, Support, SupportPolygon, WalkingSettings};
use sea_dyn::ContactSurface;
use sea_scenario::Scenario;
use std::path::Path;

/// A push on the template: a constant force over a window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemplatePush {
    /// The force, world (x, y) [N].
    pub world_force: Vector2<f64>,
    /// Its start [s].
    pub start_s: f64,
    /// Its length [s].
    pub duration_s: f64,
}

/// How a template walk ended.
#[derive(Clone, Debug, PartialEq)]
pub struct TemplateOutcome {
    /// Whether the walk was not lost (module doc).
    pub recovered: bool,
    /// The time the CoM left its reference by more than the bound, if it did [s].
    pub diverged_at: Option<f64>,
    /// The largest distance of the CoM from its reference [m].
    pub max_com_error_m: f64,
    /// Ticks at which the centre of pressure asked for was outside the support.
    pub saturated_ticks: usize,
    /// Where each step of the plan lands at the end (or when the walk was lost), world
    /// (x, y) [m].
    pub world_p_landings: Vec<Vector2<f64>>,
}

/// One whole-body tick of a template walk, handed to [`TemplateWalk::run_with`]'s sink.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemplateTick {
    /// The tick's time [s].
    pub t: f64,
    /// The CoM, world (x, y) [m].
    pub world_p_com: Vector2<f64>,
    /// The CoM reference (after the tick's step adjustment), world (x, y) [m].
    pub world_p_com_reference: Vector2<f64>,
    /// The DCM `c + cdot / omega`, world (x, y) [m].
    pub world_xi: Vector2<f64>,
    /// The centre of pressure asked for by the law, world (x, y) [m].
    pub world_p_cop_wished: Vector2<f64>,
    /// The centre of pressure held over the tick (in the support), world (x, y) [m].
    pub world_p_cop: Vector2<f64>,
}

/// A scenario's walk on its template (module doc).
#[derive(Clone, Debug)]
pub struct TemplateWalk {
    /// The plan as the controller makes it at the start.
    gait: Gait,
    /// The walking settings (step limits, adjustment).
    settings: WalkingSettings,
    /// The soles as the step adjustment sees them (the controller's contact surface).
    adjust_surface: ContactSurface,
    /// The soles the centre of pressure may use (shrunk by `cop_margin`).
    cop_surface: ContactSurface,
    /// The robot's mass [kg].
    mass_kg: f64,
    /// `momentum_proportional`, `momentum_integral` (x, y).
    gains: [[f64; 2]; 2],
    /// The whole-body period [s].
    period_s: f64,
    /// The run's length [s].
    duration_s: f64,
    /// `simulation.divergence_com_error_m`.
    com_error_bound_m: f64,
    /// The CoM at the start, world (x, y) [m].
    world_p_com0: Vector2<f64>,
}

impl TemplateWalk {
    /// The walk of the scenario at `path` with `overrides` on its template.
    ///
    /// Errors: a scenario without a walk (naming `walking`), the scenario's.
    pub fn of_scenario(path: &Path, overrides: &[(String, String)]) -> Result<Self> {
        let (scenario, setup, settings) = built_walk(path, overrides)?;
        let model = &setup.model;
        let (Some(gait), Some(settings)) = (setup.controller.gait(), settings) else {
            let message =
                "the template needs a scenario that walks ([walking] with a command or footsteps)";
            return Err(Error::config("walking", message));
        };
        let controller = setup.controller.settings();
        let constraints = &controller.constraints;
        let mut cop_surface = constraints.surface;
        cop_surface.foot_x = constraints.cop_range(cop_surface.foot_x);
        cop_surface.foot_y = constraints.cop_range(cop_surface.foot_y);
        let [kp, ki] = [
            controller.momentum_proportional,
            controller.momentum_integral,
        ];
        let world_p_com0 = gait.dcm.sample(0.0).com.position.xy();
        Ok(Self {
            gait: gait.clone(),
            settings,
            adjust_surface: constraints.surface,
            cop_surface,
            mass_kg: model.total_mass(),
            gains: [[kp[0], kp[1]], [ki[0], ki[1]]],
            period_s: 1.0 / scenario.controller.rate_hz(),
            duration_s: scenario.simulation.duration_s,
            com_error_bound_m: scenario.simulation.divergence_com_error_m,
            world_p_com0,
        })
    }

    /// The robot's mass [kg].
    pub fn mass_kg(&self) -> f64 {
        self.mass_kg
    }

    /// Runs the walk with `push` (module doc).
    pub fn run(&self, push: Option<TemplatePush>) -> TemplateOutcome {
        self.run_with(push, |_| ())
    }

    /// Whether the walk recovers a push of `impulse` [N s] along the world (x, y) unit
    /// `along`, over `(start_s, duration_s)` [s].
    pub fn recovers(
        &self,
        impulse: f64,
        along: Vector2<f64>,
        (start_s, duration_s): (f64, f64),
    ) -> bool {
        let world_force = push_force(impulse, duration_s, along);
        let push = TemplatePush {
            world_force,
            start_s,
            duration_s,
        };
        self.run(Some(push)).recovered
    }

    /// Runs the walk with `push`, handing every tick to `sink`.
    pub fn run_with(
        &self,
        push: Option<TemplatePush>,
        mut sink: impl FnMut(&TemplateTick),
    ) -> TemplateOutcome {
        let mut gait = self.gait.clone();
        let omega = gait.dcm.lip().omega;
        let (mut c, mut v) = (self.world_p_com0, Vector2::zeros());
        let mut outcome = TemplateOutcome {
            recovered: false,
            diverged_at: None,
            max_com_error_m: 0.0,
            saturated_ticks: 0,
            world_p_landings: Vec::new(),
        };
        let ticks = (self.duration_s / self.period_s).round() as usize;
        for tick in 0..ticks {
            let t = tick as f64 * self.period_s;
            self.adjust(&mut gait, t, c, v);
            let reference = gait.com_reference(t);
            let error = c - reference.position.xy();
            outcome.max_com_error_m = outcome.max_com_error_m.max(error.norm());
            if error.norm() > self.com_error_bound_m {
                outcome.diverged_at = Some(t);
                outcome.world_p_landings = landings(&gait);
                return outcome;
            }
            let [kp, ki] = self.gains;
            let accel = Vector2::from_fn(|r, _| {
                reference.acceleration[r]
                    - kp[r] * (v[r] - reference.velocity[r])
                    - ki[r] * error[r]
            });
            let wished = c - accel / omega.powi(2);
            let p = self.support_at(&gait, t).closest_point(wished);
            if (p - wished).norm() > 1e-9 {
                outcome.saturated_ticks += 1;
            }
            sink(&TemplateTick {
                t,
                world_p_com: c,
                world_p_com_reference: reference.position.xy(),
                world_xi: c + v / omega,
                world_p_cop_wished: wished,
                world_p_cop: p,
            });
            (c, v) = self.advance(c, v, p, push, t, omega);
        }
        let end = gait.footsteps.final_stance();
        let xi = c + v / omega;
        let standing = SupportPolygon::of_stance(&end, &self.adjust_surface);
        let walked = ticks as f64 * self.period_s >= gait.end_time();
        outcome.recovered = !walked || standing.signed_margin(xi) >= 0.0;
        outcome.world_p_landings = landings(&gait);
        outcome
    }

    /// Step adjustment at `t` (the controller's rule: the step in flight, adjusted by
    /// `adjust_step` with the template's CoM).
    fn adjust(&self, gait: &mut Gait, t: f64, c: Vector2<f64>, v: Vector2<f64>) {
        let measured = MeasuredCom {
            time: t,
            world_p_com: c,
            world_v_com: v,
            world_z_com: gait.world_z_com,
        };
        let settings = &self.settings;
        if !settings.step_adjustment {
            return;
        }
        let phase = gait.footsteps.phase_at(t);
        let (Support::Single { .. }, Some(index)) = (phase.support, phase.step) else {
            return;
        };
        adjust_step(gait, settings, &self.adjust_surface, index, measured);
    }

    /// The support the plan has at `t`: the stance sole in single support, both soles'
    /// hull otherwise (shrunk by `cop_margin`).
    fn support_at(&self, gait: &Gait, t: f64) -> SupportPolygon {
        let plan = &gait.footsteps;
        let phase = plan.phase_at(t);
        match (phase.support, phase.step) {
            (Support::Single { .. }, Some(index)) => {
                SupportPolygon::of_sole(plan.stance_sole(index), &self.cop_surface)
            }
            (_, step) => {
                let feet = step.map_or(plan.stances[0], |index| plan.stances[index + 1]);
                SupportPolygon::of_stance(&feet, &self.cop_surface)
            }
        }
    }

    /// The CoM's position and velocity one period after `t` from `(c, v)` with the centre of
    /// pressure held at `p` and the push's force where its window overlaps (exact).
    fn advance(
        &self,
        c: Vector2<f64>,
        v: Vector2<f64>,
        p: Vector2<f64>,
        push: Option<TemplatePush>,
        t: f64,
        omega: f64,
    ) -> (Vector2<f64>, Vector2<f64>) {
        let end = t + self.period_s;
        let mut cuts = vec![t];
        if let Some(push) = push {
            let window = [push.start_s, push.start_s + push.duration_s];
            cuts.extend(window.into_iter().filter(|&s| t < s && s < end));
        }
        cuts.push(end);
        cuts.windows(2).fold((c, v), |(c, v), piece| {
            let pushed = push.is_some_and(|push| {
                push.start_s <= piece[0] && piece[0] < push.start_s + push.duration_s
            });
            let force = push
                .filter(|_| pushed)
                .map_or(Vector2::zeros(), |push| push.world_force);
            let p_effective = p - force / (self.mass_kg * omega.powi(2));
            lip_after(c, v, p_effective, piece[1] - piece[0], omega)
        })
    }
}

/// The pushes of `sea-sim push --phase` on the template of the scenario at `path` with
/// `overrides`: a push over `window` (start, length) [s] along each of `directions` (the first
/// contact's sole axes, [`Stance::direction`]), of each of `impulses` [N s]; per direction,
/// whether each was recovered.
///
/// Errors: a push `window` that does not end within the run (naming `window`), as
/// [`TemplateWalk::of_scenario`].
pub fn template_pushes(
    path: &Path,
    overrides: &[(String, String)],
    window: (f64, f64),
    directions: &[PushDirection],
    impulses: &[f64],
) -> Result<Vec<Vec<bool>>> {
    per_direction(path, overrides, (directions, window), |walk, along| {
        impulses
            .iter()
            .map(|&impulse| walk.recovers(impulse, along, window))
            .collect()
    })
}

/// The largest push [N s] the template of the scenario at `path` with `overrides` recovers
/// along each of `directions`, pushed over `window` (start, length) [s]: the impulse doubled
/// from 1 N s until a push is lost (at most [`TEMPLATE_CEILING_N_S`], reported as such when
/// recovered there), then bisected to `tolerance_n_s` (about 0 when even a small push is
/// lost). A bisection: a recovered island above the first loss found is not seen
/// (`--impulses` shows every outcome).
///
/// Errors: a push `window` that does not end within the run (naming `window`), as
/// [`TemplateWalk::of_scenario`].
pub fn template_bisection(
    path: &Path,
    overrides: &[(String, String)],
    window: (f64, f64),
    directions: &[PushDirection],
    tolerance_n_s: f64,
) -> Result<Vec<f64>> {
    per_direction(path, overrides, (directions, window), |walk, along| {
        let recovered = |impulse| walk.recovers(impulse, along, window);
        let mut high = 1.0;
        while recovered(high) {
            if high >= TEMPLATE_CEILING_N_S {
                return TEMPLATE_CEILING_N_S;
            }
            high = (2.0 * high).min(TEMPLATE_CEILING_N_S);
        }
        bisect_holding(recovered, (0.0, high), tolerance_n_s)
    })
}

/// `study` of the template of the scenario at `path` with `overrides` along each of
/// `directions` (its world (x, y) unit vector, [`Stance::direction`]). Errors: a push
/// `window` (start, length) [s] that does not end within the run (naming `window`), as
/// [`TemplateWalk::of_scenario`].
fn per_direction<T>(
    path: &Path,
    overrides: &[(String, String)],
    (directions, window): (&[PushDirection], (f64, f64)),
    study: impl Fn(&TemplateWalk, Vector2<f64>) -> T,
) -> Result<Vec<T>> {
    let walk = TemplateWalk::of_scenario(path, overrides)?;
    let (start_s, duration_s) = window;
    let end = start_s + duration_s;
    // `end > start_s`: a length lost in rounding the end would be a push never applied.
    if !(start_s >= 0.0 && duration_s > 0.0 && end > start_s && end <= walk.duration_s) {
        let expected = format!(
            "a push from 0 s on, of positive length (after its end is rounded), ending \
             within the run's {} s (simulation.duration_s)",
            walk.duration_s
        );
        let actual = format!("from {start_s} s for {duration_s} s");
        return Err(sea_dyn::Error::invalid("window", expected, actual).into());
    }
    let stance = Stance::of(&Scenario::from_file(path, overrides)?)?;
    Ok(directions
        .iter()
        .map(|&direction| study(&walk, stance.direction(direction)))
        .collect())
}

/// The largest push [N s] [`template_bisection`] tries.
pub const TEMPLATE_CEILING_N_S: f64 = 1000.0;

/// Where each step of `gait` lands, world (x, y) [m].
fn landings(gait: &Gait) -> Vec<Vector2<f64>> {
    let steps = &gait.footsteps.steps;
    steps.iter().map(|step| step.pose.world_p_sole).collect()
}

/// The pendulum's CoM position and velocity after `duration` [s] from `(c, v)` about the fixed
/// point `p`: `c(t) = p + (c - p) cosh(omega t) + v / omega sinh(omega t)`.
pub fn lip_after(
    c: Vector2<f64>,
    v: Vector2<f64>,
    p: Vector2<f64>,
    duration: f64,
    omega: f64,
) -> (Vector2<f64>, Vector2<f64>) {
    let (sh, ch) = ((omega * duration).sinh(), (omega * duration).cosh());
    let offset = c - p;
    (
        p + offset * ch + v * (sh / omega),
        offset * (omega * sh) + v * ch,
    )
}

/// The world (x, y) force of a push of `impulse` [N s] over `duration_s` along the unit
/// `world_direction`.
pub fn push_force(impulse: f64, duration_s: f64, world_direction: Vector2<f64>) -> Vector2<f64> {
    world_direction * (impulse / duration_s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `lip_after` against a fine Runge-Kutta integration of `cddot = omega^2 (c - p)`.
    #[test]
    fn the_pendulum_in_closed_form_matches_its_integration() {
        let (omega, duration) = (4.386, 0.37);
        let p = Vector2::new(0.02, -0.07);
        let (mut c, mut v) = (Vector2::new(0.1, 0.03), Vector2::new(0.25, -0.12));
        let (c_exact, v_exact) = lip_after(c, v, p, duration, omega);
        let n = 10_000;
        let h = duration / n as f64;
        let accel = |c: Vector2<f64>| (c - p) * omega.powi(2);
        for _ in 0..n {
            let (k1c, k1v) = (v, accel(c));
            let (k2c, k2v) = (v + k1v * (h / 2.0), accel(c + k1c * (h / 2.0)));
            let (k3c, k3v) = (v + k2v * (h / 2.0), accel(c + k2c * (h / 2.0)));
            let (k4c, k4v) = (v + k3v * h, accel(c + k3c * h));
            c += (k1c + k2c * 2.0 + k3c * 2.0 + k4c) * (h / 6.0);
            v += (k1v + k2v * 2.0 + k3v * 2.0 + k4v) * (h / 6.0);
        }
        assert!((c - c_exact).norm() < 1e-12, "{c} vs {c_exact}");
        assert!((v - v_exact).norm() < 1e-11, "{v} vs {v_exact}");
    }

    #[test]
    fn a_push_force_carries_its_impulse() {
        let force = push_force(8.0, 0.1, Vector2::new(0.6, 0.8));
        assert!((force * 0.1 - Vector2::new(4.8, 6.4)).norm() < 1e-12);
    }
}
