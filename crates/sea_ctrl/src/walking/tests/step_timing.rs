//! Step timing adaptation: the landing wished for at each touchdown time, the choice of the
//! remaining swing, and the step adjustment moving a touchdown with every later time.

use super::walking;
use crate::walking::adjust::clip_landing;
use crate::walking::step_timing::{remaining_swing, SwingInFlight};
use crate::walking::{adjust_step, Gait, MeasuredCom, StepTiming, ToeOff, WalkingSettings};
use nalgebra::{Matrix3, Vector2, Vector3};
use sea_dyn::spatial::Pose;
use sea_dyn::ContactSurface;

/// A walk of eight 0.1 m steps from soles 0.14 m apart (left first), step adjustment on.
fn gait(timing: StepTiming) -> (Gait, WalkingSettings) {
    let mut settings = walking(8, 0.25, 0.0, 0.0);
    settings.step_duration = 0.4;
    settings.double_support_duration = 0.1;
    settings.step_adjustment = true;
    settings.step_timing = timing;
    let sole = |y: f64| Pose {
        rotation: Matrix3::identity(),
        translation: Vector3::new(0.0, y, 0.0),
    };
    let com = Vector3::new(0.0, 0.0, 0.53);
    let soles = [sole(0.07), sole(-0.07)];
    (
        Gait::new(&settings, &soles, com, 9.81, ToeOff::default()).unwrap(),
        settings,
    )
}

/// Step `index`'s swing at `fraction` of it, the measured DCM the plan's plus `error`.
fn in_flight(
    gait: &Gait,
    settings: &WalkingSettings,
    index: usize,
    fraction: f64,
    error: Vector2<f64>,
) -> (SwingInFlight, f64) {
    let step = gait.footsteps.steps[index];
    let t = step.lift_off + fraction * (step.touchdown - step.lift_off);
    let plan = [t, step.touchdown].map(|time| gait.dcm.sample(time).world_xi.xy());
    let swing = SwingInFlight {
        remaining: step.touchdown - t,
        earliest: step.lift_off + settings.min_adjusted_swing_duration - t,
        omega: gait.dcm.lip().omega,
        world_xi: plan[0] + error,
        world_xi_plan: plan,
        world_p_landing: step.pose.world_p_sole,
        stance: gait.footsteps.stance_sole(index),
    };
    (swing, t)
}

/// The step limits of `settings` around step `index`'s stance, as the adjustment clips.
fn clip<'a>(
    gait: &Gait,
    settings: &'a WalkingSettings,
    index: usize,
) -> impl Fn(Vector2<f64>) -> Vector2<f64> + 'a {
    let stance = gait.footsteps.stance_sole(index);
    let side = gait.footsteps.steps[index].foot.side();
    move |world_p| clip_landing(settings, stance, side, world_p)
}

#[test]
fn at_the_planned_time_the_wished_landing_is_the_step_adjustments() {
    let (gait, settings) = gait(StepTiming::Sideways);
    let error = Vector2::new(0.012, -0.02);
    let (swing, _) = in_flight(&gait, &settings, 3, 0.3, error);
    let growth = (swing.omega * swing.remaining).exp();
    let expected = swing.world_p_landing + error * growth;
    assert!((swing.wished_landing(swing.remaining) - expected).norm() < 1e-12);
    // Sooner, the error has grown less: the landing moves less.
    let sooner = swing.wished_landing(0.5 * swing.remaining) - swing.world_p_landing;
    assert!(sooner.norm() < (expected - swing.world_p_landing).norm());
}

#[test]
fn a_landing_clipped_sideways_lands_earlier_and_an_unclipped_one_keeps_its_time() {
    let (gait, settings) = gait(StepTiming::Sideways);
    // Step 3 is the right foot's, standing on the left: pushed left, its landing is clipped
    // to the smallest width.
    assert!(gait.footsteps.steps[3].foot.side() < 0.0);
    let clip = clip(&gait, &settings, 3);
    let (left, _) = in_flight(&gait, &settings, 3, 0.2, Vector2::new(0.0, 0.04));
    let (small, _) = in_flight(&gait, &settings, 3, 0.2, Vector2::new(0.0, -0.005));
    let (forward, _) = in_flight(&gait, &settings, 3, 0.2, Vector2::new(0.05, 0.0));
    let clipped = |swing: &SwingInFlight, tau: f64| {
        let wished = swing.wished_landing(tau);
        (clip(wished) - wished).norm()
    };
    assert!(clipped(&left, left.remaining) > 0.01);
    let tau = remaining_swing(&left, StepTiming::Sideways, &clip);
    assert!(
        tau < left.remaining - 0.05 && tau >= left.earliest,
        "{tau} of {}",
        left.remaining
    );
    assert!(clipped(&left, tau) < clipped(&left, left.remaining));
    assert_eq!(
        remaining_swing(&left, StepTiming::Fixed, &clip),
        left.remaining
    );
    // Unclipped: the plan's time.
    assert!(clipped(&small, small.remaining) < 1e-12);
    assert_eq!(
        remaining_swing(&small, StepTiming::Any, &clip),
        small.remaining
    );
    // Clipped by the reach: only `Any` lands earlier.
    assert!(clipped(&forward, forward.remaining) > 0.01);
    assert_eq!(
        remaining_swing(&forward, StepTiming::Sideways, &clip),
        forward.remaining
    );
    assert!(remaining_swing(&forward, StepTiming::Any, &clip) < forward.remaining);
}

#[test]
fn an_earlier_touchdown_moves_every_later_time_with_it_and_the_plan_from_the_measured_dcm() {
    for timing in [StepTiming::Fixed, StepTiming::Sideways] {
        let (mut gait, settings) = gait(timing);
        let before = gait.footsteps.steps.clone();
        let (swing, t) = in_flight(&gait, &settings, 3, 0.2, Vector2::new(0.0, 0.04));
        let lip = gait.dcm.lip();
        let world_v_com = (swing.world_xi - gait.dcm.sample(t).com.position.xy()) * lip.omega;
        let measured = MeasuredCom {
            time: t,
            world_p_com: gait.dcm.sample(t).com.position.xy(),
            world_v_com,
            world_z_com: 0.53,
        };
        let surface = ContactSurface::default();
        let made = adjust_step(&mut gait, &settings, &surface, 3, measured).expect("adjusted");
        let after = &gait.footsteps.steps;
        let shift = made.touchdown - before[3].touchdown;
        match timing {
            StepTiming::Fixed => assert_eq!(shift, 0.0),
            _ => assert!(shift < -0.05, "{made:?}"),
        }
        assert_eq!(after[3].lift_off, before[3].lift_off);
        assert_eq!(after[3].touchdown, made.touchdown);
        assert_eq!(gait.swings[3].touchdown_time(), made.touchdown);
        for (new, old) in after[4..].iter().zip(&before[4..]) {
            assert!((new.lift_off - old.lift_off - shift).abs() < 1e-12);
            assert!((new.touchdown - old.touchdown - shift).abs() < 1e-12);
        }
        // The swing lasts at least the shortest swing.
        let swing_duration = made.touchdown - after[3].lift_off;
        assert!(swing_duration >= settings.min_adjusted_swing_duration - 1e-12);
        // The plan is made again over the new times: from the measured CoM, its DCM
        // continuous through the new touchdown and the next step's lift-off and touchdown.
        let com = gait.dcm.sample(t).com.position.xy();
        assert!((com - measured.world_p_com).norm() < 1e-12);
        for time in [made.touchdown, after[4].lift_off, after[4].touchdown] {
            let [early, late] = [time - 1e-7, time + 1e-7].map(|s| gait.dcm.sample(s).world_xi);
            assert!(
                (late - early).norm() < 1e-6,
                "{time}: {early} against {late}"
            );
        }
    }
}

#[test]
fn late_in_a_swing_the_rest_goes_at_most_the_shortest_swings_pace_faster() {
    let (mut gait, settings) = gait(StepTiming::Sideways);
    let step = gait.footsteps.steps[3];
    let swing_duration = step.touchdown - step.lift_off;
    // At 70 % of the swing, pushed hard to the left: the landing is clipped at any time.
    let (swing, t) = in_flight(&gait, &settings, 3, 0.7, Vector2::new(0.0, 0.08));
    let world_p_com = gait.dcm.sample(t).com.position.xy();
    let omega = gait.dcm.lip().omega;
    let measured = MeasuredCom {
        time: t,
        world_p_com,
        world_v_com: (swing.world_xi - world_p_com) * omega,
        world_z_com: 0.53,
    };
    let surface = ContactSurface::default();
    let made = adjust_step(&mut gait, &settings, &surface, 3, measured).expect("adjusted");
    let pace = settings.min_adjusted_swing_duration / swing_duration;
    let earliest = (step.touchdown - t) * pace;
    assert!(made.touchdown < step.touchdown - 0.01, "{made:?}");
    assert!(
        made.touchdown - t >= earliest - 1e-12,
        "{made:?}: {earliest}"
    );
    // The retimed swing's height asks for no more than the planned swing's peak vertical
    // acceleration, scaled by the square of the pace.
    let planned = |s: f64| gait.swings[4].sample(s);
    let peak = |sample: &dyn Fn(f64) -> f64, from: f64, to: f64| {
        (0..=200)
            .map(|k| sample(from + (to - from) * k as f64 / 200.0).abs())
            .fold(0.0, f64::max)
    };
    let [start, end] = [gait.swings[4].start, gait.swings[4].touchdown_time()];
    let planned_peak = peak(&|s| planned(s).world_a_sole.z, start, end);
    let retimed_peak = peak(
        &|s| gait.swings[3].sample(s).world_a_sole.z,
        t,
        made.touchdown,
    );
    assert!(
        retimed_peak <= planned_peak / (pace * pace),
        "{retimed_peak} against {planned_peak}"
    );
}
