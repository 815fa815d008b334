//! Push-recovery steps from the capture point.

use super::super::capture::{
    needs_step, recovery_step, stance_margin, swing_foot_for, StepRequest,
};
use super::super::footstep::{Foot, SolePose, Stance};
use super::super::polygon::SupportPolygon;
use super::super::settings::CaptureMargin;
use super::{assert_close, lip, standing, walking};
use nalgebra::Vector2;
use sea_dyn::ContactSurface;
use std::f64::consts::FRAC_PI_2;

/// The DCM after `duration` of the LIP from its DCM `xi0` (CoM at `x0`) with the centre of
/// pressure at `p`, by integrating `xddot = omega^2 (x - p)` (RK4).
fn integrated_dcm(
    omega: f64,
    x0: Vector2<f64>,
    xi0: Vector2<f64>,
    p: Vector2<f64>,
    duration: f64,
) -> Vector2<f64> {
    let (mut x, mut v) = (x0, omega * (xi0 - x0));
    let n = 20_000;
    let h = duration / n as f64;
    let f = |x: Vector2<f64>, v: Vector2<f64>| (v, omega * omega * (x - p));
    for _ in 0..n {
        let (k1x, k1v) = f(x, v);
        let (k2x, k2v) = f(x + k1x * (h / 2.0), v + k1v * (h / 2.0));
        let (k3x, k3v) = f(x + k2x * (h / 2.0), v + k2v * (h / 2.0));
        let (k4x, k4v) = f(x + k3x * h, v + k3v * h);
        x += (k1x + 2.0 * k2x + 2.0 * k3x + k4x) * (h / 6.0);
        v += (k1v + 2.0 * k2v + 2.0 * k3v + k4v) * (h / 6.0);
    }
    x + v / omega
}

/// The request of a step of `swing_foot` from `stance` for the DCM `world_xi`.
fn request(
    world_xi: Vector2<f64>,
    stance: SolePose,
    swing_foot: Foot,
    swing_duration: f64,
) -> StepRequest {
    StepRequest {
        world_xi,
        stance,
        swing_foot,
        swing_duration,
    }
}

#[test]
fn a_dcm_inside_the_support_needs_no_step() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let surface = ContactSurface::default();
    let stance = standing(&settings);
    let two_feet = SupportPolygon::of_stance(&stance, &surface);
    assert!(!needs_step(
        &two_feet,
        Vector2::new(0.02, 0.0),
        settings.capture_margin.forward
    ));
    assert!(
        (two_feet.signed_margin(Vector2::new(0.02, 0.0)) - 0.07).abs() < 1e-12,
        "the back edge 7 cm behind"
    );
    let one_foot = SupportPolygon::of_sole(stance.right, &surface);
    assert!(!needs_step(
        &one_foot,
        Vector2::new(0.02, -0.07),
        settings.capture_margin.forward
    ));
    // Within the margin of the front edge (10 cm ahead of the sole origin).
    assert!(needs_step(
        &one_foot,
        Vector2::new(0.095, -0.07),
        settings.capture_margin.forward
    ));
}

/// `margin` is `expected` [m] to rounding.
fn assert_margin(margin: f64, expected: f64) {
    assert!((margin - expected).abs() < 1e-12, "{margin} vs {expected}");
}

#[test]
fn the_margin_follows_the_dcm_direction_from_the_mid_feet_point() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let surface = ContactSurface::default();
    let stance = standing(&settings);
    let support = SupportPolygon::of_stance(&stance, &surface);
    let margins = CaptureMargin {
        forward: 0.01,
        backward: 0.004,
        sideways: 0.002,
    };
    // The mid-feet point is the world origin (the feet at y = +-0.07, facing x).
    let ahead = Vector2::new(0.095, 0.0);
    let at_the_side = Vector2::new(0.0, 0.07 + 0.025 - 0.005);
    let behind = Vector2::new(-0.05 + 0.003, 0.0);
    assert_margin(stance_margin(&margins, &stance, ahead), 0.01);
    assert_margin(stance_margin(&margins, &stance, at_the_side), 0.002);
    assert_margin(stance_margin(&margins, &stance, behind), 0.004);
    let diagonal = Vector2::new(0.03, 0.03);
    assert_margin(
        stance_margin(&margins, &stance, diagonal),
        0.5 * 0.01 + 0.5 * 0.002,
    );
    assert_eq!(
        stance_margin(&margins, &stance, Vector2::zeros()),
        0.0,
        "no direction"
    );
    // 5 mm inside the front edge: a step; 5 mm inside the outer edge: none; 3 mm inside the
    // back edge: a step.
    for (xi, expected) in [(ahead, true), (at_the_side, false), (behind, true)] {
        let margin = stance_margin(&margins, &stance, xi);
        assert_eq!(needs_step(&support, xi, margin), expected, "{xi:?}");
    }
    // The stance moved and turned a quarter turn: its forward is world +y.
    let width = settings.nominal_width;
    let turned = Stance::side_by_side(Vector2::new(1.0, 2.0), FRAC_PI_2, width);
    let world = |local: Vector2<f64>| Vector2::new(1.0 - local.y, 2.0 + local.x);
    assert_margin(stance_margin(&margins, &turned, world(ahead)), 0.01);
    assert_margin(stance_margin(&margins, &turned, world(at_the_side)), 0.002);
    assert_margin(stance_margin(&margins, &turned, world(behind)), 0.004);
    // Equal margins: the same margin in every direction.
    let uniform = CaptureMargin::uniform(0.007);
    for xi in [ahead, at_the_side, behind, diagonal] {
        assert_margin(stance_margin(&uniform, &stance, xi), 0.007);
    }
}

#[test]
fn a_dcm_ahead_asks_for_the_step_the_dcm_evolution_predicts() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let surface = ContactSurface::default();
    let lip = lip(&settings);
    let stance = standing(&settings);
    let xi0 = Vector2::new(0.11, 0.0);
    let support = SupportPolygon::of_stance(&stance, &surface);
    assert!(needs_step(&support, xi0, settings.capture_margin.forward));
    let foot = swing_foot_for(&stance, xi0);
    assert_eq!(foot, Foot::Left, "on the line: the left foot");
    let step = recovery_step(
        &settings,
        &lip,
        &surface,
        request(xi0, stance.right, foot, 0.3),
    );
    assert_eq!(step.swing_duration, 0.3);
    // The right sole's front-left corner is its closest point to the DCM.
    assert_close(step.stance_cop, Vector2::new(0.10, -0.045), 1e-12, "CoP");
    let simulated = integrated_dcm(lip.omega, Vector2::zeros(), xi0, step.stance_cop, 0.3);
    assert_close(
        step.dcm_at_touchdown,
        simulated,
        1e-9,
        "xi(T) vs the LIP integrated",
    );
    // Within reach (forward 0.136 m, lateral 0.189 m from the right sole): the sole lands
    // under the DCM, which it then holds.
    assert_close(
        step.pose.world_p_sole,
        step.dcm_at_touchdown,
        1e-12,
        "aimed at xi(T)",
    );
    assert!(!step.clipped && step.captures);
    assert!(
        step.pose.world_p_sole.x > 0.1,
        "forward, in the DCM's direction"
    );
}

#[test]
fn a_forward_push_beyond_the_reach_is_clipped_forward() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let surface = ContactSurface::default();
    let lip = lip(&settings);
    let stance = standing(&settings);
    let xi0 = Vector2::new(0.13, 0.0);
    let request = request(xi0, stance.right, Foot::Left, 0.35);
    let step = recovery_step(&settings, &lip, &surface, request);
    assert!(step.dcm_at_touchdown.x > settings.max_step_length);
    let stance_p_step = stance.right.to_sole(step.pose.world_p_sole);
    assert!(
        (stance_p_step.x - settings.max_step_length).abs() < 1e-12,
        "{stance_p_step:?}"
    );
    let lateral = step.dcm_at_touchdown.y - stance.right.world_p_sole.y;
    assert!(
        (stance_p_step.y - lateral).abs() < 1e-12,
        "lateral within limits, kept"
    );
    assert!(step.clipped);
}

#[test]
fn a_large_push_is_clipped_to_the_reach_and_reported_not_captured() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let surface = ContactSurface::default();
    let lip = lip(&settings);
    let stance = standing(&settings);
    let xi0 = Vector2::new(0.25, -0.10);
    let foot = swing_foot_for(&stance, xi0);
    assert_eq!(foot, Foot::Right, "the DCM is on the right");
    let step = recovery_step(
        &settings,
        &lip,
        &surface,
        request(xi0, stance.left, foot, 0.1),
    );
    assert_eq!(
        step.swing_duration, settings.min_swing_duration,
        "raised to the minimum"
    );
    let left_p_step = stance.left.to_sole(step.pose.world_p_sole);
    assert!(
        (left_p_step.x - settings.max_step_length).abs() < 1e-12,
        "{left_p_step:?}"
    );
    let direction = (xi0 - stance.left.world_p_sole).normalize();
    assert!((step.pose.world_p_sole - stance.left.world_p_sole).dot(&direction) > 0.0);
    assert!(step.clipped && !step.captures);
    assert!(left_p_step.y <= -settings.min_step_width);
}

#[test]
fn a_sideways_push_steps_sideways_within_the_width_limit() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let surface = ContactSurface::default();
    let lip = lip(&settings);
    let stance = standing(&settings);
    let xi0 = Vector2::new(0.02, 0.11);
    assert!(needs_step(
        &SupportPolygon::of_stance(&stance, &surface),
        xi0,
        stance_margin(&settings.capture_margin, &stance, xi0)
    ));
    let foot = swing_foot_for(&stance, xi0);
    assert_eq!(foot, Foot::Left);
    let step = recovery_step(
        &settings,
        &lip,
        &surface,
        request(xi0, stance.right, foot, 0.3),
    );
    let right_p_step = stance.right.to_sole(step.pose.world_p_sole);
    assert!(
        right_p_step.y > settings.nominal_width,
        "steps outwards: {right_p_step:?}"
    );
    assert!(right_p_step.y <= settings.max_step_width + 1e-12);
    assert_eq!(
        step.captures,
        !step.clipped || right_p_step.y < settings.max_step_width
    );
}

/// A recovery gait (`walking::recovery`) starts at the measured CoM, CoM velocity and DCM,
/// reaches the predicted DCM at touchdown with the landing sole there, and ends at rest over
/// the new mid-feet point.
#[test]
fn a_recovery_gait_starts_at_the_measured_state_and_ends_at_rest_over_the_new_feet() {
    use super::super::recovery::{recovery_gait, MeasuredCom, RecoveryFrame};
    let settings = walking(1, 0.0, 0.0, 0.0);
    let lip = lip(&settings);
    let surface = ContactSurface::default();
    let stance = standing(&settings);
    let frame = RecoveryFrame {
        stance,
        world_z_ground: 0.0,
        world_z_com: 0.53,
        world_z_com_start: 0.545,
        contact_of: [0, 1],
    };
    // Pushed forward and a little to the right at 1 s: the DCM past the toes.
    let measured = MeasuredCom {
        time: 1.0,
        world_p_com: Vector2::new(0.01, -0.005),
        world_v_com: Vector2::new(0.5, -0.05),
        world_z_com: 0.545,
    };
    let timing = (Foot::Right, 1.0, 1.0 + settings.recovery_transfer_duration);
    let (gait, step) = recovery_gait(&settings, &lip, &surface, &frame, timing, measured);
    let start = gait.dcm.sample(1.0);
    let xi0 = lip.dcm(measured.world_p_com, measured.world_v_com);
    assert_close(start.world_xi.xy(), xi0, 1e-12, "DCM at the start");
    assert_close(
        start.com.position.xy(),
        measured.world_p_com,
        1e-12,
        "CoM at the start",
    );
    assert_close(
        start.com.velocity.xy(),
        measured.world_v_com,
        1e-9,
        "CoM velocity at the start",
    );
    // The CoM reference's height blends from the recovery's start over the transfer.
    let lowered = 1.0 + gait.footsteps.transfer_duration;
    for (t, z) in [(1.0, 0.545), (lowered, 0.53), (lowered + 1.0, 0.53)] {
        let reference = gait.com_reference(t).position.z;
        assert!(
            (reference - z).abs() < 1e-12,
            "CoM height {reference} at {t} s, not {z}"
        );
    }
    let footstep = gait.footsteps.steps[0];
    assert_eq!(footstep.foot, Foot::Right);
    assert!(step.pose.world_p_sole.x > 0.1, "{step:?}");
    let at_touchdown = gait.dcm.sample(footstep.touchdown).world_xi.xy();
    assert_close(
        at_touchdown,
        step.dcm_at_touchdown,
        1e-9,
        "DCM at touchdown",
    );
    let swing_end = gait.swings[0].sample(footstep.touchdown).world_p_sole;
    assert_close(swing_end.xy(), step.pose.world_p_sole, 1e-12, "landing");
    let rest = gait.footsteps.final_stance().mid_frame().world_p_sole;
    let end = gait.dcm.sample(gait.end_time() + 5.0);
    assert_close(end.world_xi.xy(), rest, 1e-9, "DCM at rest");
    assert!(end.com.velocity.norm() < 1e-3);
}
