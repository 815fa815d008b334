//! Swing soles: endpoints, apex, derivatives.

use super::super::command::footsteps_from_command;
use super::super::footstep::{wrap_angle, SolePose};
use super::super::swing::{SwingTrajectory, ToeOff};
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
        toe_off: ToeOff::default(),
        world_z_ground: 0.3,
        reaimed: None,
        retimed: None,
    }
}

/// The same swing with a 0.2 rad toe-off over its first half, about a toe 0.1 m ahead.
fn swing_with_toe_off() -> SwingTrajectory {
    SwingTrajectory {
        toe_off: ToeOff {
            pitch: 0.2,
            end_phase: 0.5,
            sole_x_toe: 0.1,
        },
        ..swing()
    }
}

/// The world position of the point `sole_p` of the sole at `t`.
fn point_of(swing: &SwingTrajectory, t: f64, sole_p: Vector3<f64>) -> Vector3<f64> {
    let s = swing.sample(t);
    s.world_p_sole + s.world_r_sole() * sole_p
}

/// No jump at a re-aim at `t`: the same position, velocity and acceleration.
#[track_caller]
fn assert_no_jump(original: &SwingTrajectory, reaimed: &SwingTrajectory, t: f64) {
    let (before, after) = (original.sample(t), reaimed.sample(t));
    assert_small(after.world_p_sole - before.world_p_sole, 1e-12, "position");
    assert_small(after.world_v_sole - before.world_v_sole, 1e-9, "velocity");
    assert_small(
        after.world_a_sole - before.world_a_sole,
        1e-7,
        "acceleration",
    );
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
        let swing =
            SwingTrajectory::of_step(&plan, i, (settings.swing_height, ToeOff::default()), 0.0);
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
    assert_no_jump(&original, &reaimed, t);
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

#[test]
fn a_toe_off_pitches_the_sole_about_its_toe_and_is_flat_outside_its_phase() {
    let (flat, toe_off) = (swing(), swing_with_toe_off());
    let toe = Vector3::new(0.1, 0.0, 0.0);
    for k in 0..=40 {
        let t = flat.start + flat.duration * k as f64 / 40.0;
        assert_small(
            point_of(&toe_off, t, toe) - point_of(&flat, t, toe),
            1e-12,
            "the toe follows the flat sole's",
        );
        if k == 0 || k >= 20 {
            assert_eq!(toe_off.sample(t), flat.sample(t), "flat at k = {k}");
        }
    }
    let peak = toe_off.sample(toe_off.start + 0.25 * toe_off.duration);
    assert!((peak.pitch - 0.2).abs() < 1e-12, "{}", peak.pitch);
    let heel = Vector3::new(-0.05, 0.0, 0.0);
    let (t, lifted) = (peak_time(&toe_off), 0.15 * 0.2_f64.sin());
    let heel_rise = point_of(&toe_off, t, heel).z - point_of(&flat, t, heel).z;
    assert!(
        (heel_rise - lifted).abs() < 1e-12,
        "toe down: the heel up {heel_rise}"
    );
}

fn peak_time(swing: &SwingTrajectory) -> f64 {
    swing.start + 0.5 * swing.toe_off.end_phase * swing.duration
}

#[test]
fn a_toe_off_swing_derivatives_are_those_of_its_pose() {
    let swing = swing_with_toe_off();
    let h = 1e-6;
    // Off the toe-off's end, where the jerk jumps (the acceleration is continuous there).
    for k in 0..20 {
        let t = swing.start + swing.duration * (k as f64 + 0.5) / 20.0;
        let (before, now, after) = (swing.sample(t - h), swing.sample(t), swing.sample(t + h));
        let d = |f: fn(&super::super::SwingSample) -> Vector3<f64>| {
            (f(&after) - f(&before)) / (2.0 * h)
        };
        assert_small(d(|s| s.world_p_sole) - now.world_v_sole, 1e-6, "v");
        assert_small(d(|s| s.world_v_sole) - now.world_a_sole, 1e-5, "a");
        assert_small(
            d(|s| s.world_omega_sole) - now.world_omegadot_sole,
            1e-5,
            "omegadot",
        );
        // The turn's skew part, `sin(angle) axis`: exact to the angle's cube.
        let turn = (after.world_r_sole() * before.world_r_sole().inverse()).into_inner();
        let skew = (turn - turn.transpose()) * 0.5;
        let omega = Vector3::new(skew[(2, 1)], skew[(0, 2)], skew[(1, 0)]) / (2.0 * h);
        assert_small(omega - now.world_omega_sole, 1e-6, "omega");
    }
}

#[test]
fn a_swing_reaimed_in_its_toe_off_has_no_jump() {
    let original = swing_with_toe_off();
    let mut reaimed = original;
    let t = original.start + 0.2 * original.duration;
    reaimed.reaim(t, Vector2::new(0.25, 0.02));
    assert_no_jump(&original, &reaimed, t);
    assert_eq!(reaimed.sample(t).pitch, original.sample(t).pitch);
}

#[test]
fn a_swing_retimed_in_flight_is_continuous_and_lands_at_rest_at_the_new_touchdown() {
    for original in [swing(), swing_with_toe_off()] {
        let mut retimed = original;
        let t = original.start + 0.3 * original.duration;
        let touchdown = original.start + 0.6 * original.duration;
        retimed.retime(t, touchdown);
        assert_no_jump(&original, &retimed, t);
        let (before, after) = (original.sample(t), retimed.sample(t));
        assert!((after.world_yaw_sole - before.world_yaw_sole).abs() < 1e-12);
        assert!((after.world_omega_sole - before.world_omega_sole).norm() < 1e-9);
        assert_eq!(retimed.touchdown_time(), touchdown);
        // Lands where it was aimed, flat on the ground, at rest, at the new touchdown.
        let end = retimed.sample(touchdown);
        let landing = original.sample(original.start + original.duration);
        assert_small(end.world_p_sole - landing.world_p_sole, 1e-12, "landing");
        assert_small(end.world_v_sole, 1e-9, "landing velocity");
        assert_small(end.world_a_sole, 1e-7, "landing acceleration");
        assert!((end.world_yaw_sole - (3.0 + wrap_angle(-6.0))).abs() < 1e-12);
        assert!(end.world_omega_sole.norm() < 1e-9 && end.pitch == 0.0);
        // A re-aim after the retiming keeps the new touchdown.
        let mut reaimed = retimed;
        let later = t + 0.05;
        reaimed.reaim(later, Vector2::new(0.25, 0.02));
        assert_no_jump(&retimed, &reaimed, later);
        let end = reaimed.sample(touchdown);
        assert_small(
            end.world_p_sole - Vector3::new(0.25, 0.02, 0.3),
            1e-12,
            "re-aimed",
        );
        // At or after the touchdown, nothing moves.
        let end = original.start + original.duration;
        let mut late = original;
        late.retime(end, end + 0.1);
        assert_eq!(late, original);
        let mut landed = retimed;
        landed.retime(touchdown + 0.01, touchdown + 0.1);
        assert_eq!(landed, retimed);
    }
}
