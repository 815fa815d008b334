//! Push recovery: the largest impulse of a short push on a link that the closed loop recovers
//! from (the run completes: no fall, no divergence), found by bisection
//! ([`recoverable_impulse`]), or the outcomes of pushes of given impulses
//! ([`fixed_push_table`]), and the capture-point bound of the stance for the same direction.
//!
//! The bound is the linear inverted pendulum's: a push of impulse `I` gives the CoM the
//! velocity `I / m`; the instantaneous capture point `x_com + v / omega0`,
//! `omega0 = sqrt(g / z_com)`, stays inside the support polygon while
//! `I <= m d omega0`, `d` the distance from the CoM's ground projection to the polygon's edge
//! along the push (the polygon: the convex hull of the sole rectangles
//! `controller.contact.foot_x` x `foot_y` at the contacts' poses).

use crate::error::{Error, Result};
use nalgebra::{Vector2, Vector3};
use rayon::prelude::*;
use sea_dyn::centroidal::com;
use sea_dyn::Data;
use sea_loop::Summary;
use sea_scenario::run::run_with_sinks;
use sea_scenario::{build, Scenario};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

pub use super::push_options::{check_pushed_link, PushOptions, SETTLE_AFTER_PUSH_S};

/// A push direction in the ground plane, relative to the first contact's sole frame (its x
/// axis forward, y to the left).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PushDirection {
    /// Along the sole's +x.
    Forward,
    /// Along the sole's -x.
    Backward,
    /// Along the sole's +y.
    Left,
    /// Along the sole's -y.
    Right,
}

impl PushDirection {
    /// The four directions.
    pub const ALL: [PushDirection; 4] = [
        PushDirection::Forward,
        PushDirection::Backward,
        PushDirection::Left,
        PushDirection::Right,
    ];

    /// `"forward"`, `"backward"`, `"left"` or `"right"`.
    pub fn name(&self) -> &'static str {
        match self {
            PushDirection::Forward => "forward",
            PushDirection::Backward => "backward",
            PushDirection::Left => "left",
            PushDirection::Right => "right",
        }
    }

    /// Parses a name of [`PushDirection::name`].
    pub fn parse(name: &str) -> Result<PushDirection> {
        PushDirection::ALL
            .into_iter()
            .find(|d| d.name() == name)
            .ok_or_else(|| {
                Error::config(
                    "direction",
                    format!("expected forward, backward, left or right, got \"{name}\""),
                )
            })
    }

    /// The unit vector in the sole frame's (x, y).
    pub fn in_sole(&self) -> Vector2<f64> {
        match self {
            PushDirection::Forward => Vector2::new(1.0, 0.0),
            PushDirection::Backward => Vector2::new(-1.0, 0.0),
            PushDirection::Left => Vector2::new(0.0, 1.0),
            PushDirection::Right => Vector2::new(0.0, -1.0),
        }
    }
}

/// The stance at the scenario's initial state: what the capture-point bound needs.
#[derive(Clone, Debug)]
pub struct Stance {
    /// Total mass [kg].
    pub mass_kg: f64,
    /// CoM height above the soles [m].
    pub com_height_m: f64,
    /// `sqrt(g / z_com)` [1/s].
    pub omega0: f64,
    /// The CoM's ground projection (world x, y) [m].
    pub com_xy: Vector2<f64>,
    /// The support polygon (world x, y), counter-clockwise.
    pub polygon: Vec<Vector2<f64>>,
    /// The first contact's sole x and y axes projected on the ground (world x, y).
    pub sole_axes: [Vector2<f64>; 2],
}

impl Stance {
    /// The stance of `scenario` at its initial state.
    pub fn of(scenario: &Scenario) -> Result<Stance> {
        let setup = build(scenario)?;
        let (model, plant) = (&setup.model, &setup.plant);
        let q = &setup.x0[..model.nq()];
        let com = com(model, &mut Data::new(model), q);
        let surface = plant.contact_limits;
        let mut corners = Vec::new();
        let mut ground = 0.0;
        for contact in &plant.contacts {
            let pose = &contact.world_h_frame_desired;
            ground += pose.translation.z / plant.contacts.len() as f64;
            for x in surface.foot_x {
                for y in surface.foot_y {
                    let corner = pose.translation + pose.rotation * Vector3::new(x, y, 0.0);
                    corners.push(corner.xy());
                }
            }
        }
        let first = plant
            .contacts
            .first()
            .ok_or_else(|| Error::config("robot.contacts", "a push needs a stance"))?;
        let axes = first.world_h_frame_desired.rotation;
        let com_height_m = com.z - ground;
        let gravity = model.gravity.norm();
        Ok(Stance {
            mass_kg: model.total_mass(),
            com_height_m,
            omega0: (gravity / com_height_m).sqrt(),
            com_xy: com.xy(),
            polygon: convex_hull(corners),
            sole_axes: [
                axes.column(0).xy().normalize(),
                axes.column(1).xy().normalize(),
            ],
        })
    }

    /// The unit push direction in world (x, y).
    pub fn direction(&self, direction: PushDirection) -> Vector2<f64> {
        let d = direction.in_sole();
        (self.sole_axes[0] * d.x + self.sole_axes[1] * d.y).normalize()
    }

    /// Distance from the CoM's ground projection to the polygon's edge along `direction` [m].
    pub fn distance_to_edge(&self, direction: PushDirection) -> f64 {
        let d = self.direction(direction);
        let n = self.polygon.len();
        (0..n)
            .filter_map(|i| {
                let (a, b) = (self.polygon[i], self.polygon[(i + 1) % n]);
                let edge = b - a;
                let outward = Vector2::new(edge.y, -edge.x);
                let along = outward.dot(&d);
                (along > 0.0).then(|| outward.dot(&(a - self.com_xy)) / along)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The capture-point bound on the impulse along `direction`: `m d omega0` [N s].
    pub fn capture_point_impulse(&self, direction: PushDirection) -> f64 {
        self.mass_kg * self.distance_to_edge(direction) * self.omega0
    }
}

/// The convex hull of `points`, counter-clockwise (Andrew's monotone chain).
fn convex_hull(mut points: Vec<Vector2<f64>>) -> Vec<Vector2<f64>> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let cross = |o: Vector2<f64>, a: Vector2<f64>, b: Vector2<f64>| (a - o).perp(&(b - o));
    let mut hull: Vec<Vector2<f64>> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let sequence: Box<dyn Iterator<Item = &Vector2<f64>>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &p in sequence {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// The step a push at a phase of a swing pushes by default (`sea-sim push --phase`, Python's
/// `push_table(phase=...)` and `template_push_table`): the fourth (0-based 3), the walk under
/// way ([`pushed_step`]: the plan's last on a shorter plan).
pub const DEFAULT_PUSHED_STEP: usize = 3;

/// The step `step` names in a plan of `planned` steps: `step` itself, or by default
/// [`DEFAULT_PUSHED_STEP`], the plan's last when it has fewer (a plan of three steps in
/// place).
pub fn pushed_step(step: Option<usize>, planned: usize) -> usize {
    step.unwrap_or(DEFAULT_PUSHED_STEP.min(planned.saturating_sub(1)))
}

/// A time in a walk: fraction `phase` of the swing (single support) of step `step` of the
/// scenario's walking plan (0 the first step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingPhase {
    /// The step whose swing is meant, counted from 0 in the plan's order; `None`: the default
    /// ([`pushed_step`]).
    pub step: Option<usize>,
    /// The fraction of its swing in [0, 1]: 0 at lift-off, 1 at touchdown.
    pub phase: f64,
}

/// The time at `at` in the walk of the scenario at `path` with `overrides`: the planned
/// lift-off of the step plus `phase` times its swing, as the controller's planner makes it
/// (the scenario built, its gait read), rounded to the nearest plant step; with the step's
/// lift-off and touchdown [s].
///
/// Errors: `phase` outside [0, 1] or not finite (naming `--phase`), a scenario without a
/// walk (`[walking]` with a command or footsteps; naming `--phase`), `step` beyond the plan
/// (naming `--step` and the plan's steps), the scenario's.
pub fn swing_push_start(
    path: &Path,
    overrides: &[(String, String)],
    at: SwingPhase,
) -> Result<(f64, [f64; 2])> {
    if !(0.0..=1.0).contains(&at.phase) {
        let expected = "a fraction of the swing in [0, 1]";
        return Err(sea_dyn::Error::invalid("--phase", expected, at.phase).into());
    }
    let scenario = Scenario::from_file(path, overrides)?;
    let plant_dt = scenario.plant.dt;
    let setup = build(&scenario)?;
    let steps = setup
        .controller
        .gait()
        .map_or(&[][..], |gait| &gait.footsteps.steps[..]);
    if steps.is_empty() {
        let expected = "a scenario that walks ([walking] with a command or footsteps)";
        let actual = format!("{} (it plans no step)", path.display());
        return Err(sea_dyn::Error::invalid("--phase", expected, actual).into());
    }
    let index = pushed_step(at.step, steps.len());
    let step = steps.get(index).ok_or_else(|| {
        let expected = format!("a step of the plan, 0 to {}", steps.len() - 1);
        sea_dyn::Error::invalid("--step", expected, index)
    })?;
    let start = step.lift_off + at.phase * (step.touchdown - step.lift_off);
    let start_s = (start / plant_dt).round() * plant_dt;
    Ok((start_s, [step.lift_off, step.touchdown]))
}

/// One direction's result.
#[derive(Clone, Debug)]
pub struct PushResult {
    /// The direction.
    pub direction: PushDirection,
    /// The capture-point bound [N s].
    pub capture_point_impulse: f64,
    /// The largest impulse seen recovered [N s].
    pub recovered_impulse: f64,
    /// The smallest impulse seen not recovered [N s] (`None`: every tried impulse recovered).
    pub failed_impulse: Option<f64>,
    /// The summary of the run at `failed_impulse` (its fall: foot, constraint).
    pub failed_summary: Option<Summary>,
    /// Runs done (ended completed, diverged or fallen; a run stopped by `cancel` is not one).
    pub runs: usize,
    /// Whether `cancel` stopped the bisection before its tolerance: the impulses above are
    /// the bracket as far as it got.
    pub interrupted: bool,
}

/// The `[[disturbances]]` override of one push of `impulse` [N s] along `direction` (world).
fn push_override(options: &PushOptions, direction: Vector2<f64>, impulse: f64) -> (String, String) {
    let force = direction * (impulse / options.duration_s);
    let link = toml::Value::String(options.link.clone());
    let value = format!(
        "[{{link = {link}, force = [{:e}, {:e}, 0.0], start_s = {:e}, duration_s = {:e}}}]",
        force.x, force.y, options.start_s, options.duration_s
    );
    ("disturbances".to_string(), value)
}

/// The summary of the scenario at `path` with `overrides` and one push (constant memory).
pub fn push_run(
    path: &Path,
    overrides: &[(String, String)],
    options: &PushOptions,
    direction: Vector2<f64>,
    impulse: f64,
) -> Result<Summary> {
    let never = AtomicBool::new(false);
    push_run_until(path, overrides, options, (direction, impulse), &never)
}

/// [`push_run`] of the push `(direction, impulse)`, stopped at its next sample once `cancel`
/// is raised (its summary's status then "interrupted").
fn push_run_until(
    path: &Path,
    overrides: &[(String, String)],
    options: &PushOptions,
    (direction, impulse): (Vector2<f64>, f64),
    cancel: &AtomicBool,
) -> Result<Summary> {
    let mut all = overrides.to_vec();
    all.push(push_override(options, direction, impulse));
    let scenario = Scenario::from_file(path, &all)?;
    run_with_sinks(&scenario, &mut [], cancel, |_, _| {})
}

/// One push run done, as the progress callbacks of [`push_table`] and [`fixed_push_table`]
/// see it (called from the worker threads, in the order the runs end; a run the cancellation
/// flag stopped part-way is told too, its status "interrupted").
pub struct PushProgress<'a> {
    /// The direction pushed.
    pub direction: PushDirection,
    /// The impulse [N s].
    pub impulse_n_s: f64,
    /// The run's summary (`status`: "completed" is recovered).
    pub summary: &'a Summary,
}

/// A progress callback of the push studies: told of every run as it ends.
pub type OnPushRun<'a> = &'a (dyn Fn(&PushProgress<'_>) + Sync);

/// Largest recovered impulse along `direction` by bisection between 0 (must be recovered) and
/// twice the capture-point bound (doubled while still recovered, up to 8 times the bound);
/// `on_run` is told of every run as it ends. Once `cancel` is raised no run starts, the run
/// under way stops at its next sample, and the result is the bracket so far
/// ([`PushResult::interrupted`]).
///
/// Errors: the options' ([`PushOptions::check`], [`PushOptions::check_against`]), the
/// scenario's and the runs'.
pub fn recoverable_impulse(
    path: &Path,
    overrides: &[(String, String)],
    options: &PushOptions,
    direction: PushDirection,
    on_run: OnPushRun<'_>,
    cancel: &AtomicBool,
) -> Result<PushResult> {
    options.check()?;
    let scenario = Scenario::from_file(path, overrides)?;
    options.check_against(&scenario)?;
    let stance = Stance::of(&scenario)?;
    let bound = stance.capture_point_impulse(direction);
    let d = stance.direction(direction);
    let run = |impulse_n_s: f64| {
        stoppable_push(
            path,
            overrides,
            options,
            (direction, d, impulse_n_s),
            on_run,
            cancel,
        )
    };
    let mut result = PushResult {
        direction,
        capture_point_impulse: bound,
        recovered_impulse: 0.0,
        failed_impulse: None,
        failed_summary: None,
        runs: 0,
        interrupted: false,
    };
    if !bracket_by_doubling(&mut result, &run)? {
        result.interrupted = true;
        return Ok(result);
    }
    bisect(&mut result, options.tolerance_n_s, &run)?;
    Ok(result)
}

/// Halves the bracket of `result` (recovered, failed) with `run` until it is at most
/// `tolerance` [N s] wide, or a run is stopped (`result.interrupted`), or the floats hold no
/// impulse between its ends (a tolerance finer than their spacing there).
fn bisect(
    result: &mut PushResult,
    tolerance: f64,
    run: &dyn Fn(f64) -> Result<Option<Summary>>,
) -> Result<()> {
    while let Some(failed) = result.failed_impulse {
        if failed - result.recovered_impulse <= tolerance {
            break;
        }
        let middle = 0.5 * (result.recovered_impulse + failed);
        if middle <= result.recovered_impulse || middle >= failed {
            break;
        }
        let Some(summary) = run(middle)? else {
            result.interrupted = true;
            break;
        };
        result.runs += 1;
        if summary.completed() {
            result.recovered_impulse = middle;
        } else {
            result.failed_impulse = Some(middle);
            result.failed_summary = Some(summary);
        }
    }
    Ok(())
}

/// The first bracket of [`recoverable_impulse`] in `result`: `run` at twice the capture-point
/// bound, doubled while recovered, up to 8 times the bound (`result.failed_impulse` stays
/// `None` when every run recovered). `Ok(false)` when a run did not reach its end (`cancel`).
fn bracket_by_doubling(
    result: &mut PushResult,
    run: &dyn Fn(f64) -> Result<Option<Summary>>,
) -> Result<bool> {
    let bound = result.capture_point_impulse;
    let mut high = 2.0 * bound;
    while high <= 8.0 * bound {
        let Some(summary) = run(high)? else {
            return Ok(false);
        };
        result.runs += 1;
        if !summary.completed() {
            result.failed_impulse = Some(high);
            result.failed_summary = Some(summary);
            break;
        }
        result.recovered_impulse = high;
        high *= 2.0;
    }
    Ok(true)
}

/// One push of the study, `(direction, world direction, impulse)`, told to `on_run` as it
/// ends: its summary, or `None` when `cancel` was raised before it started or stopped it
/// part-way (told to `on_run` all the same).
fn stoppable_push(
    path: &Path,
    overrides: &[(String, String)],
    options: &PushOptions,
    (direction, world_direction, impulse_n_s): (PushDirection, Vector2<f64>, f64),
    on_run: OnPushRun<'_>,
    cancel: &AtomicBool,
) -> Result<Option<Summary>> {
    if cancel.load(Ordering::Relaxed) {
        return Ok(None);
    }
    let push = (world_direction, impulse_n_s);
    let summary = push_run_until(path, overrides, options, push, cancel)?;
    on_run(&PushProgress {
        direction,
        impulse_n_s,
        summary: &summary,
    });
    Ok((!summary.interrupted()).then_some(summary))
}

/// [`recoverable_impulse`] for each of `directions`, in parallel (rayon's pool); `on_run` is
/// told of every run as it ends; `cancel` stops every direction's bisection as it stops one.
///
/// Errors: as [`recoverable_impulse`]; the options are checked before any run.
pub fn push_table(
    path: &Path,
    overrides: &[(String, String)],
    options: &PushOptions,
    directions: &[PushDirection],
    on_run: OnPushRun<'_>,
    cancel: &AtomicBool,
) -> Result<Vec<PushResult>> {
    options.check()?;
    directions
        .par_iter()
        .map(|&direction| recoverable_impulse(path, overrides, options, direction, on_run, cancel))
        .collect()
}

/// One direction's outcomes at fixed impulses ([`fixed_push_table`]).
#[derive(Clone, Debug)]
pub struct FixedPushRow {
    /// The direction.
    pub direction: PushDirection,
    /// The capture-point bound [N s].
    pub capture_point_impulse: f64,
    /// Each impulse [N s], in the order given, with its run's summary: `None` when `cancel`
    /// stopped the run part-way or before it started.
    pub outcomes: Vec<(f64, Option<Summary>)>,
}

impl FixedPushRow {
    /// How many of the pushes were recovered (their runs completed).
    pub fn recovered_count(&self) -> usize {
        self.outcomes
            .iter()
            .filter(|(_, summary)| summary.as_ref().is_some_and(Summary::completed))
            .count()
    }

    /// The largest impulse [N s] at and below which every given impulse was recovered (0 when
    /// the smallest was not): what a bisection would take for the boundary when the outcomes
    /// have one, and below the islands of recovery when they have several. `None` when a push
    /// not run to its end lies at or below the first one not recovered: the figure is not
    /// known.
    pub fn recovered_up_to(&self) -> Option<f64> {
        impulses_recovered_up_to(
            self.outcomes
                .iter()
                .map(|(impulse, summary)| (*impulse, summary.as_ref().map(Summary::completed))),
        )
    }

    /// Whether `cancel` stopped a push of the row part-way or before it started.
    pub fn interrupted(&self) -> bool {
        self.outcomes.iter().any(|(_, summary)| summary.is_none())
    }
}

/// [`FixedPushRow::recovered_up_to`] of `(impulse, recovered)` pairs in any order
/// (`recovered` `None`: not run to its end): the largest impulse at and below which every
/// push was recovered (0 when the smallest was lost; `None` when a push not run to its end
/// lies at or below the first one lost).
pub fn impulses_recovered_up_to(
    outcomes: impl Iterator<Item = (f64, Option<bool>)>,
) -> Option<f64> {
    let mut sorted: Vec<(f64, Option<bool>)> = outcomes.collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut up_to = 0.0;
    for (impulse, recovered) in sorted {
        if !recovered? {
            break;
        }
        up_to = impulse;
    }
    Some(up_to)
}

/// The largest fixed impulse a push table takes [N s]: far beyond any humanoid's recovery (the
/// iCub's capture-point bound is about 13 N s); near `f64::MAX` the pushing force (the
/// impulse over the push's duration) would overflow to infinity.
pub const MAX_IMPULSE: f64 = 1e6;

/// Checks fixed impulses: at least one, each finite, non-negative and at most
/// [`MAX_IMPULSE`] [N s]; the error names `impulses` and the value.
pub fn check_impulses(impulses: &[f64]) -> Result<()> {
    if impulses.is_empty() {
        return Err(
            sea_dyn::Error::invalid("impulses", "at least one impulse [N s]", "none").into(),
        );
    }
    match impulses.iter().find(|i| !(0.0..=MAX_IMPULSE).contains(*i)) {
        Some(bad) => {
            let bad = sea_dyn::error::readable_number(*bad);
            let expected = format!("non-negative impulses of at most {MAX_IMPULSE:e} N s");
            Err(sea_dyn::Error::invalid("impulses", expected, bad).into())
        }
        None => Ok(()),
    }
}

/// The push of each of `impulses` [N s] along each of `directions`, one run each (all in
/// parallel, rayon's pool), instead of a bisection: the outcomes over a range show where
/// recovery has islands, which a bisection, assuming one boundary, does not
/// (docs/findings/stepping.md). `on_run` is told of every run as it ends. Once `cancel` is
/// raised no run starts and the runs under way stop at their next sample
/// ([`FixedPushRow::outcomes`]).
///
/// Errors: the options' ([`PushOptions::check`], the tolerance not used;
/// [`PushOptions::check_against`]), the impulses' ([`check_impulses`]), the scenario's and the
/// runs'.
pub fn fixed_push_table(
    path: &Path,
    overrides: &[(String, String)],
    options: &PushOptions,
    directions: &[PushDirection],
    impulses: &[f64],
    on_run: OnPushRun<'_>,
    cancel: &AtomicBool,
) -> Result<Vec<FixedPushRow>> {
    options.check()?;
    check_impulses(impulses)?;
    let scenario = Scenario::from_file(path, overrides)?;
    options.check_against(&scenario)?;
    let stance = Stance::of(&scenario)?;
    let pairs: Vec<(PushDirection, f64)> = directions
        .iter()
        .flat_map(|&direction| impulses.iter().map(move |&impulse| (direction, impulse)))
        .collect();
    let summaries = pairs
        .par_iter()
        .map(|&(direction, impulse)| {
            let push = (direction, stance.direction(direction), impulse);
            stoppable_push(path, overrides, options, push, on_run, cancel)
        })
        .collect::<Result<Vec<Option<Summary>>>>()?;
    let mut summaries = summaries.into_iter();
    Ok(directions
        .iter()
        .map(|&direction| FixedPushRow {
            direction,
            capture_point_impulse: stance.capture_point_impulse(direction),
            outcomes: impulses.iter().copied().zip(summaries.by_ref()).collect(),
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hull_of_two_rectangles_and_the_distance_along_each_axis() {
        // Two 0.15 x 0.05 soles 0.1 m apart: hull x in [-0.05, 0.1], y in [-0.075, 0.075].
        let mut corners = Vec::new();
        for y0 in [-0.05, 0.05] {
            for x in [-0.05, 0.1] {
                for y in [-0.025, 0.025] {
                    corners.push(Vector2::new(x, y0 + y));
                }
            }
        }
        let stance = Stance {
            mass_kg: 10.0,
            com_height_m: 9.81,
            omega0: 1.0,
            com_xy: Vector2::new(0.0, 0.0),
            polygon: convex_hull(corners),
            sole_axes: [Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.0)],
        };
        assert_eq!(stance.polygon.len(), 4);
        let distances = PushDirection::ALL.map(|d| stance.distance_to_edge(d));
        let expected = [0.1, 0.05, 0.075, 0.075];
        for (got, want) in distances.iter().zip(expected) {
            assert!((got - want).abs() < 1e-12, "{distances:?}");
        }
        assert!((stance.capture_point_impulse(PushDirection::Forward) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_zero_tolerance_or_duration_is_refused_naming_the_field() {
        assert!(PushOptions::default().check().is_ok());
        let cases = [
            (
                "tolerance_n_s",
                PushOptions {
                    tolerance_n_s: 0.0,
                    ..Default::default()
                },
            ),
            (
                "duration_s",
                PushOptions {
                    duration_s: 0.0,
                    ..Default::default()
                },
            ),
            (
                "duration_s",
                PushOptions {
                    duration_s: f64::NAN,
                    ..Default::default()
                },
            ),
            (
                "tolerance_n_s",
                PushOptions {
                    tolerance_n_s: -1.0,
                    ..Default::default()
                },
            ),
            (
                "start_s",
                PushOptions {
                    start_s: f64::INFINITY,
                    ..Default::default()
                },
            ),
        ];
        for (field, options) in cases {
            let message = options.check().unwrap_err().to_string();
            assert!(
                message.contains(&format!("PushOptions.{field}")),
                "{message}"
            );
        }
    }

    #[test]
    fn the_pushed_step_is_the_fourth_by_default_or_a_shorter_plans_last() {
        assert_eq!(pushed_step(None, 11), DEFAULT_PUSHED_STEP);
        assert_eq!(pushed_step(None, 3), 2);
        assert_eq!(
            pushed_step(Some(7), 3),
            7,
            "a step given is kept (and refused later)"
        );
        assert_eq!(pushed_step(None, 0), 0);
    }

    #[test]
    fn fixed_impulses_are_refused_when_none_negative_or_not_finite_naming_the_flag() {
        assert!(check_impulses(&[0.0, 2.5, MAX_IMPULSE]).is_ok());
        for bad in [
            &[][..],
            &[1.0, -1.0][..],
            &[f64::NAN][..],
            &[f64::INFINITY][..],
            &[1e308][..],
        ] {
            let message = check_impulses(bad).unwrap_err().to_string();
            assert!(message.contains("impulses"), "{bad:?}: {message}");
        }
    }

    #[test]
    fn the_impulse_recovered_up_to_stops_at_the_first_failure_in_order() {
        // Given out of order, with an island of recovery above the first failure.
        let islands = [(3.0, false), (1.0, true), (4.0, true), (2.0, true)];
        let known = |pairs: &[(f64, bool)]| pairs.iter().map(|&(i, r)| (i, Some(r))).collect();
        let up_to = |pairs: Vec<(f64, Option<bool>)>| impulses_recovered_up_to(pairs.into_iter());
        assert_eq!(up_to(known(&islands)), Some(2.0));
        assert_eq!(up_to(known(&[(1.0, false)])), Some(0.0));
        assert_eq!(up_to(known(&[(1.0, true)])), Some(1.0));
        // A push not run to its end: unknown below the first failure, irrelevant above it.
        assert_eq!(
            up_to(vec![(1.0, Some(true)), (2.0, None), (3.0, Some(false))]),
            None
        );
        assert_eq!(up_to(vec![(1.0, None), (2.0, Some(false))]), None);
        let after = vec![(1.0, Some(true)), (2.0, Some(false)), (3.0, None)];
        assert_eq!(up_to(after), Some(1.0));
    }
}
