//! Touchdowns under unilateral contacts: the two-feet iCub of the push scenario dropped onto a
//! ground 2 mm below its soles lands on both feet; the summary counts the touchdowns with
//! finite figures, the record lists them, `/events` carries each as a `foxglove.Log`, and
//! `/contact_points` and the `contact_points` entity of `/scene` show the soles' points with
//! their forces. A bilateral run has neither channel.

use crate::support;

use foxglove::messages::{Log, SceneUpdate};
use foxglove::Decode;
use sea_sim::closed_loop::{run_with_sinks, ImpactKind, RecordSink, RunRecord, Summary};
use sea_sim::mcap_log::{McapSink, EVENTS_TOPIC};
use sea_sim::scenario::Scenario;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use support::TempFile;

/// The push scenario (no push) with `overrides`.
fn scenario(overrides: &[(&str, &str)]) -> Scenario {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/robot_rate/push_two_feet.toml");
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&path, &pairs).unwrap()
}

/// The iCub dropped 2 mm onto the ground: unilateral contacts, the ground's plane at z = -2
/// mm (its default is where the soles rest, about z = 0), 0.3 s.
fn dropped() -> Scenario {
    scenario(&[
        ("plant.contact_model", "\"unilateral\""),
        ("ground.height_m", "-0.002"),
        ("disturbances", "[]"),
        ("simulation.stop_at_joint_limits", "false"),
        ("simulation.duration_s", "0.3"),
    ])
}

/// Runs `scenario` into a record and an MCAP log at `file`.
fn run(scenario: &Scenario, file: &Path) -> (Summary, RunRecord) {
    let mut record = RunRecord::default();
    let mut log = McapSink::new(file);
    let mut sinks: Vec<&mut dyn RecordSink> = vec![&mut record, &mut log];
    let summary = run_with_sinks(scenario, &mut sinks, &AtomicBool::new(false), |_, _| {});
    (summary.unwrap(), record)
}

#[test]
fn a_dropped_robot_touches_down_on_both_feet_and_the_log_shows_it() {
    let file = TempFile::new("impacts", "dropped");
    let (summary, record) = run(&dropped(), &file.0);
    assert_eq!(summary.status, "completed", "{summary:?}");
    // Both feet touch down once, at the first steps' fall of 2 mm: about 0.2 m/s.
    assert_eq!(summary.touchdowns, 2, "{:?}", record.impacts);
    let jump = summary.touchdown_velocity_jump_m_s.unwrap();
    assert!(jump > 0.05 && jump < 0.3, "{jump}");
    let torque = summary.touchdown_peak_spring_torque_nm.unwrap();
    let velocity = summary.touchdown_peak_motor_velocity_rad_s.unwrap();
    assert!(torque.is_finite() && torque > 0.0, "{torque}");
    assert!(velocity.is_finite() && velocity > 0.0, "{velocity}");
    let touchdowns: Vec<_> = record
        .impacts
        .iter()
        .filter(|i| i.kind == ImpactKind::Touchdown)
        .collect();
    assert_eq!(touchdowns.len(), 2);
    let mut feet: Vec<&str> = touchdowns.iter().map(|i| &*i.name).collect();
    feet.sort();
    assert_eq!(feet, ["l_sole", "r_sole"]);
    for impact in &touchdowns {
        assert!(impact.time_s > 0.0 && impact.time_s < 0.1, "{impact}");
        assert!(impact.speed_before > 0.1, "{impact}");
        assert!(impact.speed_after.abs() < impact.speed_before, "{impact}");
        assert!((impact.window_after_s - 0.05).abs() < 1e-9, "{impact}");
        assert!(impact.peak_spring_torque_after_nm > impact.peak_spring_torque_before_nm);
    }

    let bytes = std::fs::read(&file.0).unwrap();
    let (mut events, mut point_messages, mut lifted, mut drawn) = (Vec::new(), 0, Vec::new(), 0);
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        match message.channel.topic.as_str() {
            EVENTS_TOPIC => events.push(Log::decode(&message.data[..]).unwrap()),
            "/contact_points" => {
                let body: serde_json::Value = serde_json::from_slice(&message.data).unwrap();
                let points = body["points"].as_array().unwrap();
                assert_eq!(points.len(), 8, "four corners per sole");
                assert_eq!(points[0]["contact"], "l_sole");
                assert_eq!(points[7]["contact"], "r_sole");
                assert_eq!(points[7]["index"], 3);
                point_messages += 1;
                if points.iter().all(|p| p["active"] == false) {
                    lifted.push(message.log_time as f64 * 1e-9);
                }
            }
            "/scene" => {
                let scene = SceneUpdate::decode(&message.data[..]).unwrap();
                let entity = scene.entities.iter().find(|e| e.id == "contact_points");
                let entity = entity.expect("the contact points in /scene");
                assert_eq!((entity.spheres.len(), entity.arrows.len()), (8, 8));
                drawn += 1;
            }
            _ => {}
        }
    }
    assert_eq!(point_messages, record.time.len());
    assert_eq!(drawn, record.time.len());
    // The samples before the first touchdown are in the air (a 2 mm fall takes 20 ms): no
    // point carries a force; every later one has some.
    let first = touchdowns
        .iter()
        .map(|i| i.time_s)
        .fold(f64::INFINITY, f64::min);
    assert!(!lifted.is_empty());
    assert!(lifted.iter().all(|&t| t < first), "{lifted:?} vs {first}");
    let touchdown_logs: Vec<_> = events
        .iter()
        .filter(|log| log.name == "sea_sim.touchdown")
        .collect();
    assert_eq!(touchdown_logs.len(), 2, "{events:?}");
    for (log, impact) in touchdown_logs.iter().zip(&touchdowns) {
        assert!(log.message.contains(&impact.to_string()), "{}", log.message);
        let stamp = log.timestamp.unwrap();
        let time = f64::from(stamp.sec()) + 1e-9 * f64::from(stamp.nsec());
        assert!((time - impact.time_s).abs() < 1e-9);
    }
}

#[test]
fn a_bilateral_run_has_no_contact_points_contact_check_or_events() {
    let file = TempFile::new("impacts", "bilateral");
    let bilateral = scenario(&[
        ("plant.contact_model", "\"bilateral\""),
        ("disturbances", "[]"),
        ("simulation.duration_s", "0.05"),
    ]);
    let (summary, record) = run(&bilateral, &file.0);
    assert_eq!(summary.status, "completed");
    assert_eq!(summary.touchdowns, 0);
    assert_eq!(summary.touchdown_velocity_jump_m_s, None);
    assert!(record.impacts.is_empty());
    let bytes = std::fs::read(&file.0).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    let topics: Vec<&str> = summary
        .channels
        .values()
        .map(|c| c.topic.as_str())
        .collect();
    assert!(!topics.contains(&"/contact_points"), "{topics:?}");
    assert!(!topics.contains(&"/contact_check"), "{topics:?}");
    assert!(!topics.contains(&EVENTS_TOPIC), "{topics:?}");
}
