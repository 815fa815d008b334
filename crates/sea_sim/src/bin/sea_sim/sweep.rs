//! `sea-sim sweep`: a scenario over a grid of values, runs in parallel, rows to a CSV.

use crate::common::{parse_key_value, print_text, say, Outcome};
use crate::signals::Interrupts;
use clap::Args;
use sea_sim::output::{check_distinct, OutputFile};
use sea_sim::scenario::Scenario;
use std::path::PathBuf;

/// Options of `sea-sim sweep`.
#[derive(Args, Debug)]
pub(crate) struct SweepArgs {
    /// Scenario file (TOML).
    scenario: PathBuf,
    /// A grid axis: `KEY=V1,V2,...` or `KEY=START:STOP:COUNT[:log]` (repeatable; the runs are
    /// the cartesian product, the last axis varying fastest).
    #[arg(long = "grid", value_name = "KEY=VALUES", required = true)]
    grid: Vec<String>,
    /// Override a scenario value for every run, e.g. `--set simulation.duration_s=2`
    /// (repeatable; a grid key wins over the same key here).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
    /// Runs in parallel, at most `sea_sim::sweep::MAX_WORKERS` [default: every core].
    #[arg(long, short = 'j', value_name = "N",
          help = format!("Runs in parallel, at most {} [default: every core]", sea_sim::sweep::MAX_WORKERS),
          value_parser = clap::value_parser!(u32).range(1..=sea_sim::sweep::MAX_WORKERS as i64))]
    jobs: Option<u32>,
    /// Write the results to FILE (CSV: the grid values, then status, message and every summary
    /// field; one row per run in grid order).
    #[arg(long, value_name = "FILE.csv")]
    out: PathBuf,
    /// No progress on stderr.
    #[arg(long, short)]
    quiet: bool,
}

/// One progress line of a sweep: runs done, the point and how its run ended.
pub(crate) fn sweep_progress_line(
    keys: &[String],
    progress: &sea_sim::sweep::SweepProgress<'_>,
) -> String {
    let point: Vec<String> = keys
        .iter()
        .zip(&progress.row.values)
        .map(|(key, value)| format!("{key}={value}"))
        .collect();
    let row = progress.row;
    let detail = if row.message.is_empty() {
        String::new()
    } else {
        format!(" ({})", row.message)
    };
    format!(
        "sea-sim: sweep {}/{} {}: {}{detail}",
        progress.done,
        progress.total,
        point.join(" "),
        row.status
    )
}

/// `sea-sim sweep`: every run of the grid, the CSV written when the sweep ends (also when a
/// signal stopped it: the rows done).
pub(crate) fn run_sweep_command(
    args: &SweepArgs,
    interrupts: &Interrupts,
) -> sea_sim::Result<Outcome> {
    use sea_sim::sweep::{run_sweep, write_csv, Grid};
    let grid = Grid::parse(&args.grid)?;
    let scenario = Scenario::from_file(&args.scenario, &args.overrides)?;
    let inputs = scenario.input_files();
    check_distinct(&inputs, &[("--out", args.out.as_path())])?;
    let mut out = OutputFile::create(&args.out)?;
    let keys = grid.keys();
    if !args.quiet {
        say(format_args!(
            "sea-sim: sweep of {} runs over {}",
            grid.len(),
            keys.join(", ")
        ));
    }
    let quiet = args.quiet;
    let rows = run_sweep(
        &args.scenario,
        &grid,
        &args.overrides,
        args.jobs.map(|n| n as usize),
        &interrupts.stop,
        &|progress| {
            if !quiet {
                say(sweep_progress_line(&keys, progress));
            }
        },
    )?;
    let mut csv = Vec::new();
    write_csv(&mut csv, &args.out, &keys, &rows)?;
    // A CSV that cannot be written (a full disk) is printed instead: the runs are not lost.
    if let Err(e) = out.write_all(&csv).and_then(|()| out.commit()) {
        say(format_args!(
            "sea-sim: the CSV could not be written to {}; its rows follow on stdout",
            args.out.display()
        ));
        let _ = print_text(String::from_utf8_lossy(&csv));
        return Err(e);
    }
    let count = |status: &str| rows.iter().filter(|r| r.status == status).count();
    let (completed, interrupted) = (count("completed"), count("interrupted"));
    if !quiet {
        let cut = match interrupted {
            0 => String::new(),
            n => format!(", {n} stopped part-way (their rows say \"interrupted\")"),
        };
        say(format_args!(
            "sea-sim: {} of {} runs done, {completed} completed{cut}; wrote {}",
            rows.len() - interrupted,
            grid.len(),
            args.out.display()
        ));
    }
    Ok(match interrupts.received() {
        Some(sig) => Outcome::Interrupted(sig),
        None => Outcome::Completed,
    })
}
