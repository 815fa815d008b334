//! Impacts at plant-step resolution: each touchdown of a foot (a contact whose points carried
//! no force at the previous plant step and carry force now, unilateral contacts) and each joint
//! reaching its stop (`plant.joint_stops`), with what the impact did to the actuators.
//!
//! Per impact at time `t` (the start of the first plant step whose evaluation has the force):
//! - the approach speed before and after: the rate of the approach coordinate averaged over
//!   [`SPEED_SPAN_S`] (1 ms), ending at `t` (before) and at `t +` [`SPEED_AFTER_S`] (5 ms,
//!   after). A foot's approach coordinate is the mean depth below the ground's plane
//!   (`-n . p`, positive sinking) of its touching points, those that carry force at `t` (a flat
//!   landing: all of them; an edge landing: that edge's, not the foot's centre, which may
//!   still rise as the foot rolls), so its speeds are the foot's normal speed towards the
//!   ground where it lands [m/s]; a joint's is its position towards the stop it reached (`s`
//!   at its upper limit, `-s` at its lower) [rad/s or m/s]. The velocity jump is `before -
//!   after` (positive when the impact stopped the approach). With the default compliant
//!   ground the foot is stopped over some 10 ms, so the jump at 5 ms is part of the approach
//!   speed;
//! - over the [`PEAK_WINDOW_S`] (50 ms) from `t` on, the peak spring torque `max |K_S (Gamma
//!   theta - s)|` over the elastic joints [Nm] and the peak motor velocity `max |thetadot|`
//!   [rad/s], taken at the plant steps' starts; and the same peaks over the window before `t`
//!   as a reference (shorter when the run is younger);
//! - the joint side, for any actuation (elastic or rigid): over the same window after, the
//!   largest change of a joint torque from its value at `t`, `max_j |tau_j(t') - tau_j(t)|`
//!   [Nm] (the torque the plant applies to the links: the spring's for an elastic joint, the
//!   motor's for a rigid one), and the joint velocity jump `max_j |sdot_j(t + 5 ms) -
//!   sdot_j(t)|` at the time the speed after is taken [rad/s].
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
    /// Largest change of a joint torque from its value at the impact over the window after,
    /// `max_j |tau_j(t') - tau_j(t)|` [Nm].
    pub peak_joint_torque_change_nm: f64,
    /// `max_j |sdot_j(t + SPEED_AFTER_S) - sdot_j(t)|` [rad/s] (at the step that closed the
    /// window when it closed earlier; NaN when it closed at once).
    pub joint_velocity_jump_rad_s: f64,
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
             {:.3} rad/s, largest joint torque change {:.3} Nm, joint velocity jump {:.3} rad/s; \
             over {:.0} ms before: {:.3} Nm, {:.3} rad/s",
            self.kind.name(),
            self.name,
            self.time_s,
            self.speed_before,
            self.speed_after,
            self.velocity_jump(),
            1e3 * self.window_after_s,
            self.peak_spring_torque_after_nm,
            self.peak_motor_velocity_after_rad_s,
            self.peak_joint_torque_change_nm,
            self.joint_velocity_jump_rad_s,
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
    /// Its columns `first..end` of the coordinate history: a foot's points, a joint's one.
    columns: (usize, usize),
    /// A joint: its coordinate (index of `s`); a foot: unused.
    coordinate: usize,
    /// Whether it carried force at the last step.
    active: bool,
}

/// An impact whose window after is open.
#[derive(Clone, Copy, Debug)]
struct Open {
    /// Steps observed since the impact (the impact's step is 0).
    steps: usize,
    /// The columns of the approach coordinate: bit `b` for column `first + b` (a foot's
    /// touching points, its first 64; a joint's column).
    mask: u64,
    /// Sign turning the raw coordinate into the approach coordinate.
    sign: f64,
    time_s: f64,
    speed_before: f64,
    /// NaN until taken.
    speed_after: f64,
    peaks_after: [f64; 2],
    peaks_before: [f64; 2],
    /// `max_j |tau_j - tau_j(t)|` so far.
    torque_change: f64,
    /// NaN until taken.
    velocity_jump: f64,
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
    /// Contact points over all contacts (the first columns of `coordinates`).
    points: usize,
    /// The ground's normal (world) under unilateral contacts.
    normal: [f64; 3],
    /// Per step: each contact point's height `n . p`, then each joint's `s`.
    coordinates: Ring,
    /// Per step: the peak spring torque and `|thetadot|` over the joints.
    peaks: Ring,
    /// Steps observed so far (the next step's index).
    steps: usize,
    /// Per source, its open window.
    open: Vec<Option<Open>>,
    /// Every complete impact, in the order they closed.
    impacts: Vec<Impact>,
    /// Per source, the joint torques (n) and then the joint velocities (n) at its open
    /// impact (sized once).
    at_impact: Vec<Vec<f64>>,
    /// The joint torques (n) and velocities (n) of the current step.
    joint_now: Vec<f64>,
}

impl ImpactDetector {
    /// A detector for `plant` stepped every `step_s` seconds, with `contact_names` naming
    /// its contacts; `None` when nothing can strike (bilateral contacts and no joint stops).
    pub fn new(plant: &Plant, contact_names: &[String], step_s: f64) -> Option<Self> {
        let (mut sources, mut normal, mut points) = (Vec::new(), [0.0, 0.0, 1.0], 0);
        if let Some(unilateral) = plant.unilateral() {
            normal = unilateral.ground.normal.into();
            for (c, foot) in unilateral.points.iter().enumerate() {
                let name = contact_names.get(c).cloned();
                sources.push(Source {
                    kind: ImpactKind::Touchdown,
                    name: name.unwrap_or_else(|| format!("contact_{c}")).into(),
                    columns: (points, points + foot.len()),
                    coordinate: 0,
                    active: false,
                });
                points += foot.len();
            }
        }
        let joints = plant
            .joint_stops
            .as_ref()
            .map_or(&[][..], |_| &plant.model.joints);
        for (k, joint) in joints.iter().enumerate() {
            sources.push(Source {
                kind: ImpactKind::JointStop,
                name: joint.name.as_str().into(),
                columns: (points + k, points + k + 1),
                coordinate: joint.coordinate,
                active: false,
            });
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
            points,
            normal,
            // One slot more than read back: the current step's is written first.
            coordinates: Ring::new(points + joints.len(), span_steps + 2),
            peaks: Ring::new(2, window_steps + 1),
            steps: 0,
            open: vec![None; sources.len()],
            at_impact: vec![vec![0.0; 2 * plant.model.nv().saturating_sub(6)]; sources.len()],
            joint_now: vec![0.0; 2 * plant.model.nv().saturating_sub(6)],
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
        let n = self.normal;
        let positions = outputs.contact_point_position.as_slice().chunks_exact(3);
        let slot = self.coordinates.slot_mut(step);
        let (heights, joints) = slot.split_at_mut(self.points);
        for (height, p) in heights.iter_mut().zip(positions) {
            *height = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
        }
        let s = &layout.q(x)[7..];
        let stops = self
            .sources
            .iter()
            .filter(|s| s.kind == ImpactKind::JointStop);
        for (value, source) in joints.iter_mut().zip(stops) {
            *value = s[source.coordinate];
        }
        let peaks = [
            spring_torque_peak(plant, layout, x),
            velocity_peak(layout.thetadot(x)),
        ];
        self.peaks.slot_mut(step).copy_from_slice(&peaks);
        let n = self.joint_now.len() / 2;
        let (torques, velocities) = self.joint_now.split_at_mut(n);
        copy_into(torques, outputs.joint_torque.as_slice());
        copy_into(velocities, &layout.nu(x)[6..]);
    }

    /// Whether source `index` carries force in `outputs`.
    fn is_active(&self, index: usize, outputs: &PlantOutputs) -> bool {
        let source = &self.sources[index];
        let (first, end) = source.columns;
        match source.kind {
            ImpactKind::Touchdown => outputs.contact_point_active[first..end].iter().any(|&a| a),
            ImpactKind::JointStop => outputs.joint_stop_active[source.coordinate],
        }
    }

    /// Opens the window of an impact of source `index` at this step.
    fn open_window(&mut self, index: usize, time_s: f64, outputs: &PlantOutputs) {
        let source = &self.sources[index];
        let (first, end) = source.columns;
        let (sign, mask) = match source.kind {
            ImpactKind::Touchdown => {
                let active = &outputs.contact_point_active[first..end];
                let touching = active.iter().take(64).enumerate().filter(|(_, &a)| a);
                (-1.0, touching.fold(0, |mask, (b, _)| mask | 1 << b))
            }
            // The stop pushes away from its limit: negative at the upper one.
            ImpactKind::JointStop if outputs.joint_stop_torque[source.coordinate] < 0.0 => (1.0, 1),
            ImpactKind::JointStop => (-1.0, 1),
        };
        let mut peaks_before = [0.0_f64; 2];
        for back in 1..=self.steps.min(self.window_steps) {
            for (i, peak) in peaks_before.iter_mut().enumerate() {
                *peak = peak.max(self.peaks.get(self.steps - back, i));
            }
        }
        let speed_before = sign * self.rate((first, mask), self.steps, self.span_steps);
        self.at_impact[index].copy_from_slice(&self.joint_now);
        self.open[index] = Some(Open {
            steps: 0,
            mask,
            sign,
            time_s,
            speed_before,
            speed_after: f64::NAN,
            peaks_after: [0.0; 2],
            peaks_before,
            torque_change: 0.0,
            velocity_jump: f64::NAN,
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
            let n = self.joint_now.len() / 2;
            let at_impact = &self.at_impact[index];
            let torques = (&self.joint_now[..n], &at_impact[..n]);
            open.torque_change = open.torque_change.max(largest_difference(torques));
            if open.steps == self.after_steps {
                let columns = (self.sources[index].columns.0, open.mask);
                open.speed_after = open.sign * self.rate(columns, step, self.span_steps);
                let velocities = (&self.joint_now[n..], &at_impact[n..]);
                open.velocity_jump = largest_difference(velocities);
            }
            self.open[index] = Some(open);
        }
    }

    /// Mean rate of the raw coordinates of `columns` (`first` and a mask of the columns
    /// after it) over the `span` steps (fewer when fewer were observed) ending at step `now`;
    /// NaN with no step or no column.
    fn rate(&self, (first, mask): (usize, u64), now: usize, span: usize) -> f64 {
        let span = span.min(now);
        let (mut sum, mut count) = (0.0, 0);
        for b in (0..64).filter(|b| mask & (1 << b) != 0) {
            let column = first + b;
            sum += self.coordinates.get(now, column) - self.coordinates.get(now - span, column);
            count += 1;
        }
        if span == 0 || count == 0 {
            return f64::NAN;
        }
        sum / (count as f64 * span as f64 * self.step_s)
    }

    /// Closes source `index`'s window: its impact joins the list.
    fn close(&mut self, index: usize) {
        let Some(open) = self.open[index].take() else {
            return;
        };
        let source = &self.sources[index];
        let mut speed_after = open.speed_after;
        if speed_after.is_nan() && open.steps > 1 {
            // Closed before the speed after was due: over what the window had (its steps
            // `steps - open.steps..steps`, the current step not included).
            let span = self.span_steps.min(open.steps - 1);
            let columns = (source.columns.0, open.mask);
            speed_after = open.sign * self.rate(columns, self.steps - 1, span);
        }
        let mut velocity_jump = open.velocity_jump;
        if velocity_jump.is_nan() && open.steps > 1 {
            // The velocities of the step that closed the window.
            let n = self.joint_now.len() / 2;
            let at_impact = &self.at_impact[index][n..];
            velocity_jump = largest_difference((&self.joint_now[n..], at_impact));
        }
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
            peak_joint_torque_change_nm: open.torque_change,
            joint_velocity_jump_rad_s: velocity_jump,
            window_after_s: open.steps as f64 * self.step_s,
        });
    }
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

/// `max_j |a_j - b_j|` (0 when empty).
fn largest_difference((a, b): (&[f64], &[f64])) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (a, b)| m.max((a - b).abs()))
}

/// Copies `source` into `target` as far as both reach.
fn copy_into(target: &mut [f64], source: &[f64]) {
    let n = target.len().min(source.len());
    target[..n].copy_from_slice(&source[..n]);
}

/// `max |v|` (0 when empty).
fn velocity_peak(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}
