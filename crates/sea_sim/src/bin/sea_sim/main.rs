//! `sea-sim`: runs scenarios and benchmarks of sea-momentum from the command line.
//!
//! `sea-sim --help` lists the subcommands, `sea-sim SUBCOMMAND --help` their options and
//! defaults.
//!
//! Exit status: 0 completed, 3 diverged or fell, 1 error (including a bad command line), and after
//! SIGINT, SIGTERM or SIGHUP 128 + the signal (130, 143, 129): the run stopped at the next
//! tick, its MCAP log was finished and its summary written with status "interrupted". A second
//! signal exits at once, leaving any earlier output file untouched. A signal ignored when
//! `sea-sim` starts (`nohup sea-sim ...`) stays ignored.
//!
//! Outputs (`--mcap`, `--summary`) are checked before the run (their folder exists, none is an
//! input or another output, no other process writes them) and written beside their target as
//! `.NAME.partial`, renamed over the target when the run ends (completed, diverged or
//! interrupted: all three leave a finished, readable log). A run killed outright or stopped by
//! an error never replaces the target. Nothing written to stdout or stderr can abort a run: a
//! closed pipe only loses the text. A summary or report that cannot be written on stdout for
//! another reason (a full disk behind a redirection) makes the exit status 1 once the work is
//! done. Control characters of file names and keys are echoed escaped (`\u{1b}`).

mod bench;
mod common;
mod init;
mod margin;
mod progress;
mod push;
mod run;
mod schema;
mod signals;
mod sweep;

use clap::{Parser, Subcommand};
use common::{say, Outcome, EXIT_DIVERGED, EXIT_ERROR};
use signals::{signal_name, Interrupts};
use std::process::ExitCode;

/// Simulations and benchmarks of momentum control of humanoid robots with series elastic
/// actuators.
#[derive(Parser, Debug)]
#[command(name = "sea-sim", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scenario: the closed loop of controller and plant, with an MCAP log and a summary.
    ///
    /// Exit status: 0 completed, 3 diverged or fell, 1 error, 130/143/129 stopped by
    /// SIGINT/SIGTERM/SIGHUP (log finished, summary status "interrupted").
    Run(run::RunArgs),
    /// Benchmark the dynamics algorithms and the controller tick on a URDF or a scenario.
    ///
    /// Medians of batch means in microseconds (compare ratios measured in one run). With
    /// `--scenario` (e.g. a file `sea-sim init` wrote): the dynamics of its robot,
    /// `controller_tick_us` (one tick of its controller as the scenario sets it up) and
    /// `scenario_second_ms` (the wall time of its first simulated second).
    Bench(bench::BenchArgs),
    /// Sweep a scenario over a grid of values of numeric keys, runs in parallel; writes a CSV.
    ///
    /// Exit status: 0 done (whatever the runs' outcomes), 1 error, 130/143/129 stopped by a
    /// signal (the rows done are written).
    Sweep(sweep::SweepArgs),
    /// Find the values of one numeric scenario key where the closed loop's stability changes
    /// (grid scan, then bisection); prints a report (a table, or JSON with `--json`).
    ///
    /// Exit status: 0 done, 1 error, 130/143/129 stopped by a signal (the evaluations done
    /// reported, conclusion "interrupted").
    Margin(margin::MarginArgs),
    /// Write a scenario for a new robot from its URDF and two contacts.
    ///
    /// A two-feet balancing scenario (or with `--walking` a walk): SEA on every joint, a
    /// standing posture, the foot rectangle and gains, all scaled to the robot; `sea-sim run`
    /// runs it with no edit. A walk is run before `init` ends: where it does not complete at
    /// the robot's standing CoM height, `walking.com_height` is lowered by 3 % steps (at most
    /// 12 %) until it does; each run is printed.
    ///
    /// Exit status: 0 written, 1 error, 130/143/129 stopped by a signal before the scenario was
    /// written (nothing written; a signal during the write lets it finish, status 0) or
    /// during the walk's runs, or during a walk's write, which the runs then notice at once
    /// (the walk written at the standing CoM height, not confirmed to walk).
    Init(init::InitArgs),
    /// Find, per direction, the largest push the closed loop recovers from; prints a JSON report.
    ///
    /// The impulse of a short push on a link is bisected on full runs, directions in parallel,
    /// and reported beside the stance's capture-point bound; with `--phase`, pushing a walk,
    /// also the gait's bound on a sideways push (`gait_bound_impulse_n_s`) and the bound with
    /// only the landings the step adjustment moves (`adjustment_bound_impulse_n_s`); on a
    /// scenario with `walking.stepping`, the stepping settings' bound (`stepping_bound`).
    ///
    /// Exit status: 0 done (whatever the pushes' outcomes), 1 error, 130/143/129 stopped by
    /// a signal (the pushes done reported, `"interrupted": true`).
    Push(push::PushArgs),
    /// Print the JSON Schema of scenario files (derived from the types that read them; the
    /// shipped copy is schemas/scenario.schema.json).
    Schema(schema::SchemaArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // A bad command line (exit 1): clap's message, with the control characters of
            // the values it echoes escaped as every message is.
            say(e.render().to_string().trim_end());
            return ExitCode::from(EXIT_ERROR);
        }
        Err(e) => {
            // --help and --version are not errors.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    let (outcome, stopped_by) = match &cli.command {
        Command::Run(args) => with_interrupts(|interrupts| run::run_scenario(args, interrupts)),
        Command::Sweep(args) => {
            with_interrupts(|interrupts| sweep::run_sweep_command(args, interrupts))
        }
        Command::Bench(args) => (bench::run_bench(args).map(|()| Outcome::Completed), None),
        Command::Margin(args) => with_interrupts(|interrupts| margin::run_margin(args, interrupts)),
        Command::Init(args) => with_interrupts(|interrupts| init::run_init(args, interrupts)),
        Command::Push(args) => with_interrupts(|interrupts| push::run_push(args, interrupts)),
        Command::Schema(args) => (
            schema::print_schema(args).map(|()| Outcome::Completed),
            None,
        ),
    };
    let finished = match cli.command {
        Command::Sweep(_) => "the rows of the runs done written",
        Command::Push(_) => "the pushes done reported",
        Command::Margin(_) => "the evaluations done reported",
        Command::Init(_) => "nothing written unless said above",
        _ => "log and summary finished",
    };
    exit_code(outcome, stopped_by, finished)
}

/// Runs `work` with the stop signals handled ([`Interrupts`]), installed before the scenario
/// is read so that a signal while it loads ends the run with the signal's status; returns
/// its outcome and the signal that stopped it, if any.
fn with_interrupts(
    work: impl FnOnce(&Interrupts) -> sea_sim::Result<Outcome>,
) -> (sea_sim::Result<Outcome>, Option<i32>) {
    match Interrupts::install() {
        Ok(interrupts) => (work(&interrupts), interrupts.received()),
        Err(source) => {
            let path = "the stop signals' handlers".to_string();
            (Err(sea_sim::Error::Io { path, source }), None)
        }
    }
}

/// The exit status of an `outcome` (module doc), saying why on stderr; an error after a stop
/// signal (`stopped_by`) is the signal's status.
fn exit_code(
    outcome: sea_sim::Result<Outcome>,
    stopped_by: Option<i32>,
    finished: &str,
) -> ExitCode {
    match (outcome, stopped_by) {
        (Ok(Outcome::Completed), _) => ExitCode::SUCCESS,
        (Ok(Outcome::Diverged), _) => ExitCode::from(EXIT_DIVERGED),
        (Ok(Outcome::Interrupted(sig)), _) => {
            say(format_args!(
                "sea-sim: stopped by {}; {finished}",
                signal_name(sig)
            ));
            ExitCode::from(128 + sig as u8)
        }
        (Err(e), Some(sig)) => {
            say(format_args!(
                "sea-sim: stopped by {} ({e})",
                signal_name(sig)
            ));
            ExitCode::from(128 + sig as u8)
        }
        (Err(e), None) => {
            say(format_args!("sea-sim: {e}"));
            ExitCode::from(EXIT_ERROR)
        }
    }
}
