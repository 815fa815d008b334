//! `sea-sim`: runs sea-momentum benchmarks (and, later, scenarios) from the command line.
//!
//! ```text
//! sea-sim bench --urdf PATH [--joints a,b,c] [--batches N] [--calls N] [--json]
//! ```

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
    let result = sea_ctrl::bench::bench_dynamics(&model, args.batches, args.calls);
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

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("bench") => run_bench(&args[1..]),
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
