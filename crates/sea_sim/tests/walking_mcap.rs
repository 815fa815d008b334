//! `[walking]` in the MCAP log: a short walk of `scenarios/walking/walk_straight.toml` (two
//! steps and the stop, cut at 1.6 s: the first transfer, the first step, the second's swing)
//! draws the planned footsteps (one sole rectangle per step at its landing, the step under
//! way and the next one in their own colours), the swing path, the planned and measured DCM,
//! the planned VRP and CoM in `/scene`, and puts the planned lift-offs and touchdowns and the
//! measured lift-offs on `/events` beside the touchdowns. The plan compared with is the
//! controller's own (`MomentumController::gait`). A walk the controller changes (a step
//! adjusted after a push, a recovery step planned) is drawn as changed from the change on. A
//! run without `[walking]` draws none of it.

use crate::support;

use foxglove::messages::{Log, SceneEntity, SceneUpdate};
use foxglove::Decode;
use sea_sim::closed_loop::RecordSink;
use sea_sim::mcap_log::{McapSink, EVENTS_TOPIC};
use sea_sim::scenario::run::run_setup_with_sinks;
use sea_sim::scenario::{build, Scenario};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use support::{walk_straight, TempFile};

/// Runs `scenario` into an MCAP log at `file`; the setup after the run (its controller's
/// gait readable).
fn run(scenario: &Scenario, file: &Path) -> (sea_sim::closed_loop::Summary, sea_loop::Setup) {
    let mut setup = build(scenario).unwrap();
    let mut log = McapSink::new(file);
    let mut sinks: Vec<&mut dyn RecordSink> = vec![&mut log];
    let cancel = AtomicBool::new(false);
    let summary = run_setup_with_sinks(scenario, &mut setup, &mut sinks, &cancel, |_, _| ());
    (summary.unwrap(), setup)
}

/// The `/scene` messages (log time [s], update) and the `/events` logs of the MCAP at `file`.
fn read(file: &Path) -> (Vec<(f64, SceneUpdate)>, Vec<Log>) {
    let bytes = std::fs::read(file).unwrap();
    let (mut scenes, mut events) = (Vec::new(), Vec::new());
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        match message.channel.topic.as_str() {
            "/scene" => scenes.push((
                message.log_time as f64 * 1e-9,
                SceneUpdate::decode(&message.data[..]).unwrap(),
            )),
            EVENTS_TOPIC => events.push(Log::decode(&message.data[..]).unwrap()),
            _ => {}
        }
    }
    (scenes, events)
}

/// The entity `id` of `update`.
fn entity<'a>(update: &'a SceneUpdate, id: &str) -> &'a SceneEntity {
    let found = update.entities.iter().find(|e| e.id == id);
    found.unwrap_or_else(|| panic!("no {id} in /scene"))
}

/// The `/scene` message nearest to time `t` [s], with its time.
fn scene_at(scenes: &[(f64, SceneUpdate)], t: f64) -> (f64, &SceneUpdate) {
    let nearest = scenes
        .iter()
        .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
        .expect("a /scene message");
    assert!((nearest.0 - t).abs() < 0.02, "no /scene near {t} s");
    (nearest.0, &nearest.1)
}

/// The colour of footstep `k` in `update`, `[r, g, b]`.
fn footstep_color(update: &SceneUpdate, k: usize) -> [f64; 3] {
    let c = entity(update, "walking/footsteps").lines[k].color.unwrap();
    [c.r, c.g, c.b]
}

#[test]
fn a_short_walk_draws_its_plan_and_its_events() {
    let file = TempFile::new("walking_mcap", "walk");
    let walk = walk_straight(&[
        ("walking.command", "{ forward_velocity = 0.1, steps = 2 }"),
        ("simulation.duration_s", "1.6"),
        ("simulation.record_every", "1"),
    ]);
    let (summary, setup) = run(&walk, &file.0);
    assert_eq!(summary.status, "completed", "{summary:?}");
    let gait = setup.controller.gait().expect("walking");
    let steps = &gait.footsteps.steps;
    assert_eq!(steps.len(), 3, "two steps and the stop");
    let (scenes, events) = read(&file.0);
    assert!(!scenes.is_empty());

    // Every /scene message has the footsteps at their landing poses: the rectangle's centre
    // is the sole frame's foot-rectangle centre at the step's pose.
    let foot = walk_foot(&walk);
    for (_, update) in &scenes {
        let footsteps = entity(update, "walking/footsteps");
        assert_eq!(footsteps.lines.len(), steps.len());
        for (line, step) in footsteps.lines.iter().zip(steps) {
            assert_eq!(line.points.len(), 4);
            let centre = line
                .points
                .iter()
                .fold([0.0; 2], |c, p| [c[0] + p.x / 4.0, c[1] + p.y / 4.0]);
            let expected = step.pose.to_world(nalgebra::Vector2::new(
                0.5 * (foot.0[0] + foot.0[1]),
                0.5 * (foot.1[0] + foot.1[1]),
            ));
            assert!((centre[0] - expected.x).abs() < 1e-9 && (centre[1] - expected.y).abs() < 1e-9);
        }
        for id in [
            "walking/swing",
            "walking/dcm_planned",
            "walking/dcm_measured",
            "walking/vrp_planned",
            "walking/com_planned",
            "walking/dcm_path",
        ] {
            entity(update, id);
        }
    }

    // Mid-swing of the first step: it is the current one (orange), the second the next
    // (yellow), the stop planned (blue); the swing path runs from its lift-off sole to its
    // landing and rises; the planned DCM disc is the plan's DCM.
    let first = steps[0];
    let (mid, update) = scene_at(&scenes, 0.5 * (first.lift_off + first.touchdown));
    let colors = [0, 1, 2].map(|k| footstep_color(update, k));
    assert!(
        colors[0] != colors[1] && colors[1] != colors[2] && colors[0] != colors[2],
        "{colors:?}"
    );
    let swing = &entity(update, "walking/swing").lines[0].points;
    assert!(swing.len() > 2);
    let (start, end) = (swing[0], swing[swing.len() - 1]);
    let landing = first.pose.world_p_sole;
    assert!((end.x - landing.x).abs() < 1e-9 && (end.y - landing.y).abs() < 1e-9);
    assert!(swing
        .iter()
        .any(|p| p.z > start.z + 0.5 * gait.swings[0].height));
    let planned = entity(update, "walking/dcm_planned").cylinders[0]
        .pose
        .unwrap();
    let planned = planned.position.unwrap();
    let xi = gait.dcm.sample(mid).world_xi;
    assert!((planned.x - xi.x).abs() < 1e-9 && (planned.y - xi.y).abs() < 1e-9);
    // The measured DCM is near the planned one (the walk tracks it within centimetres).
    let measured = entity(update, "walking/dcm_measured").cylinders[0]
        .pose
        .unwrap();
    let measured = measured.position.unwrap();
    let error = (measured.x - planned.x).hypot(measured.y - planned.y);
    assert!(error < 0.05, "DCM error {error} m");
    // After the first touchdown the first step is landed (grey), the second current.
    let (_, update) = scene_at(&scenes, 1.55);
    assert_ne!(footstep_color(update, 0), colors[0]);
    assert_eq!(footstep_color(update, 1), colors[0]);

    // /events: the planned lift-offs and touchdowns reached, at their times, the measured
    // touchdowns (impacts) and lift-offs of the feet.
    let named = |name: &str| events.iter().filter(|e| e.name == name).collect::<Vec<_>>();
    let time = |log: &Log| {
        let stamp = log.timestamp.unwrap();
        f64::from(stamp.sec()) + 1e-9 * f64::from(stamp.nsec())
    };
    let lift_offs = named("sea_sim.planned_lift_off");
    let touchdowns = named("sea_sim.planned_touchdown");
    assert_eq!(lift_offs.len(), 2, "{events:?}");
    assert_eq!(touchdowns.len(), 1, "{events:?}");
    assert!((time(lift_offs[0]) - first.lift_off).abs() < 1e-9);
    assert!((time(touchdowns[0]) - first.touchdown).abs() < 1e-9);
    assert!(
        touchdowns[0].message.contains("step 0"),
        "{}",
        touchdowns[0].message
    );
    let measured_lift_offs = named("sea_sim.lift_off");
    assert!(!measured_lift_offs.is_empty(), "{events:?}");
    // Each stepping foot's first measured lift-off comes within 0.1 s before its planned one
    // (its load goes to zero through the double support) or at the first sample after it (a
    // grounded foot is settled onto the ground until the swing lifts it; the events are found
    // on the recorded samples, one per whole-body tick of 10 ms).
    for k in [0, 1] {
        let foot = gait_foot_name(&walk, &setup, k);
        let first_lift = measured_lift_offs
            .iter()
            .find(|log| log.message.contains(foot) && time(log) > steps[k].lift_off - 0.1)
            .unwrap_or_else(|| panic!("no lift-off of {foot}: {measured_lift_offs:?}"));
        let t = time(first_lift);
        let latest = steps[k].lift_off + WHOLE_BODY_PERIOD_S + 1e-9;
        assert!(
            t <= latest,
            "{foot} lifts off at {t} s, planned {}",
            steps[k].lift_off
        );
    }
    assert!(!named("sea_sim.touchdown").is_empty(), "{events:?}");
}

/// The whole-body controller's period of `walk_straight` (100 Hz) [s].
const WHOLE_BODY_PERIOD_S: f64 = 0.01;

/// The foot rectangle of the scenario's contacts, `(x, y)` bounds in the sole frame.
fn walk_foot(scenario: &Scenario) -> ([f64; 2], [f64; 2]) {
    let settings = scenario.loop_settings().unwrap();
    settings
        .scene
        .foot
        .expect("the controller's foot rectangle")
}

/// The contact name of the foot that makes step `k`.
fn gait_foot_name<'a>(scenario: &'a Scenario, setup: &sea_loop::Setup, k: usize) -> &'a str {
    let gait = setup.controller.gait().unwrap();
    let foot = gait.footsteps.steps[k].foot;
    let index = match foot {
        sea_ctrl::walking::Foot::Left => gait.contact_of[0],
        sea_ctrl::walking::Foot::Right => gait.contact_of[1],
    };
    &scenario.robot.contacts[index]
}

#[test]
fn a_run_without_walking_draws_no_walk() {
    let file = TempFile::new("walking_mcap", "standing");
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/robot_rate/push_two_feet.toml");
    let overrides = [
        ("plant.contact_model", "\"unilateral\""),
        ("disturbances", "[]"),
        ("simulation.duration_s", "0.05"),
    ];
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let standing = Scenario::from_file(&path, &pairs).unwrap();
    run(&standing, &file.0);
    let (scenes, events) = read(&file.0);
    assert!(!scenes.is_empty());
    for (_, update) in &scenes {
        assert!(update
            .entities
            .iter()
            .all(|e| !e.id.starts_with("walking/")));
    }
    assert!(events.iter().all(|e| !e.name.contains("lift_off")));
}

/// The centre of each footstep rectangle of `update`, `[x, y]`.
fn footstep_centres(update: &SceneUpdate) -> Vec<[f64; 2]> {
    let footsteps = entity(update, "walking/footsteps");
    let centre = |points: &[foxglove::messages::Point3]| {
        let n = points.len() as f64;
        points
            .iter()
            .fold([0.0; 2], |c, p| [c[0] + p.x / n, c[1] + p.y / n])
    };
    footsteps.lines.iter().map(|l| centre(&l.points)).collect()
}

/// The centre of the foot rectangle at each footstep of `gait`, `[x, y]`.
fn landing_centres(gait: &sea_ctrl::walking::Gait, foot: ([f64; 2], [f64; 2])) -> Vec<[f64; 2]> {
    let middle =
        nalgebra::Vector2::new(0.5 * (foot.0[0] + foot.0[1]), 0.5 * (foot.1[0] + foot.1[1]));
    gait.footsteps
        .steps
        .iter()
        .map(|step| {
            let p = step.pose.to_world(middle);
            [p.x, p.y]
        })
        .collect()
}

/// Whether the footsteps `a` and `b` are the same within 1e-9 m.
fn same_landings(a: &[[f64; 2]], b: &[[f64; 2]]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9)
}

/// A sideways push in a swing with the step adjustment on: the log draws the walk as planned
/// until the controller first moves a landing, and from the sample after each change the
/// walk as changed (the landings, the swing path to the moved landing, the DCM path from the
/// re-plan on); the planned touchdown of the adjusted step names its moved landing.
#[test]
fn an_adjusted_walk_is_drawn_as_the_controller_changed_it() {
    let overrides = [
        ("walking.command", "{ forward_velocity = 0.1, steps = 3 }"),
        ("walking.step_adjustment", "true"),
        ("simulation.duration_s", "3.0"),
        ("simulation.record_every", "1"),
    ];
    let planned = build(&walk_straight(&overrides)).unwrap();
    let planned = planned.controller.gait().unwrap().clone();
    let step = planned.footsteps.steps[1];
    let start_s = step.lift_off + 0.3 * (step.touchdown - step.lift_off);
    let push = format!(
        "[{{link = \"root_link\", force = [0.0, 30.0, 0.0], start_s = {start_s}, duration_s = 0.1}}]"
    );
    let mut pushed = overrides.to_vec();
    pushed.push(("disturbances", &push));
    let walk = walk_straight(&pushed);
    let file = TempFile::new("walking_mcap", "adjusted");
    let (summary, setup) = run(&walk, &file.0);
    assert_eq!(summary.status, "completed", "{summary:?}");
    let adjustments = setup.controller.step_adjustments();
    let first_change = adjustments.first().expect("an adjustment").time;
    let gait = setup.controller.gait().unwrap();
    let foot = walk_foot(&walk);
    let (before, after) = (landing_centres(&planned, foot), landing_centres(gait, foot));
    assert!(!same_landings(&before, &after), "the push moved no landing");

    let (scenes, events) = read(&file.0);
    let (t0, first) = scene_at(&scenes, 0.0);
    assert!(
        same_landings(&footstep_centres(first), &before),
        "at {t0} s"
    );
    for (t, update) in scenes.iter().filter(|(t, _)| *t < first_change - 1e-9) {
        assert!(
            same_landings(&footstep_centres(update), &before),
            "at {t} s"
        );
    }
    let (t_end, last) = scenes.last().unwrap();
    assert!(
        same_landings(&footstep_centres(last), &after),
        "at {t_end} s"
    );
    // The swing path shown in the adjusted step's swing ends on its moved landing.
    let adjusted = adjustments.last().unwrap().step;
    let landing = gait.footsteps.steps[adjusted].pose.world_p_sole;
    let late = gait.footsteps.steps[adjusted].touchdown - 0.02;
    let (_, update) = scene_at(&scenes, late);
    let swing = &entity(update, "walking/swing").lines[0].points;
    let end = swing.last().expect("a swing path");
    assert!((end.x - landing.x).abs() < 1e-9 && (end.y - landing.y).abs() < 1e-9);
    // The DCM path starts where the last re-plan's DCM plan starts.
    let path = &entity(last, "walking/dcm_path").lines[0].points;
    let xi = gait.dcm.sample(gait.dcm.start_time()).world_xi;
    assert!((path[0].x - xi.x).abs() < 1e-9 && (path[0].y - xi.y).abs() < 1e-9);
    assert!(gait.dcm.start_time() > 0.0);
    // One planned touchdown per step, the adjusted one's at its moved landing.
    let touchdowns: Vec<&Log> = events
        .iter()
        .filter(|e| e.name == "sea_sim.planned_touchdown")
        .collect();
    assert_eq!(
        touchdowns.len(),
        gait.footsteps.steps.len(),
        "{touchdowns:?}"
    );
    let text = &touchdowns[adjusted].message;
    assert!(text.contains(&format!("step {adjusted}:")), "{text}");
    assert!(
        text.contains(&format!("x = {:.4} m, y = {:.4} m", landing.x, landing.y)),
        "{text}"
    );
}

/// The pushed walk of [`an_adjusted_walk_is_drawn_as_the_controller_changed_it`] recorded
/// every whole-body tick and every tenth: at each sample of the second, the swing path and the
/// footsteps drawn are those of the first. The pushed swing is re-aimed at several ticks
/// between two samples; each re-aim reaches the drawing, whatever the recording's resolution.
#[test]
fn the_walk_drawn_does_not_depend_on_the_recording_resolution() {
    let base = [
        ("walking.command", "{ forward_velocity = 0.1, steps = 3 }"),
        ("walking.step_adjustment", "true"),
        ("simulation.duration_s", "3.0"),
    ];
    let planned = build(&walk_straight(&base)).unwrap();
    let step = planned.controller.gait().unwrap().footsteps.steps[1];
    let start_s = step.lift_off + 0.3 * (step.touchdown - step.lift_off);
    let push = format!(
        "[{{link = \"root_link\", force = [0.0, 30.0, 0.0], start_s = {start_s}, duration_s = 0.1}}]"
    );
    let drawn = |every: &str| {
        let mut overrides = base.to_vec();
        overrides.push(("disturbances", &push));
        overrides.push(("simulation.record_every", every));
        let file = TempFile::new("walking_mcap", &format!("every_{every}"));
        let (summary, setup) = run(&walk_straight(&overrides), &file.0);
        assert_eq!(summary.status, "completed", "{summary:?}");
        (read(&file.0).0, setup.controller.step_adjustments().len())
    };
    let ((fine, adjustments), (coarse, _)) = (drawn("1"), drawn("10"));
    assert!(adjustments >= 2, "{adjustments} adjustments");
    let mut compared = 0;
    for (t, update) in &coarse {
        let (t_fine, same_time) = scene_at(&fine, *t);
        assert!(
            (t_fine - t).abs() < 1e-9,
            "no sample at {t} s in the fine log"
        );
        let swing = |u: &SceneUpdate| entity(u, "walking/swing").lines[0].points.clone();
        assert_eq!(swing(update), swing(same_time), "the swing at {t} s");
        assert_eq!(
            footstep_centres(update),
            footstep_centres(same_time),
            "at {t} s"
        );
        compared += usize::from(!swing(update).is_empty());
    }
    assert!(compared > 10, "{compared} samples with a swing drawn");
}

/// The centre of the foot rectangle `foot` at each recovery step of `recovery`, `[x, y]`.
fn recovery_centres(
    recovery: &[(f64, sea_ctrl::walking::RecoveryStep)],
    foot: ([f64; 2], [f64; 2]),
) -> Vec<[f64; 2]> {
    let middle =
        nalgebra::Vector2::new(0.5 * (foot.0[0] + foot.0[1]), 0.5 * (foot.1[0] + foot.1[1]));
    recovery
        .iter()
        .map(|(_, step)| {
            let p = step.pose.to_world(middle);
            [p.x, p.y]
        })
        .collect()
}

/// Standing, a push beyond what one step recovers (17.5 N s forward on
/// push_recovery_step.toml; the robot takes a second step and falls): each recovery walk
/// holds its own step only, and the log still draws the first step's landing beside the
/// second's once the second is planned.
#[test]
fn a_second_recovery_step_keeps_the_first_drawn() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/walking/push_recovery_step.toml");
    let push =
        "[{link = \"root_link\", force = [175.0, 0.0, 0.0], start_s = 1.0, duration_s = 0.1}]";
    let pairs = [("simulation.record_every", "10"), ("disturbances", push)]
        .map(|(k, v)| (k.to_string(), v.to_string()));
    let scenario = Scenario::from_file(&path, &pairs).unwrap();
    let file = TempFile::new("walking_mcap", "two_recovery_steps");
    let (_, setup) = run(&scenario, &file.0);
    let recovery = setup.controller.recovery_steps();
    assert!(recovery.len() >= 2, "one recovery step: {recovery:?}");
    let gait = setup.controller.gait().unwrap();
    let foot = walk_foot(&scenario);
    let own = landing_centres(gait, foot);
    let all = recovery_centres(recovery, foot);
    assert!(
        own.len() == 1 && same_landings(&own, &all[all.len() - 1..]),
        "the last recovery walk holds {own:?}, the steps are {all:?}"
    );
    let (scenes, _) = read(&file.0);
    let (t_end, last) = scenes.last().unwrap();
    let mut drawn = footstep_centres(last);
    // The current walk's footstep first, then the landed ones of the former walks.
    drawn.rotate_left(1);
    assert!(
        same_landings(&drawn, &all),
        "at {t_end} s: {drawn:?} against {all:?}"
    );
}

/// Standing, a push past the stepping threshold (push_recovery_step.toml's 12 N s forward,
/// recorded every 10 whole-body ticks):
/// the log draws no footsteps before the push and, once the controller plans its recovery,
/// the recovery's footsteps as the controller ends with them.
#[test]
fn a_recovery_step_is_drawn_once_planned() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/walking/push_recovery_step.toml");
    let pairs = [("simulation.record_every", "10")].map(|(k, v)| (k.to_string(), v.to_string()));
    let scenario = Scenario::from_file(&path, &pairs).unwrap();
    let file = TempFile::new("walking_mcap", "recovery");
    let (summary, setup) = run(&scenario, &file.0);
    assert_eq!(summary.status, "completed", "{summary:?}");
    assert!(
        !setup.controller.recovery_steps().is_empty(),
        "no recovery step"
    );
    let gait = setup.controller.gait().unwrap();
    let foot = walk_foot(&scenario);
    let (scenes, events) = read(&file.0);
    let before = scenes.iter().filter(|(t, _)| *t < 1.0);
    for (t, update) in before {
        assert!(footstep_centres(update).is_empty(), "footsteps at {t} s");
    }
    let (t_end, last) = scenes.last().unwrap();
    let after = landing_centres(gait, foot);
    assert!(!after.is_empty());
    assert!(
        same_landings(&footstep_centres(last), &after),
        "at {t_end} s"
    );
    // One planned touchdown per recovery step, each at its landing, though the step is
    // planned again at every tick before its lift-off and the samples are 10 ticks apart.
    let recovery = setup.controller.recovery_steps();
    let touchdowns: Vec<&Log> = events
        .iter()
        .filter(|e| e.name == "sea_sim.planned_touchdown")
        .collect();
    assert_eq!(touchdowns.len(), recovery.len(), "{touchdowns:?}");
    for (log, (_, step)) in touchdowns.iter().zip(recovery) {
        let p = step.pose.world_p_sole;
        let at = format!("x = {:.4} m, y = {:.4} m", p.x, p.y);
        assert!(log.message.contains(&at), "{} against {at}", log.message);
    }
}
