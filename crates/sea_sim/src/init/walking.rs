//! `sea-sim init --walking`: the `[walking]` table for the new robot, the defaults scaled to
//! it by the one rule of `sea_ctrl::walking::WalkingSettings::scaled_to` from the figures of
//! its standing posture ([`walking_figures`]), and the controller settings the iCub walks
//! with (scenarios/walking/walk_straight.toml, [`WALKING_CONTROLLER`]).

use super::posture::Standing;
use crate::closed_loop::{RunEnd, Summary};
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

/// How much lower each try of the walk check ([`check_walk`]) puts `walking.com_height`, as a
/// fraction of the standing CoM height: the G1 of example-robot-data diverges at its standing
/// height (the stance knee straight onto its stop at mid-stance) and walks 3 % lower, while
/// the iCub and Talos walk at theirs (docs/findings/walking_robots.md, "The walk check").
pub const CHECK_LOWERING: f64 = 0.03;

/// The most runs of the walk check: the standing CoM height, then down to 12 % below it.
pub const CHECK_TRIES: usize = 5;

/// [`WalkTry::status`] of a run that could not be made: the file could not be written at its
/// height, did not build, or the run stopped on an error (its text is the reason); the check
/// ends there.
pub const RUN_FAILED: &str = "error";

/// One run of the walk check.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkTry {
    /// `walking.com_height` of the run [m].
    pub com_height: f64,
    /// The run's status: "completed", "diverged", "fell", "interrupted" or [`RUN_FAILED`].
    pub status: String,
    /// Why it ended before its duration (empty when completed).
    pub reason: String,
    /// Simulated time reached [s].
    pub duration_s: f64,
}

impl WalkTry {
    /// Whether no lower height is tried after this run: it completed, was stopped by a signal
    /// or could not be made; a run that diverged or fell goes on to the next height.
    pub fn ends_the_check(&self) -> bool {
        [
            RunEnd::Completed.status(),
            RunEnd::Interrupted.status(),
            RUN_FAILED,
        ]
        .contains(&self.status.as_str())
    }
}

impl std::fmt::Display for WalkTry {
    /// `com_height 0.660 m: diverged at 4.09 s (joint error ...)`, `... completed` or
    /// `... error (the error)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "com_height {:.3} m: {}", self.com_height, self.status)?;
        if self.status == RUN_FAILED {
            write!(f, " ({})", self.reason)
        } else if self.ends_the_check() {
            Ok(())
        } else {
            write!(f, " at {:.2} s ({})", self.duration_s, self.reason)
        }
    }
}

/// What the check of a written walk found ([`check_walk`]): its runs, in order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WalkCheck {
    /// The runs; the last one completed, was interrupted or could not be made, or none
    /// completed.
    pub tries: Vec<WalkTry>,
}

impl WalkCheck {
    /// The run that completed (its `com_height` is the one written), if any.
    pub fn completed(&self) -> Option<&WalkTry> {
        let completed = RunEnd::Completed.status();
        self.tries.iter().find(|t| t.status == completed)
    }

    /// Whether a stop signal ended the check before a run completed.
    pub fn interrupted(&self) -> bool {
        let interrupted = RunEnd::Interrupted.status();
        self.tries.last().is_some_and(|t| t.status == interrupted)
    }

    /// The run that could not be made ([`RUN_FAILED`]), which ended the check.
    pub fn failed(&self) -> Option<&WalkTry> {
        self.tries.last().filter(|t| t.status == RUN_FAILED)
    }
}

/// Runs the walk written at `out` ([`crate::scenario::run::run_with_sinks`], no record) at the
/// standing CoM height of `settings`, then, while the run does not complete, at
/// [`CHECK_LOWERING`] of it lower each time, [`CHECK_TRIES`] runs at most; `rewrite` writes
/// the scenario again with the settings of the next run. The file ends with the height of the
/// first run that completed, or with the standing height when none did, `stop` was raised
/// (which ends the run under way) or a run could not be made ([`RUN_FAILED`]: the file did not
/// build, a run failed, or the file could not be written for the next run; the error is the
/// run's reason). An error is returned only when the standing height cannot be written back.
pub fn check_walk(
    out: &std::path::Path,
    settings: &mut WalkingSettings,
    mut rewrite: impl FnMut(&WalkingSettings) -> Result<()>,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<WalkCheck> {
    let standing = settings.com_height;
    let mut check = WalkCheck::default();
    for k in 0..CHECK_TRIES {
        if k > 0 {
            let lowered = standing * (1.0 - k as f64 * CHECK_LOWERING);
            settings.com_height = (lowered * 1e3).round() / 1e3;
        }
        let run = match k {
            0 => Ok(()),
            _ => rewrite(settings),
        }
        .and_then(|()| walk_once(out, stop));
        let tried = match run {
            Ok(summary) => WalkTry {
                com_height: settings.com_height,
                status: summary.status.clone(),
                reason: summary.reason.clone(),
                duration_s: summary.duration_s,
            },
            Err(error) => WalkTry {
                com_height: settings.com_height,
                status: RUN_FAILED.into(),
                reason: error.to_string(),
                duration_s: 0.0,
            },
        };
        let ends = tried.ends_the_check();
        check.tries.push(tried);
        if ends {
            break;
        }
    }
    if check.completed().is_none() && settings.com_height != standing {
        settings.com_height = standing;
        rewrite(settings)?;
    }
    Ok(check)
}

/// One run of the walk written at `out`, stopped by `stop`, nothing recorded.
fn walk_once(out: &std::path::Path, stop: &std::sync::atomic::AtomicBool) -> Result<Summary> {
    let scenario = crate::scenario::Scenario::from_file(out, &[])?;
    crate::scenario::run::run_with_sinks(&scenario, &mut [], stop, |_, _| {})
}
