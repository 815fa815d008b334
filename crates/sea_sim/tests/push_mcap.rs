//! A push that ends in a fall, as the MCAP log and the record show it: `/disturbances` has the
//! push's wrench at the samples of its window (zero elsewhere), the record's
//! `disturbance_wrench` the same sum, `/scene` an arrow at the pushed link as long as the push
//! (zero outside it), and the fall is a `foxglove.Log` warning on `/events` at its time plus the
//! metadata record `run`.

use crate::support;

use foxglove::messages::SceneUpdate;
use foxglove::Decode;
use sea_sim::closed_loop::{run_with_sinks, RecordSink, RunRecord};
use sea_sim::foxglove::ARROW_M_PER_N;
use sea_sim::mcap_log::{McapSink, EVENTS_TOPIC};
use sea_sim::scenario::Scenario;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A 20 N s forward push (200 N over 0.1 s at 1 s) on the two-feet iCub: it falls
/// (docs/findings/pushes.md: 11.19 N s is recovered).
fn pushed() -> Scenario {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/robot_rate/push_two_feet.toml");
    let push =
        "[{link = \"root_link\", force = [200.0, 0.0, 0.0], start_s = 1.0, duration_s = 0.1}]";
    let pairs = [
        // The figures of docs/findings/pushes.md are with the fixed estimates.
        ("controller.stiffness_identification", "false"),
        ("disturbances", push),
        ("simulation.record_every", "1"),
        ("simulation.duration_s", "2.0"),
    ]
    .map(|(k, v)| (k.to_string(), v.to_string()));
    Scenario::from_file(&path, &support::welded_push(&pairs)).unwrap()
}

/// A file in the temporary folder, removed when dropped.
struct TempFile(PathBuf);

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

#[test]
fn a_fall_after_a_push_is_in_the_log_with_the_push() {
    let scenario = pushed();
    let file =
        TempFile(std::env::temp_dir().join(format!("push_mcap_{}.mcap", std::process::id())));
    let mut record = RunRecord::default();
    let mut log = McapSink::new(&file.0);
    let mut sinks: Vec<&mut dyn RecordSink> = vec![&mut record, &mut log];
    let summary =
        run_with_sinks(&scenario, &mut sinks, &AtomicBool::new(false), |_, _| {}).unwrap();
    assert_eq!(summary.status, "fell", "{summary:?}");
    let fall = summary.fall.clone().unwrap();

    // The record: the push summed per sample, [200, 0, 0, 0, 0, 0] inside its window.
    let in_window = |t: f64| (1.0 - 1e-9..1.1 - 1e-9).contains(&t);
    for (t, wrench) in record
        .time
        .iter()
        .zip(record.disturbance_wrench.chunks_exact(6))
    {
        let expected = if in_window(*t) { 200.0 } else { 0.0 };
        assert_eq!(wrench, [expected, 0.0, 0.0, 0.0, 0.0, 0.0], "t = {t}");
    }

    let bytes = std::fs::read(&file.0).unwrap();
    let (mut pushed_samples, mut quiet_samples, mut events) = (0, 0, Vec::new());
    let mut arrows_drawn = 0;
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        let t = message.log_time as f64 * 1e-9;
        match message.channel.topic.as_str() {
            "/disturbances" => {
                let body: serde_json::Value = serde_json::from_slice(&message.data).unwrap();
                let entry = &body["disturbances"][0];
                assert_eq!(entry["link"], "root_link");
                assert_eq!(entry["torque"], serde_json::json!([0.0, 0.0, 0.0]));
                if in_window(t) {
                    assert_eq!(entry["active"], true, "t = {t}");
                    assert_eq!(entry["force"], serde_json::json!([200.0, 0.0, 0.0]));
                    pushed_samples += 1;
                } else {
                    assert_eq!(entry["active"], false, "t = {t}");
                    quiet_samples += 1;
                }
            }
            "/scene" => {
                let scene = SceneUpdate::decode(&message.data[..]).expect("protobuf /scene");
                let push = scene
                    .entities
                    .iter()
                    .find(|e| e.id == "push/0/root_link")
                    .expect("the push's arrow");
                let length = push.arrows[0].shaft_length;
                if in_window(t) {
                    assert!((length - 200.0 * ARROW_M_PER_N).abs() < 1e-12, "t = {t}");
                    arrows_drawn += 1;
                } else {
                    assert_eq!(length, 0.0, "t = {t}");
                }
            }
            EVENTS_TOPIC => {
                let schema = message.channel.schema.as_ref().unwrap();
                assert_eq!(schema.name, "foxglove.Log");
                events.push((message.log_time, message.data.to_vec()));
            }
            _ => {}
        }
    }
    // Every recorded sample is logged (it falls during the push, about 0.08 s into it, at
    // 10 ms per sample: the scenario's whole-body period).
    let window = record.time.iter().filter(|&&t| in_window(t)).count();
    assert!(window >= 5, "{window}");
    assert_eq!(pushed_samples, window);
    assert_eq!(arrows_drawn, window);
    assert_eq!(quiet_samples, record.time.len() - window);
    // One fall event, at the fall's time, naming the foot and the constraint.
    assert_eq!(events.len(), 1);
    let (time, data) = &events[0];
    assert_eq!(*time, (fall.at_s * 1e9).round() as u64);
    let text = String::from_utf8_lossy(data);
    assert!(text.contains(&fall.foot), "{text}");
    assert!(text.contains(fall.constraint), "{text}");

    // The metadata record `run`.
    let summary_section = mcap::Summary::read(&bytes).unwrap().expect("summary");
    let run = summary_section
        .metadata_indexes
        .iter()
        .find(|index| index.name == "run")
        .expect("a `run` metadata record");
    let run = mcap::read::metadata(&bytes, run).unwrap().metadata;
    assert_eq!(run["status"], "fell");
    assert_eq!(run["fall_foot"], fall.foot);
    assert_eq!(run["fall_constraint"], fall.constraint);
    assert_eq!(run["fell_at_s"].parse::<f64>().unwrap(), fall.at_s);
    assert_eq!(run["fall_value"].parse::<f64>().unwrap(), fall.value);
    assert_eq!(run["fall_bound"].parse::<f64>().unwrap(), fall.bound);
}
