//! The settings' check names the key, the rule and the value.

use super::super::lip::Lip;
use super::walking;
use crate::error::Error;

/// The key of a setting error.
fn key_of(error: Error) -> String {
    match error {
        Error::Setting { key, .. } => key,
        other => panic!("expected a setting error, got {other}"),
    }
}

#[test]
fn defaults_with_a_length_are_valid() {
    walking(4, 0.2, 0.0, 0.0).validate(0.01).expect("valid");
}

#[test]
fn a_step_shorter_than_one_whole_body_period_names_step_duration() {
    let mut settings = walking(4, 0.2, 0.0, 0.0);
    settings.step_duration = 0.008;
    settings.double_support_duration = 0.004;
    let error = settings.validate(0.01).unwrap_err();
    let message = error.to_string();
    assert!(message.contains("walking.step_duration"), "{message}");
    assert!(
        message.contains("0.01 s") && message.contains("got 0.008"),
        "{message}"
    );
}

#[test]
fn a_double_support_leaving_no_swing_names_double_support_duration() {
    let mut settings = walking(4, 0.2, 0.0, 0.0);
    settings.double_support_duration = settings.step_duration - 0.005;
    let key = key_of(settings.validate(0.01).unwrap_err());
    assert_eq!(key, "walking.double_support_duration");
}

#[test]
fn a_negative_height_names_com_height() {
    let mut settings = walking(4, 0.2, 0.0, 0.0);
    settings.com_height = -0.5;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.com_height"
    );
    let error = Lip::new(9.81, -0.5).unwrap_err().to_string();
    assert!(
        error.contains("walking.com_height") && error.contains("-0.5"),
        "{error}"
    );
}

#[test]
fn widths_out_of_order_name_nominal_width() {
    let mut settings = walking(4, 0.2, 0.0, 0.0);
    settings.nominal_width = settings.max_step_width + 0.01;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.nominal_width"
    );
}

#[test]
fn steps_and_duration_are_exclusive() {
    let mut settings = walking(4, 0.2, 0.0, 0.0);
    settings.command.duration = Some(3.0);
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.command.steps"
    );
    settings.command.steps = None;
    settings.validate(0.01).expect("duration alone");
    assert_eq!(settings.command_steps(), Some(5));
    settings.command.steps = Some(0);
    settings.command.duration = None;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.command.steps"
    );
}

#[test]
fn a_command_longer_than_the_plan_can_hold_is_refused_naming_the_key() {
    use super::super::settings::MAX_COMMAND_STEPS;
    let mut settings = walking(MAX_COMMAND_STEPS, 0.2, 0.0, 0.0);
    settings.validate(0.01).expect("the most steps");
    settings.command.steps = Some(MAX_COMMAND_STEPS + 1);
    let error = settings.validate(0.01).unwrap_err().to_string();
    assert!(error.contains("walking.command.steps"), "{error}");
    assert!(error.contains("100000"), "{error}");
    settings.command.steps = None;
    settings.command.duration = Some(1e12);
    let error = settings.validate(0.01).unwrap_err();
    assert_eq!(key_of(error), "walking.command.duration");
    settings.command.duration = Some(0.9 * MAX_COMMAND_STEPS as f64 * settings.step_duration);
    settings.validate(0.01).expect("below the longest");
}

/// A change that makes one setting invalid.
type Spoil = fn(&mut super::WalkingSettings);

#[test]
fn other_bad_values_name_their_keys() {
    let cases: [(&str, Spoil); 6] = [
        ("walking.swing_height", |s| s.swing_height = -0.01),
        ("walking.max_step_width", |s| {
            s.max_step_width = f64::INFINITY
        }),
        ("walking.max_step_turn", |s| s.max_step_turn = 2.0),
        ("walking.min_swing_duration", |s| s.min_swing_duration = 0.0),
        ("walking.transfer_duration", |s| {
            s.transfer_duration = f64::NAN
        }),
        ("walking.command.forward_velocity", |s| {
            s.command.forward_velocity = f64::INFINITY
        }),
    ];
    for (key, spoil) in cases {
        let mut settings = walking(4, 0.2, 0.0, 0.0);
        spoil(&mut settings);
        assert_eq!(key_of(settings.validate(0.01).unwrap_err()), key);
    }
}

#[test]
fn the_scaled_settings_follow_the_rule_and_are_valid() {
    use super::super::settings::{
        RobotWalkingFigures, WalkingSettings, ICUB_LEG_LENGTH, STEP_LENGTH_PER_REACH,
    };
    let icub = WalkingSettings::default();
    // A robot with legs 4 times the iCub's: lengths x4, durations x2.
    let figures = RobotWalkingFigures {
        com_height: 1.9,
        feet_distance: 0.28,
        leg_length: 4.0 * ICUB_LEG_LENGTH,
        reach: 1.5,
    };
    let scaled = WalkingSettings::scaled_to(&figures).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(scaled.com_height, 1.9));
    assert!(close(scaled.nominal_width, 0.28));
    assert!(close(scaled.min_step_width, 2.0 * icub.min_step_width));
    assert!(close(scaled.max_step_width, 2.0 * icub.max_step_width));
    assert!(close(scaled.max_step_length, STEP_LENGTH_PER_REACH * 1.5));
    assert!(close(scaled.swing_height, 4.0 * icub.swing_height));
    assert!(close(scaled.step_duration, 2.0 * icub.step_duration));
    assert!(close(
        scaled.double_support_duration,
        2.0 * icub.double_support_duration
    ));
    assert!(close(
        scaled.transfer_duration,
        2.0 * icub.transfer_duration
    ));
    assert!(close(
        scaled.min_swing_duration,
        2.0 * icub.min_swing_duration
    ));
    assert!(close(
        scaled.min_adjusted_swing_duration,
        2.0 * icub.min_adjusted_swing_duration
    ));
    assert_eq!(scaled.max_step_turn, icub.max_step_turn);
    let mut walking = scaled.clone();
    walking.command.steps = Some(2);
    walking.validate(0.01).expect("valid");
    let bad = RobotWalkingFigures {
        reach: f64::NAN,
        ..figures
    };
    let message = WalkingSettings::scaled_to(&bad).unwrap_err().to_string();
    assert!(message.contains("reach"), "{message}");
}

#[test]
fn stepping_stands_and_refuses_a_walk_naming_walking_stepping() {
    let mut settings = super::WalkingSettings {
        stepping: true,
        ..Default::default()
    };
    settings.validate(0.01).expect("standing with stepping");
    settings.command.steps = Some(2);
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.stepping"
    );
    settings.command.steps = None;
    settings.max_recovery_steps = 0;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.max_recovery_steps"
    );
    settings.max_recovery_steps = 2;
    settings.recovery_step_offset = -0.01;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.recovery_step_offset"
    );
    settings.recovery_step_offset = 0.03;
    settings.recovery_transfer_duration = 0.001;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.recovery_transfer_duration"
    );
}

#[test]
fn step_adjustment_settings_out_of_range_or_with_stepping_are_refused_naming_the_key() {
    let mut settings = super::WalkingSettings {
        step_adjustment: true,
        ..Default::default()
    };
    settings.command.steps = Some(2);
    settings
        .validate(0.01)
        .expect("a walk with step adjustment");
    settings.step_adjustment_threshold = -0.01;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.step_adjustment_threshold"
    );
    settings.step_adjustment_threshold = 0.03;
    refuses(
        &mut settings,
        |s, v| s.step_adjustment_end_phase = v,
        [0.0, 1.5, f64::NAN],
        "walking.step_adjustment_end_phase",
    );
    settings.step_adjustment_end_phase = 1.0;
    settings.validate(0.01).expect("adjusting up to touchdown");
    settings.command.steps = None;
    settings.stepping = true;
    assert_eq!(
        key_of(settings.validate(0.01).unwrap_err()),
        "walking.step_adjustment"
    );
}

#[test]
fn a_toe_off_out_of_range_names_its_key() {
    let mut settings = super::WalkingSettings::default();
    settings.command.steps = Some(2);
    settings.swing_toe_off_pitch = 0.1;
    settings.validate(0.01).expect("a 0.1 rad toe-off");
    refuses(
        &mut settings,
        |s, v| s.swing_toe_off_pitch = v,
        [-0.1, 0.6, f64::NAN],
        "walking.swing_toe_off_pitch",
    );
    settings.swing_toe_off_pitch = 0.1;
    refuses(
        &mut settings,
        |s, v| s.swing_toe_off_end = v,
        [0.0, 1.2, f64::NAN],
        "walking.swing_toe_off_end",
    );
}

/// Each of `bad`, set by `set`, is refused naming `key`.
#[track_caller]
fn refuses(
    settings: &mut super::WalkingSettings,
    set: fn(&mut super::WalkingSettings, f64),
    bad: [f64; 3],
    key: &str,
) {
    for value in bad {
        set(settings, value);
        assert_eq!(key_of(settings.validate(0.01).unwrap_err()), key, "{value}");
    }
}

#[test]
fn a_shortest_adjusted_swing_beyond_the_swing_is_refused_when_the_timing_moves() {
    use super::super::StepTiming;
    let mut settings = walking(4, 0.2, 0.0, 0.0);
    settings.step_adjustment = true;
    // 0.45 s single supports by default.
    settings.min_adjusted_swing_duration = 0.5;
    settings
        .validate(0.01)
        .expect("the plan's timing: the key is not used");
    for timing in [StepTiming::Sideways, StepTiming::Any] {
        settings.step_timing = timing;
        let message = settings.validate(0.01).unwrap_err().to_string();
        assert!(
            message.contains("walking.min_adjusted_swing_duration")
                && message.contains("0.45")
                && message.contains("0.5"),
            "{message}"
        );
    }
    settings.min_adjusted_swing_duration = 0.005;
    let key = key_of(settings.validate(0.01).unwrap_err());
    assert_eq!(key, "walking.min_adjusted_swing_duration");
    settings.min_adjusted_swing_duration = 0.2;
    settings.validate(0.01).expect("valid");
    // A toe-off over half the 0.45 s swing: a retimed foot may not land before its end.
    settings.swing_toe_off_pitch = 0.2;
    let message = settings.validate(0.01).unwrap_err().to_string();
    assert!(
        message.contains("walking.min_adjusted_swing_duration") && message.contains("0.225"),
        "{message}"
    );
    settings.min_adjusted_swing_duration = 0.23;
    settings.validate(0.01).expect("landing after the toe-off");
}
