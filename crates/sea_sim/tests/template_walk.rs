//! The walk's planner and momentum law on the linear inverted pendulum
//! (`sea_sim::analysis::template_walk`): the unpushed walk of walk_push.toml completes on its
//! template, a push is recovered up to a size and lost beyond, and no push beyond the
//! pendulum's own bound of the gait (`gait_bound`) is recovered.

use sea_sim::analysis::gait_bound::gait_bounds;
use sea_sim::analysis::push::Stance;
use sea_sim::analysis::push::{swing_push_start, PushDirection, SwingPhase};
use sea_sim::analysis::template_walk::{push_force, TemplatePush};
use sea_sim::analysis::template_walk::{template_bisection, template_pushes, TemplateWalk};
use sea_sim::scenario::Scenario;
use std::path::{Path, PathBuf};

fn walk_push() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/walking/walk_push.toml")
}

/// Step adjustment on (the walking-push grid's setting), with `TEMPLATE_SET`'s
/// `key=value;;key=value` in the printing tests.
fn adjusted(with_env: bool) -> Vec<(String, String)> {
    let mut overrides = vec![("walking.step_adjustment".into(), "true".into())];
    let extra = with_env
        .then(|| std::env::var("TEMPLATE_SET").ok())
        .flatten();
    for pair in extra
        .iter()
        .flat_map(|s| s.split(";;"))
        .filter(|s| !s.is_empty())
    {
        let (key, value) = pair.split_once('=').expect("TEMPLATE_SET: key=value;;...");
        overrides.push((key.to_string(), value.to_string()));
    }
    overrides
}

/// The push's start and length at `phase` of the fourth swing (0.1 s pushes).
fn window(overrides: &[(String, String)], phase: f64) -> (f64, f64) {
    let at = SwingPhase {
        step: Some(3),
        phase,
    };
    (
        swing_push_start(&walk_push(), overrides, at).unwrap().0,
        0.1,
    )
}

#[test]
fn the_unpushed_walk_completes_on_its_template_close_to_its_reference() {
    let walk = TemplateWalk::of_scenario(&walk_push(), &adjusted(false)).unwrap();
    let outcome = walk.run(None);
    assert!(outcome.recovered, "{outcome:?}");
    assert!(outcome.max_com_error_m < 2e-3, "{outcome:?}");
    assert_eq!(outcome.saturated_ticks, 0, "{outcome:?}");
    assert_eq!(outcome.world_p_landings.len(), 11);
}

#[test]
fn a_sideways_push_is_recovered_up_to_a_size_never_beyond_the_gaits_bound() {
    let overrides = adjusted(false);
    let directions = [PushDirection::Left, PushDirection::Right];
    for phase in [0.2, 0.5, 0.8] {
        let at = SwingPhase {
            step: Some(3),
            phase,
        };
        let bounds = gait_bounds(&walk_push(), &overrides, at, 0.1, &directions).unwrap();
        let span = window(&overrides, phase);
        let found = template_bisection(&walk_push(), &overrides, span, &directions, 0.01).unwrap();
        for ((direction, bound), template) in directions.iter().zip(bounds).zip(found) {
            let bound = bound.unwrap().adjusted;
            // A push of 1 N s is recovered; nothing the pendulum's bound cannot capture is.
            assert!(template >= 1.0, "{direction:?} at {phase}: {template}");
            assert!(
                template <= bound,
                "{direction:?} at {phase}: {template} > {bound}"
            );
            let beyond = template_pushes(
                &walk_push(),
                &overrides,
                span,
                &[*direction],
                &[bound + 0.25],
            );
            assert_eq!(
                beyond.unwrap(),
                vec![vec![false]],
                "{direction:?} at {phase}"
            );
        }
    }
}

#[test]
fn the_template_is_deterministic_and_a_zero_push_is_the_unpushed_walk() {
    let overrides = adjusted(false);
    let walk = TemplateWalk::of_scenario(&walk_push(), &overrides).unwrap();
    let stance = Stance::of(&Scenario::from_file(&walk_push(), &overrides).unwrap()).unwrap();
    let (start_s, duration_s) = window(&overrides, 0.5);
    let push = |impulse| TemplatePush {
        world_force: push_force(impulse, duration_s, stance.direction(PushDirection::Left)),
        start_s,
        duration_s,
    };
    let (zero, none) = (walk.run(Some(push(0.0))), walk.run(None));
    assert!(zero.recovered && none.recovered, "{zero:?}");
    assert!(
        (zero.max_com_error_m - none.max_com_error_m).abs() < 1e-12,
        "{zero:?}"
    );
    let landings = zero.world_p_landings.iter().zip(&none.world_p_landings);
    assert!(
        landings.into_iter().all(|(a, b)| (a - b).norm() < 1e-12),
        "{zero:?}"
    );
    assert_eq!(walk.run(Some(push(6.0))), walk.run(Some(push(6.0))));
    assert_ne!(walk.run(Some(push(6.0))), walk.run(None));
}

#[test]
#[ignore = "prints the template's walking-push grid (docs/findings/walking_template.md)"]
fn print_the_template_push_grid() {
    let overrides = adjusted(true);
    let walk = TemplateWalk::of_scenario(&walk_push(), &overrides).unwrap();
    println!("unpushed: {:?}", walk.run(None));
    let impulses: Vec<f64> = (1..=12).map(f64::from).collect();
    for direction in [
        PushDirection::Forward,
        PushDirection::Left,
        PushDirection::Right,
    ] {
        for phase in [0.2, 0.5, 0.8] {
            let span = window(&overrides, phase);
            let cells = &template_pushes(&walk_push(), &overrides, span, &[direction], &impulses)
                .unwrap()[0];
            let text: String = cells.iter().map(|&o| if o { 'o' } else { 'x' }).collect();
            let up_to = cells.iter().take_while(|&&o| o).count();
            let at = SwingPhase {
                step: Some(3),
                phase,
            };
            let bound = gait_bounds(&walk_push(), &overrides, at, 0.1, &[direction]).unwrap()[0];
            let bound = bound.map_or(f64::NAN, |b| b.adjusted);
            let found = template_bisection(&walk_push(), &overrides, span, &[direction], 0.01);
            println!(
                "{} {phase}: {text} up to {up_to} N s, bisected {:.2}, bound {bound:.2}",
                direction.name(),
                found.unwrap()[0]
            );
        }
    }
}

#[test]
#[ignore = "prints one template push, tick by tick (TEMPLATE_PUSH=\"direction phase impulse\")"]
fn print_a_template_push() {
    let spec = std::env::var("TEMPLATE_PUSH").unwrap_or("left 0.2 8".into());
    let words: Vec<&str> = spec.split_whitespace().collect();
    let direction = PushDirection::parse(words[0]).unwrap();
    let (phase, impulse): (f64, f64) = (words[1].parse().unwrap(), words[2].parse().unwrap());
    let overrides = adjusted(true);
    let walk = TemplateWalk::of_scenario(&walk_push(), &overrides).unwrap();
    let stance = Stance::of(&Scenario::from_file(&walk_push(), &overrides).unwrap()).unwrap();
    let (start_s, duration_s) = window(&overrides, phase);
    let world_force = push_force(impulse, duration_s, stance.direction(direction));
    let push = TemplatePush {
        world_force,
        start_s,
        duration_s,
    };
    let outcome = walk.run_with(Some(push), |tick| {
        let [c, r, xi] = [tick.world_p_com, tick.world_p_com_reference, tick.world_xi];
        let [wished, p] = [tick.world_p_cop_wished, tick.world_p_cop];
        println!(
            "T {:.2} c {:.4} {:.4} ref {:.4} {:.4} xi {:.4} {:.4} p* {:.4} {:.4} p {:.4} {:.4}",
            tick.t, c.x, c.y, r.x, r.y, xi.x, xi.y, wished.x, wished.y, p.x, p.y
        )
    });
    println!("{outcome:?}");
}

#[test]
fn the_cli_reports_the_template_beside_the_robot() {
    // Unpushed robot runs that end soon after the push; the template runs as long.
    let impulses = [2.0, 5.0, 8.0, 11.0];
    let list: Vec<String> = impulses.iter().map(f64::to_string).collect();
    let walk = walk_push();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sea-sim"))
        .args(["push", "-q", walk.to_str().unwrap(), "--phase", "0.2"])
        .args([
            "--directions",
            "left,forward",
            "--impulses",
            &list.join(","),
        ])
        .args([
            "--set",
            "walking.step_adjustment=true",
            "--set",
            "simulation.duration_s=2.1",
        ])
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let mut overrides = adjusted(false);
    overrides.push(("simulation.duration_s".into(), "2.1".into()));
    let span = window(&overrides, 0.2);
    let directions = [PushDirection::Left, PushDirection::Forward];
    let library = template_pushes(&walk_push(), &overrides, span, &directions, &impulses).unwrap();
    let rows = report["directions"].as_array().unwrap();
    assert_eq!(rows.len(), library.len(), "{report}");
    for (row, recovered) in rows.iter().zip(library) {
        let outcomes: String = recovered
            .iter()
            .map(|&o| if o { 'o' } else { 'x' })
            .collect();
        assert_eq!(row["template_outcomes"], outcomes.as_str(), "{row}");
        let up_to = impulses
            .iter()
            .zip(&recovered)
            .take_while(|(_, &o)| o)
            .last();
        let up_to = up_to.map_or(0.0, |(&impulse, _)| impulse);
        assert_eq!(row["template_recovered_up_to_n_s"], up_to, "{row}");
    }
    // Within the 2.1 s run the left pushes have not ended the walk: none is lost yet.
    assert_eq!(report["directions"][0]["template_outcomes"], "oooo");
}

#[test]
fn a_push_that_ends_after_the_run_is_refused_naming_the_window() {
    let mut overrides = adjusted(false);
    overrides.push(("simulation.duration_s".into(), "2.0".into()));
    let directions = [PushDirection::Left];
    for window in [(1.95, 0.1), (1.0, 0.0), (-0.1, 0.1)] {
        let error = template_pushes(&walk_push(), &overrides, window, &directions, &[1.0])
            .unwrap_err()
            .to_string();
        assert!(error.contains("window") && error.contains("2 s"), "{error}");
        let error = template_bisection(&walk_push(), &overrides, window, &directions, 0.1)
            .unwrap_err()
            .to_string();
        assert!(error.contains("window"), "{error}");
    }
}

#[test]
fn the_step_timing_lifts_the_planner_limited_cells_past_the_goal_on_the_template() {
    // The goal: 0.25 m/s of velocity change, 8.3 N s on the iCub; left at 20 % and right at
    // 80 % of the swing are the cells the plan's timing leaves under it.
    let fixed = adjusted(false);
    let mut retimed = fixed.clone();
    retimed.push(("walking.step_timing".into(), "sideways".into()));
    retimed.push(("walking.min_adjusted_swing_duration".into(), "0.15".into()));
    for (direction, phase) in [(PushDirection::Left, 0.2), (PushDirection::Right, 0.8)] {
        let span = window(&fixed, phase);
        let outcomes = |overrides: &[(String, String)]| {
            template_pushes(&walk_push(), overrides, span, &[direction], &[8.3]).unwrap()
        };
        assert_eq!(outcomes(&fixed), vec![vec![false]], "{direction:?} {phase}");
        assert_eq!(
            outcomes(&retimed),
            vec![vec![true]],
            "{direction:?} {phase}"
        );
    }
    // Unpushed, adjusted at every tick (no threshold), nothing is clipped: the same walk.
    let unpushed = |overrides: &[(String, String)]| {
        let mut every_tick = overrides.to_vec();
        every_tick.push(("walking.step_adjustment_threshold".into(), "0".into()));
        TemplateWalk::of_scenario(&walk_push(), &every_tick)
            .unwrap()
            .run(None)
    };
    let (walked, retimed_walk) = (unpushed(&fixed), unpushed(&retimed));
    assert!(walked.recovered, "{walked:?}");
    assert_eq!(walked, retimed_walk);
}
