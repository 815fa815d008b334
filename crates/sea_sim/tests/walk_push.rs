//! Pushes while walking (issue 32): `sea-sim push --phase` resolves the push's start inside
//! the chosen swing of `scenarios/walking/walk_push.toml` (0.25 m/s) from the walking plan;
//! step adjustment (`walking.step_adjustment`) recovers a push at mid-swing that the walk as
//! planned does not (docs/findings/stepping.md, "Pushes while walking").

use sea_ctrl::walking::Support;
use sea_dyn::spatial::{heading, rotation_from_quaternion};
use sea_sim::analysis::push::{swing_push_start, SwingPhase};
use sea_sim::closed_loop::RunRecord;
use sea_sim::scenario::run::run_keeping_setup;
use sea_sim::scenario::{build, Scenario};
use std::path::{Path, PathBuf};

fn walk_push() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/walking/walk_push.toml")
}

/// The override of one 0.1 s push on the pelvis at `start_s` of `impulse` [N s] along world
/// (`x`, `y`).
fn push(x: f64, y: f64, impulse: f64, start_s: f64) -> (String, String) {
    let force = [x * impulse / 0.1, y * impulse / 0.1];
    (
        "disturbances".to_string(),
        format!(
            "[{{link = \"root_link\", force = [{:e}, {:e}, 0.0], start_s = {start_s:e}, \
             duration_s = 0.1}}]",
            force[0], force[1]
        ),
    )
}

/// A run of walk_push.toml with `overrides`: record, summary and the setup after it.
fn run(
    overrides: &[(String, String)],
) -> (
    RunRecord,
    sea_sim::closed_loop::Summary,
    sea_sim::closed_loop::Setup,
) {
    let scenario = Scenario::from_file(&walk_push(), overrides).unwrap();
    run_keeping_setup(&scenario).unwrap()
}

#[test]
fn the_phase_resolves_the_push_start_inside_the_chosen_swing() {
    let scenario = Scenario::from_file(&walk_push(), &[]).unwrap();
    let setup = build(&scenario).unwrap();
    let plan = &setup.controller.gait().unwrap().footsteps;
    for (step, phase) in [(3, 0.2), (3, 0.5), (3, 0.8), (5, 0.5)] {
        let at = SwingPhase {
            step: Some(step),
            phase,
        };
        let (start_s, [lift_off, touchdown]) = swing_push_start(&walk_push(), &[], at).unwrap();
        assert_eq!(
            [lift_off, touchdown],
            [plan.steps[step].lift_off, plan.steps[step].touchdown]
        );
        // A whole number of plant steps (0.25 ms), within half a step of the fraction.
        let wished = lift_off + phase * (touchdown - lift_off);
        assert!(
            (start_s - wished).abs() <= 0.5 * 0.00025 + 1e-12,
            "{start_s} vs {wished}"
        );
        let ticks = start_s / 0.00025;
        assert!((ticks - ticks.round()).abs() < 1e-6, "{start_s}");
        // The plan has step `step` swinging then, that far into its single support.
        let gait_phase = plan.phase_at(start_s);
        assert!(
            matches!(gait_phase.support, Support::Single { .. }),
            "{gait_phase:?}"
        );
        assert_eq!(gait_phase.step, Some(step));
        assert!((gait_phase.fraction - phase).abs() < 1e-3, "{gait_phase:?}");
    }
    // The plan's steps are the command's ten and the stop.
    assert_eq!(plan.steps.len(), 11);
    let beyond = SwingPhase {
        step: Some(11),
        phase: 0.5,
    };
    let message = swing_push_start(&walk_push(), &[], beyond)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("--step") && message.contains("0 to 10"),
        "{message}"
    );
    // By default the fourth step, or the last of a shorter plan (three steps in place).
    let default = SwingPhase {
        step: None,
        phase: 0.0,
    };
    let (_, [lift_off, _]) = swing_push_start(&walk_push(), &[], default).unwrap();
    assert_eq!(lift_off, plan.steps[3].lift_off);
    let in_place =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/walking/steps_in_place.toml");
    let last = SwingPhase {
        step: Some(2),
        ..default
    };
    assert_eq!(
        swing_push_start(&in_place, &[], default).unwrap(),
        swing_push_start(&in_place, &[], last).unwrap()
    );
    let outside = SwingPhase {
        step: Some(3),
        phase: 1.5,
    };
    let message = swing_push_start(&walk_push(), &[], outside)
        .unwrap_err()
        .to_string();
    assert!(message.contains("--phase"), "{message}");
    let standing =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/robot_rate/push_two_feet.toml");
    let at = SwingPhase {
        step: Some(0),
        phase: 0.5,
    };
    let message = swing_push_start(&standing, &[], at)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("--phase") && message.contains("walk"),
        "{message}"
    );
}

/// The gait's bound on a sideways push reads walk_push.toml's plan: at step 3 (the right foot
/// swings, the left stands) the feet 0.14 m apart (`walking.nominal_width`), 0.3 s swings, 0.1 s double supports, the
/// pendulum of `walking.com_height`, the QP's sole, and the plan's DCM at the lift-off near
/// the periodic walk's; a left push is towards the stance foot, forward has no bound; the
/// swing foot's side mirrors the axis at step 4 (the left swings).
#[test]
fn the_gait_bound_reads_the_walks_plan_and_maps_the_directions() {
    use sea_sim::analysis::gait_bound::{
        gait_bounds, lateral_gait_of_walk, GaitBounds, Landings, LateralSide,
    };
    use sea_sim::analysis::push::PushDirection;
    let walk = lateral_gait_of_walk(&walk_push(), &[], Some(3), 0.1).unwrap();
    let (gait, world_axis) = (walk.gait, walk.world_axis);
    assert_eq!(walk.landings, Landings::Planned);
    let close = |a: f64, b: f64, tolerance: f64| (a - b).abs() <= tolerance;
    assert!(close(gait.swing_s, 0.3, 1e-12) && close(gait.double_support_s, 0.1, 1e-12));
    assert!(close(gait.width_m, 0.14, 1e-9), "{gait:?}");
    assert!(
        close(gait.omega, (9.81_f64 / 0.51).sqrt(), 1e-3),
        "{gait:?}"
    );
    assert!(close(gait.half_width_m, 0.025 * 0.7, 1e-12), "{gait:?}");
    assert!(close(gait.mass_kg, 33.0, 0.5), "{gait:?}");
    assert_eq!([gait.min_width_m, gait.max_width_m], [0.09, 0.25]);
    let periodic = gait.periodic_dcm_at_lift_off();
    assert!(
        close(gait.dcm_at_lift_off_m, periodic, 0.005),
        "{gait:?}: {periodic}"
    );
    assert!(world_axis.y > 0.99, "{world_axis}");
    let at = SwingPhase {
        step: Some(3),
        phase: 0.5,
    };
    let directions = [
        PushDirection::Forward,
        PushDirection::Left,
        PushDirection::Right,
    ];
    let bounds = gait_bounds(&walk_push(), &[], at, 0.1, &directions).unwrap();
    assert_eq!(bounds[0], None);
    let both = |side| GaitBounds {
        within_limits: gait.bound(side, 0.5, Landings::WithinLimits),
        adjusted: gait.bound(side, 0.5, Landings::Planned),
    };
    assert_eq!(bounds[1], Some(both(LateralSide::TowardStance)));
    assert_eq!(bounds[2], Some(both(LateralSide::TowardSwing)));
    // With the step adjustment on, its end phase is the scenario's.
    let adjusting = [
        ("walking.step_adjustment".to_string(), "true".to_string()),
        (
            "walking.step_adjustment_end_phase".to_string(),
            "0.6".to_string(),
        ),
    ];
    let walk = lateral_gait_of_walk(&walk_push(), &adjusting, Some(3), 0.1).unwrap();
    assert_eq!(walk.landings, Landings::Adjusted { end_phase: 0.6 });
    let left_swing = lateral_gait_of_walk(&walk_push(), &[], Some(4), 0.1).unwrap();
    let (left_swing, axis) = (left_swing.gait, left_swing.world_axis);
    assert!(axis.y < -0.99, "{axis}");
    assert!(
        close(left_swing.width_m, gait.width_m, 1e-3),
        "{left_swing:?}"
    );
    let message = lateral_gait_of_walk(&walk_push(), &[], Some(11), 0.1)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("--step") && message.contains("0 to 10"),
        "{message}"
    );
}

/// Prints what a push while walking does (`WALK_PUSH="x y impulse start_s"`,
/// `WALK_SET="key=value,..."`): the outcome, the adjustments, the CoM and reference every
/// 50 ms around the push.
#[test]
#[ignore]
fn print_a_push_while_walking() {
    let spec = std::env::var("WALK_PUSH").unwrap_or("0 1 5 1.95".into());
    let v: Vec<f64> = spec
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    let mut overrides = vec![push(v[0], v[1], v[2], v[3])];
    if let Ok(extra) = std::env::var("WALK_SET") {
        for pair in extra.split(',') {
            let (k, val) = pair.split_once('=').unwrap();
            overrides.push((k.into(), val.into()));
        }
    }
    let (record, summary, setup) = run(&overrides);
    println!(
        "{} {} at {:.3} s, steps {:?}",
        summary.status, summary.reason, summary.duration_s, summary.steps_taken
    );
    for made in setup.controller.step_adjustments() {
        println!(
            "t {:.2} step {} error ({:.3} {:.3}) shift ({:.3} {:.3}) clipped {}",
            made.time,
            made.step,
            made.world_dcm_error.x,
            made.world_dcm_error.y,
            made.world_shift.x,
            made.world_shift.y,
            made.clipped
        );
    }
    let steps = &setup.controller.gait().unwrap().footsteps.steps;
    for (i, step) in steps.iter().enumerate() {
        println!(
            "step {i} {:?} lands ({:.3} {:.3}) at {:.2}",
            step.foot, step.pose.world_p_sole.x, step.pose.world_p_sole.y, step.touchdown
        );
    }
    if std::env::var("WALK_SOLES").is_ok() {
        print_the_landed_soles(&record, steps);
    }
    if std::env::var("WALK_FEET").is_ok() {
        let from = std::env::var("WALK_FEET_FROM").map_or(v[3], |t| t.parse().unwrap());
        print_the_feet(&record, from);
        return;
    }
    for (row, t) in record.time.iter().enumerate().step_by(5) {
        if *t < v[3] - 0.1 {
            continue;
        }
        let com = &record.com[3 * row..3 * row + 3];
        let reference = &record.com_reference[3 * row..3 * row + 3];
        let [base, left, right] = yaws(&record, row);
        println!(
            "t {t:.2} com ({:.3} {:.3}) ref ({:.3} {:.3}) yaw base {base:+.3} soles {left:+.3} {right:+.3}",
            com[0], com[1], reference[0], reference[1]
        );
    }
}

/// The yaws [rad] of the base and of the left and right soles (from their back-right to
/// their front-right corners) at the recorded `row`.
fn yaws(record: &RunRecord, row: usize) -> [f64; 3] {
    let nx = record.state.len() / record.time.len();
    let x = &record.state[nx * row..];
    let base = heading(&rotation_from_quaternion(x[3], x[4], x[5], x[6]));
    let points = record.contact_point_active.len() / record.time.len();
    let corner = |k: usize| &record.contact_point_positions[3 * (row * points + k)..][..2];
    let sole = |first: usize| {
        let (back, front) = (corner(first), corner(first + 2));
        (front[1] - back[1]).atan2(front[0] - back[0])
    };
    [base, sole(0), sole(4)]
}

/// The angles [rad] at the recorded `row` of the joints `WALK_JOINTS` names (comma separated;
/// a name not in the model panics, naming it), or with `WALK_JOINTS=1` the hip pitch, knee and
/// ankle pitch of the right then the left leg (the knee's stop is at +0.07 rad, straight).
fn printed_joints(record: &RunRecord, row: usize) -> String {
    let nx = record.state.len() / record.time.len();
    let q = &record.state[nx * row + 7..];
    let asked = std::env::var("WALK_JOINTS").unwrap_or_default();
    let names: Vec<&str> = match asked.as_str() {
        "" | "1" => vec![
            "r_hip_pitch",
            "r_knee",
            "r_ankle_pitch",
            "l_hip_pitch",
            "l_knee",
            "l_ankle_pitch",
        ],
        _ => asked.split(',').collect(),
    };
    let angles: Vec<String> = names
        .iter()
        .map(|name| {
            let j = record
                .joint_names
                .iter()
                .position(|m| m == name)
                .unwrap_or_else(|| panic!("WALK_JOINTS: no joint '{name}' in the model"));
            format!("{:+.3}", q[j])
        })
        .collect();
    angles.join(" ")
}

/// `print_a_push_while_walking` with `WALK_FEET` set (and `WALK_SET` with
/// `simulation.record_every=1`; `WALK_FEET_FROM=t` starts at `t` [s] instead of the push's
/// start): from 0.05 s before `start` [s] for 0.7 s, each recorded sample's CoM and
/// reference (lateral), each sole corner's height [mm] and normal force [N] (left sole's four
/// corners, then the right's), the yaws of the base and the soles [rad] and the centroidal
/// angular momentum [N m s]; with `WALK_JOINTS` set, the joints of [`printed_joints`] before
/// each line.
fn print_the_feet(record: &RunRecord, start: f64) {
    let points = record.contact_point_active.len() / record.time.len();
    for (row, t) in record.time.iter().enumerate() {
        if *t < start - 0.05 || *t > start + 0.7 {
            continue;
        }
        let heights: Vec<String> = (0..points)
            .map(|k| {
                format!(
                    "{:5.1}",
                    1e3 * record.contact_point_positions[3 * (row * points + k) + 2]
                )
            })
            .collect();
        let forces: Vec<String> = (0..points)
            .map(|k| {
                format!(
                    "{:4.0}",
                    record.contact_point_forces[3 * (row * points + k) + 2]
                )
            })
            .collect();
        let [base, left, right] = yaws(record, row);
        if std::env::var("WALK_JOINTS").is_ok() {
            println!("{t:.4} joints {}", printed_joints(record, row));
        }
        let l_com = &record.momentum[6 * row + 3..6 * row + 6];
        println!(
            "{t:.4} comy {:+.3} refy {:+.3} z {} N {} yaw {base:+.3} {left:+.3} {right:+.3} L ({:+.3} {:+.3} {:+.3})",
            record.com[3 * row + 1],
            record.com_reference[3 * row + 1],
            heights.join(" "),
            forces.join(" "),
            l_com[0],
            l_com[1],
            l_com[2]
        );
    }
}

/// Forward pushes of 7-10 N s at 20 % of the fourth step's swing and backward pushes of
/// 8-12 N s at mid-swing (around and above the goal's 8.3 N s, 0.25 m/s times the iCub's
/// 33 kg): the walk as planned recovers at most 2 of the 9, with step adjustment it walks on
/// after at least 8 (measured: 1 and 9; the outcomes have islands, a push recovered above
/// one that fell, so the test counts over a range; docs/findings/stepping.md). The pushed
/// step of the 9 N s forward push lands moved along it, every landing within the step limits.
#[test]
fn step_adjustment_recovers_pushes_the_planned_walk_does_not() {
    let plan_start = |phase: f64| {
        swing_push_start(
            &walk_push(),
            &[],
            SwingPhase {
                step: Some(3),
                phase,
            },
        )
        .unwrap()
        .0
    };
    let on = ("walking.step_adjustment".to_string(), "true".to_string());
    let pushes: Vec<(f64, f64, f64)> = [7.0, 8.0, 9.0, 10.0]
        .map(|impulse| (1.0, impulse, 0.2))
        .into_iter()
        .chain([8.0, 9.0, 10.0, 11.0, 12.0].map(|impulse| (-1.0, impulse, 0.5)))
        .collect();
    let recovered = |adjusting: bool| {
        pushes
            .iter()
            .filter(|&&(direction, impulse, phase)| {
                let mut overrides = vec![push(direction, 0.0, impulse, plan_start(phase))];
                overrides.extend(adjusting.then(|| on.clone()));
                let (_, summary, _) = run(&overrides);
                summary.status == "completed"
            })
            .count()
    };
    let (without, with) = (recovered(false), recovered(true));
    assert!(without <= 2, "{without} of 9 recovered without adjustment");
    assert!(with >= 8, "{with} of 9 recovered with adjustment");
    let (_, summary, setup) = run(&[push(1.0, 0.0, 9.0, plan_start(0.2)), on]);
    assert_eq!(summary.status, "completed", "{}", summary.reason);
    assert_eq!(summary.steps_taken, Some(11));
    let made = setup.controller.step_adjustments();
    let pushed_step: Vec<_> = made.iter().filter(|m| m.step == 3).collect();
    assert!(!pushed_step.is_empty(), "{made:?}");
    let shift_x: f64 = pushed_step.iter().map(|m| m.world_shift.x).sum();
    assert!(shift_x > 0.02, "{made:?}");
    let plan = &setup.controller.gait().unwrap().footsteps;
    let settings = &Scenario::from_file(&walk_push(), &[])
        .unwrap()
        .walking
        .unwrap();
    for (i, step) in plan.steps.iter().enumerate() {
        sea_ctrl::walking::check_step(settings, plan.stance_sole(i), step.foot, step.pose)
            .unwrap_or_else(|rule| panic!("step {i}: {rule:?}"));
    }
}

/// Unpushed, the walk's DCM errors stay within 0.7 cm before the end phase: at the default
/// threshold (`walking.step_adjustment_threshold` 0.005 m) its landings move by at most
/// 2.5 cm each and it completes its 11 steps; at 0.03 m nothing is adjusted and the walk is
/// the one without step adjustment, bitwise.
#[test]
fn an_unpushed_walk_is_adjusted_by_little_and_not_at_all_above_its_errors() {
    let on = ("walking.step_adjustment".to_string(), "true".to_string());
    let (_, with, setup) = run(std::slice::from_ref(&on));
    assert_eq!(with.status, "completed", "{}", with.reason);
    assert_eq!(with.steps_taken, Some(11));
    for made in setup.controller.step_adjustments() {
        assert!(made.world_shift.norm() < 0.025, "{made:?}");
    }
    let above = (
        "walking.step_adjustment_threshold".to_string(),
        "0.03".to_string(),
    );
    let (above_record, _, setup) = run(&[on, above]);
    assert!(setup.controller.step_adjustments().is_empty());
    let (without_record, _, _) = run(&[]);
    assert_eq!(above_record.com, without_record.com);
}

/// `print_a_push_while_walking` with `WALK_SOLES` set: for each step, 0.05 s after its
/// planned touchdown, where the landed sole is (the mean of its four corners less the sole
/// frame's 0.025 m to their middle along its yaw, the iCub's `foot_x` [-0.05, 0.10]) and its
/// yaw, against the plan's landing.
fn print_the_landed_soles(record: &RunRecord, steps: &[sea_ctrl::walking::Footstep]) {
    let points = record.contact_point_active.len() / record.time.len();
    for (i, step) in steps.iter().enumerate() {
        let at = step.touchdown + 0.05;
        let Some(row) = record.time.iter().position(|t| *t >= at) else {
            continue;
        };
        let first = match step.foot {
            sea_ctrl::walking::Foot::Left => 0,
            sea_ctrl::walking::Foot::Right => points / 2,
        };
        let corner =
            |k: usize| &record.contact_point_positions[3 * (row * points + first + k)..][..2];
        let mean = (0..4).fold([0.0, 0.0], |m, k| {
            [m[0] + corner(k)[0] / 4.0, m[1] + corner(k)[1] / 4.0]
        });
        let yaw = yaws(record, row)[if first == 0 { 1 } else { 2 }];
        let origin = [mean[0] - 0.025 * yaw.cos(), mean[1] - 0.025 * yaw.sin()];
        let plan = step.pose.world_p_sole;
        println!(
            "sole {i} {:?} at {at:.2}: ({:.3} {:.3}) yaw {yaw:+.3}, planned ({:.3} {:.3}) yaw {:+.3}, off ({:+.3} {:+.3})",
            step.foot, origin[0], origin[1], plan.x, plan.y, step.pose.world_yaw_sole,
            origin[0] - plan.x, origin[1] - plan.y
        );
    }
}
