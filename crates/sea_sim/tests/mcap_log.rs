//! The MCAP logger writes a file Foxglove and the `mcap` reader accept, also when dropped
//! without `finish()`; `/tf`, `/robot` and `/scene` decode as the SDK's protobuf messages, the
//! robot's scene entities sit on `/tf` frames and the URDF is attached.

use foxglove::messages::{FrameTransforms, SceneUpdate};
use foxglove::Decode;
use sea_ctrl::qp::QpStatus;
use sea_dyn::{Data, LoadOptions, Model, StateLayout};
use sea_sim::closed_loop::Sample;
use sea_sim::foxglove::{FootRectangle, SceneSource, ARROW_M_PER_N};
use sea_sim::mcap_log::{McapLogger, ThreadedMcapLogger};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

const URDF: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../urdf/mini_biped.urdf");

/// Topics and schema names; the first two are protobuf, the others JSON.
const TOPICS: [(&str, &str); 11] = [
    ("/tf", "foxglove.FrameTransforms"),
    ("/scene", "foxglove.SceneUpdate"),
    ("/com", "sea_momentum.Com"),
    ("/momentum", "sea_momentum.Momentum"),
    ("/joints", "sea_momentum.JointState"),
    ("/motors", "sea_momentum.MotorState"),
    ("/contact_wrenches", "sea_momentum.ContactWrenches"),
    ("/qp", "sea_momentum.QpStatus"),
    ("/base", "sea_momentum.BasePose"),
    ("/disturbances", "sea_momentum.Disturbances"),
    ("/planned_wrenches", "sea_momentum.ContactWrenches"),
];

fn model() -> Model {
    Model::from_urdf_file(URDF, &LoadOptions::default()).expect("mini_biped loads")
}

/// A unique file in the temporary directory, removed on drop.
struct TempFile(PathBuf);

impl TempFile {
    fn new(tag: &str) -> Self {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .unwrap()
            .as_nanos();
        Self(std::env::temp_dir().join(format!(
            "sea_ctrl_mcap_log_{tag}_{}_{nanos}.mcap",
            std::process::id()
        )))
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Configuration of sample `k`: base moving and turning, joints swinging.
fn configuration(model: &Model, k: usize) -> Vec<f64> {
    let t = k as f64 * 0.01;
    let mut q = model.neutral();
    q[0] = 0.1 * t;
    q[2] = 0.6 + 0.01 * t.sin();
    let (angle, axis) = (0.3 * t + 0.2, [0.2_f64, -0.5, 0.84]);
    let n = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
    let (s, c) = (angle / 2.0).sin_cos();
    q[3] = c;
    for i in 0..3 {
        q[4 + i] = s * axis[i] / n;
    }
    for (j, s) in q[7..].iter_mut().enumerate() {
        *s = 0.4 * (t + j as f64).sin();
    }
    q
}

/// A logger with every joint elastic and both soles as contacts.
fn create(model: &Model, path: &std::path::Path) -> McapLogger {
    let elastic: Vec<String> = model.joint_names.clone();
    let contacts = vec!["l_sole".to_string(), "r_sole".to_string()];
    McapLogger::create(path, model, &elastic, &contacts).expect("create")
}

/// Logs `count` samples, then returns the logger (unfinished).
fn log_samples(model: &Model, path: &std::path::Path, count: usize) -> McapLogger {
    let mut logger = create(model, path);
    for_each_sample(model, count, |sample| logger.log(sample).expect("log"));
    logger
}

/// Calls `f` with `count` varied samples.
fn for_each_sample(model: &Model, count: usize, mut f: impl FnMut(&Sample)) {
    let n = model.n_joints();
    let layout = StateLayout {
        nq: model.nq(),
        nv: model.nv(),
        ne: n,
    };
    let (solved, fallback) = (QpStatus::Solved, QpStatus::Fallback("test".into()));
    for k in 0..count {
        // The state [q; theta; nu; thetadot].
        let q = configuration(model, k);
        let mut state = q.clone();
        state.extend(q[7..].iter().map(|s| s + 0.01));
        state.extend((0..model.nv()).map(|i| 0.01 * (i + k) as f64));
        state.extend(std::iter::repeat_n(0.1, n));
        let thetadot_desired = vec![0.2; n];
        let wrenches: Vec<f64> = (0..12).map(|i| i as f64 + k as f64).collect();
        let planned: Vec<f64> = wrenches.iter().map(|w| -w).collect();
        let motor_torques = vec![1.0; n];
        let joint_torques = vec![2.0; n];
        let sample = Sample {
            time_s: k as f64 * 0.01,
            state: &state,
            layout,
            thetadot_desired: &thetadot_desired,
            com: [0.0, 0.0, 0.5],
            com_reference: [0.01, 0.0, 0.5],
            momentum: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
            contact_wrenches: &wrenches,
            planned_wrenches: &planned,
            contact_point_positions: &[],
            contact_point_forces: &[],
            contact_point_active: &[],
            contact_checks: &[],
            motor_torques: &motor_torques,
            joint_torques: &joint_torques,
            com_error_norm: 0.01,
            joint_error_norm: 0.0,
            qp_status: if k % 10 == 9 { &fallback } else { &solved },
            disturbance_wrenches: &[],
            external_wrench: [0.0; 6],
            qp_failures: k / 10,
        };
        f(&sample);
    }
}

/// `/tf` message `index`: every frame, time-stamped `time`, reproduces the frame's pose.
fn check_tf(model: &Model, data: &mut Data, tf: &FrameTransforms, index: usize, time: u64) {
    assert_eq!(tf.transforms.len(), model.frames.len());
    let q = configuration(model, index);
    sea_dyn::forward_kinematics(model, data, &q);
    for (id, (frame, transform)) in model.frames.iter().zip(&tf.transforms).enumerate() {
        assert_eq!(transform.parent_frame_id, "world");
        assert_eq!(transform.child_frame_id, frame.name);
        let stamp = transform.timestamp.expect("stamp");
        assert_eq!(
            stamp.sec() as u64 * 1_000_000_000 + stamp.nsec() as u64,
            time
        );
        let r = transform.rotation.expect("rotation");
        let norm = (r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z).sqrt();
        assert!(
            (norm - 1.0).abs() < 1e-12,
            "{}: |quat| = {norm}",
            frame.name
        );
        // The quaternion reproduces the frame's rotation, the translation its origin.
        let pose = sea_dyn::frame_placement(model, data, id);
        let rotation = sea_dyn::spatial::rotation_from_quaternion(r.w, r.x, r.y, r.z);
        assert!(
            (rotation - pose.rotation).abs().max() < 1e-12,
            "{}",
            frame.name
        );
        let t = transform.translation.expect("translation");
        let translation = nalgebra::Vector3::new(t.x, t.y, t.z);
        assert!((translation - pose.translation).abs().max() < 1e-12);
    }
}

/// Reads every message and checks topics, schemas, counts, times and `/tf` contents.
fn check_file(model: &Model, bytes: &[u8], count: usize) {
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut last_time: BTreeMap<String, u64> = BTreeMap::new();
    let mut data = Data::new(model);
    let mut tf_index = 0;
    for message in mcap::MessageStream::new(bytes).expect("stream") {
        let message = message.expect("message");
        let topic = message.channel.topic.clone();
        let schema = message.channel.schema.as_ref().expect("schema");
        if topic == "/robot" {
            // The robot's bodies, once, with the first sample (checked by the scene test).
            assert_eq!(schema.name, "foxglove.SceneUpdate");
            assert_eq!(message.channel.message_encoding, "protobuf");
            *counts.entry(topic).or_default() += 1;
            continue;
        }
        let position = TOPICS
            .iter()
            .position(|(t, _)| *t == topic)
            .unwrap_or_else(|| panic!("unexpected topic {topic}"));
        assert_eq!(schema.name, TOPICS[position].1, "schema of {topic}");
        let protobuf = position < 2;
        let (schema_encoding, encoding) = if protobuf {
            ("protobuf", "protobuf")
        } else {
            ("jsonschema", "json")
        };
        assert_eq!(schema.encoding, schema_encoding, "{topic}");
        assert_eq!(message.channel.message_encoding, encoding, "{topic}");
        if !protobuf {
            let _: serde_json::Value =
                serde_json::from_slice(&schema.data).expect("schema is JSON");
        }
        assert_eq!(message.log_time, message.publish_time);
        if let Some(&previous) = last_time.get(&topic) {
            assert!(message.log_time > previous, "{topic}: time not increasing");
        }
        last_time.insert(topic.clone(), message.log_time);
        *counts.entry(topic.clone()).or_default() += 1;

        if topic == "/tf" {
            let tf = FrameTransforms::decode(&message.data[..]).expect("protobuf /tf");
            check_tf(model, &mut data, &tf, tf_index, message.log_time);
            tf_index += 1;
            continue;
        }
        if topic == "/scene" {
            let scene = SceneUpdate::decode(&message.data[..]).expect("protobuf /scene");
            let ids: Vec<&str> = scene.entities.iter().map(|e| e.id.as_str()).collect();
            assert!(ids.starts_with(&["com", "com_reference"]) || ids.contains(&"com"));
            continue;
        }
        let json: serde_json::Value = serde_json::from_slice(&message.data).expect("JSON body");
        match topic.as_str() {
            "/com" => {
                assert_eq!(json["com"].as_array().unwrap().len(), 3);
                assert!((json["error"][0].as_f64().unwrap() + 0.01).abs() < 1e-15);
            }
            "/momentum" => {
                assert_eq!(json["linear"], serde_json::json!([1.0, 2.0, 3.0]));
                assert_eq!(json["angular"], serde_json::json!([4.0, 5.0, 6.0]));
            }
            "/joints" => {
                assert_eq!(json["names"].as_array().unwrap().len(), model.n_joints());
                assert_eq!(json["position"].as_array().unwrap().len(), model.n_joints());
                assert_eq!(json["velocity"].as_array().unwrap().len(), model.n_joints());
                assert_eq!(json["torque"].as_array().unwrap().len(), model.n_joints());
            }
            "/motors" => {
                for key in [
                    "names",
                    "position",
                    "velocity",
                    "velocity_desired",
                    "torque",
                ] {
                    assert_eq!(
                        json[key].as_array().unwrap().len(),
                        model.n_joints(),
                        "{key}"
                    );
                }
            }
            "/contact_wrenches" | "/planned_wrenches" => {
                let contacts = json["contacts"].as_array().unwrap();
                assert_eq!(contacts.len(), 2);
                assert_eq!(contacts[0]["frame"], "l_sole");
                assert_eq!(contacts[1]["frame"], "r_sole");
                assert_eq!(contacts[1]["moment"].as_array().unwrap().len(), 3);
                // The samples' planned wrenches are the delivered ones negated.
                let sign = if topic == "/planned_wrenches" {
                    -1.0
                } else {
                    1.0
                };
                let fz = contacts[0]["force"][2].as_f64().unwrap();
                let k = (sign * fz - 2.0).round();
                assert_eq!(
                    contacts[1]["moment"][2].as_f64().unwrap(),
                    sign * (11.0 + k)
                );
            }
            "/qp" => {
                assert!(json["status"].is_string());
                assert!(json["failures"].is_u64());
            }
            "/base" => {
                assert_eq!(json["orientation_wxyz"].as_array().unwrap().len(), 4);
            }
            // No `[[disturbances]]` in these samples.
            "/disturbances" => assert_eq!(json["disturbances"], serde_json::json!([])),
            _ => unreachable!(),
        }
    }
    for (topic, _) in TOPICS {
        assert_eq!(counts.get(topic), Some(&count), "message count of {topic}");
    }
    assert!(counts.get("/robot").is_none_or(|n| *n == 1), "one /robot");
}

#[test]
fn writes_a_readable_file_with_every_channel() {
    let model = model();
    let file = TempFile::new("finished");
    let logger = log_samples(&model, &file.0, 50);
    logger.finish().expect("finish");
    let bytes = std::fs::read(&file.0).unwrap();
    check_file(&model, &bytes, 50);

    // The summary section is present and counts the messages.
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    let stats = summary.stats.expect("statistics");
    assert_eq!(stats.message_count, 50 * 11);
    assert_eq!(stats.channel_count, 11);
    assert_eq!(stats.schema_count, 10);
    assert_eq!(stats.message_start_time, 0);
    assert_eq!(stats.message_end_time, 490_000_000);
    assert!(!summary.chunk_indexes.is_empty());
    assert!(summary.chunk_indexes.iter().all(|c| c.compression == "lz4"));
}

#[test]
fn threaded_logger_writes_the_same_file_and_reports_writer_errors() {
    let model = model();
    let file = TempFile::new("threaded");
    let mut logger = ThreadedMcapLogger::spawn(create(&model, &file.0));
    for_each_sample(&model, 40, |sample| logger.log(sample).expect("log"));
    logger.finish().expect("finish");
    let bytes = std::fs::read(&file.0).unwrap();
    check_file(&model, &bytes, 40);
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    assert_eq!(summary.stats.unwrap().message_count, 40 * 11);

    // A bad sample stops the writer; its error comes back from a later call.
    let bad_file = TempFile::new("threaded_bad");
    let mut logger = ThreadedMcapLogger::spawn(create(&model, &bad_file.0));
    let mut outcomes = Vec::new();
    for_each_sample(&model, 3, |sample| {
        let mut truncated = *sample;
        truncated.state = &sample.state[..5];
        outcomes.push(logger.log(&truncated));
    });
    assert!(outcomes[0].is_ok(), "the first log only queues");
    let error = outcomes
        .into_iter()
        .find_map(|o| o.err())
        .or_else(|| logger.finish().err())
        .expect("the writer's error is reported");
    assert!(matches!(error, sea_sim::Error::Log(_)), "{error}");
}

#[test]
fn dropped_logger_still_leaves_a_readable_file() {
    let model = model();
    let file = TempFile::new("dropped");
    {
        let logger = log_samples(&model, &file.0, 37);
        drop(logger); // an interrupted run: no finish()
    }
    let bytes = std::fs::read(&file.0).unwrap();
    check_file(&model, &bytes, 37);
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    assert_eq!(summary.stats.unwrap().message_count, 37 * 11);
}

#[test]
fn bad_sizes_are_errors_and_unwritable_path_is_io_error() {
    let model = model();
    let file = TempFile::new("bad");
    let mut logger = McapLogger::create(&file.0, &model, &[], &[]).unwrap();
    // A rigid robot's state [q; nu], first with q cut to 5 entries.
    let (nq, nv) = (model.nq(), model.nv());
    let mut state = model.neutral();
    state.extend(std::iter::repeat_n(0.0, nv));
    let short: Vec<f64> = state[..5].iter().chain(&state[nq..]).copied().collect();
    let mut sample = Sample {
        time_s: 0.0,
        state: &short,
        layout: StateLayout { nq: 5, nv, ne: 0 },
        thetadot_desired: &[],
        com: [0.0; 3],
        com_reference: [0.0; 3],
        momentum: [0.0; 6],
        contact_wrenches: &[],
        planned_wrenches: &[],
        contact_point_positions: &[],
        contact_point_forces: &[],
        contact_point_active: &[],
        contact_checks: &[],
        motor_torques: &[],
        joint_torques: &[],
        com_error_norm: 0.0,
        joint_error_norm: 0.0,
        qp_status: &QpStatus::Solved,
        disturbance_wrenches: &[],
        external_wrench: [0.0; 6],
        qp_failures: 0,
    };
    assert!(matches!(logger.log(&sample), Err(sea_sim::Error::Log(_))));
    // A state shorter than its layout.
    sample.layout.nq = nq;
    assert!(matches!(logger.log(&sample), Err(sea_sim::Error::Log(_))));
    sample.state = &state;
    sample.contact_wrenches = &[0.0; 7];
    assert!(matches!(logger.log(&sample), Err(sea_sim::Error::Log(_))));
    sample.contact_wrenches = &[0.0; 6];
    sample.planned_wrenches = &[0.0; 5];
    let refused = logger.log(&sample);
    assert!(
        matches!(&refused, Err(sea_sim::Error::Log(m)) if m.contains("planned_wrenches")),
        "{refused:?}"
    );
    sample.planned_wrenches = &[0.0; 6];
    logger.log(&sample).unwrap();
    logger.finish().unwrap();

    let missing = std::env::temp_dir().join("sea_ctrl_no_such_dir_4f1c/x.mcap");
    assert!(matches!(
        McapLogger::create(&missing, &model, &[], &[]),
        Err(sea_sim::Error::Io { .. })
    ));
}

#[test]
fn flushed_chunks_are_readable_before_the_log_is_finished() {
    // What a killed process leaves: chunks closed by `flush`, no summary section.
    let model = model();
    let file = TempFile::new("flushed");
    let mut logger = log_samples(&model, &file.0, 12);
    logger.flush().expect("flush");
    let bytes = std::fs::read(&file.0).unwrap();
    let recovered = mcap::MessageStream::new(&bytes)
        .expect("header")
        .map_while(Result::ok)
        .count();
    assert_eq!(recovered, 12 * 11);
    assert!(mcap::Summary::read(&bytes).is_err() || mcap::Summary::read(&bytes).unwrap().is_none());
    logger.finish().expect("finish");
}

/// A device (`/dev/full`, `/dev/null`) is refused before anything is written: the writer seeks
/// back over each chunk, which a device cannot do (`/dev/null` failed a second into a run). A
/// full disk under a regular file is the CLI's `a_full_file_system_...` test.
#[test]
fn a_device_is_refused_as_a_log_naming_the_path() {
    let model = model();
    let contacts = ["l_sole".to_string(), "r_sole".to_string()];
    for device in ["/dev/full", "/dev/null"] {
        let path = std::path::Path::new(device);
        if !path.exists() {
            eprintln!("no {device} here; skipped");
            continue;
        }
        let error = McapLogger::create(path, &model, &model.joint_names, &contacts)
            .expect_err("a device refused");
        match &error {
            sea_sim::Error::Io { path, source } => {
                assert_eq!(path, device);
                assert_eq!(source.kind(), std::io::ErrorKind::InvalidInput, "{source}");
            }
            other => panic!("expected an I/O error, got {other}"),
        }
        assert!(
            error.to_string().contains("must be a regular file"),
            "{error}"
        );
    }
}

#[test]
fn scene_draws_the_urdf_on_tf_frames_and_the_urdf_is_attached() {
    let model = model();
    let file = TempFile::new("scene");
    let foot = FootRectangle {
        x: [-0.05, 0.1],
        y: [-0.03, 0.04],
    };
    let mut logger = create(&model, &file.0);
    let source = SceneSource {
        foot: Some(foot),
        ..SceneSource::new(URDF)
    };
    logger.set_scene(&source).expect("scene");
    for_each_sample(&model, 5, |sample| logger.log(sample).expect("log"));
    logger.finish().expect("finish");
    let bytes = std::fs::read(&file.0).unwrap();
    check_file(&model, &bytes, 5);

    let link_frames: BTreeSet<&str> = model.frames.iter().map(|f| f.name.as_str()).collect();
    let urdf = urdf_rs::read_file(URDF).unwrap();
    let visual_links: BTreeSet<&str> = urdf
        .links
        .iter()
        .filter(|l| !l.visual.is_empty())
        .map(|l| l.name.as_str())
        .collect();
    let first = |topic: &str| {
        let message = mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(Result::unwrap)
            .find(|m| m.channel.topic == topic)
            .unwrap_or_else(|| panic!("a {topic} message"));
        assert_eq!(message.log_time, 0, "{topic} with the first sample");
        SceneUpdate::decode(&message.data[..]).unwrap()
    };
    let scene = first("/scene");
    let robot = first("/robot");
    assert!(scene.entities.iter().all(|e| !e.id.starts_with("link/")));
    let mut drawn_links = BTreeSet::new();
    for entity in scene.entities.iter().chain(&robot.entities) {
        assert!(
            entity.frame_id == "world" || link_frames.contains(entity.frame_id.as_str()),
            "{}: frame {} is not in /tf",
            entity.id,
            entity.frame_id
        );
        if let Some(link) = entity.id.strip_prefix("link/") {
            assert!(entity.frame_locked && entity.frame_id == link);
            drawn_links.insert(link);
        }
    }
    assert_eq!(
        drawn_links, visual_links,
        "one body entity per link with visuals"
    );
    let primitives: usize = robot
        .entities
        .iter()
        .map(|e| e.cubes.len() + e.spheres.len() + e.cylinders.len())
        .sum::<usize>();
    assert_eq!(
        primitives,
        urdf.links.iter().map(|l| l.visual.len()).sum::<usize>()
    );
    // The support polygon: each sole's rectangle, closed, in the sole frame.
    for sole in ["l_sole", "r_sole"] {
        let entity = scene
            .entities
            .iter()
            .find(|e| e.id == format!("support/{sole}"));
        let line = &entity.expect("support polygon").lines[0];
        assert_eq!(line.points.len(), 4);
        assert_eq!((line.points[2].x, line.points[2].y), (foot.x[1], foot.y[1]));
    }
    // The wrench arrows start at the soles and are as long as the force says.
    let arrow = &scene
        .entities
        .iter()
        .find(|e| e.id == "wrench/r_sole")
        .unwrap()
        .arrows[0];
    let force = [6.0, 7.0, 8.0_f64]; // sample 0, contact 1
    let length = force.iter().map(|f| f * f).sum::<f64>().sqrt() * ARROW_M_PER_N;
    assert!((arrow.shaft_length - length).abs() < 1e-12);
    let mut data = Data::new(&model);
    sea_dyn::forward_kinematics(&model, &mut data, &configuration(&model, 0));
    let sole = sea_dyn::frame_placement(&model, &data, model.frame_id("r_sole").unwrap());
    let start = arrow.pose.unwrap().position.unwrap();
    assert!((nalgebra::Vector3::new(start.x, start.y, start.z) - sole.translation).norm() < 1e-12);

    let attachment = mcap::read::Summary::read(&bytes)
        .unwrap()
        .unwrap()
        .attachment_indexes;
    assert_eq!(attachment.len(), 1);
    assert_eq!(attachment[0].name, "mini_biped.urdf");
    assert_eq!(attachment[0].media_type, "application/xml");
    let attached = mcap::read::attachment(&bytes, &attachment[0]).unwrap();
    assert_eq!(&attached.data[..], &std::fs::read(URDF).unwrap()[..]);
}

#[test]
fn a_scene_given_up_by_the_runs_flag_leaves_a_log_without_the_robot() {
    use std::sync::atomic::AtomicBool;
    let model = model();
    let log_with = |raised: bool, file: &TempFile| {
        let mut logger = create(&model, &file.0);
        let cancel = AtomicBool::new(raised);
        let scene = logger
            .set_scene_unless_cancelled(&SceneSource::new(URDF), &cancel)
            .expect("scene");
        for_each_sample(&model, 2, |sample| logger.log(sample).expect("log"));
        logger.finish().expect("finish");
        let bytes = std::fs::read(&file.0).unwrap();
        check_file(&model, &bytes, 2);
        let summary = mcap::read::Summary::read(&bytes).unwrap().unwrap();
        let robot = mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(Result::unwrap)
            .any(|m| m.channel.topic == "/robot");
        (scene, summary.attachment_indexes.len(), robot)
    };
    let (file_given_up, file_drawn) = (TempFile::new("given_up"), TempFile::new("drawn"));
    assert_eq!(log_with(true, &file_given_up), (None, 0, false));
    assert_eq!(log_with(false, &file_drawn), (Some(Vec::new()), 1, true));
}
