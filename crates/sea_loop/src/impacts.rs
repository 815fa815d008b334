//! Impacts at plant-step resolution: each touchdown of a foot (a contact whose points carried
//! no force at the previous plant step and carry force now, unilateral contacts) and each joint
//! reaching its stop (`plant.joint_stops`), with what the impact did to the actuators.
//!
//! Per impact at time `t` (the start of the first plant step whose evaluation has the force):
//! - the approach speed before and after: the rate of the approach coordinate averaged over
//!   [`SPEED_SPAN_S`] (1 ms), ending at `t` (before) and at `t +` [`SPEED_AFTER_S`] (5 ms,
//!   after). A foot's approach coordinate is the depth of its points' centroid below the
//!   ground's plane (`-n . c`, positive sinking), so its speeds are the foot's normal speed
//!   towards the ground [m/s]; a joint's is its position towards the stop it reached (`s` at
//!   its upper limit, `-s` at its lower) [rad/s or m/s]. The velocity jump is `before -
//!   after` (positive when the impact stopped the approach);
//! - over the [`PEAK_WINDOW_S`] (50 ms) from `t` on, the peak spring torque `max |K_S (Gamma
//!   theta - s)|` over the elastic joints [Nm] and the peak motor velocity `max |thetadot|`
//!   [rad/s], taken at the plant steps' starts; and the same peaks over the window before `t`
//!   as a reference (shorter when the run is younger).
//!
//! An impact is complete when its window after closes; it closes early (a shorter window,
//! [`Impact::window_after_s`]) when the same foot or joint strikes again or the run ends. The
//! detector's buffers are sized once: per step it reads the plant's outputs and the state and
//! allocates nothing (an impact's record goes into a list reserved for [`RESERVED_IMPACTS`]).

use sea_plant::{Plant, PlantOutputs, StateLayout};
use std::sync::Arc;

/// Span over which an approach speed is averaged [s].
pub const SPEED_SPAN_S: f64 = 1e-3;

/// Time after the impact at which the speed after it is taken (the end of its span) [s].
pub const SPEED_AFTER_S: f64 = 5e-3;

/// Window of the peaks after (and before) an impact [s].
pub const PEAK_WINDOW_S: f64 = 50e-3;

/// Impacts the record list holds without growing.
pub const RESERVED_IMPACTS: usize = 256;

/// What struck.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImpactKind {
    /// A foot touched down (unilateral contacts).
    Touchdown,
    /// A joint reached its stop (`plant.joint_stops`).
    JointStop,
}

impl ImpactKind {
    /// `"touchdown"` or `"joint_stop"`.
    pub fn name(self) -> &'static str {
        match self {
            ImpactKind::Touchdown => "touchdown",
            ImpactKind::JointStop => "joint_stop",
        }
    }
}

/// One impact and its figures (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Impact {
    /// Touchdown or joint stop.
    pub kind: ImpactKind,
    /// The contact frame (a touchdown) or the joint (a stop).
    pub name: Arc<str>,
    /// Start of the first plant step with the force [s].
    pub time_s: f64,
    /// Approach speed over the span before the impact [m/s; rad/s for a revolute joint].
    pub speed_before: f64,
    /// Approach speed over the span ending [`SPEED_AFTER_S`] after it (over what the window
    /// had when it closed early; NaN when it closed at once).
    pub speed_after: f64,
    /// Peak spring torque over the window after [Nm].
    pub peak_spring_torque_after_nm: f64,
    /// Peak `|thetadot|` over the window after [rad/s].
    pub peak_motor_velocity_after_rad_s: f64,
    /// Peak spring torque over the window before [Nm].
    pub peak_spring_torque_before_nm: f64,
    /// Peak `|thetadot|` over the window before [rad/s].
    pub peak_motor_velocity_before_rad_s: f64,
    /// Length of the window after [s]: [`PEAK_WINDOW_S`] unless it closed early.
    pub window_after_s: f64,
}

impl Impact {
    /// `speed_before - speed_after`: the approach speed the impact removed.
    pub fn velocity_jump(&self) -> f64 {
        self.speed_before - self.speed_after
    }

    /// The unit of the speeds: `m/s` for a touchdown, `rad/s` for a stop (of a revolute joint).
    pub fn speed_unit(&self) -> &'static str {
        match self.kind {
            ImpactKind::Touchdown => "m/s",
            ImpactKind::JointStop => "rad/s",
        }
    }
}

impl std::fmt::Display for Impact {
    /// One line, e.g. `touchdown of l_sole at t = 1.2345 s: speed before 0.1 m/s, after
    /// 0.001 m/s, jump 0.099 m/s; over 50 ms after: peak spring torque 12 Nm, peak motor
    /// velocity 3 rad/s; over 50 ms before: 4 Nm, 1 rad/s`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let unit = self.speed_unit();
        write!(
            f,
            "{} of {} at t = {:.4} s: speed before {:.4} {unit}, after {:.4} {unit}, jump {:.4} \
             {unit}; over {:.0} ms after: peak spring torque {:.3} Nm, peak motor velocity \
             {:.3} rad/s; over {:.0} ms before: {:.3} Nm, {:.3} rad/s",
            self.kind.name(),
            self.name,
            self.time_s,
            self.speed_before,
            self.speed_after,
            self.velocity_jump(),
            1e3 * self.window_after_s,
            self.peak_spring_torque_after_nm,
            self.peak_motor_velocity_after_rad_s,
            1e3 * PEAK_WINDOW_S,
            self.peak_spring_torque_before_nm,
            self.peak_motor_velocity_before_rad_s,
        )
    }
}

/// A foot or a joint with a stop.
#[derive(Clone, Debug)]
struct Source {
    kind: ImpactKind,
    name: Arc<str>,
    /// A foot: its points `points.0..points.1` (over all contacts); a joint: its coordinate
    /// in `points.0`.
    points: (usize, usize),
    /// Whether it carried force at the last step.
    active: bool,
}

/// An impact whose window after is open.
#[derive(Clone, Copy, Debug)]
struct Open {
    /// Steps observed since the impact (the impact's step is 0).
    steps: usize,
    /// Sign turning the raw coordinate into the approach coordinate.
    sign: f64,
    time_s: f64,
    speed_before: f64,
    /// NaN until taken.
    speed_after: f64,
    peaks_after: [f64; 2],
    peaks_before: [f64; 2],
}

/// Fixed-size history of per-step values: `width` values per slot, `slots` slots.
#[derive(Clone, Debug)]
struct Ring {
    values: Vec<f64>,
    width: usize,
    slots: usize,
}

impl Ring {
    fn new(width: usize, slots: usize) -> Self {
        Self {
            values: vec![0.0; width * slots],
            width,
            slots,
        }
    }

    /// The slot of step `step` (mutable).
    fn slot_mut(&mut self, step: usize) -> &mut [f64] {
        let start = (step % self.slots) * self.width;
        &mut self.values[start..start + self.width]
    }

    /// Value `i` of step `step`.
    fn get(&self, step: usize, i: usize) -> f64 {
        self.values[(step % self.slots) * self.width + i]
    }
}

/// The impact detector of a run (module documentation).
#[derive(Clone, Debug)]
pub(crate) struct ImpactDetector {
    step_s: f64,
    /// Steps per speed span, per speed-after delay, per peak window.
    span_steps: usize,
    after_steps: usize,
    window_steps: usize,
    sources: Vec<Source>,
    /// The ground's normal (world) under unilateral contacts.
    normal: [f64; 3],
    /// Per step: each source's raw coordinate (`n . c` of a foot, `s` of a joint).
    coordinates: Ring,
    /// Per step: the peak spring torque and `|thetadot|` over the joints.
    peaks: Ring,
    /// Steps observed so far (the next step's index).
    steps: usize,
    /// Per source, its open window.
    open: Vec<Option<Open>>,
    /// Every complete impact, in the order they closed.
    impacts: Vec<Impact>,
}

impl ImpactDetector {
    /// A detector for `plant` stepped every `step_s` seconds, with `contact_names` naming
    /// its contacts; `None` when nothing can strike (bilateral contacts and no joint stops).
    pub fn new(plant: &Plant, contact_names: &[String], step_s: f64) -> Option<Self> {
        let mut sources = Vec::new();
        let mut normal = [0.0, 0.0, 1.0];
        if let Some(unilateral) = plant.unilateral() {
            normal = unilateral.ground.normal.into();
            let mut first = 0;
            for (c, points) in unilateral.points.iter().enumerate() {
                let name = contact_names
                    .get(c)
                    .map_or_else(|| format!("contact_{c}"), Clone::clone);
                sources.push(Source {
                    kind: ImpactKind::Touchdown,
                    name: name.into(),
                    points: (first, first + points.len()),
                    active: false,
                });
                first += points.len();
            }
        }
        if plant.joint_stops.is_some() {
            for joint in &plant.model.joints {
                sources.push(Source {
                    kind: ImpactKind::JointStop,
                    name: joint.name.as_str().into(),
                    points: (joint.coordinate, joint.coordinate),
                    active: false,
                });
            }
        }
        if sources.is_empty() {
            return None;
        }
        let steps = |span: f64| ((span / step_s).round() as usize).max(1);
        let (span_steps, window_steps) = (steps(SPEED_SPAN_S), steps(PEAK_WINDOW_S));
        Some(Self {
            step_s,
            span_steps,
            after_steps: steps(SPEED_AFTER_S),
            window_steps,
            normal,
            // One slot more than read back: the current step's is written first.
            coordinates: Ring::new(sources.len(), span_steps + 2),
            peaks: Ring::new(2, window_steps + 1),
            steps: 0,
            open: vec![None; sources.len()],
            sources,
            impacts: Vec::with_capacity(RESERVED_IMPACTS),
        })
    }

    /// Every complete impact so far, in the order they closed.
    pub fn impacts(&self) -> &[Impact] {
        &self.impacts
    }

    /// Observes the start of a plant step at `time_s`: the state `x` and `outputs`, the
    /// plant's evaluation there. Closes the windows that are over and opens one per new
    /// impact. Allocates nothing (but when the impact list outgrows its reserve).
    pub fn observe(
        &mut self,
        (plant, layout): (&Plant, StateLayout),
        time_s: f64,
        x: &[f64],
        outputs: &PlantOutputs,
    ) {
        let step = self.steps;
        self.record_step(plant, layout, x, outputs);
        for index in 0..self.sources.len() {
            if let Some(open) = &mut self.open[index] {
                open.steps += 1;
                if open.steps >= self.window_steps {
                    self.close(index);
                }
            }
            let active = self.is_active(index, outputs);
            let source = &mut self.sources[index];
            let struck = active && !source.active && step > 0;
            source.active = active;
            if struck {
                if self.open[index].is_some() {
                    self.close(index);
                }
                self.open_window(index, time_s, outputs);
            }
        }
        self.update_open();
        self.steps += 1;
    }

    /// Closes every open window (the run ended after the last observed step).
    pub fn close_all(&mut self) {
        for index in 0..self.sources.len() {
            if let Some(open) = &mut self.open[index] {
                // Counted as in `observe`: the steps the window covered.
                open.steps += 1;
                self.close(index);
            }
        }
    }

    /// Stores this step's coordinates and peaks in the rings.
    fn record_step(
        &mut self,
        plant: &Plant,
        layout: StateLayout,
        x: &[f64],
        outputs: &PlantOutputs,
    ) {
        let step = self.steps;
        let positions = outputs.contact_point_position.as_slice();
        let slot = self.coordinates.slot_mut(step);
        for (value, source) in slot.iter_mut().zip(&self.sources) {
            let (first, end) = source.points;
            *value = match source.kind {
                ImpactKind::Touchdown => {
                    centroid_height(&positions[3 * first..3 * end], self.normal)
                }
                ImpactKind::JointStop => layout.q(x)[7 + first],
            };
        }
        let peaks = [
            spring_torque_peak(plant, layout, x),
            velocity_peak(layout.thetadot(x)),
        ];
        self.peaks.slot_mut(step).copy_from_slice(&peaks);
    }

    /// Whether source `index` carries force in `outputs`.
    fn is_active(&self, index: usize, outputs: &PlantOutputs) -> bool {
        let source = &self.sources[index];
        let (first, end) = source.points;
        match source.kind {
            ImpactKind::Touchdown => outputs.contact_point_active[first..end].iter().any(|&a| a),
            ImpactKind::JointStop => outputs.joint_stop_active[first],
        }
    }

    /// Opens the window of an impact of source `index` at this step.
    fn open_window(&mut self, index: usize, time_s: f64, outputs: &PlantOutputs) {
        let source = &self.sources[index];
        let sign = match source.kind {
            ImpactKind::Touchdown => -1.0,
            // The stop pushes away from its limit: negative at the upper one.
            ImpactKind::JointStop if outputs.joint_stop_torque[source.points.0] < 0.0 => 1.0,
            ImpactKind::JointStop => -1.0,
        };
        let mut peaks_before = [0.0_f64; 2];
        for back in 1..=self.steps.min(self.window_steps) {
            for (i, peak) in peaks_before.iter_mut().enumerate() {
                *peak = peak.max(self.peaks.get(self.steps - back, i));
            }
        }
        self.open[index] = Some(Open {
            steps: 0,
            sign,
            time_s,
            speed_before: sign * self.speed(index, self.span_steps),
            speed_after: f64::NAN,
            peaks_after: [0.0; 2],
            peaks_before,
        });
    }

    /// Adds this step's peaks to every open window, and takes the speed after when due.
    fn update_open(&mut self) {
        let step = self.steps;
        let peaks = [self.peaks.get(step, 0), self.peaks.get(step, 1)];
        for index in 0..self.sources.len() {
            let Some(mut open) = self.open[index] else {
                continue;
            };
            for (after, now) in open.peaks_after.iter_mut().zip(peaks) {
                *after = after.max(now);
            }
            if open.steps == self.after_steps {
                open.speed_after = open.sign * self.speed(index, self.span_steps);
            }
            self.open[index] = Some(open);
        }
    }

    /// Rate of source `index`'s raw coordinate over the last `span` steps (fewer when fewer
    /// were observed) ending at the current step; NaN with none.
    fn speed(&self, index: usize, span: usize) -> f64 {
        let span = span.min(self.steps);
        if span == 0 {
            return f64::NAN;
        }
        let now = self.coordinates.get(self.steps, index);
        let then = self.coordinates.get(self.steps - span, index);
        (now - then) / (span as f64 * self.step_s)
    }

    /// Closes source `index`'s window: its impact joins the list.
    fn close(&mut self, index: usize) {
        let Some(open) = self.open[index].take() else {
            return;
        };
        let mut speed_after = open.speed_after;
        // Closed before the speed after was due: over what the window had (its steps
        // `steps - open.steps..steps`, the current step not included).
        let span = self.span_steps.min(open.steps.saturating_sub(1));
        if speed_after.is_nan() && span > 0 {
            let last = self.steps - 1;
            let now = self.coordinates.get(last, index);
            let then = self.coordinates.get(last - span, index);
            speed_after = open.sign * (now - then) / (span as f64 * self.step_s);
        }
        let source = &self.sources[index];
        self.impacts.push(Impact {
            kind: source.kind,
            name: Arc::clone(&source.name),
            time_s: open.time_s,
            speed_before: open.speed_before,
            speed_after,
            peak_spring_torque_after_nm: open.peaks_after[0],
            peak_motor_velocity_after_rad_s: open.peaks_after[1],
            peak_spring_torque_before_nm: open.peaks_before[0],
            peak_motor_velocity_before_rad_s: open.peaks_before[1],
            window_after_s: open.steps as f64 * self.step_s,
        });
    }
}

/// `n . c` of the centroid `c` of the points `positions` (3 per point).
fn centroid_height(positions: &[f64], normal: [f64; 3]) -> f64 {
    let points = (positions.len() / 3).max(1) as f64;
    let sum: f64 = positions
        .chunks_exact(3)
        .map(|p| p[0] * normal[0] + p[1] * normal[1] + p[2] * normal[2])
        .sum();
    sum / points
}

/// `max |K_S (Gamma theta - s)|` over the elastic joints of `plant` at `x` (0 without any).
fn spring_torque_peak(plant: &Plant, layout: StateLayout, x: &[f64]) -> f64 {
    let actuation = &plant.actuation;
    let (s, theta) = (&layout.q(x)[7..], layout.theta(x));
    let joints = actuation.elastic_joints.iter().zip(&actuation.elastic);
    joints
        .zip(theta)
        .map(|((&j, e), theta)| (e.stiffness * (e.ratio * theta - s[j])).abs())
        .fold(0.0, f64::max)
}

/// `max |v|` (0 when empty).
fn velocity_peak(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}
