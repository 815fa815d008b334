//! Error messages name what is wrong: the scenario key (not the value, not a neighbouring
//! key), the file and line of malformed TOML, the path and OS cause of I/O failures; the
//! variants carry the same facts as fields.

use sea_sim::scenario::{build, Scenario};
use sea_sim::Error;
use std::path::{Path, PathBuf};

fn tracking() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper/tracking.toml")
}

fn load(overrides: &[(&str, &str)]) -> sea_sim::Result<Scenario> {
    let overrides: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&tracking(), &overrides)
}

/// The key of a scenario error (panics on any other error).
#[track_caller]
fn scenario_key(result: sea_sim::Result<Scenario>) -> (String, String) {
    match result {
        Err(error @ Error::Scenario { .. }) => {
            let text = error.to_string();
            let Error::Scenario { key, .. } = error else {
                unreachable!()
            };
            (key, text)
        }
        Err(other) => panic!("expected Error::Scenario, got {other:?}"),
        Ok(_) => panic!("accepted an invalid scenario"),
    }
}

#[test]
fn negative_postural_scale_names_its_key() {
    let (key, text) = scenario_key(load(&[("controller.postural_scale", "-1")]));
    assert_eq!(key, "controller.postural_scale", "{text}");
    assert!(text.contains("-1"), "{text}");
}

#[test]
fn negative_proportional_gain_names_the_proportional_gain() {
    let (key, text) = scenario_key(load(&[(
        "controller.momentum_proportional",
        "[1.0, 1.0, -1.0, 1.0, 1.0, 1.0]",
    )]));
    assert_eq!(key, "controller.momentum_proportional", "{text}");
    let (key, _) = scenario_key(load(&[(
        "controller.momentum_integral",
        "[1.0, 1.0, -1.0, 1.0, 1.0, 1.0]",
    )]));
    assert_eq!(key, "controller.momentum_integral");
}

#[test]
fn type_errors_name_the_key_not_the_value() {
    let (key, text) = scenario_key(load(&[("controller.kind", "3")]));
    assert_eq!(key, "controller.kind", "{text}");
    let (key, text) = scenario_key(load(&[("controller.postural_scale", "\"big\"")]));
    assert_eq!(key, "controller.postural_scale", "{text}");
    assert!(text.contains("big"), "the rule keeps the value: {text}");
}

#[test]
fn unknown_keys_are_named_with_their_table() {
    let (key, text) = scenario_key(load(&[("controller.dampnig", "1")]));
    assert_eq!(key, "controller.dampnig", "{text}");
    let (key, text) = scenario_key(load(&[("nonsense", "1")]));
    assert_eq!(key, "nonsense", "{text}");
}

#[test]
fn all_nan_initial_posture_names_the_key() {
    let nans = vec!["nan"; 25].join(", ");
    let scenario = load(&[("robot.initial_posture", &format!("[{nans}]"))]).unwrap();
    match build(&scenario) {
        Err(error @ Error::Scenario { .. }) => {
            let text = error.to_string();
            assert!(text.contains("robot.initial_posture[0]"), "{text}");
            assert!(text.contains("nan"), "{text}");
        }
        Err(other) => panic!("expected Error::Scenario, got {other:?}"),
        Ok(_) => panic!("accepted an all-NaN initial posture"),
    }
}

/// The tracking scenario's text with its URDF's absolute path, edited by `edit`, written to
/// `scenario.toml` in a new folder of the temporary directory: (folder, file, text written).
fn tracking_copy(tag: &str, edit: impl FnOnce(String) -> String) -> (PathBuf, PathBuf, String) {
    let dir = std::env::temp_dir().join(format!("sea_sim_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scenario.toml");
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../urdf/icub25.urdf");
    let text = std::fs::read_to_string(tracking())
        .unwrap()
        .replace("../../urdf/icub25.urdf", &urdf.display().to_string());
    let text = edit(text);
    std::fs::write(&path, &text).unwrap();
    (dir, path, text)
}

#[test]
fn a_key_error_found_at_build_names_the_file_and_the_keys_line() {
    let nans = vec!["nan"; 25].join(", ");
    let (dir, path, _) = tracking_copy("build_line", |text| {
        text.replace("\"left_stance\"", &format!("[{nans}]"))
    });
    let built = |overrides: &[(String, String)]| {
        let scenario = Scenario::from_file(&path, overrides).unwrap();
        let error = build(&scenario).err().expect("an all-NaN posture refused");
        error
            .to_string()
            .replace(&path.display().to_string(), "FILE")
    };
    let message = built(&[]);
    assert!(
        message.starts_with("FILE:9: scenario key 'robot.initial_posture[0]'"),
        "{message}"
    );
    // The posture from an override: no line of the file is where it came from.
    let set = [("robot.initial_posture".to_string(), format!("[{nans}]"))];
    let message = built(&set);
    assert!(message.starts_with("FILE: scenario key"), "{message}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_disturbance_error_found_at_the_runs_start_names_the_file_and_the_line() {
    let disturbance = "[[disturbances]]\nlink = \"no_such_link\"\nforce = [1.0, 0.0, 0.0]\n";
    let (dir, path, text) = tracking_copy("run_line", |text| {
        format!("{text}\n{disturbance}start_s = 0.1\nduration_s = 0.1\n")
    });
    let line = text.lines().position(|l| l.starts_with("link = ")).unwrap() + 1;
    let scenario = Scenario::from_file(&path, &[]).unwrap();
    let run = sea_sim::scenario::run::run(&scenario, |_, _| ());
    std::fs::remove_dir_all(&dir).unwrap();
    let message = run.expect_err("an unknown link refused").to_string();
    let expected = format!(
        "{}:{line}: scenario key 'disturbances[0].link'",
        path.display()
    );
    assert!(message.starts_with(&expected), "{message}");
}

#[test]
fn malformed_toml_names_the_file_and_the_line() {
    let path = std::env::temp_dir().join(format!("sea_sim_malformed_{}.toml", std::process::id()));
    std::fs::write(&path, "name = \"x\"\n\n[controller\nkind = \"sea\"\n").unwrap();
    let result = Scenario::from_file(&path, &[]);
    std::fs::remove_file(&path).unwrap();
    match result {
        Err(error @ Error::Parse { .. }) => {
            let text = error.to_string();
            assert!(
                text.starts_with(&format!("{}:3:", path.display())),
                "{text}"
            );
            let Error::Parse { file, line, .. } = error else {
                unreachable!()
            };
            assert_eq!(file.as_deref(), Some(path.as_path()));
            assert_eq!(line, Some(3));
        }
        Err(other) => panic!("expected Error::Parse, got {other:?}"),
        Ok(_) => panic!("accepted malformed TOML"),
    }
}

#[test]
fn a_key_error_names_the_file_and_the_keys_line_unless_an_override_set_it() {
    let path = std::env::temp_dir().join(format!("sea_sim_key_line_{}.toml", std::process::id()));
    let read = |text: &str, overrides: &[(String, String)]| {
        std::fs::write(&path, text).unwrap();
        let (key, message) = scenario_key(Scenario::from_file(&path, overrides));
        (key, message.replace(&path.display().to_string(), "FILE"))
    };
    let head = "[robot]\nurdf = \"x.urdf\"\n\n[controller]\n";
    let (key, message) = read(&format!("{head}postural_scale = -1\n"), &[]);
    assert_eq!(key, "controller.postural_scale");
    assert!(message.starts_with("FILE:5: scenario key"), "{message}");
    let (key, message) = read(&format!("{head}postural_scale = 1\ndampnig = 2\n"), &[]);
    assert_eq!(key, "controller.dampnig");
    assert!(message.starts_with("FILE:6: scenario key"), "{message}");
    // A missing key: its table's header.
    let (key, message) = read("[robot]\n\n[simulation]\nduration_s = 1.0\n", &[]);
    assert_eq!(key, "robot.urdf");
    assert!(message.starts_with("FILE:1: scenario key"), "{message}");
    // The value came from the override: the file's line is not where it is.
    let set = [("controller.postural_scale".to_string(), "-2".to_string())];
    let (_, message) = read(&format!("{head}postural_scale = 1\n"), &set);
    assert!(message.starts_with("FILE: scenario key"), "{message}");
    std::fs::remove_file(&path).unwrap();
}

#[test]
fn missing_scenario_file_is_an_io_error_with_path_and_cause() {
    let path = Path::new("/nonexistent/folder/scenario.toml");
    match Scenario::from_file(path, &[]) {
        Err(error @ Error::Io { .. }) => {
            let text = error.to_string();
            assert_eq!(
                text,
                "/nonexistent/folder/scenario.toml: No such file or directory"
            );
        }
        other => panic!("expected Error::Io, got {other:?}"),
    }
}

#[test]
fn unparsable_urdf_is_a_parse_error_naming_the_file() {
    let dir = std::env::temp_dir().join(format!("sea_sim_bad_urdf_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("robot.urdf");
    std::fs::write(&urdf, "<robot name=\"r\">\n<link name=\"a\">\n</robot>\n").unwrap();
    let text = std::fs::read_to_string(tracking()).unwrap();
    let scenario = Scenario::from_toml(
        &text,
        &[("robot.urdf".into(), format!("\"{}\"", urdf.display()))],
        &dir,
    )
    .unwrap();
    let result = build(&scenario);
    std::fs::remove_dir_all(&dir).unwrap();
    match result {
        Err(Error::Dynamics(error @ sea_dyn::Error::Parse { .. })) => {
            assert!(error.to_string().contains("robot.urdf"), "{error}");
        }
        Err(other) => panic!("expected a URDF parse error, got {other:?}"),
        Ok(_) => panic!("accepted an unparsable URDF"),
    }
}

/// A scenario file larger than `MAX_TOML_BYTES` (4 MiB) is refused before it is parsed: a
/// 30 MB array of numbers used to take about 0.5 GB to read.
#[test]
fn a_scenario_file_over_the_toml_limit_is_refused_naming_the_sizes() {
    let limit = sea_dyn::files::MAX_TOML_BYTES as usize;
    let (dir, path, _) = tracking_copy("toml_limit", |text| {
        let count = limit / 12 + 1;
        format!(
            "extra = [{}]\n{text}",
            vec!["0.123456789"; count].join(", ")
        )
    });
    let message = Scenario::from_file(&path, &[]).unwrap_err().to_string();
    std::fs::remove_dir_all(dir).unwrap();
    assert!(
        message.contains("scenario.toml") && message.contains(&format!("limit of {limit} bytes")),
        "{message}"
    );
}

/// An error inside a scenario's inline `[robot.description]` names the scenario's key and the
/// line of the scenario file it is on (it named line 218 of a re-serialised copy).
#[test]
fn an_error_in_an_inline_robot_description_names_its_key_and_line() {
    let talos =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/robots/talos_two_feet.toml");
    let text = std::fs::read_to_string(talos).unwrap();
    let line = 1 + text
        .lines()
        .position(|l| l.starts_with("stance_leg = ["))
        .expect("the stance leg's stiffness");
    let text = text.replacen("stance_leg = [", "stance_leg = [\"x\", ", 1);
    let dir = std::env::temp_dir().join(format!("sea_sim_inline_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("talos.toml");
    std::fs::write(&path, text).unwrap();
    let message = Scenario::from_file(&path, &[]).unwrap_err().to_string();
    std::fs::remove_dir_all(dir).unwrap();
    assert!(
        message.contains(&format!("talos.toml:{line}:"))
            && message.contains("'robot.description.postural_stiffness.stance_leg'"),
        "line {line}: {message}"
    );
}

/// A relative URDF path found neither beside the scenario nor from the working directory is
/// named from the scenario's folder, where a scenario's relative paths belong.
#[test]
fn a_urdf_found_nowhere_is_named_from_the_scenarios_folder() {
    let dir = std::env::temp_dir().join(format!("sea_sim_nowhere_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("moved.toml");
    let text = std::fs::read_to_string(tracking()).unwrap();
    let text = text.replace("../../urdf/icub25.urdf", "../nowhere/robot.urdf");
    std::fs::write(&path, text).unwrap();
    let scenario = Scenario::from_file(&path, &[]).unwrap();
    let message = build(&scenario).err().expect("no URDF").to_string();
    let expected = dir.join("../nowhere/robot.urdf");
    assert!(
        message.starts_with(&format!("{}: No such file", expected.display())),
        "{message}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}
