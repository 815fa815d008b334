//! `sea-sim init --walking`: the `[walking]` table for the new robot, the defaults scaled to
//! it by the one rule of `sea_ctrl::walking::WalkingSettings::scaled_to` from the figures of
//! its standing posture ([`walking_figures`]), and the controller settings the iCub walks
//! with (scenarios/walking/walk_straight.toml, [`WALKING_CONTROLLER`]).

use super::posture::Standing;
use crate::error::Result;
use sea_ctrl::walking::{RobotWalkingFigures, WalkingSettings};
use sea_dyn::{FrameId, Model};

/// The command of the written walk: this many steps forward, then the stop step.
pub const WALK_STEPS: usize = 8;

/// The written walk's forward step as a fraction of `max_step_length` (the iCub's
/// walk_straight.toml steps 0.06 m, 0.3 of the 0.20 m its `max_step_length` was then).
pub const STEP_FRACTION: f64 = 0.3;

/// How long the run stands after the walk ends [s].
pub const STANDING_AFTER_S: f64 = 2.0;

/// The controller and simulation settings of a walking scenario, as the iCub walks
/// (scenarios/walking/walk_straight.toml and docs/findings/walking.md give the reasons): the
/// robot-rate design (100 Hz whole-body law over 1 kHz joint loops, plant step 0.25 ms), a
/// postural task 12.5 times the description's, no minimum normal force (a foot's wrench goes
/// to zero before it lifts), the QP's centre of pressure 30 % inside the soles, the joint
/// error bound at 3 rad (the legs leave the initial posture while stepping).
pub const WALKING_CONTROLLER: &str = "\
[plant]
dt = 0.00025

[actuators]
kind = \"elastic\"
torque_limit_from_urdf = true

[controller]
sampling = \"multi_rate\"
kind = \"rigid\"
reflected_inertia = false
postural_scale = 2.5

[controller.contact]
min_normal_force = 0.0
cop_margin = 0.3

[simulation]
divergence_joint_error_rad = 3.0
";

/// The figures of the robot standing at `standing` on the soles `feet`
/// (`sea_scenario::walking::walking_figures`: the CoM's height above the soles, the soles'
/// distance, the shorter straight leg and the legs' reach, the scenario's reach check).
pub fn walking_figures(
    model: &Model,
    feet: [FrameId; 2],
    standing: &Standing,
) -> RobotWalkingFigures {
    let mut q = model.neutral();
    q[7..].copy_from_slice(&standing.joints);
    crate::scenario::walking::walking_figures(model, &q, &feet)
}

/// The walking settings written for `figures`: the scaled defaults
/// (`WalkingSettings::scaled_to`) rounded to 1 mm and 1 ms for reading, and a command of
/// [`WALK_STEPS`] steps forward of [`STEP_FRACTION`] of `max_step_length`.
pub fn walking_settings(figures: &RobotWalkingFigures) -> Result<WalkingSettings> {
    let round = |value: f64| (value * 1e3).round() / 1e3;
    let mut settings = WalkingSettings::scaled_to(figures)?;
    for value in [
        &mut settings.com_height,
        &mut settings.step_duration,
        &mut settings.double_support_duration,
        &mut settings.transfer_duration,
        &mut settings.swing_height,
        &mut settings.nominal_width,
        &mut settings.max_step_length,
        &mut settings.min_step_width,
        &mut settings.max_step_width,
        &mut settings.min_swing_duration,
        &mut settings.min_adjusted_swing_duration,
        &mut settings.capture_margin.forward,
        &mut settings.capture_margin.backward,
        &mut settings.capture_margin.sideways,
    ] {
        *value = round(*value);
    }
    settings.command.steps = Some(WALK_STEPS);
    settings.command.forward_velocity =
        round(STEP_FRACTION * settings.max_step_length / settings.step_duration);
    Ok(settings)
}

/// The run's duration for `settings` [s]: the transfer, the command's steps and the stop
/// step, the transfer back, then [`STANDING_AFTER_S`] standing, rounded up to 0.1 s.
pub fn walking_duration(settings: &WalkingSettings) -> f64 {
    let steps = settings.command_steps().unwrap_or(0) + 1;
    let walk = 2.0 * settings.transfer_duration + steps as f64 * settings.step_duration;
    ((walk + STANDING_AFTER_S) * 10.0).ceil() / 10.0
}
