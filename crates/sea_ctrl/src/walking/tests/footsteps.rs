//! Footsteps from a command (straight, sideways, turning in place, stop) and from a list.

use super::super::command::{
    command_clips, footsteps_from_command, footsteps_from_list, stop_after,
};
use super::super::footstep::{check_step, wrap_angle, Foot, FootstepPlan, SolePose};
use super::{assert_close, standing, walking};
use nalgebra::Vector2;
use std::f64::consts::FRAC_PI_2;

/// Every step obeys the step rule against the sole it stands on, and the feet end side by
/// side, the nominal width apart, with the same yaw.
fn assert_valid_and_stopped(plan: &FootstepPlan, settings: &super::WalkingSettings) {
    for (i, step) in plan.steps.iter().enumerate() {
        check_step(settings, plan.stance_sole(i), step.foot, step.pose)
            .unwrap_or_else(|rule| panic!("step {i}: {rule:?}"));
    }
    let last = plan.final_stance();
    assert!((last.left.world_yaw_sole - last.right.world_yaw_sole).abs() < 1e-12);
    let right_p_left = last.right.to_sole(last.left.world_p_sole);
    assert_close(
        right_p_left,
        Vector2::new(0.0, settings.nominal_width),
        1e-12,
        "feet side by side",
    );
}

#[test]
fn straight_walk_advances_by_the_command_and_stops() {
    let settings = walking(6, 0.25, 0.0, 0.0);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    assert_eq!(plan.steps.len(), 7, "six steps and the stop");
    let dx = 0.25 * settings.step_duration;
    for (i, step) in plan.steps.iter().enumerate() {
        let expected_foot = if i % 2 == 0 { Foot::Left } else { Foot::Right };
        assert_eq!(step.foot, expected_foot, "alternating from the left");
        let x = dx * (i.min(5) + 1) as f64;
        let y = 0.5 * settings.nominal_width * step.foot.side();
        assert_close(step.pose.world_p_sole, Vector2::new(x, y), 1e-12, "landing");
        assert_eq!(step.pose.world_yaw_sole, 0.0);
        let lift_off = settings.transfer_duration + i as f64 * settings.step_duration;
        assert!((step.lift_off - lift_off).abs() < 1e-12);
        assert!((step.touchdown - lift_off - settings.single_support_duration()).abs() < 1e-12);
    }
    assert_valid_and_stopped(&plan, &settings);
}

#[test]
fn forward_steps_are_clipped_to_the_reach() {
    let settings = walking(3, 2.0, 0.0, 0.0);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    let x = plan.final_stance().left.world_p_sole.x;
    assert!((x - 3.0 * settings.max_step_length).abs() < 1e-12, "{x}");
    assert_valid_and_stopped(&plan, &settings);
}

#[test]
fn a_command_within_the_limits_is_not_clipped() {
    let settings = walking(3, 0.25, 0.05, 0.3);
    assert!(command_clips(&settings).is_empty());
}

#[test]
fn clipped_axes_name_their_key_the_limit_and_the_speed_walked() {
    // Forward 2 m/s: the reach clips it; sideways 1 m/s: the room to max_step_width;
    // turning -5 rad/s: max_step_turn.
    let settings = walking(3, 2.0, 1.0, -5.0);
    let clips = command_clips(&settings);
    let keys: Vec<_> = clips.iter().map(|c| c.key).collect();
    assert_eq!(
        keys,
        [
            "walking.command.forward_velocity",
            "walking.command.sideways_velocity",
            "walking.command.turning_velocity"
        ]
    );
    let period = settings.step_duration;
    let forward = clips[0];
    assert_eq!(forward.limit_rule, "walking.max_step_length");
    assert!((forward.allowed - settings.max_step_length).abs() < 1e-12);
    let room = (settings.max_step_width - settings.nominal_width)
        .min(settings.nominal_width - settings.min_step_width);
    assert!((clips[1].allowed - room).abs() < 1e-12);
    assert!((clips[2].allowed + settings.max_step_turn).abs() < 1e-12);
    let message = forward.to_string();
    let speed = format!("{:.3} m/s", settings.max_step_length / period);
    assert!(
        message.starts_with("walking.command.forward_velocity = 2 m/s"),
        "{message}"
    );
    assert!(
        message.contains("walking.max_step_length allows"),
        "{message}"
    );
    assert!(message.ends_with(&speed), "{message}");
    // The plan walks what the clip says: three steps of the allowed length.
    let plan = footsteps_from_command(&walking(3, 2.0, 0.0, 0.0), standing(&settings)).unwrap();
    let x = plan.final_stance().left.world_p_sole.x;
    assert!((x - 3.0 * forward.allowed).abs() < 1e-12, "{x}");
}

#[test]
fn a_list_of_footsteps_or_stepping_walks_no_command() {
    let mut settings = walking(3, 2.0, 0.0, 0.0);
    settings.stepping = true;
    settings.command.steps = None;
    assert!(command_clips(&settings).is_empty());
}

#[test]
fn sideways_walk_keeps_the_feet_apart_within_limits() {
    let mut settings = walking(4, 0.0, 0.05, 0.0);
    settings.command.first_foot = Foot::Right;
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    assert_eq!(plan.steps[0].foot, Foot::Right);
    let dy = 0.05 * settings.step_duration;
    let mid = plan.final_stance().mid_frame();
    assert_close(
        mid.world_p_sole,
        Vector2::new(0.0, 4.0 * dy),
        1e-12,
        "moved left",
    );
    // The right foot steps first, towards the left foot: the width shrinks, then grows.
    let width =
        |i: usize| (plan.steps[i].pose.world_p_sole - plan.stance_sole(i).world_p_sole).norm();
    assert!((width(0) - (settings.nominal_width - dy)).abs() < 1e-12);
    assert!((width(1) - (settings.nominal_width + dy)).abs() < 1e-12);
    assert_valid_and_stopped(&plan, &settings);
}

#[test]
fn turning_in_place_ninety_degrees() {
    let steps = 6;
    let settings = walking(steps, 0.0, 0.0, FRAC_PI_2 / (steps as f64 * 0.6));
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    let turns: f64 = (0..plan.steps.len())
        .map(|i| wrap_angle(plan.steps[i].pose.world_yaw_sole - plan.stance_sole(i).world_yaw_sole))
        .sum::<f64>();
    let last = plan.final_stance();
    assert!((last.left.world_yaw_sole - FRAC_PI_2).abs() < 1e-12);
    assert!((last.right.world_yaw_sole - FRAC_PI_2).abs() < 1e-12);
    // The yaw gained step after step (each new sole's over the sole it stood on) sums to 90.
    assert!((turns - FRAC_PI_2).abs() < 1e-12, "{turns}");
    assert_close(
        last.mid_frame().world_p_sole,
        Vector2::zeros(),
        1e-12,
        "in place",
    );
    // The width in the turned frame: the left sole at +y of the turned frame is at -x.
    let left_minus_right = last.left.world_p_sole - last.right.world_p_sole;
    assert_close(
        left_minus_right,
        Vector2::new(-settings.nominal_width, 0.0),
        1e-12,
        "width",
    );
    assert_valid_and_stopped(&plan, &settings);
}

/// A clockwise turn stepping with the right foot first is the mirror image (y and yaw
/// negated, the feet swapped) of the counter-clockwise turn with the left foot first, and the
/// clockwise turn with the left foot first (its first step turns the left foot inwards) is
/// valid and turns as far.
#[test]
fn clockwise_turns_mirror_counter_clockwise_ones() {
    let steps = 6;
    let rate = FRAC_PI_2 / (steps as f64 * 0.6);
    let ccw = walking(steps, 0.0, 0.0, rate);
    let mut cw = walking(steps, 0.0, 0.0, -rate);
    cw.command.first_foot = Foot::Right;
    let ccw_plan = footsteps_from_command(&ccw, standing(&ccw)).unwrap();
    let cw_plan = footsteps_from_command(&cw, standing(&cw)).unwrap();
    for (a, b) in ccw_plan.steps.iter().zip(&cw_plan.steps) {
        assert_eq!(a.foot.other(), b.foot);
        let mirrored = Vector2::new(a.pose.world_p_sole.x, -a.pose.world_p_sole.y);
        assert_close(b.pose.world_p_sole, mirrored, 1e-12, "mirrored landing");
        assert!((b.pose.world_yaw_sole + a.pose.world_yaw_sole).abs() < 1e-12);
    }
    cw.command.first_foot = Foot::Left;
    let inwards = footsteps_from_command(&cw, standing(&cw)).unwrap();
    assert_valid_and_stopped(&inwards, &cw);
    let yaw = inwards.final_stance().mid_frame().world_yaw_sole;
    assert!((yaw + FRAC_PI_2).abs() < 1e-12, "{yaw}");
}

#[test]
fn turns_are_clipped_per_step() {
    let settings = walking(2, 0.0, 0.0, 10.0);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    let yaw = plan.final_stance().left.world_yaw_sole;
    assert!((yaw - 2.0 * settings.max_step_turn).abs() < 1e-12, "{yaw}");
}

#[test]
fn stop_from_one_step() {
    let settings = walking(1, 0.1, 0.0, 0.0);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    assert_eq!(plan.steps.len(), 2);
    assert_eq!(plan.steps[1].foot, Foot::Right);
    assert_valid_and_stopped(&plan, &settings);
    let end = plan.steps[1].touchdown + settings.transfer_duration;
    assert!((plan.end_time() - end).abs() < 1e-12);
}

#[test]
fn an_explicit_list_is_timed_and_checked() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let pose = |x: f64, y: f64| SolePose::new(Vector2::new(x, y), 0.0);
    let list = [
        (Foot::Left, pose(0.1, 0.07)),
        (Foot::Right, pose(0.2, -0.07)),
    ];
    let plan = footsteps_from_list(&settings, standing(&settings), &list).unwrap();
    assert_eq!(plan.steps.len(), 2);
    assert!(
        (plan.steps[1].lift_off - settings.transfer_duration - settings.step_duration).abs()
            < 1e-12
    );

    let too_long = [
        (Foot::Left, pose(0.1, 0.07)),
        (Foot::Right, pose(0.45, -0.07)),
    ];
    let message = footsteps_from_list(&settings, standing(&settings), &too_long)
        .unwrap_err()
        .to_string();
    assert!(message.contains("walking.footsteps[1]"), "{message}");
    assert!(
        message.contains("walking.max_step_length = 0.17 m"),
        "{message}"
    );
    assert!(message.contains("got 0.35"), "{message}");

    let crossing = [(Foot::Left, pose(0.1, -0.12))];
    let message = footsteps_from_list(&settings, standing(&settings), &crossing)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("walking.footsteps[0]") && message.contains("min_step_width"),
        "{message}"
    );

    let twisted = [(Foot::Left, SolePose::new(Vector2::new(0.0, 0.07), 1.0))];
    let message = footsteps_from_list(&settings, standing(&settings), &twisted)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("walking.footsteps[0]") && message.contains("max_step_turn"),
        "{message}"
    );

    for bad in [
        SolePose::new(Vector2::new(f64::NAN, 0.07), 0.0),
        SolePose::new(Vector2::new(0.1, f64::NAN), 0.0),
        SolePose::new(Vector2::new(0.1, 0.07), f64::NAN),
    ] {
        let message = footsteps_from_list(&settings, standing(&settings), &[(Foot::Left, bad)])
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("walking.footsteps[0]") && message.contains("must be finite"),
            "{message}"
        );
    }
}

#[test]
fn random_commands_give_valid_steps_that_end_side_by_side() {
    let mut uniform = super::Uniform(0xfeed_beef);
    let mut spread = |scale: f64| scale * (2.0 * uniform.next() - 1.0);
    for _ in 0..500 {
        let mut settings = walking(7, spread(0.6), spread(0.15), spread(1.0));
        settings.command.first_foot = if spread(1.0) > 0.0 {
            Foot::Left
        } else {
            Foot::Right
        };
        let plan = footsteps_from_command(&settings, standing(&settings))
            .unwrap_or_else(|e| panic!("{:?}: {e}", settings.command));
        assert_valid_and_stopped(&plan, &settings);
    }
}

#[test]
fn stopping_on_command_keeps_the_steps_taken_and_closes_the_feet() {
    let settings = walking(10, 0.25, 0.0, 0.3);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    let stopped = stop_after(&settings, &plan, 3).unwrap();
    assert_eq!(stopped.steps.len(), 5, "steps 0..=3 and the stop");
    assert_eq!(
        &stopped.steps[..4],
        &plan.steps[..4],
        "the steps taken, same timing"
    );
    assert_eq!(stopped.steps[4].foot, plan.steps[3].foot.other());
    assert_valid_and_stopped(&stopped, &settings);
    assert!(stopped.end_time() < plan.end_time());
    // Stopping at or after the plan's own stop step changes nothing.
    assert_eq!(
        stop_after(&settings, &plan, plan.steps.len() - 1).unwrap(),
        plan
    );
    assert_eq!(stop_after(&settings, &plan, 99).unwrap(), plan);
}
