//! The figures of docs/findings/walking.md (ignored: they print, and time the planner):
//! `cargo test --release -p sea_ctrl --lib walking::tests::figures -- --ignored --nocapture`.

use super::super::command::footsteps_from_command;
use super::super::dcm::DcmPlan;
use super::super::footstep::FootstepPlan;
use super::super::phase::Support;
use super::super::polygon::SupportPolygon;
use super::{lip, standing, walking};
use nalgebra::Vector2;
use sea_dyn::ContactSurface;
use std::time::Instant;

/// The support polygon at `t`: the stance sole, or both soles' hull.
fn support_at(footsteps: &FootstepPlan, t: f64, surface: &ContactSurface) -> SupportPolygon {
    let phase = footsteps.phase_at(t);
    match (phase.support, phase.step) {
        (Support::Single { stance }, Some(i)) => {
            SupportPolygon::of_sole(footsteps.stances[i].get(stance), surface)
        }
        (_, step) => {
            let feet = step.map_or(footsteps.stances[0], |i| footsteps.stances[i + 1]);
            SupportPolygon::of_stance(&feet, surface)
        }
    }
}

#[test]
#[ignore = "prints figures and timings"]
fn figures() {
    let surface = ContactSurface::default();
    println!("| v [m/s] | transfer [s] | double support [s] | smallest VRP margin [m] | largest CoM speed [m/s] | largest CoM acceleration [m/s^2] | sample [ns] | plan [us] |");
    println!("|---|---|---|---|---|---|---|---|");
    for (v, transfer, ds) in [
        (0.0, 0.6, 0.15),
        (0.3, 0.6, 0.15),
        (0.3, 0.3, 0.15),
        (0.3, 0.6, 0.1),
        (0.4, 0.6, 0.15),
    ] {
        let mut settings = walking(10, v, 0.0, 0.0);
        settings.max_step_length = 0.25;
        settings.transfer_duration = transfer;
        settings.double_support_duration = ds;
        let footsteps = footsteps_from_command(&settings, standing(&settings)).unwrap();
        let plan = DcmPlan::new(&footsteps, lip(&settings), Vector2::zeros(), 0.0);
        let end = plan.end_time();
        let (mut margin, mut speed, mut acceleration) = (f64::INFINITY, 0.0_f64, 0.0_f64);
        for k in 0..=20_000 {
            let t = end * k as f64 / 20_000.0;
            let sample = plan.sample(t);
            let support = support_at(&footsteps, t, &surface);
            margin = margin.min(support.signed_margin(sample.world_p_vrp.xy()));
            speed = speed.max(sample.com.velocity.norm());
            acceleration = acceleration.max(sample.com.acceleration.norm());
        }
        let reps = 1_000_000;
        let start = Instant::now();
        let mut sum = 0.0;
        for k in 0..reps {
            sum += plan.sample(end * k as f64 / reps as f64).com.position.x;
        }
        let sample_ns = start.elapsed().as_nanos() as f64 / reps as f64;
        let start = Instant::now();
        for _ in 0..1000 {
            std::hint::black_box(DcmPlan::new(
                &footsteps,
                lip(&settings),
                Vector2::zeros(),
                0.0,
            ));
        }
        let plan_us = start.elapsed().as_nanos() as f64 / 1e6;
        std::hint::black_box(sum);
        println!("| {v} | {transfer} | {ds} | {margin:.4} | {speed:.3} | {acceleration:.3} | {sample_ns:.0} | {plan_us:.1} |");
    }
}
