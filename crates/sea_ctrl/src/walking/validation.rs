//! The checks of [`WalkingSettings`]: [`WalkingSettings::validate`] and its parts (the
//! timing, the geometry, the toe-off, the command, stepping), each error naming the key
//! (`walking.step_duration`, ...), the rule and the value.

use super::settings::{WalkingSettings, MAX_COMMAND_STEPS};
use super::step_timing::StepTiming;
use crate::error::{require_non_negative, require_positive, Error, Result};

impl WalkingSettings {
    /// Checks every setting for a controller whose whole-body period is `whole_body_period`
    /// [s] (no phase may be shorter than one tick); the error names the key, the rule and
    /// the value.
    pub fn validate(&self, whole_body_period: f64) -> Result<()> {
        require_positive("whole_body_period", whole_body_period)?;
        self.validate_timing(whole_body_period)?;
        self.validate_geometry()?;
        self.validate_toe_off()?;
        self.validate_command()
    }

    /// The swing's toe-off: its pitch and the fraction of the swing it lasts.
    fn validate_toe_off(&self) -> Result<()> {
        let pitch = self.swing_toe_off_pitch;
        if !(0.0..=0.5).contains(&pitch) {
            return Err(Error::invalid(
                "walking.swing_toe_off_pitch",
                "must be in [0, 0.5] rad (toe down)",
                pitch,
            ));
        }
        fraction_of_swing("walking.swing_toe_off_end", self.swing_toe_off_end)
    }

    /// The durations: steps, double and single support, transfers, recovery swings.
    fn validate_timing(&self, period: f64) -> Result<()> {
        let at_least_period =
            format!("must be finite and at least one whole-body period ({period} s)");
        for (key, value) in [
            ("walking.step_duration", self.step_duration),
            (
                "walking.double_support_duration",
                self.double_support_duration,
            ),
            ("walking.transfer_duration", self.transfer_duration),
            ("walking.min_swing_duration", self.min_swing_duration),
            (
                "walking.min_adjusted_swing_duration",
                self.min_adjusted_swing_duration,
            ),
            (
                "walking.recovery_transfer_duration",
                self.recovery_transfer_duration,
            ),
        ] {
            if !(value.is_finite() && value >= period) {
                return Err(Error::invalid(key, at_least_period.clone(), value));
            }
        }
        if self.single_support_duration() < period {
            return Err(Error::invalid(
                "walking.double_support_duration",
                format!(
                    "must leave a single support of at least one whole-body period ({period} s) \
                     within walking.step_duration = {} s",
                    self.step_duration
                ),
                self.double_support_duration,
            ));
        }
        let retimed = self.step_timing != StepTiming::Fixed;
        if retimed && self.min_adjusted_swing_duration > self.single_support_duration() {
            return Err(Error::invalid(
                "walking.min_adjusted_swing_duration",
                format!(
                    "must be at most the single support, walking.step_duration - \
                     walking.double_support_duration = {:.4} s",
                    self.single_support_duration()
                ),
                self.min_adjusted_swing_duration,
            ));
        }
        let toe_off_end = self.swing_toe_off_end * self.single_support_duration();
        let toe_off = self.swing_toe_off_pitch > 0.0;
        if retimed && toe_off && self.min_adjusted_swing_duration < toe_off_end {
            return Err(Error::invalid(
                "walking.min_adjusted_swing_duration",
                format!(
                    "must be at least the toe-off's end, walking.swing_toe_off_end times the \
                     single support = {toe_off_end:.4} s, so that a retimed foot lands flat"
                ),
                self.min_adjusted_swing_duration,
            ));
        }
        Ok(())
    }

    /// Heights, widths, reach and turn; the margins, gains, weights and times that must be
    /// non-negative.
    fn validate_geometry(&self) -> Result<()> {
        for (key, value) in [
            ("walking.com_height", self.com_height),
            ("walking.max_step_length", self.max_step_length),
            ("walking.min_step_width", self.min_step_width),
            ("walking.max_step_width", self.max_step_width),
        ] {
            require_positive(key, value)?;
        }
        for (key, value) in [
            ("walking.swing_height", self.swing_height),
            (
                "walking.capture_margin.forward",
                self.capture_margin.forward,
            ),
            (
                "walking.capture_margin.backward",
                self.capture_margin.backward,
            ),
            (
                "walking.capture_margin.sideways",
                self.capture_margin.sideways,
            ),
            ("walking.recovery_step_offset", self.recovery_step_offset),
            ("walking.identification_settle", self.identification_settle),
            (
                "walking.identification_single_support",
                self.identification_single_support.unwrap_or(0.0),
            ),
            (
                "walking.step_adjustment_threshold",
                self.step_adjustment_threshold,
            ),
            ("walking.swing_position_gain", self.swing_position_gain),
            ("walking.swing_velocity_gain", self.swing_velocity_gain),
            ("walking.settle_position_gain", self.settle_position_gain),
            ("walking.settle_velocity_gain", self.settle_velocity_gain),
            (
                "walking.double_support_momentum_weight",
                self.double_support_momentum_weight,
            ),
            ("walking.touchdown_debounce", self.touchdown_debounce),
        ] {
            require_non_negative(key, value)?;
        }
        self.validate_widths()?;
        fraction_of_swing(
            "walking.step_adjustment_end_phase",
            self.step_adjustment_end_phase,
        )?;
        let turn = self.max_step_turn;
        if !(turn > 0.0 && turn <= std::f64::consts::FRAC_PI_2) {
            return Err(Error::invalid(
                "walking.max_step_turn",
                "must be in (0, pi/2] rad",
                turn,
            ));
        }
        Ok(())
    }

    /// The step widths' limits in order, and the nominal width between them.
    fn validate_widths(&self) -> Result<()> {
        let (min, max) = (self.min_step_width, self.max_step_width);
        if min >= max {
            return Err(Error::invalid(
                "walking.max_step_width",
                format!("must exceed walking.min_step_width = {min} m"),
                max,
            ));
        }
        let width = self.nominal_width;
        if !(width.is_finite() && min < width && width < max) {
            return Err(Error::invalid(
                "walking.nominal_width",
                format!(
                    "must lie between walking.min_step_width = {min} m and \
                     walking.max_step_width = {max} m"
                ),
                width,
            ));
        }
        Ok(())
    }

    /// The command's velocities and length (only when it is used: `footsteps` empty).
    fn validate_command(&self) -> Result<()> {
        let command = &self.command;
        for (key, value) in [
            ("walking.command.forward_velocity", command.forward_velocity),
            (
                "walking.command.sideways_velocity",
                command.sideways_velocity,
            ),
            ("walking.command.turning_velocity", command.turning_velocity),
        ] {
            if !value.is_finite() {
                return Err(Error::invalid(key, "must be finite", value));
            }
        }
        if let Some(steps) = command.steps {
            if steps == 0 || steps > MAX_COMMAND_STEPS {
                return Err(Error::invalid(
                    "walking.command.steps",
                    format!("must be at least 1 and at most {MAX_COMMAND_STEPS}"),
                    steps,
                ));
            }
        }
        if let Some(duration) = command.duration {
            let longest = MAX_COMMAND_STEPS as f64 * self.step_duration;
            if !(duration.is_finite() && duration > 0.0 && duration < longest) {
                return Err(Error::invalid(
                    "walking.command.duration",
                    format!(
                        "must be positive and below {longest} s ({MAX_COMMAND_STEPS} steps of \
                         walking.step_duration)"
                    ),
                    duration,
                ));
            }
        }
        if self.max_recovery_steps == 0 {
            return Err(Error::invalid(
                "walking.max_recovery_steps",
                "must be at least 1",
                0,
            ));
        }
        if self.stepping && self.step_adjustment {
            return Err(Error::config(
                "walking.step_adjustment",
                "adjusts the steps of a walk; walking.stepping (standing) takes its own \
                 recovery steps: set one of them",
            ));
        }
        if self.stepping {
            return self.validate_stepping();
        }
        let command_given = command.steps.is_some()
            || command.duration.is_some()
            || [
                command.forward_velocity,
                command.sideways_velocity,
                command.turning_velocity,
            ]
            .iter()
            .any(|&velocity| velocity != 0.0);
        if !self.footsteps.is_empty() && command_given {
            return Err(Error::config(
                "walking.command",
                "is not used when walking.footsteps is given (the walk follows the list): \
                 remove one of them",
            ));
        }
        if self.footsteps.is_empty() && command.steps.is_some() == command.duration.is_some() {
            return Err(Error::config(
                "walking.command.steps",
                "set exactly one of walking.command.steps and walking.command.duration \
                 (or give walking.footsteps, or stand with walking.stepping = true)",
            ));
        }
        Ok(())
    }

    /// Stepping: standing only (no command length, no footsteps).
    fn validate_stepping(&self) -> Result<()> {
        if self.command.steps.is_some()
            || self.command.duration.is_some()
            || !self.footsteps.is_empty()
        {
            return Err(Error::config(
                "walking.stepping",
                "stepping recovers pushes while standing: leave walking.command.steps, \
                 walking.command.duration and walking.footsteps unset (pushes while walking \
                 are not handled)",
            ));
        }
        Ok(())
    }
}

/// `value` of the setting `key` as a fraction of a swing: in (0, 1], or the error naming `key`.
fn fraction_of_swing(key: &str, value: f64) -> Result<()> {
    if value > 0.0 && value <= 1.0 {
        return Ok(());
    }
    Err(Error::invalid(
        key,
        "must be in (0, 1], a fraction of the swing",
        value,
    ))
}
