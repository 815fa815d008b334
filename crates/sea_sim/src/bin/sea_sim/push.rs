//! `sea-sim push`: the largest push recovered per direction, bisected, or the outcomes of
//! pushes of fixed impulses (`--impulses`), beside the bounds of the pendulum: the stance's
//! capture point, and the gait's (`--phase`) or the stepping settings' (`walking.stepping`).

use crate::common::{parse_key_value, parse_non_negative, parse_positive, print_out, say, Outcome};
use crate::signals::Interrupts;
use clap::Args;
use sea_sim::analysis::gait_bound::gait_bounds;
use sea_sim::analysis::push::{
    fixed_push_table, impulses_recovered_up_to, push_table, PushDirection, PushOptions,
    PushProgress, SwingPhase, DEFAULT_PUSHED_STEP,
};
use sea_sim::analysis::step_bound::stepping_bounds_json;
use sea_sim::analysis::template_walk::{template_bisection, template_pushes};
use std::path::PathBuf;

/// Options of `sea-sim push`.
#[derive(Args, Debug)]
pub(crate) struct PushArgs {
    /// Scenario file (TOML), e.g. scenarios/robot_rate/push_two_feet.toml; its own
    /// `[[disturbances]]` are replaced by the push.
    scenario: PathBuf,
    /// Directions, comma-separated: forward, backward, left, right (the first contact's sole
    /// axes), each at most once.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "forward,backward,left,right",
        value_parser = ["forward", "backward", "left", "right"]
    )]
    directions: Vec<String>,
    /// The pushed link.
    #[arg(long, default_value_t = PushOptions::default().link)]
    link: String,
    /// Start of the push [s] (without `--phase`; finite, non-negative).
    #[arg(
        long,
        default_value_t = PushOptions::default().start_s,
        conflicts_with = "phase",
        value_parser = parse_non_negative
    )]
    start: f64,
    /// Start the push at this fraction of a swing of the scenario's walk, in [0, 1] (0 the
    /// swing foot's lift-off, 1 its planned touchdown) instead of at `--start`; the swing is
    /// step `--step`'s, the time the scenario's walking plan's (rounded to a plant step).
    /// Each sideways row then also gives `gait_bound_impulse_n_s`: the largest push the
    /// gait's timing and step widths could capture with the best centre of pressure and
    /// landings (the linear inverted pendulum, `sea_study::analysis::gait_bound`), and
    /// `adjustment_bound_impulse_n_s`: the same with only the landings the controller's step
    /// adjustment moves (`walking.step_adjustment`: the swing in flight when the push starts
    /// before `walking.step_adjustment_end_phase`, and the later ones; without it, none);
    /// `null` forward and backward. `capture_point_impulse_n_s` stays the initial stance's.
    /// Every row also gives the same push, at the CoM, on the walk's template, the
    /// controller's planner and momentum law on the pendulum with the robot left out
    /// (`sea_study::analysis::template_walk`): `template_impulse_n_s` bisected, or with
    /// `--impulses` `template_outcomes` (`o` recovered, `x` not) and
    /// `template_recovered_up_to_n_s`.
    #[arg(long)]
    phase: Option<f64>,
    /// With `--phase`: the step whose swing is pushed, counted from 0 in the plan's order.
    #[arg(long, default_value_t = DEFAULT_PUSHED_STEP, requires = "phase")]
    step: usize,
    /// Length of the push [s] (finite, positive).
    #[arg(long, default_value_t = PushOptions::default().duration_s, value_parser = parse_positive)]
    duration: f64,
    /// Bisection resolution [N s] (finite, positive).
    #[arg(long, default_value_t = PushOptions::default().tolerance_n_s, value_parser = parse_positive)]
    tolerance: f64,
    /// Instead of the bisection, push once at each of these impulses [N s], comma-separated
    /// (non-negative, at most 1e6 N s), e.g. `--impulses 1,2,3,4`: every outcome is reported, so
    /// islands of recovery above a failure show (all runs in parallel).
    #[arg(long, value_delimiter = ',', conflicts_with = "tolerance")]
    impulses: Option<Vec<f64>>,
    /// Override a scenario value, e.g. `--set controller.kind=rigid` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
    /// No progress lines on stderr (one as the runs start, then one per run as it ends).
    #[arg(short, long)]
    quiet: bool,
}

/// The progress line of a push run that ended: direction, impulse and outcome.
fn push_progress_line(progress: &PushProgress<'_>) -> String {
    let summary = progress.summary;
    let end = if summary.completed() {
        String::new()
    } else {
        format!(" at {:.2} s", summary.duration_s)
    };
    format!(
        "sea-sim: push {} {} N s: {}{end}",
        progress.direction.name(),
        progress.impulse_n_s,
        summary.status
    )
}

/// The line said as the runs start: how many, on how many threads.
fn start_line(args: &PushArgs, directions: usize) -> String {
    let threads = rayon::current_num_threads();
    match &args.impulses {
        Some(impulses) => format!(
            "sea-sim: push: {} runs at fixed impulses on {threads} threads",
            impulses.len() * directions
        ),
        None => format!("sea-sim: push: bisecting {directions} direction(s) on {threads} threads"),
    }
}

/// Says each run's outcome on stderr unless `--quiet`.
fn on_run(args: &PushArgs) -> impl Fn(&PushProgress<'_>) + Sync + '_ {
    move |progress| {
        if !args.quiet {
            say(push_progress_line(progress));
        }
    }
}

/// The bisection's rows of the JSON report, one per direction (`interrupted`: a stop signal
/// ended its bisection before the tolerance, the bracket as far as it got).
fn bisected_rows(
    args: &PushArgs,
    options: &PushOptions,
    directions: &[PushDirection],
    interrupts: &Interrupts,
) -> sea_sim::Result<Vec<serde_json::Value>> {
    let progress = on_run(args);
    let table = push_table(
        &args.scenario,
        &args.overrides,
        options,
        directions,
        &progress,
        &interrupts.stop,
    )?;
    Ok(table
        .iter()
        .map(|row| {
            let fall = row.failed_summary.as_ref().map(|s| s.to_json());
            serde_json::json!({
                "direction": row.direction.name(),
                "capture_point_impulse_n_s": row.capture_point_impulse,
                "recovered_impulse_n_s": row.recovered_impulse,
                "failed_impulse_n_s": row.failed_impulse,
                "failed_status": fall.as_ref().map(|j| j["status"].clone()),
                "failed_reason": fall.as_ref().map(|j| j["reason"].clone()),
                "runs": row.runs,
                "interrupted": row.interrupted,
            })
        })
        .collect())
}

/// `--impulses`: the rows of the JSON report, one per direction, with every push's outcome
/// (its status, reason and end time; status and reason "interrupted" and the end `null` for
/// a push a stop signal kept from its end) and `outcomes`, one character per impulse in the
/// order given (`o` recovered, `x` not, `-` not run to its end).
fn fixed_rows(
    args: &PushArgs,
    options: &PushOptions,
    (directions, impulses): (&[PushDirection], &[f64]),
    interrupts: &Interrupts,
) -> sea_sim::Result<Vec<serde_json::Value>> {
    let table = fixed_push_table(
        &args.scenario,
        &args.overrides,
        options,
        directions,
        impulses,
        &on_run(args),
        &interrupts.stop,
    )?;
    Ok(table
        .iter()
        .map(|row| {
            let pushes: Vec<serde_json::Value> = row
                .outcomes
                .iter()
                .map(|(impulse, summary)| match summary {
                    Some(summary) => serde_json::json!({
                        "impulse_n_s": impulse,
                        "status": summary.status,
                        "reason": summary.reason,
                        "end_s": summary.duration_s,
                    }),
                    None => serde_json::json!({
                        "impulse_n_s": impulse,
                        "status": "interrupted",
                        "reason": "interrupted",
                        "end_s": null,
                    }),
                })
                .collect();
            let outcomes: String = row
                .outcomes
                .iter()
                .map(|(_, summary)| match summary {
                    Some(summary) if summary.completed() => 'o',
                    Some(_) => 'x',
                    None => '-',
                })
                .collect();
            serde_json::json!({
                "direction": row.direction.name(),
                "capture_point_impulse_n_s": row.capture_point_impulse,
                "recovered_count": row.recovered_count(),
                "recovered_up_to_n_s": row.recovered_up_to(),
                "outcomes": outcomes,
                "pushes": pushes,
                "interrupted": row.interrupted(),
            })
        })
        .collect())
}

/// Per direction, the bounds the report adds to its row, with their keys: pushing a walk
/// (`at`), the gait's bounds on a sideways push (`gait_bound_impulse_n_s` with every landing
/// within the step widths, `adjustment_bound_impulse_n_s` with those the controller's step
/// adjustment moves; `null` along the walk) and the template's figures of the push
/// (`options`, [`template_by_direction`]); on a scenario that steps, the stepping settings'
/// bound (`stepping_bound`); none otherwise.
fn bounds_by_direction(
    args: &PushArgs,
    at: Option<SwingPhase>,
    options: &PushOptions,
    directions: &[PushDirection],
) -> sea_sim::Result<Vec<Vec<(&'static str, serde_json::Value)>>> {
    let (path, overrides, duration) = (&args.scenario, &args.overrides, args.duration);
    if let Some(at) = at {
        let bounds = gait_bounds(path, overrides, at, duration, directions)?;
        let template = template_by_direction(args, options, directions)?;
        return Ok(bounds
            .into_iter()
            .zip(template)
            .map(|(bounds, template)| {
                let mut row = vec![
                    (
                        "gait_bound_impulse_n_s",
                        serde_json::json!(bounds.map(|b| b.within_limits)),
                    ),
                    (
                        "adjustment_bound_impulse_n_s",
                        serde_json::json!(bounds.map(|b| b.adjusted)),
                    ),
                ];
                row.extend(template);
                row
            })
            .collect());
    }
    let stepping = stepping_bounds_json(path, overrides, duration, directions)?;
    Ok(stepping
        .unwrap_or_default()
        .into_iter()
        .map(|bound| vec![("stepping_bound", bound)])
        .collect())
}

/// Pushing a walk, per direction, the template's figures the report adds to its row
/// (`sea_study::analysis::template_walk`): with `--impulses` each push's outcome
/// (`template_outcomes`, `template_recovered_up_to_n_s`), else the bisected
/// `template_impulse_n_s`.
fn template_by_direction(
    args: &PushArgs,
    options: &PushOptions,
    directions: &[PushDirection],
) -> sea_sim::Result<Vec<Vec<(&'static str, serde_json::Value)>>> {
    let (path, overrides) = (&args.scenario, &args.overrides);
    let window = (options.start_s, options.duration_s);
    let Some(impulses) = &args.impulses else {
        let found = template_bisection(path, overrides, window, directions, args.tolerance)?;
        return Ok(found
            .into_iter()
            .map(|impulse| vec![("template_impulse_n_s", serde_json::json!(impulse))])
            .collect());
    };
    let table = template_pushes(path, overrides, window, directions, impulses)?;
    Ok(table
        .into_iter()
        .map(|recovered| {
            let outcomes: String = recovered
                .iter()
                .map(|&o| if o { 'o' } else { 'x' })
                .collect();
            let pairs = impulses.iter().zip(&recovered);
            let up_to = impulses_recovered_up_to(pairs.map(|(&i, &o)| (i, Some(o))));
            vec![
                ("template_outcomes", serde_json::json!(outcomes)),
                ("template_recovered_up_to_n_s", serde_json::json!(up_to)),
            ]
        })
        .collect())
}

/// The library's push arguments as the command line's flags.
fn flags(args: &PushArgs) -> [(&'static str, &'static str); 3] {
    let start = if args.phase.is_some() {
        "--phase"
    } else {
        "--start"
    };
    [
        ("PushOptions.link", "--link"),
        ("PushOptions.start_s", start),
        ("PushOptions.duration_s", "--duration"),
    ]
}

/// With `--phase`: the pushed swing, its push's start and its lift-off and touchdown [s].
type PushedSwing = (SwingPhase, (f64, [f64; 2]));

/// The swing `--phase` and `--step` push, found in the scenario's walking plan; `None`
/// without `--phase`.
fn pushed_swing(args: &PushArgs) -> sea_sim::Result<Option<PushedSwing>> {
    use sea_sim::analysis::push::swing_push_start;
    args.phase
        .map(|phase| {
            let at = SwingPhase {
                step: Some(args.step),
                phase,
            };
            swing_push_start(&args.scenario, &args.overrides, at).map(|found| (at, found))
        })
        .transpose()
}

/// `sea-sim push`: the push table as JSON on stdout. After a stop signal no run starts, the
/// runs under way stop at their next sample, and the table of the runs done is printed
/// (`"interrupted": true`).
pub(crate) fn run_push(args: &PushArgs, interrupts: &Interrupts) -> sea_sim::Result<Outcome> {
    use sea_sim::analysis::push::check_pushed_link;
    let as_flag = |e: sea_sim::Error| e.argument_named(&flags(args));
    // The link first: the swing's timing takes a run; a bad flag is said before it.
    let scenario = sea_sim::scenario::Scenario::from_file(&args.scenario, &args.overrides)?;
    check_pushed_link(&scenario, &args.link).map_err(as_flag)?;
    let directions = args
        .directions
        .iter()
        .map(|name| PushDirection::parse(name))
        .collect::<sea_sim::Result<Vec<_>>>()?;
    if let Some(twice) = args
        .directions
        .iter()
        .enumerate()
        .find_map(|(i, name)| args.directions[..i].contains(name).then_some(name))
    {
        return Err(sea_sim::Error::argument(
            "--directions",
            "each direction at most once",
            format!("'{twice}' given twice"),
        ));
    }
    let swing = pushed_swing(args)?;
    let options = PushOptions {
        link: args.link.clone(),
        start_s: swing.map_or(args.start, |(_, (start_s, _))| start_s),
        duration_s: args.duration,
        tolerance_n_s: args.tolerance,
    };
    options.check_within_run(&scenario).map_err(as_flag)?;
    if let Some(warning) = options.short_run_warning(&scenario) {
        say(format_args!("sea-sim: warning: {warning}"));
    }
    // The bounds first: cheap, and their errors come before the runs, not after.
    let bounds = bounds_by_direction(args, swing.map(|(at, _)| at), &options, &directions)?;
    if !args.quiet {
        say(start_line(args, directions.len()));
    }
    let mut rows = match &args.impulses {
        Some(impulses) => fixed_rows(args, &options, (&directions, impulses), interrupts)?,
        None => bisected_rows(args, &options, &directions, interrupts)?,
    };
    for (row, bounds) in rows.iter_mut().zip(bounds) {
        for (key, bound) in bounds {
            row[key] = bound;
        }
    }
    let interrupted = rows.iter().any(|row| row["interrupted"] == true);
    let mut json = serde_json::json!({
        "scenario": args.scenario,
        "overrides": args.overrides.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>(),
        "link": options.link,
        "start_s": options.start_s,
        "duration_s": options.duration_s,
        "directions": rows,
        "interrupted": interrupted,
    });
    if let Some((at, (_, [lift_off, touchdown]))) = swing {
        json["swing"] = serde_json::json!({
            "step": at.step,
            "phase": at.phase,
            "lift_off_s": lift_off,
            "touchdown_s": touchdown,
        });
    }
    let text = serde_json::to_string_pretty(&json)
        .map_err(|e| sea_sim::Error::Output(format!("push JSON: {e}")))?;
    print_out(text)?;
    // A signal that came as the last run ended stopped nothing: the table is whole.
    Ok(match interrupts.received() {
        Some(sig) if interrupted => Outcome::Interrupted(sig),
        _ => Outcome::Completed,
    })
}
