//! `sea-sim run`: a scenario's closed loop with its MCAP log, summary and live view.

use crate::common::{parse_folder, parse_key_value, print_out, say, Outcome};
use crate::progress::Progress;
use crate::signals::Interrupts;
use clap::Args;
use sea_sim::closed_loop::{build, run_setup_with_sinks, RecordSink};
use sea_sim::mcap_log::{McapSink, LOG_NEEDS_A_FILE};
use sea_sim::output::{check_distinct, OutputFile};
use sea_sim::scenario::Scenario;
use signal_hook::consts::SIGINT;
use std::path::{Path, PathBuf};

/// Options of `sea-sim run`.
#[derive(Args, Debug)]
pub(crate) struct RunArgs {
    /// Scenario file (TOML).
    scenario: PathBuf,
    /// Override a scenario value, e.g. `--set simulation.duration_s=2` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
    /// Write the MCAP log (Foxglove) to FILE [default: no log].
    #[arg(long, value_name = "FILE")]
    mcap: Option<PathBuf>,
    /// Write the summary JSON to FILE (it is also printed on stdout) [default: stdout only].
    #[arg(long, value_name = "FILE")]
    summary: Option<PathBuf>,
    /// No progress on stderr.
    #[arg(long, short)]
    quiet: bool,
    /// Serve the run live to the Foxglove app (Foxglove WebSocket protocol on 127.0.0.1) at
    /// real-time pace; its address is printed on stderr.
    #[arg(long)]
    live: bool,
    /// Port of the live server (0: any free port).
    #[arg(long, value_name = "N", default_value_t = sea_sim::foxglove::live::DEFAULT_LIVE_PORT,
          requires = "live")]
    port: u16,
    /// Look for the URDF's `package://` meshes in DIR first (repeatable; then ROS_PACKAGE_PATH,
    /// AMENT/CMAKE_PREFIX_PATH, the Python environment's cmeel prefix, then above the URDF).
    #[arg(long = "package-dir", value_name = "DIR", value_parser = parse_folder)]
    package_dirs: Vec<PathBuf>,
}

/// The run's outputs, opened (checked, locked, partial) before the simulation starts.
pub(crate) struct Outputs {
    mcap: Option<OutputFile>,
    summary: Option<OutputFile>,
}

/// Checks that no output is an input or another output, then opens them.
pub(crate) fn open_outputs(args: &RunArgs, scenario: &Scenario) -> sea_sim::Result<Outputs> {
    let inputs = scenario.input_files();
    let outputs: Vec<(&str, &Path)> = [("--mcap", &args.mcap), ("--summary", &args.summary)]
        .into_iter()
        .filter_map(|(role, path)| path.as_deref().map(|p| (role, p)))
        .collect();
    check_distinct(&inputs, &outputs)?;
    Ok(Outputs {
        mcap: args
            .mcap
            .as_deref()
            .map(|path| OutputFile::create_regular(path, LOG_NEEDS_A_FILE))
            .transpose()?,
        summary: args
            .summary
            .as_deref()
            .map(OutputFile::create)
            .transpose()?,
    })
}

/// Replaces the MCAP log's target, then writes the summary and replaces its target: each is
/// kept whatever happens to the other (a full disk under the summary keeps the finished log).
/// The first error is returned.
pub(crate) fn finish_outputs(outputs: Outputs, json: &str) -> sea_sim::Result<()> {
    let mcap = outputs.mcap.map_or(Ok(()), OutputFile::commit);
    let summary = outputs.summary.map_or(Ok(()), |mut summary| {
        summary.write_all(json.as_bytes())?;
        summary.write_all(b"\n")?;
        summary.commit()
    });
    mcap.and(summary)
}

/// Starts the live server of `--live` and says where it listens (also under `--quiet`: the
/// address is what the user needs to connect).
pub(crate) fn start_live(port: u16) -> sea_sim::Result<sea_sim::foxglove::live::LiveSink> {
    let sink = sea_sim::foxglove::live::LiveSink::start(port)?;
    say(format_args!(
        "sea-sim: live view on ws://{}:{} (Foxglove: Open connection > Foxglove WebSocket)",
        sea_sim::foxglove::live::LIVE_HOST,
        sink.port()
    ));
    Ok(sink)
}

/// `sea-sim run`.
pub(crate) fn run_scenario(args: &RunArgs, interrupts: &Interrupts) -> sea_sim::Result<Outcome> {
    let scenario = Scenario::from_file(&args.scenario, &args.overrides)?;
    let outputs = open_outputs(args, &scenario)?;
    let duration_s = scenario.simulation.duration_s;
    if !args.quiet {
        say(format_args!(
            "sea-sim: running {} ({duration_s} s simulated)",
            args.scenario.display()
        ));
    }
    let mut progress = Progress::new(args.quiet, duration_s);
    // Only the log keeps samples: memory stays bounded however long the run.
    let mut log = outputs
        .mcap
        .as_ref()
        .map(|o| McapSink::new(o.path()).with_package_dirs(&args.package_dirs));
    let mut live = args
        .live
        .then(|| start_live(args.port))
        .transpose()?
        .map(|live| live.with_package_dirs(&args.package_dirs));
    let mut sinks: Vec<&mut dyn RecordSink> = log
        .iter_mut()
        .map(|sink| sink as &mut dyn RecordSink)
        .chain(live.iter_mut().map(|sink| sink as &mut dyn RecordSink))
        .collect();
    let result = build(&scenario).and_then(|mut setup| {
        for warning in &setup.warnings {
            say(format_args!("warning: {warning}"));
        }
        let cancel = &interrupts.stop;
        run_setup_with_sinks(&scenario, &mut setup, &mut sinks, cancel, |t, total| {
            progress.update(t, total);
        })
    });
    progress.finish();
    drop(sinks);
    if let (Some(log), Some(mcap)) = (&log, &outputs.mcap) {
        for warning in log.warnings() {
            say(format_args!(
                "warning: {}: {warning}",
                mcap.target().display()
            ));
        }
    }
    let summary = match (result, &outputs.mcap) {
        (Err(e), Some(mcap)) => return Err(mcap.explain(e)),
        (result, _) => result?,
    };
    let json = serde_json::to_string_pretty(&summary.to_json())
        .map_err(|e| sea_sim::Error::Output(format!("summary JSON: {e}")))?;
    // The summary is printed even when an output fails: the run is done, and it says how.
    let finished = finish_outputs(outputs, &json);
    let printed = print_out(&json);
    finished?;
    printed?;
    Ok(match summary.status.as_str() {
        "completed" => Outcome::Completed,
        "interrupted" => Outcome::Interrupted(interrupts.received().unwrap_or(SIGINT)),
        _ => Outcome::Diverged,
    })
}
