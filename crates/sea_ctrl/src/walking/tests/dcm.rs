//! The DCM and CoM reference against the closed form and the LIP dynamics.

use super::super::command::footsteps_from_command;
use super::super::dcm::DcmPlan;
use super::super::footstep::FootstepPlan;
use super::{assert_close, lip, standing, walking, Uniform};
use nalgebra::{Vector2, Vector3};

/// The planar part of a vector.
fn xy(v: Vector3<f64>) -> Vector2<f64> {
    v.xy()
}

/// A walk and its DCM plan, starting with the CoM 2 cm off the mid-feet point.
fn planned(
    forward: f64,
    sideways: f64,
    turning: f64,
) -> (FootstepPlan, DcmPlan, super::WalkingSettings) {
    let settings = walking(5, forward, sideways, turning);
    let footsteps = footsteps_from_command(&settings, standing(&settings)).unwrap();
    let plan = DcmPlan::new(&footsteps, lip(&settings), Vector2::new(0.02, -0.01), 0.1);
    (footsteps, plan, settings)
}

const COMMANDS: [(f64, f64, f64); 4] = [
    (0.25, 0.0, 0.0),
    (0.0, 0.05, 0.0),
    (0.0, 0.0, 0.4),
    (0.3, -0.04, 0.2),
];

#[test]
fn single_support_follows_the_closed_form() {
    for (forward, sideways, turning) in COMMANDS {
        let (footsteps, plan, settings) = planned(forward, sideways, turning);
        let lip = lip(&settings);
        for (i, step) in footsteps.steps.iter().enumerate() {
            let p = footsteps.stance_sole(i).world_p_sole;
            let xi0 = xy(plan.sample(step.lift_off).world_xi);
            for k in 0..10 {
                let tau = (step.touchdown - step.lift_off) * k as f64 / 10.0;
                let sample = plan.sample(step.lift_off + tau);
                assert_close(
                    xy(sample.world_xi),
                    lip.dcm_after(p, xi0, tau),
                    1e-12,
                    "xi(t)",
                );
                assert_close(xy(sample.world_p_vrp), p, 1e-12, "VRP at the stance sole");
            }
        }
    }
}

#[test]
fn dcm_com_and_vrp_are_continuous_at_every_switch() {
    for (forward, sideways, turning) in COMMANDS {
        let (_, plan, _) = planned(forward, sideways, turning);
        let durations = plan.segment_durations();
        assert_eq!(
            durations.len(),
            2 * 6 + 2,
            "transfer, 6 x (single, double), rest"
        );
        for (k, duration) in durations.iter().enumerate().take(durations.len() - 1) {
            let end = plan.sample_segment(k, *duration);
            let next = plan.sample_segment(k + 1, 0.0);
            let pairs = [
                (end.world_xi, next.world_xi, "xi"),
                (end.world_p_vrp, next.world_p_vrp, "VRP"),
                (end.com.position, next.com.position, "CoM"),
                (end.com.velocity, next.com.velocity, "CoM velocity"),
                (
                    end.com.acceleration,
                    next.com.acceleration,
                    "CoM acceleration",
                ),
            ];
            for (a, b, what) in pairs {
                assert_close(xy(a), xy(b), 1e-9, &format!("{what} at switch {k}"));
            }
        }
    }
}

#[test]
fn the_walk_starts_at_rest_at_the_com_and_ends_at_rest_over_the_mid_feet_point() {
    for (forward, sideways, turning) in COMMANDS {
        let (footsteps, plan, _) = planned(forward, sideways, turning);
        let start = plan.sample(0.0);
        let com0 = Vector2::new(0.02, -0.01);
        assert_close(xy(start.world_xi), com0, 1e-12, "xi(0)");
        assert_close(xy(start.com.position), com0, 1e-12, "x(0)");
        assert_close(xy(start.com.velocity), Vector2::zeros(), 1e-12, "xdot(0)");
        assert_close(
            xy(start.com.acceleration),
            Vector2::zeros(),
            1e-12,
            "xddot(0)",
        );
        let mid = footsteps.final_stance().mid_frame().world_p_sole;
        assert!((plan.end_time() - footsteps.end_time()).abs() < 1e-12);
        let end = plan.sample(plan.end_time());
        assert_close(xy(end.world_xi), mid, 1e-12, "terminal DCM");
        assert_close(
            xy(end.world_xidot),
            Vector2::zeros(),
            1e-12,
            "terminal DCM velocity",
        );
        let later = plan.sample(plan.end_time() + 10.0);
        assert_close(xy(later.com.position), mid, 1e-9, "CoM at rest");
        assert_close(
            xy(later.com.velocity),
            Vector2::zeros(),
            1e-9,
            "CoM velocity at rest",
        );
        assert!(
            (start.com.position.z - (0.1 + 0.53)).abs() < 1e-12,
            "CoM height"
        );
    }
}

#[test]
fn the_returned_derivatives_satisfy_the_lip() {
    let mut uniform = Uniform(0x5eed_1234);
    for (forward, sideways, turning) in COMMANDS {
        let (_, plan, settings) = planned(forward, sideways, turning);
        let omega = lip(&settings).omega;
        let horizon = plan.end_time() + 1.0;
        for _ in 0..400 {
            let t = horizon * uniform.next();
            let s = plan.sample(t);
            let (x, v, a) = (
                xy(s.com.position),
                xy(s.com.velocity),
                xy(s.com.acceleration),
            );
            let (xi, p) = (xy(s.world_xi), xy(s.world_p_vrp));
            assert_close(a, omega * omega * (x - p), 1e-9, "xddot = omega^2 (x - p)");
            assert_close(v, -omega * (x - xi), 1e-9, "xdot = -omega (x - xi)");
            assert_close(
                xy(s.world_xidot),
                omega * (xi - p),
                1e-9,
                "xidot = omega (xi - p)",
            );
            // The derivatives are those of the position (central differences).
            let h = 1e-5;
            let (before, after) = (plan.sample(t - h), plan.sample(t + h));
            let fd_v = (xy(after.com.position) - xy(before.com.position)) / (2.0 * h);
            let fd_a = (xy(after.com.velocity) - xy(before.com.velocity)) / (2.0 * h);
            let fd_xi = (xy(after.world_xi) - xy(before.world_xi)) / (2.0 * h);
            if t > h {
                assert_close(v, fd_v, 1e-6, "velocity vs finite differences");
                assert_close(a, fd_a, 1e-4, "acceleration vs finite differences");
                assert_close(
                    xy(s.world_xidot),
                    fd_xi,
                    1e-4,
                    "xidot vs finite differences",
                );
            }
        }
    }
}

#[test]
fn the_vrp_stays_between_the_soles_in_double_support() {
    let (footsteps, plan, _) = planned(0.25, 0.0, 0.3);
    for i in 0..footsteps.steps.len() - 1 {
        let (from, to) = (
            footsteps.stance_sole(i).world_p_sole,
            footsteps.stance_sole(i + 1).world_p_sole,
        );
        let (t0, t1) = (
            footsteps.steps[i].touchdown,
            footsteps.steps[i + 1].lift_off,
        );
        for k in 0..=8 {
            let u = k as f64 / 8.0;
            let p = xy(plan.sample(t0 + u * (t1 - t0) - 1e-12 * u).world_p_vrp);
            assert_close(
                p,
                from + (to - from) * u,
                1e-9,
                "VRP on the segment between soles",
            );
        }
    }
}

#[test]
fn without_steps_the_com_moves_to_the_mid_feet_point() {
    let settings = walking(1, 0.0, 0.0, 0.0);
    let mut footsteps = footsteps_from_command(&settings, standing(&settings)).unwrap();
    footsteps.steps.clear();
    footsteps.stances.truncate(1);
    let plan = DcmPlan::new(&footsteps, lip(&settings), Vector2::new(0.03, 0.0), 0.0);
    let end = plan.sample(plan.end_time());
    assert_close(
        xy(end.world_xi),
        Vector2::zeros(),
        1e-12,
        "DCM at the mid-feet point",
    );
    assert_close(
        xy(plan.sample(30.0).com.position),
        Vector2::zeros(),
        1e-9,
        "CoM converged",
    );
}

#[test]
fn the_vrp_stays_in_the_support_polygon_of_every_phase() {
    use super::super::phase::Support;
    use super::super::polygon::SupportPolygon;
    let surface = sea_dyn::ContactSurface::default();
    for (forward, sideways, turning) in COMMANDS {
        let (footsteps, plan, _) = planned(forward, sideways, turning);
        // Starting from the mid-feet point (the planned start above is 2 cm off it).
        let plan_from_mid = DcmPlan::new(&footsteps, plan.lip(), Vector2::zeros(), 0.1);
        let n = 5000;
        for k in 0..=n {
            let t = (plan.end_time() + 0.5) * k as f64 / n as f64;
            let phase = footsteps.phase_at(t);
            let support = match (phase.support, phase.step) {
                (Support::Single { stance }, Some(i)) => {
                    SupportPolygon::of_sole(footsteps.stances[i].get(stance), &surface)
                }
                (_, step) => {
                    let feet = step.map_or(footsteps.stances[0], |i| footsteps.stances[i + 1]);
                    SupportPolygon::of_stance(&feet, &surface)
                }
            };
            let vrp = xy(plan_from_mid.sample(t).world_p_vrp);
            assert!(
                support.signed_margin(vrp) >= -1e-12,
                "VRP {vrp:?} outside at {t}"
            );
        }
    }
}

#[test]
fn random_walks_are_continuous_and_end_at_rest() {
    let mut uniform = Uniform(0xdcdc_0042);
    for _ in 0..200 {
        let mut spread = |scale: f64| scale * (2.0 * uniform.next() - 1.0);
        let mut settings = walking(
            3 + (spread(3.0).abs() as usize),
            spread(0.5),
            spread(0.1),
            spread(0.8),
        );
        settings.double_support_duration = 0.05 + 0.1 * spread(1.0).abs();
        settings.transfer_duration = 0.2 + 0.6 * spread(1.0).abs();
        let com0 = Vector2::new(spread(0.03), spread(0.03));
        let footsteps = footsteps_from_command(&settings, standing(&settings)).unwrap();
        let plan = DcmPlan::new(&footsteps, lip(&settings), com0, 0.0);
        let durations = plan.segment_durations();
        for (k, duration) in durations.iter().enumerate().take(durations.len() - 1) {
            let (end, next) = (
                plan.sample_segment(k, *duration),
                plan.sample_segment(k + 1, 0.0),
            );
            assert_close(xy(end.world_xi), xy(next.world_xi), 1e-9, "xi");
            assert_close(xy(end.com.position), xy(next.com.position), 1e-9, "CoM");
            assert_close(
                xy(end.com.velocity),
                xy(next.com.velocity),
                1e-9,
                "CoM velocity",
            );
        }
        let mid = footsteps.final_stance().mid_frame().world_p_sole;
        assert_close(
            xy(plan.sample(plan.end_time()).world_xi),
            mid,
            1e-12,
            "terminal DCM",
        );
        assert_close(xy(plan.sample(0.0).world_xi), com0, 1e-12, "initial DCM");
    }
}
