//! The contact schedule and the load share.

use super::super::command::footsteps_from_command;
use super::super::footstep::Foot;
use super::super::phase::Support;
use super::{standing, walking};

#[test]
fn phases_follow_the_footsteps() {
    let settings = walking(2, 0.2, 0.0, 0.0);
    let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
    let first = plan.phase_at(0.1);
    assert_eq!(first.support, Support::Double);
    assert_eq!(
        (first.start, first.end, first.step),
        (0.0, plan.steps[0].lift_off, None)
    );
    assert_eq!(first.next_touchdown, Some(plan.steps[0].touchdown));

    let step = plan.steps[0];
    let swing = plan.phase_at(0.5 * (step.lift_off + step.touchdown));
    assert_eq!(
        swing.support,
        Support::Single {
            stance: Foot::Right
        }
    );
    assert!(!swing.in_contact(Foot::Left) && swing.in_contact(Foot::Right));
    assert!((swing.fraction - 0.5).abs() < 1e-12);
    assert_eq!(
        (swing.step, swing.next_touchdown),
        (Some(0), Some(step.touchdown))
    );

    let landed = plan.phase_at(step.touchdown);
    assert_eq!(landed.support, Support::Double);
    assert_eq!((landed.step, landed.fraction), (Some(0), 0.0));
    assert_eq!(landed.end, plan.steps[1].lift_off);
    assert_eq!(landed.next_touchdown, Some(plan.steps[1].touchdown));

    let second = plan.phase_at(plan.steps[1].lift_off);
    assert_eq!(second.support, Support::Single { stance: Foot::Left });

    let last = plan.steps.last().unwrap();
    let settling = plan.phase_at(last.touchdown + 0.01);
    assert_eq!(
        (settling.support, settling.end, settling.next_touchdown),
        (Support::Double, plan.end_time(), None)
    );
    let standing = plan.phase_at(plan.end_time() + 1.0);
    assert_eq!(
        (standing.support, standing.end),
        (Support::Double, f64::INFINITY)
    );
}

#[test]
fn the_load_share_has_no_jump_and_reaches_the_stance_foot() {
    for first_foot in [Foot::Left, Foot::Right] {
        let mut settings = walking(3, 0.2, 0.0, 0.0);
        settings.command.first_foot = first_foot;
        let plan = footsteps_from_command(&settings, standing(&settings)).unwrap();
        assert_eq!(plan.left_load_share(0.0), 0.5);
        assert_eq!(plan.left_load_share(plan.end_time() + 0.1), 0.5);
        for (i, step) in plan.steps.iter().enumerate() {
            let on_left = if step.foot == Foot::Left { 0.0 } else { 1.0 };
            let mid = 0.5 * (step.lift_off + step.touchdown);
            assert_eq!(plan.left_load_share(mid), on_left, "step {i}");
        }
        let mut switches: Vec<f64> = plan
            .steps
            .iter()
            .flat_map(|s| [s.lift_off, s.touchdown])
            .collect();
        switches.push(plan.end_time());
        for t in switches {
            let (before, after) = (
                plan.left_load_share(t - 1e-9),
                plan.left_load_share(t + 1e-9),
            );
            assert!(
                (before - after).abs() < 1e-6,
                "jump at {t}: {before} -> {after}"
            );
        }
        // The quintic's largest slope is 15/8 per phase: 1 over the double support.
        let dt = (plan.end_time() + 0.5) / 2000.0;
        let largest_step = 1.875 / settings.double_support_duration * dt * 1.001;
        let mut previous = plan.left_load_share(0.0);
        for k in 1..=2000 {
            let share = plan.left_load_share(dt * k as f64);
            assert!((0.0..=1.0).contains(&share));
            assert!(
                (share - previous).abs() <= largest_step,
                "smooth: {previous} -> {share}"
            );
            previous = share;
        }
    }
}
