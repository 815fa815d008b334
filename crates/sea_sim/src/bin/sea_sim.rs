//! `sea-sim`: runs sea-momentum benchmarks (and, later, scenarios) from the command line.
//!
//! ```text
//! sea-sim bench --urdf PATH [--joints a,b,c] [--batches N] [--calls N] [--json]
//! sea-sim run SCENARIO.toml [--set key=value ...] [--mcap FILE] [--summary FILE] [--quiet]
//! ```
//!
//! `run` prints progress on stderr, writes the MCAP log incrementally (finished even when the run
//! diverges) and the summary JSON; the exit status is 0 when the run completed, 3 when it
//! diverged, 1 on an error.

use sea_dyn::{LoadOptions, Model};
use std::process::ExitCode;

const USAGE: &str =
    "usage: sea-sim bench --urdf PATH [--joints a,b,c] [--batches N] [--calls N] [--json]";

struct BenchArgs {
    urdf: String,
    joints: Option<Vec<String>>,
    batches: usize,
    calls: usize,
    json: bool,
}

fn parse_bench(args: &[String]) -> Result<BenchArgs, String> {
    let mut out = BenchArgs {
        urdf: String::new(),
        joints: None,
        batches: 31,
        calls: 2000,
        json: false,
    };
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| format!("{name} needs a value"))
        };
        match arg.as_str() {
            "--urdf" => out.urdf = value("--urdf")?,
            "--joints" => {
                out.joints = Some(
                    value("--joints")?
                        .split(',')
                        .map(|s| s.trim().to_string())
                        .collect(),
                )
            }
            "--batches" => {
                out.batches = value("--batches")?
                    .parse()
                    .map_err(|e| format!("--batches: {e}"))?
            }
            "--calls" => {
                out.calls = value("--calls")?
                    .parse()
                    .map_err(|e| format!("--calls: {e}"))?
            }
            "--json" => out.json = true,
            other => return Err(format!("unknown argument '{other}'")),
        }
    }
    if out.urdf.is_empty() {
        return Err("--urdf is required".into());
    }
    if out.batches == 0 || out.calls == 0 {
        return Err("--batches and --calls must be positive".into());
    }
    Ok(out)
}

fn run_bench(args: &[String]) -> Result<(), String> {
    let args = parse_bench(args)?;
    let options = LoadOptions {
        joints: args.joints.clone(),
        ..Default::default()
    };
    let model = Model::from_urdf_file(&args.urdf, &options).map_err(|e| e.to_string())?;
    let mut result = sea_sim::bench::bench_dynamics(&model, args.batches, args.calls);
    if let Some(ticks) =
        sea_sim::bench::bench_controller(&args.urdf, args.batches, args.calls / 20 + 1)
    {
        result.figures.extend(ticks);
    }
    if args.json {
        let mut map = serde_json::Map::new();
        map.insert("urdf".into(), args.urdf.clone().into());
        map.insert("nv".into(), model.nv().into());
        map.insert("frame".into(), result.frame.clone().into());
        for (key, value) in &result.figures {
            map.insert((*key).into(), (*value).into());
        }
        println!("{}", serde_json::Value::Object(map));
    } else {
        println!(
            "{} (nv = {}), frame {}:",
            args.urdf,
            model.nv(),
            result.frame
        );
        for (key, value) in &result.figures {
            println!("  {key:<32} {value:8.3}");
        }
    }
    Ok(())
}

/// Exit status of a run that diverged (distinct from errors).
const DIVERGED: u8 = 3;

fn run_scenario(args: &[String]) -> Result<bool, String> {
    let mut path = None;
    let mut overrides = Vec::new();
    let (mut mcap, mut summary_path, mut quiet) = (None, None, false);
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| format!("{name} needs a value"))
        };
        match arg.as_str() {
            "--set" => {
                let pair = value("--set")?;
                let (key, v) = pair
                    .split_once('=')
                    .ok_or_else(|| format!("--set expects key=value, got '{pair}'"))?;
                overrides.push((key.trim().to_string(), v.trim().to_string()));
            }
            "--mcap" => mcap = Some(std::path::PathBuf::from(value("--mcap")?)),
            "--summary" => summary_path = Some(std::path::PathBuf::from(value("--summary")?)),
            "--quiet" => quiet = true,
            other if other.starts_with("--") => return Err(format!("unknown argument '{other}'")),
            other => path = Some(std::path::PathBuf::from(other)),
        }
    }
    let path = path.ok_or("a scenario file is required")?;
    let scenario =
        sea_sim::scenario::Scenario::from_file(&path, &overrides).map_err(|e| e.to_string())?;
    if !quiet {
        eprintln!(
            "sea-sim: running {} ({} s simulated)",
            path.display(),
            scenario.simulation.duration_s
        );
    }
    let (_, summary) = sea_sim::closed_loop::run(&scenario, mcap.as_deref(), |t, total| {
        if !quiet {
            eprintln!("  t = {t:6.2} / {total:.2} s");
        }
    })
    .map_err(|e| e.to_string())?;
    let json = serde_json::to_string_pretty(&summary.to_json()).map_err(|e| e.to_string())?;
    if let Some(p) = summary_path {
        std::fs::write(&p, &json).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    println!("{json}");
    Ok(summary.status == "completed")
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("bench") => run_bench(&args[1..]),
        Some("run") => match run_scenario(&args[1..]) {
            Ok(true) => Ok(()),
            Ok(false) => return ExitCode::from(DIVERGED),
            Err(e) => Err(e),
        },
        Some("-h" | "--help") => {
            println!("{USAGE}");
            Ok(())
        }
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("sea-sim: {message}");
            ExitCode::FAILURE
        }
    }
}
