//! The walk in the scene (`[walking]` only): what the controller plans, drawn beside what the
//! robot does, on `/scene` (world frame, on the ground plane) and `/events`.
//!
//! Entities of `/scene`:
//! - `walking/footsteps`: one closed line per planned landing (the sole rectangle at the
//!   footstep's pose, in step order), coloured by its state at the sample: landed (grey), the
//!   step under way (swinging, orange), the next one to lift off (yellow), later ones (blue);
//! - `walking/swing`: the planned path of the swinging sole's origin (a line strip, the step
//!   under way, or in double support the next one; empty after the last);
//! - `walking/dcm_planned`, `walking/dcm_measured`: the planned DCM (capture point) and the
//!   measured one `x + xdot / omega` (`xdot` = the linear momentum over the mass), as discs on
//!   the ground; `walking/vrp_planned`, `walking/com_planned`: the planned VRP (the centre of
//!   pressure the plan asks for) and the planned CoM's ground projection;
//! - `walking/dcm_path`: the planned DCM from the plan's start to the walk's end (a line
//!   strip).
//!
//! `/events` (`foxglove.Log`, level INFO): `sea_sim.planned_lift_off` and
//! `sea_sim.planned_touchdown` at each step's planned times, and `sea_sim.lift_off` when a
//! foot's contact points stop carrying force (at the first recorded sample without force, so
//! at the recording's resolution; the touchdowns are the impacts' `sea_sim.touchdown`, at
//! plant-step resolution).
//!
//! The walk is the one planned at the run's start ([`sea_loop::RunInfo::walking`]) until the
//! controller changes it ([`sea_loop::RecordSink::walking`]: a step adjusted or retimed, a
//! recovery step planned); from then on the footsteps, the swing paths, the DCM path and the
//! planned events still to come are the changed walk's (a re-planned DCM path starts at the
//! re-plan). What happened before a change stays drawn: the footsteps that had landed by
//! then and are not in the changed walk (a recovery walk holds only its own steps) stay as
//! landed footsteps, and a swing re-aimed in flight is drawn as the controller followed it,
//! each part up to the next re-aim, so a swing re-aimed several times has no jump.

use super::scene::{color, encode_to_vec, identity_pose, pose_at, vector, world_entity};
use super::FootRectangle;
use crate::Result;
use ::foxglove::messages::{
    line_primitive, log::Level, CylinderPrimitive, LinePrimitive, Point3, SceneEntity, SceneUpdate,
    Timestamp,
};
use ::foxglove::Encode;
use nalgebra::{Vector2, Vector3};
use sea_ctrl::walking::{Foot, Footstep, Gait, Support, SwingTrajectory};
use sea_loop::Sample;

/// Colour of a landed footstep.
const LANDED_COLOR: [f64; 4] = [0.5, 0.5, 0.5, 0.6];
/// Colour of the footstep under way (its foot swinging).
const CURRENT_COLOR: [f64; 4] = [1.0, 0.4, 0.0, 1.0];
/// Colour of the next footstep to lift off.
const NEXT_COLOR: [f64; 4] = [1.0, 0.85, 0.0, 1.0];
/// Colour of the later footsteps.
const PLANNED_COLOR: [f64; 4] = [0.3, 0.6, 1.0, 0.7];
/// Colour of the swing path.
const SWING_COLOR: [f64; 4] = [1.0, 0.4, 0.0, 1.0];
/// Colour of the planned DCM path.
const DCM_PATH_COLOR: [f64; 4] = [0.7, 0.2, 0.9, 0.6];
/// Line width of the footsteps and paths [m].
const LINE_WIDTH_M: f64 = 0.003;
/// Points per swing path.
const SWING_POINTS: usize = 25;
/// Time between the points of the DCM path [s].
const DCM_PATH_STEP_S: f64 = 0.02;
/// Height of the drawn points above the ground, so that they are not hidden by it [m].
const ABOVE_GROUND_M: f64 = 0.001;
/// Two walks' steps (or swings) within this of each other in pose [m, rad] and time [s] are
/// the same step.
const SAME_STEP_TOLERANCE: f64 = 1e-9;

/// The point markers: entity id, disc diameter [m], colour.
const POINT_MARKERS: [(&str, f64, [f64; 4]); 4] = [
    ("walking/dcm_planned", 0.03, [0.7, 0.2, 0.9, 1.0]),
    ("walking/dcm_measured", 0.024, [1.0, 0.1, 0.5, 1.0]),
    ("walking/vrp_planned", 0.02, [0.1, 0.7, 0.7, 1.0]),
    ("walking/com_planned", 0.02, [0.1, 0.8, 0.2, 1.0]),
];

/// What the walk's markers show at one sample (module doc).
pub(crate) struct WalkingScene {
    gait: Gait,
    /// `omega` of the plan's pendulum [1/s].
    omega: f64,
    /// The robot's mass [kg].
    mass: f64,
    /// The ground's height [m].
    world_z_ground: f64,
    /// The soles, when known (the footsteps' rectangles).
    foot: Option<FootRectangle>,
    /// The swing path of each step (its sole origin over its swing).
    swing_paths: Vec<SwingPath>,
    /// The footsteps of former walks that had landed when the walk changed and are not in
    /// the current one (drawn after the current walk's, as landed).
    former_landings: Vec<LinePrimitive>,
    /// `walking/dcm_path`, encoded (sent with every sample; made again when the walk changes).
    dcm_path_encoded: Vec<u8>,
    /// The moving entities: footsteps (when the sole is known), swing, the point markers.
    update: SceneUpdate,
    /// The planned events (time [s], name, text) in time order, and how many were emitted.
    planned_events: Vec<PlannedEvent>,
    planned_emitted: usize,
    /// The time of the last sample whose events were given [s] (`-inf` before any).
    events_given_to_s: f64,
    /// Per contact, its points' range in the samples' contact points (unilateral contacts).
    contact_points: Vec<(usize, usize)>,
    /// The contact names (the events' feet).
    contact_names: Vec<String>,
    /// Per contact, whether it carried force at the last sample.
    loaded: Vec<bool>,
}

impl WalkingScene {
    /// The scene of `gait` for a robot of `mass` [kg] whose soles are `foot` (no footstep
    /// rectangles when `None`), with `contact_names` and `counts[c]` contact points on
    /// contact `c` (unilateral contacts; empty: no measured lift-offs).
    pub fn new(
        gait: &Gait,
        mass: f64,
        foot: Option<FootRectangle>,
        (contact_names, counts): (&[String], &[usize]),
    ) -> Self {
        let lip = gait.dcm.lip();
        let world_z_ground = gait.dcm.sample(0.0).world_xi.z - lip.com_height;
        let z = world_z_ground + ABOVE_GROUND_M;
        let swing_paths = swing_paths(gait);
        let mut entities = Vec::new();
        if let Some(foot) = foot {
            entities.push(footsteps_entity(&gait.footsteps.steps, foot, z));
        }
        entities.push(line_entity("walking/swing", Vec::new(), SWING_COLOR));
        entities.extend(POINT_MARKERS.iter().map(|(id, diameter, rgba)| {
            let mut entity = world_entity(id.to_string());
            entity.cylinders.push(CylinderPrimitive {
                pose: Some(identity_pose()),
                size: Some(vector([*diameter, *diameter, 0.002])),
                bottom_scale: 1.0,
                top_scale: 1.0,
                color: Some(color(*rgba)),
            });
            entity
        }));
        let mut start = 0;
        let contact_points = counts
            .iter()
            .map(|&n| {
                start += n;
                (start - n, start)
            })
            .collect();
        Self {
            dcm_path_encoded: encoded_dcm_path(gait, z),
            omega: lip.omega,
            mass,
            world_z_ground,
            foot,
            swing_paths,
            former_landings: Vec::new(),
            update: SceneUpdate {
                deletions: Vec::new(),
                entities,
            },
            planned_events: planned_events(gait),
            planned_emitted: 0,
            events_given_to_s: f64::NEG_INFINITY,
            contact_points,
            contact_names: contact_names.to_vec(),
            loaded: vec![false; counts.len()],
            gait: gait.clone(),
        }
    }

    /// Draws `gait`, the walk as the controller changed it, from the next sample on (module
    /// doc): its footsteps, then the former walks' footsteps landed by the change (the time
    /// `gait`'s DCM plan starts from) that `gait` does not hold; its swing paths, a swing
    /// re-aimed in flight drawn as drawn up to the re-aim; its DCM path. The planned events
    /// not given yet are the former walk's up to the change, then `gait`'s after it.
    pub fn set_gait(&mut self, gait: Gait) {
        let z = self.world_z_ground + ABOVE_GROUND_M;
        let changed_at = gait.dcm.start_time();
        if let Some(foot) = self.foot {
            let left_behind = landed_steps_left_behind(&self.gait, &gait, changed_at);
            let former_lines = footsteps_entity(&left_behind, foot, z).lines;
            self.former_landings
                .extend(former_lines.into_iter().map(|mut line| {
                    line.color = Some(color(LANDED_COLOR));
                    line
                }));
            let mut footsteps = footsteps_entity(&gait.footsteps.steps, foot, z);
            footsteps.lines.extend(self.former_landings.iter().cloned());
            self.update.entities[0] = footsteps;
        }
        self.swing_paths = spliced_swing_paths(&self.swing_paths, &self.gait, &gait);
        self.dcm_path_encoded = encoded_dcm_path(&gait, z);
        let unsent = self.planned_events.split_off(self.planned_emitted);
        self.planned_events = events_after_change(
            unsent,
            planned_events(&gait),
            changed_at,
            self.events_given_to_s,
        );
        self.planned_emitted = 0;
        self.gait = gait;
    }

    /// Sets the markers of `sample` and appends the encoded `walking/*` entities (the DCM
    /// path, then the moving ones) to `buffer`; `false`, appending nothing, when a value is not
    /// finite.
    pub fn encode(&mut self, stamp: Timestamp, sample: &Sample<'_>, buffer: &mut Vec<u8>) -> bool {
        let t = sample.time_s;
        let planned = self.gait.dcm.sample(t);
        let com = Vector3::from(sample.com);
        let com_velocity =
            Vector3::new(sample.momentum[0], sample.momentum[1], sample.momentum[2]) / self.mass;
        let measured_dcm = com + com_velocity / self.omega;
        let positions = [
            planned.world_xi.xy(),
            measured_dcm.xy(),
            planned.world_p_vrp.xy(),
            planned.com.position.xy(),
        ];
        if !positions.iter().all(|p| p.iter().all(|v| v.is_finite())) {
            return false;
        }
        let step = self.step_shown(t);
        let has_footsteps = self.foot.is_some();
        let first_point = usize::from(has_footsteps) + 1;
        let (lines, points) = self.update.entities.split_at_mut(first_point);
        if has_footsteps {
            set_footstep_colors(&mut lines[0], &self.gait, t);
        }
        let swing = &mut lines[first_point - 1];
        swing.lines[0].points.clear();
        if let Some(path) = step.and_then(|k| self.swing_paths.get(k)) {
            swing.lines[0].points.extend_from_slice(&path.points);
        }
        let z = self.world_z_ground + ABOVE_GROUND_M;
        for (entity, p) in points.iter_mut().zip(positions) {
            entity.cylinders[0].pose = Some(pose_at([p.x, p.y, z], [1.0, 0.0, 0.0, 0.0]));
        }
        for entity in &mut self.update.entities {
            entity.timestamp = Some(stamp);
        }
        buffer.extend_from_slice(&self.dcm_path_encoded);
        Encode::encode(&self.update, buffer).is_ok()
    }

    /// The step whose swing is drawn at `t`: the one under way, else the next to lift off.
    fn step_shown(&self, t: f64) -> Option<usize> {
        let phase = self.gait.footsteps.phase_at(t);
        match (phase.support, phase.step) {
            (Support::Single { .. }, Some(step)) => Some(step),
            _ => self
                .gait
                .footsteps
                .steps
                .iter()
                .position(|s| s.lift_off > t),
        }
    }

    /// The `/events` messages due at `sample` (time [ns], encoded `foxglove.Log`): the planned
    /// lift-offs and touchdowns up to its time, and each foot whose points stopped carrying
    /// force since the last sample.
    ///
    /// Errors: [`Error::Log`] when a message does not encode.
    pub fn events(&mut self, sample: &Sample<'_>) -> Result<Vec<(u64, Vec<u8>)>> {
        let mut events = Vec::new();
        self.events_given_to_s = sample.time_s;
        while let Some((time_s, name, text)) = self.planned_events.get(self.planned_emitted) {
            if *time_s > sample.time_s {
                break;
            }
            events.push(crate::mcap_log::log_event(
                *time_s,
                Level::Info,
                text.clone(),
                name,
            )?);
            self.planned_emitted += 1;
        }
        let active = sample.contact_point_active;
        for (c, &(first, end)) in self.contact_points.iter().enumerate() {
            let Some(points) = active.get(first..end) else {
                continue;
            };
            let loaded = points.iter().any(|&a| a);
            if self.loaded[c] && !loaded {
                let name = self.contact_names.get(c).map_or("contact", String::as_str);
                let text = format!(
                    "lift-off of {name} at t = {:.4} s (its points carry no force)",
                    sample.time_s
                );
                events.push(crate::mcap_log::log_event(
                    sample.time_s,
                    Level::Info,
                    text,
                    "sea_sim.lift_off",
                )?);
            }
            self.loaded[c] = loaded;
        }
        Ok(events)
    }
}

/// Each step's planned lift-off and touchdown as (time [s], event name, text), in time order.
fn planned_events(gait: &Gait) -> Vec<PlannedEvent> {
    let mut events = Vec::with_capacity(2 * gait.footsteps.steps.len());
    for (k, step) in gait.footsteps.steps.iter().enumerate() {
        let foot = match step.foot {
            Foot::Left => "left",
            Foot::Right => "right",
        };
        let p = step.pose.world_p_sole;
        events.push((
            step.lift_off,
            "sea_sim.planned_lift_off",
            format!(
                "step {k}: the {foot} foot lifts off at t = {:.4} s (planned)",
                step.lift_off
            ),
        ));
        events.push((
            step.touchdown,
            "sea_sim.planned_touchdown",
            format!(
                "step {k}: the {foot} foot lands at t = {:.4} s on x = {:.4} m, y = {:.4} m, \
                 yaw = {:.4} rad (planned)",
                step.touchdown, p.x, p.y, step.pose.world_yaw_sole
            ),
        ));
    }
    events.sort_by(|a, b| a.0.total_cmp(&b.0));
    events
}

/// A planned event: time [s], event name, text.
type PlannedEvent = (f64, &'static str, String);

/// The planned events still to give after the walk changed at `changed_at` [s], the last
/// sample's events given up to `given_to` [s]: the former walk's `unsent` up to the change
/// (they happened), then the changed walk's `planned` after the change and after
/// `given_to`, in time order.
fn events_after_change(
    unsent: Vec<PlannedEvent>,
    planned: Vec<PlannedEvent>,
    changed_at: f64,
    given_to: f64,
) -> Vec<PlannedEvent> {
    let after = changed_at.max(given_to);
    let mut events: Vec<PlannedEvent> = unsent
        .into_iter()
        .filter(|(time_s, _, _)| *time_s <= changed_at)
        .chain(planned.into_iter().filter(|(time_s, _, _)| *time_s > after))
        .collect();
    events.sort_by(|a, b| a.0.total_cmp(&b.0));
    events
}

/// `walking/footsteps`: one closed line per landing of `steps`, at height `z` (colours set
/// per sample).
fn footsteps_entity(steps: &[Footstep], foot: FootRectangle, z: f64) -> SceneEntity {
    let mut entity = world_entity("walking/footsteps".to_string());
    let corners = [
        [foot.x[0], foot.y[0]],
        [foot.x[1], foot.y[0]],
        [foot.x[1], foot.y[1]],
        [foot.x[0], foot.y[1]],
    ];
    for step in steps {
        let points = corners
            .iter()
            .map(|&[x, y]| {
                let world_p = step.pose.to_world(Vector2::new(x, y));
                point(world_p.x, world_p.y, z)
            })
            .collect();
        entity
            .lines
            .push(line(line_primitive::Type::LineLoop, points, PLANNED_COLOR));
    }
    entity
}

/// The steps of `former` that had landed by `changed_at` [s] and that `current` does not
/// hold (the same foot, landing pose and touchdown within [`SAME_STEP_TOLERANCE`]).
fn landed_steps_left_behind(former: &Gait, current: &Gait, changed_at: f64) -> Vec<Footstep> {
    let same = |a: &Footstep, b: &Footstep| {
        a.foot == b.foot
            && (a.pose.world_p_sole - b.pose.world_p_sole).norm() <= SAME_STEP_TOLERANCE
            && (a.pose.world_yaw_sole - b.pose.world_yaw_sole).abs() <= SAME_STEP_TOLERANCE
            && (a.touchdown - b.touchdown).abs() <= SAME_STEP_TOLERANCE
    };
    let kept = &current.footsteps.steps;
    former
        .footsteps
        .steps
        .iter()
        .enumerate()
        .filter(|(_, step)| step.touchdown <= changed_at)
        .filter(|&(k, step)| find_from(kept, k, |other| same(step, other)).is_none())
        .map(|(_, step)| *step)
        .collect()
}

/// The index of an item of `items` that `matches`: `hint` first (the same step's index in two
/// walks, in the common case), then the others in order; `None` when none matches.
fn find_from<T>(items: &[T], hint: usize, matches: impl Fn(&T) -> bool) -> Option<usize> {
    if items.get(hint).is_some_and(&matches) {
        return Some(hint);
    }
    items.iter().position(matches)
}

/// Colours the footsteps of `entity` by their state at `t` (module doc).
fn set_footstep_colors(entity: &mut SceneEntity, gait: &Gait, t: f64) {
    let steps = &gait.footsteps.steps;
    let next = steps.iter().position(|s| s.lift_off > t);
    for (k, (line, step)) in entity.lines.iter_mut().zip(steps).enumerate() {
        let rgba = if step.touchdown <= t {
            LANDED_COLOR
        } else if step.lift_off <= t {
            CURRENT_COLOR
        } else if Some(k) == next {
            NEXT_COLOR
        } else {
            PLANNED_COLOR
        };
        line.color = Some(color(rgba));
    }
}

/// A drawn swing path: the sole origin's points and their times [s].
#[derive(Clone, Debug, Default, PartialEq)]
struct SwingPath {
    /// The time of each point [s], increasing.
    times: Vec<f64>,
    /// The points, above the ground by [`ABOVE_GROUND_M`].
    points: Vec<Point3>,
}

impl SwingPath {
    /// `swing`'s sole origin at [`SWING_POINTS`] times from `from` [s] to its touchdown,
    /// appended.
    fn extend_from(&mut self, swing: &SwingTrajectory, from: f64) {
        let end = swing.touchdown_time();
        for k in 0..SWING_POINTS {
            let t = from + (end - from) * k as f64 / (SWING_POINTS - 1) as f64;
            let p = swing.sample(t).world_p_sole;
            self.times.push(t);
            self.points.push(point(p.x, p.y, p.z + ABOVE_GROUND_M));
        }
    }
}

/// The swing path of each step of `gait`: its sole origin from its lift-off to its
/// touchdown (a retimed swing's included).
fn swing_paths(gait: &Gait) -> Vec<SwingPath> {
    gait.swings
        .iter()
        .map(|swing| {
            let mut path = SwingPath::default();
            path.extend_from(swing, swing.start);
            path
        })
        .collect()
}

/// The swing paths of `current`, the walk that replaced `former` (drawn as `drawn`): a swing
/// of both walks (the same lift-off time and pose) re-aimed in flight is the drawn path up to
/// the re-aim, then the current swing from it; every other swing is drawn whole.
fn spliced_swing_paths(drawn: &[SwingPath], former: &Gait, current: &Gait) -> Vec<SwingPath> {
    let same_lift_off = |a: &SwingTrajectory, b: &SwingTrajectory| {
        (a.start - b.start).abs() <= SAME_STEP_TOLERANCE
            && (a.lift_off.world_p_sole - b.lift_off.world_p_sole).norm() <= SAME_STEP_TOLERANCE
    };
    current
        .swings
        .iter()
        .enumerate()
        .map(|(k, swing)| {
            let reaimed_at = swing.reaimed.map(|q| q.start).filter(|&t| t > swing.start);
            let before = reaimed_at
                .and_then(|_| find_from(&former.swings, k, |old| same_lift_off(old, swing)))
                .and_then(|j| drawn.get(j));
            match (reaimed_at, before) {
                (Some(t), Some(before)) => {
                    let kept = before.times.partition_point(|&time| time < t);
                    let mut path = SwingPath {
                        times: before.times[..kept].to_vec(),
                        points: before.points[..kept].to_vec(),
                    };
                    path.extend_from(swing, t);
                    path
                }
                _ => {
                    let mut path = SwingPath::default();
                    path.extend_from(swing, swing.start);
                    path
                }
            }
        })
        .collect()
}

/// The encoded update of `walking/dcm_path` at height `z`.
fn encoded_dcm_path(gait: &Gait, z: f64) -> Vec<u8> {
    encode_to_vec(&SceneUpdate {
        deletions: Vec::new(),
        entities: vec![dcm_path_entity(gait, z)],
    })
}

/// `walking/dcm_path`: the planned DCM from the plan's start to the walk's end, at height `z`.
fn dcm_path_entity(gait: &Gait, z: f64) -> SceneEntity {
    let (start, end) = (gait.dcm.start_time(), gait.end_time());
    let count = ((end - start).max(0.0) / DCM_PATH_STEP_S).ceil() as usize + 1;
    let points = (0..count)
        .map(|k| {
            let t = (start + k as f64 * DCM_PATH_STEP_S).min(end);
            let xi = gait.dcm.sample(t).world_xi;
            point(xi.x, xi.y, z)
        })
        .collect();
    line_entity("walking/dcm_path", points, DCM_PATH_COLOR)
}

/// A world entity `id` with one line strip through `points`.
fn line_entity(id: &str, points: Vec<Point3>, rgba: [f64; 4]) -> SceneEntity {
    let mut entity = world_entity(id.to_string());
    entity
        .lines
        .push(line(line_primitive::Type::LineStrip, points, rgba));
    entity
}

/// A line of `kind` through `points` (world axes).
fn line(kind: line_primitive::Type, points: Vec<Point3>, rgba: [f64; 4]) -> LinePrimitive {
    LinePrimitive {
        r#type: kind as i32,
        pose: Some(identity_pose()),
        thickness: LINE_WIDTH_M,
        scale_invariant: false,
        points,
        color: Some(color(rgba)),
        colors: Vec::new(),
        indices: Vec::new(),
    }
}

/// A Foxglove point.
fn point(x: f64, y: f64, z: f64) -> Point3 {
    Point3 { x, y, z }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;
    use sea_ctrl::walking::{ToeOff, WalkingSettings};
    use sea_dyn::spatial::Pose;

    /// Four steps forward at 0.25 m/s from soles 0.14 m apart (the left first), the default
    /// settings otherwise.
    fn gait() -> Gait {
        let mut settings = WalkingSettings::default();
        settings.command.steps = Some(4);
        settings.command.forward_velocity = 0.25;
        let sole = |y: f64| Pose {
            rotation: Matrix3::identity(),
            translation: Vector3::new(0.0, y, 0.0),
        };
        let com = Vector3::new(0.0, 0.0, 0.53);
        Gait::new(
            &settings,
            &[sole(0.07), sole(-0.07)],
            com,
            9.81,
            ToeOff::default(),
        )
        .unwrap()
    }

    /// The iCub's sole rectangle (about).
    const FOOT: FootRectangle = FootRectangle {
        x: [-0.04, 0.1],
        y: [-0.03, 0.03],
    };

    /// A swing re-aimed twice in flight is drawn as followed: the plan from lift-off up to the
    /// first re-aim, the first re-aim's up to the second, then the second's to the landing.
    /// The swing as last changed differs from the first re-aim between the two, so drawing it
    /// whole (the path redrawn from the last walk only) fails this.
    #[test]
    fn a_swing_reaimed_twice_is_drawn_as_followed() {
        let planned = gait();
        let mut scene = WalkingScene::new(&planned, 33.0, Some(FOOT), (&[], &[]));
        let swing = planned.swings[1];
        let at = |u: f64| swing.start + u * swing.duration;
        let landing = planned.footsteps.steps[1].pose.world_p_sole;
        let mut first = planned.clone();
        first.swings[1].reaim(at(0.3), landing + Vector2::new(0.0, -0.04));
        scene.set_gait(first.clone());
        let mut second = first.clone();
        second.swings[1].reaim(at(0.6), landing + Vector2::new(0.03, 0.02));
        scene.set_gait(second.clone());

        let path = &scene.swing_paths[1];
        assert!(path.times.len() >= SWING_POINTS);
        let mut apart_most: f64 = 0.0;
        for (&t, p) in path.times.iter().zip(&path.points) {
            let followed = if t < at(0.3) {
                &planned
            } else if t < at(0.6) {
                let apart = second.swings[1].sample(t).world_p_sole
                    - first.swings[1].sample(t).world_p_sole;
                apart_most = apart_most.max(apart.norm());
                &first
            } else {
                &second
            };
            let expected = followed.swings[1].sample(t).world_p_sole;
            let drawn = Vector3::new(p.x, p.y, p.z - ABOVE_GROUND_M);
            assert!((drawn - expected).norm() < 1e-12, "at {t} s: {drawn:?}");
        }
        assert!(apart_most > 5e-3, "the two walks agree between the re-aims");
        let end = path.points.last().unwrap();
        let aimed = landing + Vector2::new(0.03, 0.02);
        assert!((end.x - aimed.x).abs() < 1e-12 && (end.y - aimed.y).abs() < 1e-12);
        // The other swings are drawn whole, from their lift-off.
        assert_eq!(scene.swing_paths[2], swing_paths(&planned)[2]);
    }

    /// The hint is tried first, then every item in order.
    #[test]
    fn find_from_tries_the_hint_then_the_others() {
        let items = [3, 5, 3];
        assert_eq!(find_from(&items, 2, |&v| v == 3), Some(2));
        assert_eq!(find_from(&items, 1, |&v| v == 3), Some(0));
        assert_eq!(find_from(&items, 9, |&v| v == 5), Some(1));
        assert_eq!(find_from(&items, 0, |&v| v == 4), None);
    }

    /// The footsteps of a former walk that had landed by the change and are not in the new
    /// walk are kept; those the new walk holds, or that had not landed, are not.
    #[test]
    fn the_landed_footsteps_a_new_walk_drops_are_kept() {
        let former = gait();
        let steps = &former.footsteps.steps;
        let after_second = 0.5 * (steps[1].touchdown + steps[2].touchdown);
        let mut other = former.clone();
        for step in &mut other.footsteps.steps {
            step.pose.world_p_sole.y += 0.05;
        }
        let kept = landed_steps_left_behind(&former, &other, after_second);
        assert_eq!(kept, steps[..2].to_vec());
        assert!(landed_steps_left_behind(&former, &former, after_second).is_empty());
        let mut adjusted = former.clone();
        adjusted.footsteps.steps[2].pose.world_p_sole.y += 0.05;
        assert!(landed_steps_left_behind(&former, &adjusted, after_second).is_empty());
        assert!(landed_steps_left_behind(&former, &other, 0.0).is_empty());
    }

    fn event(time_s: f64, text: &str) -> PlannedEvent {
        (time_s, "sea_sim.planned_touchdown", text.to_string())
    }

    /// A recovery walk that replaces the former between two samples: the former's touchdown
    /// that happened before the change is kept, its later events are dropped, and the new
    /// walk's events before the last sample or the change are not given again.
    #[test]
    fn a_change_keeps_the_former_walks_events_up_to_it_and_the_new_ones_after() {
        let unsent = vec![event(1.32, "old touchdown"), event(1.60, "old later")];
        let planned = vec![
            event(1.00, "new, before the last sample"),
            event(1.33, "new, before the change"),
            event(1.50, "new lift-off"),
            event(1.80, "new touchdown"),
        ];
        let events = events_after_change(unsent, planned, 1.34, 1.30);
        let texts: Vec<&str> = events.iter().map(|e| e.2.as_str()).collect();
        assert_eq!(texts, ["old touchdown", "new lift-off", "new touchdown"]);
    }

    /// A change before any sample's events keeps only the new walk's after the change.
    #[test]
    fn a_change_at_the_start_gives_the_new_walk_after_it() {
        let planned = vec![event(0.5, "a"), event(1.0, "b")];
        let events = events_after_change(Vec::new(), planned, 0.6, f64::NEG_INFINITY);
        assert_eq!(events.len(), 1);
        assert_eq!(events[0].2, "b");
    }
}
