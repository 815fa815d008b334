//! `sea-sim`: runs scenarios and benchmarks of sea-momentum from the command line.
//!
//! `sea-sim --help` lists the subcommands, `sea-sim SUBCOMMAND --help` their options and
//! defaults.
//!
//! Exit status: 0 completed, 3 diverged, 1 error (including a bad command line), and after
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
//! closed pipe only loses the text.

use clap::{Args, Parser, Subcommand};
use sea_dyn::{LoadOptions, Model};
use sea_sim::analysis::margin::MarginOptions;
use sea_sim::analysis::push::PushOptions;
use sea_sim::closed_loop::{run_with_sinks, RecordSink};
use sea_sim::mcap_log::McapSink;
use sea_sim::output::{check_distinct, OutputFile};
use sea_sim::scenario::Scenario;
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use std::fmt::Display;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

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
    /// Exit status: 0 completed, 3 diverged, 1 error, 130/143/129 stopped by
    /// SIGINT/SIGTERM/SIGHUP (log finished, summary status "interrupted").
    Run(RunArgs),
    /// Benchmark the dynamics algorithms and the controller tick on a URDF.
    Bench(BenchArgs),
    /// Sweep a scenario over a grid of values of numeric keys, runs in parallel; writes a CSV.
    ///
    /// Exit status: 0 done (whatever the runs' outcomes), 1 error, 130/143/129 stopped by a
    /// signal (the rows done are written).
    Sweep(SweepArgs),
    /// Find the values of one numeric scenario key where the closed loop's stability changes
    /// (grid scan, then bisection); prints a JSON report.
    Margin(MarginArgs),
    /// Write a two-feet balancing scenario for a new robot from its URDF and two contacts
    /// (SEA on every joint, a standing posture, the foot rectangle and gains, all scaled to
    /// the robot); `sea-sim run` balances it with no edit.
    Init(InitArgs),
    /// Find, per direction, the largest impulse of a short push on a link that the closed loop
    /// recovers from (bisection on full runs, directions in parallel), with the stance's
    /// capture-point bound; prints a JSON report.
    Push(PushArgs),
    /// Print the JSON Schema of scenario files (derived from the types that read them; the
    /// shipped copy is schemas/scenario.schema.json).
    Schema(SchemaArgs),
}

/// Options of `sea-sim schema`.
#[derive(Args, Debug)]
struct SchemaArgs {
    /// Print the reference page of every key (Markdown; the shipped copy is
    /// docs/reference/scenario_keys.md) instead of the schema.
    #[arg(long)]
    markdown: bool,
}

/// Options of `sea-sim init`.
#[derive(Args, Debug)]
struct InitArgs {
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
    #[arg(long = "package-dir", value_name = "DIR")]
    package_dirs: Vec<PathBuf>,
}

/// Options of `sea-sim run`.
#[derive(Args, Debug)]
struct RunArgs {
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
    #[arg(long = "package-dir", value_name = "DIR")]
    package_dirs: Vec<PathBuf>,
}

/// Options of `sea-sim bench`.
#[derive(Args, Debug)]
struct BenchArgs {
    /// Robot URDF.
    #[arg(long, value_name = "PATH")]
    urdf: PathBuf,
    /// Joints to keep, comma separated [default: every joint of the URDF].
    #[arg(long, value_name = "A,B,C", value_delimiter = ',')]
    joints: Option<Vec<String>>,
    /// Timed batches (the median is reported).
    #[arg(long, value_name = "N", default_value_t = 31,
          value_parser = clap::value_parser!(u32).range(1..))]
    batches: u32,
    /// Calls per batch (the controller tick uses CALLS / 20 + 1).
    #[arg(long, value_name = "N", default_value_t = 2000,
          value_parser = clap::value_parser!(u32).range(1..))]
    calls: u32,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

/// Options of `sea-sim sweep`.
#[derive(Args, Debug)]
struct SweepArgs {
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
    /// Runs in parallel [default: every core].
    #[arg(long, short = 'j', value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..))]
    jobs: Option<u32>,
    /// Write the results to FILE (CSV: the grid values, then status, message and every summary
    /// field; one row per run in grid order).
    #[arg(long, value_name = "FILE.csv")]
    out: PathBuf,
    /// No progress on stderr.
    #[arg(long, short)]
    quiet: bool,
}

/// Options of `sea-sim margin`.
#[derive(Args, Debug)]
struct MarginArgs {
    /// Scenario file (TOML).
    scenario: PathBuf,
    /// The numeric scenario key to vary, e.g. `actuators.damping`.
    #[arg(long, value_name = "KEY")]
    param: String,
    /// The range searched, `LOWER:UPPER`.
    #[arg(long, value_name = "LOWER:UPPER", value_parser = parse_range)]
    range: (f64, f64),
    /// How stability is judged: `eigen` (growth rate of the linearisation) or `simulate`
    /// (the run completes).
    #[arg(long, value_name = "METHOD", default_value = "eigen",
          value_parser = ["eigen", "simulate"])]
    method: String,
    /// Points of the initial scan, ends included.
    #[arg(long, value_name = "N", default_value_t = MarginOptions::default().grid_points as u32,
          value_parser = clap::value_parser!(u32).range(2..))]
    points: u32,
    /// Space the scan logarithmically (both ends positive).
    #[arg(long)]
    log: bool,
    /// Bisection stops below this fraction of `UPPER - LOWER`.
    #[arg(long, value_name = "F", default_value_t = MarginOptions::default().relative_tolerance)]
    tolerance: f64,
    /// Override a scenario value, e.g. `--set simulation.duration_s=2` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
    /// Also write the JSON report to FILE.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Print the JSON report on stdout instead of a table.
    #[arg(long)]
    json: bool,
}

/// Options of `sea-sim push`.
#[derive(Args, Debug)]
struct PushArgs {
    /// Scenario file (TOML), e.g. scenarios/robot_rate/push_two_feet.toml; its own
    /// `[[disturbances]]` are replaced by the push.
    scenario: PathBuf,
    /// Directions, comma-separated: forward, backward, left, right (the first contact's sole
    /// axes).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "forward,backward,left,right"
    )]
    directions: Vec<String>,
    /// The pushed link.
    #[arg(long, default_value_t = PushOptions::default().link)]
    link: String,
    /// Start of the push [s].
    #[arg(long, default_value_t = PushOptions::default().start_s)]
    start: f64,
    /// Length of the push [s].
    #[arg(long, default_value_t = PushOptions::default().duration_s)]
    duration: f64,
    /// Bisection resolution [N s].
    #[arg(long, default_value_t = PushOptions::default().tolerance_n_s)]
    tolerance: f64,
    /// Override a scenario value, e.g. `--set controller.kind=rigid` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value)]
    overrides: Vec<(String, String)>,
}

/// `LOWER:UPPER` of `--range`.
fn parse_range(text: &str) -> Result<(f64, f64), String> {
    let (lower, upper) = text
        .split_once(':')
        .ok_or_else(|| format!("expected LOWER:UPPER, got '{text}'"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .map_err(|e| format!("'{s}' in '{text}': {e}"))
    };
    Ok((number(lower)?, number(upper)?))
}

/// `KEY=VALUE` of `--set`.
fn parse_key_value(text: &str) -> Result<(String, String), String> {
    let (key, value) = text
        .split_once('=')
        .ok_or_else(|| format!("expected KEY=VALUE, got '{text}'"))?;
    if key.trim().is_empty() {
        return Err(format!("empty key in '{text}'"));
    }
    Ok((key.trim().to_string(), value.trim().to_string()))
}

/// Exit status of a run that diverged (distinct from errors).
const EXIT_DIVERGED: u8 = 3;
/// Exit status of an error.
const EXIT_ERROR: u8 = 1;

/// Writes a line on stderr; a closed or full stderr loses the line, never the run.
fn say(message: impl Display) {
    let _ = writeln!(std::io::stderr().lock(), "{message}");
}

/// Writes text on stdout; a closed stdout (`| head -c1`) loses the text, never the run.
fn print_out(text: impl Display) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{text}").and_then(|()| out.flush());
}

// ---- Signals ----

/// The signals that stop a run cleanly.
const STOP_SIGNALS: [i32; 3] = [SIGINT, SIGTERM, SIGHUP];

/// Records the first stop signal: `stop` is the closed loop's cancellation flag, `signal` the
/// signal number for the exit status.
struct Interrupts {
    stop: Arc<AtomicBool>,
    signal: Arc<AtomicUsize>,
}

impl Interrupts {
    /// Installs the handlers: the first signal sets the flags, a second exits at once with
    /// 128 + signal (partial files stay; earlier targets are untouched). A signal ignored when
    /// the process started (`nohup`, a background job of a script) stays ignored.
    fn install() -> std::io::Result<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let signal = Arc::new(AtomicUsize::new(0));
        for sig in STOP_SIGNALS {
            if ignored_at_start(sig) {
                continue;
            }
            // Registered first, so it sees the flag as the previous signal left it.
            signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, stop.clone())?;
            signal_hook::flag::register_usize(sig, signal.clone(), sig as usize)?;
            signal_hook::flag::register(sig, stop.clone())?;
        }
        Ok(Self { stop, signal })
    }

    /// The signal that stopped the run, if any.
    fn received(&self) -> Option<i32> {
        match self.signal.load(Ordering::SeqCst) {
            0 => None,
            sig => Some(sig as i32),
        }
    }
}

/// Whether `sig` was ignored when the process started (read from the `SigIgn` mask of
/// `/proc/self/status`, which needs no unsafe code; elsewhere than Linux: never).
fn ignored_at_start(sig: i32) -> bool {
    let Ok(status) = std::fs::read_to_string("/proc/self/status") else {
        return false;
    };
    status
        .lines()
        .find_map(|line| line.strip_prefix("SigIgn:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| (mask >> (sig - 1)) & 1 == 1)
}

/// The conventional name of a stop signal.
fn signal_name(sig: i32) -> &'static str {
    match sig {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    }
}

// ---- Progress ----

/// Progress of a run on stderr: a bar on a terminal, periodic lines otherwise, or nothing.
enum Progress {
    Bar(indicatif::ProgressBar),
    Lines { last: Option<Instant> },
    Quiet,
}

/// Wall time between two plain progress lines.
const LINE_INTERVAL: Duration = Duration::from_secs(2);

impl Progress {
    /// The right kind for this stderr; `duration_s` is the simulated time to reach.
    fn new(quiet: bool, duration_s: f64) -> Self {
        if quiet {
            return Progress::Quiet;
        }
        if !std::io::stderr().is_terminal() {
            return Progress::Lines { last: None };
        }
        let bar = indicatif::ProgressBar::with_draw_target(
            Some((duration_s * 1000.0).max(1.0) as u64),
            indicatif::ProgressDrawTarget::stderr(),
        );
        let style = indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {msg} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
        Progress::Bar(bar.with_style(style))
    }

    /// Simulated time `t_s` of `total_s` reached.
    fn update(&mut self, t_s: f64, total_s: f64) {
        match self {
            Progress::Bar(bar) => {
                bar.set_position((t_s * 1000.0) as u64);
                bar.set_message(format!("t = {t_s:.2} / {total_s:.2} s"));
            }
            Progress::Lines { last } => {
                if last.is_none_or(|l| l.elapsed() >= LINE_INTERVAL) {
                    *last = Some(Instant::now());
                    say(format_args!("sea-sim: t = {t_s:6.2} / {total_s:.2} s"));
                }
            }
            Progress::Quiet => {}
        }
    }

    /// Removes the bar.
    fn finish(&self) {
        if let Progress::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}

// ---- run ----

/// How a run ended.
enum Outcome {
    Completed,
    Diverged,
    Interrupted(i32),
}

/// The run's outputs, opened (checked, locked, partial) before the simulation starts.
struct Outputs {
    mcap: Option<OutputFile>,
    summary: Option<OutputFile>,
}

/// Checks that no output is an input or another output, then opens them.
fn open_outputs(args: &RunArgs, scenario: &Scenario) -> sea_sim::Result<Outputs> {
    let urdf = scenario.resolve(&scenario.robot.urdf);
    let inputs = [
        ("the scenario file", args.scenario.as_path()),
        ("the URDF", urdf.as_path()),
    ];
    let outputs: Vec<(&str, &Path)> = [("--mcap", &args.mcap), ("--summary", &args.summary)]
        .into_iter()
        .filter_map(|(role, path)| path.as_deref().map(|p| (role, p)))
        .collect();
    check_distinct(&inputs, &outputs)?;
    Ok(Outputs {
        mcap: args.mcap.as_deref().map(OutputFile::create).transpose()?,
        summary: args
            .summary
            .as_deref()
            .map(OutputFile::create)
            .transpose()?,
    })
}

/// Writes the summary, then replaces both targets.
fn finish_outputs(outputs: Outputs, json: &str) -> sea_sim::Result<()> {
    if let Some(mut summary) = outputs.summary {
        summary.write_all(json.as_bytes())?;
        summary.write_all(b"\n")?;
        if let Some(mcap) = outputs.mcap {
            mcap.commit()?;
        }
        summary.commit()
    } else {
        outputs.mcap.map_or(Ok(()), OutputFile::commit)
    }
}

/// Starts the live server of `--live` and says where it listens (also under `--quiet`: the
/// address is what the user needs to connect).
fn start_live(port: u16) -> sea_sim::Result<sea_sim::foxglove::live::LiveSink> {
    let sink = sea_sim::foxglove::live::LiveSink::start(port)?;
    say(format_args!(
        "sea-sim: live view on ws://{}:{} (Foxglove: Open connection > Foxglove WebSocket)",
        sea_sim::foxglove::live::LIVE_HOST,
        sink.port()
    ));
    Ok(sink)
}

/// `sea-sim run`.
fn run_scenario(args: &RunArgs, interrupts: &Interrupts) -> sea_sim::Result<Outcome> {
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
    let result = run_with_sinks(&scenario, &mut sinks, &interrupts.stop, |t, total| {
        progress.update(t, total);
    });
    progress.finish();
    let summary = match (result, &outputs.mcap) {
        (Err(e), Some(mcap)) => return Err(mcap.explain(e)),
        (result, _) => result?,
    };
    let json = serde_json::to_string_pretty(&summary.to_json())
        .map_err(|e| sea_sim::Error::Log(format!("summary JSON: {e}")))?;
    finish_outputs(outputs, &json)?;
    print_out(&json);
    Ok(match summary.status.as_str() {
        "completed" => Outcome::Completed,
        "interrupted" => Outcome::Interrupted(interrupts.received().unwrap_or(SIGINT)),
        _ => Outcome::Diverged,
    })
}

// ---- bench ----

/// `sea-sim bench`.
/// `sea-sim init`: writes the scenario, says what it found on stderr.
fn run_init(args: &InitArgs) -> sea_sim::Result<()> {
    use sea_sim::init::{init, parse_foot, InitOptions};
    let started = Instant::now();
    let foot = args.foot.as_deref().map(parse_foot).transpose()?;
    let stem = Path::new(&args.urdf)
        .file_stem()
        .map_or("robot".into(), |s| s.to_string_lossy().to_string());
    let options = InitOptions {
        urdf: args.urdf.clone(),
        contacts: [args.contacts[0].clone(), args.contacts[1].clone()],
        foot,
        package_dirs: args.package_dirs.clone(),
        out: args
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("{stem}_two_feet.toml"))),
        name: None,
    };
    let report = init(&options)?;
    let (name, mass, joints) = &report.robot;
    for warning in &report.warnings {
        say(format_args!("sea-sim: warning: {warning}"));
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
    Ok(())
}

fn run_bench(args: &BenchArgs) -> sea_sim::Result<()> {
    let options = LoadOptions {
        joints: args.joints.clone(),
        ..Default::default()
    };
    let model = Model::from_urdf_file(&args.urdf, &options)?;
    let (batches, calls) = (args.batches as usize, args.calls as usize);
    let mut result = sea_sim::bench::bench_dynamics(&model, batches, calls);
    let urdf = args.urdf.display().to_string();
    if let Some(ticks) = sea_sim::bench::bench_controller(&urdf, batches, calls / 20 + 1) {
        result.figures.extend(ticks);
    }
    // One run is about a thousand ticks and steps: batches / 6 runs keep the default near 1 s.
    if let Some(loops) = sea_sim::bench::bench_closed_loop(&urdf, batches / 6 + 1) {
        result.figures.extend(loops);
    }
    if args.json {
        let mut map = serde_json::Map::new();
        map.insert("urdf".into(), urdf.into());
        map.insert("nv".into(), model.nv().into());
        map.insert("frame".into(), result.frame.clone().into());
        for (key, value) in &result.figures {
            map.insert((*key).into(), (*value).into());
        }
        print_out(serde_json::Value::Object(map));
    } else {
        let mut table = format!("{urdf} (nv = {}), frame {}:", model.nv(), result.frame);
        for (key, value) in &result.figures {
            table += &format!("\n  {key:<32} {value:8.3}");
        }
        print_out(table);
    }
    Ok(())
}

// ---- sweep ----

/// One progress line of a sweep: runs done, the point and how its run ended.
fn sweep_progress_line(keys: &[String], progress: &sea_sim::sweep::SweepProgress<'_>) -> String {
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
fn run_sweep_command(args: &SweepArgs, interrupts: &Interrupts) -> sea_sim::Result<Outcome> {
    use sea_sim::sweep::{run_sweep, write_csv, Grid};
    let grid = Grid::parse(&args.grid)?;
    let scenario = Scenario::from_file(&args.scenario, &args.overrides)?;
    let urdf = scenario.resolve(&scenario.robot.urdf);
    check_distinct(
        &[
            ("the scenario file", args.scenario.as_path()),
            ("the URDF", urdf.as_path()),
        ],
        &[("--out", args.out.as_path())],
    )?;
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
    out.write_all(&csv)?;
    out.commit()?;
    let completed = rows.iter().filter(|r| r.status == "completed").count();
    if !quiet {
        say(format_args!(
            "sea-sim: {} of {} runs done, {completed} completed; wrote {}",
            rows.len(),
            grid.len(),
            args.out.display()
        ));
    }
    Ok(match interrupts.received() {
        Some(sig) => Outcome::Interrupted(sig),
        None => Outcome::Completed,
    })
}

// ---- margin ----

/// `sea-sim margin`: the report as a table or (`--json`) JSON on stdout; JSON in `--out`.
fn run_margin(args: &MarginArgs) -> sea_sim::Result<()> {
    use sea_sim::analysis::margin::{stability_margin_report, MarginMethod};
    let out = match &args.out {
        Some(path) => {
            check_distinct(
                &[("the scenario file", args.scenario.as_path())],
                &[("--out", path)],
            )?;
            Some(OutputFile::create(path)?)
        }
        None => None,
    };
    let options = MarginOptions {
        method: MarginMethod::parse(&args.method)?,
        grid_points: args.points as usize,
        log_grid: args.log,
        relative_tolerance: args.tolerance,
        ..Default::default()
    };
    let (lower, upper) = args.range;
    let report = stability_margin_report(
        &args.scenario,
        &args.overrides,
        &args.param,
        lower,
        upper,
        &options,
    )?;
    let samples: Vec<serde_json::Value> = report
        .samples
        .iter()
        .map(|s| serde_json::json!({"value": s.value, "stable": s.stable, "growth_rate": s.growth_rate}))
        .collect();
    let json = serde_json::json!({
        "parameter": report.parameter,
        "method": report.method.name(),
        "range": [lower, upper],
        "boundaries": report.boundaries,
        "integer": report.integer,
        "conclusion": report.conclusion().name(),
        "own_value": report.own_value,
        "own_value_stable": report.own_value_stable(),
        "stable_island": report.island().map(|ends| ends.map(|end| end.value())),
        "evaluations": report.evaluations(),
        "samples": samples,
    });
    let text = serde_json::to_string_pretty(&json)
        .map_err(|e| sea_sim::Error::Log(format!("margin JSON: {e}")))?;
    if let Some(mut out) = out {
        out.write_all(text.as_bytes())?;
        out.write_all(b"\n")?;
        out.commit()?;
    }
    print_out(if args.json {
        text
    } else {
        margin_table(&report)
    });
    Ok(())
}

/// What the margin scan found, in words: the boundaries or the range's one verdict, then the
/// scenario's own value and its stable island.
fn margin_verdict(report: &sea_sim::analysis::margin::MarginReport) -> String {
    use sea_sim::analysis::margin::{IslandEnd, MarginConclusion};
    let [lower, upper] = report.range;
    let mut text = match report.conclusion() {
        MarginConclusion::Boundaries if report.integer => {
            let between: Vec<String> = report
                .boundaries
                .iter()
                .map(|b| format!("between {} and {}", b - 0.5, b + 0.5))
                .collect();
            format!("stability changes {}", between.join(", "))
        }
        MarginConclusion::Boundaries => {
            let boundaries: Vec<String> =
                report.boundaries.iter().map(|b| format!("{b}")).collect();
            format!("stability changes at [{}]", boundaries.join(", "))
        }
        MarginConclusion::StableOverRange => format!("stable over [{lower}, {upper}]"),
        MarginConclusion::UnstableOverRange => {
            format!("unstable over the whole scanned range [{lower}, {upper}]")
        }
    };
    let end = |end: IslandEnd| match end {
        IslandEnd::Boundary(value) => format!("{value}"),
        IslandEnd::RangeEnd(value) => format!("{value} (range end)"),
    };
    text += &match (report.own_value, report.own_value_stable(), report.island()) {
        (_, _, Some([low, high])) => format!(
            "; the scenario's own value {} lies in the stable island [{}, {}]",
            report.own_value.unwrap_or(f64::NAN),
            end(low),
            end(high)
        ),
        (Some(own), Some(false), _) => format!("; the scenario's own value {own} is unstable"),
        (Some(own), _, _) => format!("; the scenario's own value {own} is outside the range"),
        (None, _, _) => "; the scenario's own value is not a readable number".to_string(),
    };
    text
}

/// The margin report for a reader: the verdict, then every evaluation in value order.
fn margin_table(report: &sea_sim::analysis::margin::MarginReport) -> String {
    let mut table = format!(
        "{} ({} method, {} evaluations): {}",
        report.parameter,
        report.method.name(),
        report.evaluations(),
        margin_verdict(report)
    );
    let mut samples: Vec<_> = report.samples.iter().collect();
    samples.sort_by(|a, b| a.value.total_cmp(&b.value));
    for sample in samples {
        let growth = sample
            .growth_rate
            .map_or(String::new(), |g| format!("  growth {g:10.4} 1/s"));
        let verdict = if sample.stable { "stable" } else { "unstable" };
        table += &format!("\n  {:14.6}  {verdict:<8}{growth}", sample.value);
    }
    table
}

// ---- push ----

/// `sea-sim push`: the push table as JSON on stdout.
fn run_push(args: &PushArgs) -> sea_sim::Result<()> {
    use sea_sim::analysis::push::{push_table, PushDirection};
    let directions = args
        .directions
        .iter()
        .map(|name| PushDirection::parse(name))
        .collect::<sea_sim::Result<Vec<_>>>()?;
    let options = PushOptions {
        link: args.link.clone(),
        start_s: args.start,
        duration_s: args.duration,
        tolerance_n_s: args.tolerance,
    };
    let table = push_table(&args.scenario, &args.overrides, &options, &directions)?;
    let rows: Vec<serde_json::Value> = table
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
            })
        })
        .collect();
    let json = serde_json::json!({
        "scenario": args.scenario,
        "overrides": args.overrides.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>(),
        "link": options.link,
        "start_s": options.start_s,
        "duration_s": options.duration_s,
        "directions": rows,
    });
    let text = serde_json::to_string_pretty(&json)
        .map_err(|e| sea_sim::Error::Log(format!("push JSON: {e}")))?;
    print_out(text);
    Ok(())
}

/// `sea-sim schema`: the scenario file's JSON Schema, or its reference page, on stdout.
fn print_schema(args: &SchemaArgs) {
    if args.markdown {
        let schema = sea_sim::scenario::schema::json_schema();
        print!("{}", sea_sim::scenario::reference::markdown(&schema));
    } else {
        print!("{}", sea_sim::scenario::schema::json_schema_text());
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version are not errors; everything else is (exit 1).
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { EXIT_ERROR } else { 0 });
        }
    };
    let outcome = match &cli.command {
        Command::Bench(args) => run_bench(args).map(|()| Outcome::Completed),
        Command::Margin(args) => run_margin(args).map(|()| Outcome::Completed),
        Command::Init(args) => run_init(args).map(|()| Outcome::Completed),
        Command::Push(args) => run_push(args).map(|()| Outcome::Completed),
        Command::Schema(args) => {
            print_schema(args);
            Ok(Outcome::Completed)
        }
        Command::Sweep(args) => match Interrupts::install() {
            Ok(interrupts) => run_sweep_command(args, &interrupts),
            Err(e) => Err(sea_sim::Error::Log(format!("cannot handle signals: {e}"))),
        },
        Command::Run(args) => match Interrupts::install() {
            Ok(interrupts) => run_scenario(args, &interrupts),
            Err(e) => Err(sea_sim::Error::Log(format!("cannot handle signals: {e}"))),
        },
    };
    match outcome {
        Ok(Outcome::Completed) => ExitCode::SUCCESS,
        Ok(Outcome::Diverged) => ExitCode::from(EXIT_DIVERGED),
        Ok(Outcome::Interrupted(sig)) => {
            say(format_args!(
                "sea-sim: stopped by {}; log and summary finished",
                signal_name(sig)
            ));
            ExitCode::from(128 + sig as u8)
        }
        Err(e) => {
            say(format_args!("sea-sim: {e}"));
            ExitCode::from(EXIT_ERROR)
        }
    }
}
