//! `sea-sim bench`: the dynamics algorithms, the controller tick and the closed loop timed.

use crate::common::{parse_key_value, print_out, say};
use clap::Args;
use sea_dyn::{LoadOptions, Model};
use sea_sim::bench::DynamicsBench;
use std::path::{Path, PathBuf};

/// Most timed batches: a median of 100000 batch means is as good as it gets, and each batch
/// keeps its mean (`--batches 4294967295` asked for 34 GB before the first call).
const MAX_BATCHES: i64 = 100_000;

/// Most calls per batch: ten million calls of the fastest algorithm take seconds per batch.
const MAX_CALLS: i64 = 10_000_000;

/// Options of `sea-sim bench`: `--urdf` or `--scenario` (one of them, required).
#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("robot").required(true).args(["urdf", "scenario"])))]
pub(crate) struct BenchArgs {
    /// Robot URDF: the dynamics, and for the paper's iCub the controller tick and the closed
    /// loop of a two-feet benchmark scenario.
    #[arg(long, value_name = "PATH")]
    urdf: Option<PathBuf>,
    /// Joints to keep, comma separated [default: every joint of the URDF].
    #[arg(
        long,
        value_name = "A,B,C",
        value_delimiter = ',',
        requires = "urdf",
        conflicts_with = "scenario"
    )]
    joints: Option<Vec<String>>,
    /// A scenario file instead of --urdf (e.g. one `sea-sim init` wrote): the dynamics of its
    /// robot, one tick of its controller and its first simulated second.
    #[arg(long, value_name = "FILE", conflicts_with = "urdf")]
    scenario: Option<PathBuf>,
    /// Override a value of the --scenario, e.g. `--set controller.rate_hz=500` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = parse_key_value,
          requires = "scenario", conflicts_with = "urdf")]
    overrides: Vec<(String, String)>,
    /// Timed batches (the median is reported), 1 to 100000.
    #[arg(long, value_name = "N", default_value_t = 31,
          value_parser = clap::value_parser!(u32).range(1..=MAX_BATCHES))]
    batches: u32,
    /// Calls per batch (the controller tick uses CALLS / 20 + 1), 1 to 10000000.
    #[arg(long, value_name = "N", default_value_t = 2000,
          value_parser = clap::value_parser!(u32).range(1..=MAX_CALLS))]
    calls: u32,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

/// `sea-sim bench`: the figures of the --urdf or the --scenario, printed as a table or JSON.
pub(crate) fn run_bench(args: &BenchArgs) -> sea_sim::Result<()> {
    let (source, model, figures) = match (&args.scenario, &args.urdf) {
        (Some(path), _) => bench_scenario(args, path)?,
        (None, Some(urdf)) => bench_urdf(args, urdf)?,
        (None, None) => unreachable!("clap requires --urdf or --scenario"),
    };
    if args.json {
        let mut map = serde_json::Map::new();
        map.insert(source.0.into(), source.1.clone().into());
        map.insert("nv".into(), model.nv().into());
        map.insert("frame".into(), figures.frame.clone().into());
        for (key, value) in &figures.figures {
            map.insert((*key).into(), (*value).into());
        }
        print_out(serde_json::Value::Object(map))?;
    } else {
        let mut table = format!(
            "{} (nv = {}), frame {}:",
            source.1,
            model.nv(),
            figures.frame
        );
        for (key, value) in &figures.figures {
            table += &format!("\n  {key:<32} {value:8.3}");
        }
        print_out(table)?;
    }
    Ok(())
}

/// What was benchmarked (`("urdf" or "scenario", its path)`), its model and the figures.
type Benched = ((&'static str, String), Model, DynamicsBench);

/// The dynamics of `urdf` and, when it is the paper's iCub, the controller tick and the closed
/// loop of the two-feet benchmark scenario.
fn bench_urdf(args: &BenchArgs, urdf: &Path) -> sea_sim::Result<Benched> {
    let options = LoadOptions {
        joints: args.joints.clone(),
        ..Default::default()
    };
    let model = Model::from_urdf_file(urdf, &options)?;
    // Each URDF element a run warns of (`sea_sim::scenario::build::model_warnings`).
    for warning in sea_sim::scenario::build::model_warnings(urdf, &model) {
        say(format_args!("warning: {warning}"));
    }
    let (batches, calls) = (args.batches as usize, args.calls as usize);
    let mut result = sea_sim::bench::bench_dynamics(&model, batches, calls);
    let urdf = urdf.display().to_string();
    if let Some(ticks) = sea_sim::bench::bench_controller(&urdf, batches, calls / 20 + 1) {
        result.figures.extend(ticks);
    }
    // One run is about a thousand ticks and steps: batches / 6 runs keep the default near 1 s.
    if let Some(loops) = sea_sim::bench::bench_closed_loop(&urdf, batches / 6 + 1) {
        result.figures.extend(loops);
    }
    Ok((("urdf", urdf), model, result))
}

/// The dynamics of the robot of the scenario at `path`, one tick of its controller and its
/// first simulated second (`sea_sim::bench::bench_scenario_controller`, `bench_scenario_second`).
fn bench_scenario(args: &BenchArgs, path: &Path) -> sea_sim::Result<Benched> {
    let scenario = sea_sim::scenario::Scenario::from_file(path, &args.overrides)?;
    let mut ticks = sea_sim::bench::TickBench::try_new(&scenario)?;
    let model = ticks.model().clone();
    for warning in ticks.warnings() {
        say(format_args!("warning: {warning}"));
    }
    let (batches, calls) = (args.batches as usize, args.calls as usize);
    let mut result = sea_sim::bench::bench_dynamics(&model, batches, calls);
    let tick = sea_sim::bench::bench_scenario_controller(&mut ticks, batches, calls / 20 + 1)?;
    result.figures.push(("controller_tick_us", tick));
    let second = sea_sim::bench::bench_scenario_second(path, &args.overrides, batches / 6 + 1)?;
    result.figures.push(("scenario_second_ms", second));
    Ok((("scenario", path.display().to_string()), model, result))
}
