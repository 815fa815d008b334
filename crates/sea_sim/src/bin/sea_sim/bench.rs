//! `sea-sim bench`: the dynamics algorithms, the controller tick and the closed loop timed.

use crate::common::print_out;
use clap::Args;
use sea_dyn::{LoadOptions, Model};
use std::path::PathBuf;

/// Most timed batches: a median of 100000 batch means is as good as it gets, and each batch
/// keeps its mean (`--batches 4294967295` asked for 34 GB before the first call).
const MAX_BATCHES: i64 = 100_000;

/// Most calls per batch: ten million calls of the fastest algorithm take seconds per batch.
const MAX_CALLS: i64 = 10_000_000;

/// Options of `sea-sim bench`.
#[derive(Args, Debug)]
pub(crate) struct BenchArgs {
    /// Robot URDF.
    #[arg(long, value_name = "PATH")]
    urdf: PathBuf,
    /// Joints to keep, comma separated [default: every joint of the URDF].
    #[arg(long, value_name = "A,B,C", value_delimiter = ',')]
    joints: Option<Vec<String>>,
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

pub(crate) fn run_bench(args: &BenchArgs) -> sea_sim::Result<()> {
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
        print_out(serde_json::Value::Object(map))?;
    } else {
        let mut table = format!("{urdf} (nv = {}), frame {}:", model.nv(), result.frame);
        for (key, value) in &result.figures {
            table += &format!("\n  {key:<32} {value:8.3}");
        }
        print_out(table)?;
    }
    Ok(())
}
