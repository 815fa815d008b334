//! The settings read from a `[walking]` table (with the `serde` feature).

use super::super::footstep::Foot;
use super::super::settings::WalkingSettings;

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
