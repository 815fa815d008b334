//! `sea-sim init`: a scenario for a new humanoid from its URDF.

use crate::common::{parse_folder, say, Outcome};
use crate::signals::Interrupts;
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `sea-sim init`.
#[derive(Args, Debug)]
pub(crate) struct InitArgs {
    /// The URDF: a path or a package://NAME/PATH or file:// URI.
    urdf: String,
    /// The two contacts, left then right: frame names, or LINK:x,y,z (a point of a link, its
    /// frame, metres) for robots without sole frames.
    #[arg(long, num_args = 2, value_names = ["LEFT", "RIGHT"], required = true)]
    contacts: Vec<String>,
    /// The foot rectangle in the contact frame [m]; measured on the feet's collision geometry
    /// (boxes, spheres, STL and OBJ meshes) when absent.
    #[arg(long, value_name = "X0,X1,Y0,Y1", allow_hyphen_values = true)]
    foot: Option<String>,
    /// The scenario file to write [default: ROBOT_two_feet.toml].
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// A folder searched first for package:// URIs (repeatable).
    #[arg(long = "package-dir", value_name = "DIR", value_parser = parse_folder)]
    package_dirs: Vec<PathBuf>,
    /// Write a walking scenario ([walking] with the defaults scaled to the robot, 8 steps
    /// forward and the stop) instead of the CoM sinusoid [default file: ROBOT_walk.toml].
    #[arg(long)]
    walking: bool,
    /// With --walking: write the scaled settings without running the walk.
    #[arg(long, requires = "walking")]
    no_walk_check: bool,
}

/// `sea-sim init`: writes the scenario, says what it found on stderr. A stop signal before
/// the scenario is written (a large robot loading) writes nothing; one during the write lets
/// it finish (the file is written whole, through a temporary file); one during a walk's runs
/// (or during the write, which the runs then notice at once) ends them, the walk written at the
/// standing CoM height.
pub(crate) fn run_init(args: &InitArgs, interrupts: &Interrupts) -> sea_sim::Result<Outcome> {
    use sea_sim::init::{init_unless_stopped, parse_foot, InitOptions};
    let started = Instant::now();
    let flags = [("foot", "--foot"), ("urdf", "URDF")];
    let as_flag = |e: sea_sim::Error| e.argument_named(&flags);
    let foot = args
        .foot
        .as_deref()
        .map(parse_foot)
        .transpose()
        .map_err(as_flag)?;
    let stem = Path::new(&args.urdf)
        .file_stem()
        .map_or("robot".into(), |s| s.to_string_lossy().to_string());
    let options = InitOptions {
        urdf: args.urdf.clone(),
        contacts: [args.contacts[0].clone(), args.contacts[1].clone()],
        foot,
        package_dirs: args.package_dirs.clone(),
        out: args.out.clone().unwrap_or_else(|| {
            let suffix = if args.walking { "walk" } else { "two_feet" };
            PathBuf::from(format!("{stem}_{suffix}.toml"))
        }),
        name: None,
        walking: args.walking,
        skip_walk_check: args.no_walk_check,
    };
    let Some(report) = init_unless_stopped(&options, &interrupts.stop).map_err(as_flag)? else {
        let sig = interrupts
            .received()
            .unwrap_or(signal_hook::consts::SIGTERM);
        return Ok(Outcome::Interrupted(sig));
    };
    let (name, mass, joints) = &report.robot;
    for warning in &report.warnings {
        say(format_args!("sea-sim: warning: {warning}"));
    }
    if report.feet_rank < 12 {
        say(format_args!(
            "sea-sim: note: the two feet's 12 constraints have rank {} (legs of fewer than 6 \
             joints): the controller keeps to the wrenches the joints can produce, with \
             controller.pinv_damping {}",
            report.feet_rank,
            sea_sim::init::write::REDUNDANT_PINV_DAMPING
        ));
    }
    if args.walking {
        let figures = &report.walking_figures;
        say(format_args!(
            "sea-sim: walking scaled to CoM height {:.3} m, feet {:.3} m apart, leg {:.3} m, \
             reach {:.3} m",
            figures.com_height, figures.feet_distance, figures.leg_length, figures.reach
        ));
    }
    match &report.walk_check {
        Some(check) => say_walk_check(check),
        None if args.walking && !args.no_walk_check => say(format_args!(
            "sea-sim: note: the walk is not checked: {} is not a regular file (init runs the \
             walk from the file it wrote)",
            report.out.display()
        )),
        None => {}
    }
    if report.walk_check.as_ref().is_some_and(|c| c.interrupted()) {
        let sig = interrupts
            .received()
            .unwrap_or(signal_hook::consts::SIGTERM);
        return Ok(Outcome::Interrupted(sig));
    }
    if report.com_offset_m > 0.0 {
        say(format_args!(
            "sea-sim: the CoM stands {:.2} mm beside the middle of the foot rectangles' centres: \
             no posture shifts it sideways (legs without a hip yaw cannot)",
            1e3 * report.com_offset_m
        ));
    }
    let [left, _] = report.feet;
    say(format_args!(
        "sea-sim: {} written for '{name}' ({mass:.1} kg, {joints} joints): foot x {:?} y {:?} m \
         ({}), base lowered {:.3} m, posture error {:.1e}, {:.2} s",
        report.out.display(),
        left.x,
        left.y,
        if report.measured { "measured" } else { "given" },
        report.lowering_m,
        report.residual,
        started.elapsed().as_secs_f64()
    ));
    Ok(Outcome::Completed)
}

/// Prints each run of the walk check and what was written.
fn say_walk_check(check: &sea_sim::init::walking::WalkCheck) {
    for run in &check.tries {
        say(format_args!("sea-sim: walk check: {run}"));
    }
    let standing = check.tries.first().map_or(f64::NAN, |run| run.com_height);
    if check.interrupted() {
        say(format_args!(
            "sea-sim: walk check stopped: the walk is written at the standing CoM height \
             {standing:.3} m, not confirmed to walk"
        ));
    } else if let Some(run) = check.failed() {
        say(format_args!(
            "sea-sim: warning: the walk at walking.com_height {:.3} m could not be run (above); \
             it is written at the standing CoM height {standing:.3} m",
            run.com_height
        ));
    } else if let Some(run) = check.completed() {
        if check.tries.len() > 1 {
            say(format_args!(
                "sea-sim: walking.com_height {:.3} m written: the walk completed there",
                run.com_height
            ));
        }
    } else {
        say(format_args!(
            "sea-sim: warning: the written walk completes at no walking.com_height tried; \
             it is written at the standing CoM height {standing:.3} m (docs/guide/your_robot.md)"
        ));
    }
}
