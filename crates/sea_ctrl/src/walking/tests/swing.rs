//! Swing soles: endpoints, apex, derivatives.

use super::super::command::footsteps_from_command;
use super::super::footstep::SolePose;
use super::super::swing::SwingTrajectory;
use super::{standing, walking};
use nalgebra::{Vector2, Vector3};

/// A swing from (0, 0.07, 3.0 rad) to (0.2, 0.1, -3.0 rad) at 0.3 m ground height.
fn swing() -> SwingTrajectory {
    SwingTrajectory {
        lift_off: SolePose::new(Vector2::new(0.0, 0.07), 3.0),
        touchdown: SolePose::new(Vector2::new(0.2, 0.1), -3.0),
        start: 1.0,
        duration: 0.45,
        height: 0.04,
        world_z_ground: 0.3,
        reaimed: None,
    }
}

#[track_caller]
fn assert_small(v: Vector3<f64>, tol: f64, what: &str) {
    assert!(v.norm() <= tol, "{what}: {v:?}");
}

#[test]
fn the_swing_starts_and_ends_at_rest_on_the_ground_at_its_poses() {
    let swing = swing();
    for (t, pose) in [
        (swing.start, swing.lift_off),
        (swing.start + swing.duration, swing.touchdown),
    ] {
        let s = swing.sample(t);
        let expected = Vector3::new(pose.world_p_sole.x, pose.world_p_sole.y, 0.3);
        assert_small(s.world_p_sole - expected, 1e-12, "position");
        let yaw_error = super::super::footstep::wrap_angle(s.world_yaw_sole - pose.world_yaw_sole);
        assert!(yaw_error.abs() < 1e-12, "yaw {}", s.world_yaw_sole);
        for v in [
            s.world_v_sole,
            s.world_a_sole,
            s.world_omega_sole,
            s.world_omegadot_sole,
        ] {
            assert_small(v, 1e-12, "rest at the ends");
        }
    }
}

#[test]
fn the_swing_reaches_its_apex_at_mid_swing_and_turns_the_short_way() {
    let swing = swing();
    let mid = swing.sample(swing.start + 0.5 * swing.duration);
    assert!(
        (mid.world_p_sole.z - 0.34).abs() < 1e-12,
        "{}",
        mid.world_p_sole.z
    );
    assert!(mid.world_v_sole.z.abs() < 1e-12);
    assert!(mid.world_a_sole.z < 0.0, "a maximum");
    // 3.0 -> -3.0 rad is +0.283 rad the short way: yaw rate positive, yaw past pi.
    assert!(mid.world_omega_sole.z > 0.0);
    assert!((mid.world_yaw_sole - (3.0 + 0.5 * (2.0 * std::f64::consts::PI - 6.0))).abs() < 1e-12);
    for k in 0..=100 {
        let z = swing
            .sample(swing.start + swing.duration * k as f64 / 100.0)
            .world_p_sole
            .z;
        assert!((0.3..=0.34 + 1e-12).contains(&z), "{z}");
    }
}

#[test]
fn the_swing_derivatives_are_those_of_its_pose() {
    let swing = swing();
    let h = 1e-6;
    for k in 1..20 {
        let t = swing.start + swing.duration * k as f64 / 20.0;
        let (before, now, after) = (swing.sample(t - h), swing.sample(t), swing.sample(t + h));
        assert_small(
            (after.world_p_sole - before.world_p_sole) / (2.0 * h) - now.world_v_sole,
            1e-6,
            "v",
        );
        assert_small(
            (after.world_v_sole - before.world_v_sole) / (2.0 * h) - now.world_a_sole,
            1e-5,
            "a",
        );
        let yaw_rate = (after.world_yaw_sole - before.world_yaw_sole) / (2.0 * h);
        assert!((yaw_rate - now.world_omega_sole.z).abs() < 1e-6);
    }
}

#[test]
fn a_planned_swing_goes_from_the_previous_pose_to_the_footstep() {
    let settings = walking(3, 0.2, 0.0, 0.2);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    for i in 0..plan.steps.len() {
        let swing = SwingTrajectory::of_step(&plan, i, settings.swing_height, 0.0);
        let step = plan.steps[i];
        let start = swing.sample(step.lift_off);
        let before = plan.stances[i].get(step.foot);
        assert!((start.world_p_sole.xy() - before.world_p_sole).norm() < 1e-12);
        let end = swing.sample(step.touchdown);
        assert!((end.world_p_sole.xy() - step.pose.world_p_sole).norm() < 1e-12);
        assert!((end.world_yaw_sole - step.pose.world_yaw_sole).abs() < 1e-12);
    }
}

#[test]
fn a_swing_reaimed_in_flight_is_continuous_and_lands_at_rest_at_the_new_target() {
    let original = swing();
    let mut reaimed = original;
    let t = original.start + 0.4 * original.duration;
    let target = Vector2::new(0.25, 0.02);
    reaimed.reaim(t, target);
    // No jump at the re-aim: the same position, velocity and acceleration.
    let (before, after) = (original.sample(t), reaimed.sample(t));
    assert_small(after.world_p_sole - before.world_p_sole, 1e-12, "position");
    assert_small(after.world_v_sole - before.world_v_sole, 1e-9, "velocity");
    assert_small(
        after.world_a_sole - before.world_a_sole,
        1e-7,
        "acceleration",
    );
    // Before the re-aim, the original.
    let earlier = original.start + 0.1;
    assert_eq!(reaimed.sample(earlier), original.sample(earlier));
    // Lands at the new target, on the ground, at rest, at the planned touchdown.
    let end = reaimed.sample(original.start + original.duration);
    let expected = Vector3::new(target.x, target.y, 0.3);
    assert_small(end.world_p_sole - expected, 1e-12, "landing");
    assert_small(end.world_v_sole, 1e-9, "landing velocity");
    assert_small(end.world_a_sole, 1e-7, "landing acceleration");
    // Velocity and acceleration are the position's derivatives (central differences).
    let (tm, h) = (t + 0.1, 1e-5);
    let (a, b, c) = (
        reaimed.sample(tm - h),
        reaimed.sample(tm),
        reaimed.sample(tm + h),
    );
    let velocity = (c.world_p_sole - a.world_p_sole) / (2.0 * h);
    let acceleration = (c.world_v_sole - a.world_v_sole) / (2.0 * h);
    assert_small(velocity - b.world_v_sole, 1e-6, "velocity by differences");
    assert_small(
        acceleration - b.world_a_sole,
        1e-4,
        "acceleration by differences",
    );
}
