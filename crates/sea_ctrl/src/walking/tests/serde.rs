//! The settings read from a `[walking]` table (with the `serde` feature).

use super::super::footstep::Foot;
use super::super::settings::{CaptureMargin, WalkingSettings};

/// The `[walking]` table of `text` as settings.
fn walking_table(text: &str) -> Result<WalkingSettings, toml::de::Error> {
    #[derive(serde::Deserialize)]
    struct File {
        walking: WalkingSettings,
    }
    toml::from_str::<File>(text).map(|file| file.walking)
}

#[test]
fn a_walking_table_reads_into_the_settings_with_defaults() {
    let settings = walking_table(
        "[walking]\nstep_duration = 0.7\nswing_height = 0.05\n\
         [walking.command]\nforward_velocity = 0.3\nfirst_foot = \"right\"\nsteps = 20\n",
    )
    .unwrap();
    assert_eq!(settings.step_duration, 0.7);
    assert_eq!(settings.swing_height, 0.05);
    assert_eq!(settings.command.first_foot, Foot::Right);
    assert_eq!(settings.command.steps, Some(20));
    assert_eq!(settings.com_height, WalkingSettings::default().com_height);
    settings.validate(0.01).unwrap();
}

#[test]
fn explicit_footsteps_read_as_a_table_array() {
    let settings = walking_table(
        "[[walking.footsteps]]\nfoot = \"left\"\nx = 0.1\ny = 0.07\nyaw = 0.0\n\
         [[walking.footsteps]]\nfoot = \"right\"\nx = 0.2\ny = -0.07\nyaw = 0.1\n",
    )
    .unwrap();
    assert_eq!(settings.footsteps.len(), 2);
    assert_eq!(settings.footsteps[1].foot, Foot::Right);
    assert_eq!(settings.footsteps[1].yaw, 0.1);
    settings.validate(0.01).unwrap();
}

#[test]
fn explicit_footsteps_and_a_command_together_are_refused() {
    let steps = "[[walking.footsteps]]\nfoot = \"left\"\nx = 0.1\ny = 0.07\nyaw = 0.0\n";
    for command in ["steps = 10", "duration = 2.0", "forward_velocity = 0.2"] {
        let settings = walking_table(&format!("[walking.command]\n{command}\n{steps}")).unwrap();
        let error = settings.validate(0.01).unwrap_err().to_string();
        assert!(
            error.contains("walking.command") && error.contains("walking.footsteps"),
            "{command}: {error}"
        );
    }
}

#[test]
fn the_capture_margin_reads_as_a_number_or_a_table() {
    let uniform = walking_table("[walking]\ncapture_margin = 0.02\n").unwrap();
    assert_eq!(uniform.capture_margin, CaptureMargin::uniform(0.02));
    let table = walking_table(
        "[walking]\ncapture_margin = { forward = 0.01, backward = 0.003, sideways = 0.0 }\n",
    )
    .unwrap();
    assert_eq!(table.capture_margin.backward, 0.003);
    let default = walking_table("[walking]\n").unwrap();
    assert_eq!(
        default.capture_margin,
        WalkingSettings::default().capture_margin
    );
    let partial = walking_table("[walking]\ncapture_margin = { backward = 0.005 }\n").unwrap();
    assert_eq!(
        partial.capture_margin,
        CaptureMargin {
            backward: 0.005,
            ..CaptureMargin::default()
        }
    );
    for bad in [
        "capture_margin = { forward = 0.01, up = 1 }",
        "capture_margin = { forward = \"far\" }",
        "capture_margin = \"wide\"",
    ] {
        let message = walking_table(&format!("[walking]\n{bad}\n"))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains(
                "expected a number or a table with numbers among forward, backward, sideways"
            ),
            "{bad}: {message}"
        );
    }
    let negative = walking_table(
        "[walking]\ncapture_margin = { forward = 0.01, backward = -1, sideways = 0 }\n",
    )
    .unwrap();
    let message = negative.validate(0.01).unwrap_err().to_string();
    assert!(
        message.contains("walking.capture_margin.backward"),
        "{message}"
    );
    // A negative number is refused when read, as the number it is (not as one direction).
    let message = walking_table("[walking]\ncapture_margin = -0.01\n")
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("must be non-negative and finite, got -0.01")
            && !message.contains("forward"),
        "{message}"
    );
}

#[test]
fn unknown_keys_are_refused_by_name() {
    let message = walking_table("[walking]\nstep_lenght = 0.2\n")
        .unwrap_err()
        .to_string();
    assert!(message.contains("step_lenght"), "{message}");
    let message = walking_table("[walking.command]\nspeed = 0.2\n")
        .unwrap_err()
        .to_string();
    assert!(message.contains("speed"), "{message}");
}

#[test]
fn the_schema_documents_each_key_with_its_unit() {
    let schema = serde_json::to_value(schemars::schema_for!(WalkingSettings)).unwrap();
    let description = schema["properties"]["com_height"]["description"]
        .as_str()
        .unwrap();
    assert!(description.contains("[m]"), "{description}");
    let text = schema.to_string();
    for key in [
        "step_duration",
        "max_step_turn",
        "forward_velocity",
        "footsteps",
    ] {
        assert!(text.contains(key), "{key} missing from the schema");
    }
}

#[test]
fn the_schema_bounds_the_command_steps_as_the_check_does() {
    let schema = serde_json::to_value(schemars::schema_for!(super::super::WalkCommand)).unwrap();
    let steps = &schema["properties"]["steps"];
    let maximum = steps["maximum"]
        .as_f64()
        .unwrap_or_else(|| panic!("{steps}"));
    assert_eq!(maximum, super::super::MAX_COMMAND_STEPS as f64);
}
