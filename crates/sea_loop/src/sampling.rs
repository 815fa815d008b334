//! Control sampling (`controller.sampling`) and the time grid it gives a run.
//!
//! - Zero-order hold: the controller runs at `controller.rate_hz` and its input is held over
//!   the control period, which is split into the smallest whole number of equal plant steps
//!   not longer than `plant.dt` (so any rate works with any step bound).
//! - Continuous: the controller is evaluated at every stage of every plant step, as in the
//!   paper, whose controller runs inside ode15s's right-hand side; the run is split into equal
//!   steps not longer than `plant.dt` and `controller.rate_hz` is not used.
//! - Multi-rate: the whole-body controller at `controller.rate_hz` (the samples), its desired
//!   joint torques held over its period; that period is `inner_ticks` periods of the joint
//!   torque loops (`controller.inner_rate_hz`), each split into the smallest whole number of
//!   equal plant steps not longer than `plant.dt`.

/// `controller.sampling`: how the controller is sampled.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Deserialize,
    serde::Serialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// At every integrator stage, as in the paper (its controller runs inside ode15s's
    /// right-hand side).
    Continuous,
    /// At `controller.rate_hz`, the input held between ticks (the default).
    #[default]
    ZeroOrderHold,
    /// The robot's architecture: the whole-body controller at `controller.rate_hz` (default
    /// 100 Hz), its desired joint torques held, and per elastic joint a torque loop
    /// (`sea_ctrl::joint_loop`) at `controller.inner_rate_hz` that sets the desired motor
    /// velocity from the measured deflection and joint velocity.
    MultiRate,
}

impl Sampling {
    /// The value's name in scenario files (its serde name).
    pub fn name(self) -> &'static str {
        match self {
            Sampling::ZeroOrderHold => "zero_order_hold",
            Sampling::Continuous => "continuous",
            Sampling::MultiRate => "multi_rate",
        }
    }

    /// The default of `controller.rate_hz` [Hz] under this sampling: 1 kHz (the paper's
    /// sampled-data study), 100 Hz for the whole-body loop of `multi_rate` (the iCub's
    /// whole-body controllers' rate, docs/references.md "Control rates of real robots").
    pub fn default_rate_hz(self) -> f64 {
        match self {
            Sampling::Continuous | Sampling::ZeroOrderHold => 1000.0,
            Sampling::MultiRate => 100.0,
        }
    }
}

/// The time grid of a run: samples `0..=last_sample` at `index * period` (control ticks with
/// zero-order hold, plant steps in continuous mode); between two samples, `steps_per_period`
/// plant steps of `step` seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Schedule {
    /// The sampling setting.
    pub sampling: Sampling,
    /// Time between two samples [s].
    pub period: f64,
    /// Plant steps between two samples (1 in continuous mode).
    pub steps_per_period: usize,
    /// Joint loop ticks per sample period (multi-rate; 1 otherwise): each holds its input
    /// over `steps_per_period / inner_ticks` plant steps.
    pub inner_ticks: usize,
    /// Plant step [s], at most `plant.dt`.
    pub step: f64,
    /// Index of the last sample (the end of the run).
    pub last_sample: usize,
}

impl Schedule {
    /// The grid of a run under `sampling` with the whole-body rate `rate_hz` and the joint
    /// loops' `inner_rate_hz` [Hz] (multi-rate), plant steps of at most `max_step` [s], over
    /// `duration` [s]. (`controller.sampling`, `controller.rate_hz`,
    /// `controller.inner_rate_hz`, `plant.dt`, `simulation.duration_s` in scenario files.)
    pub fn new(
        sampling: Sampling,
        (rate_hz, inner_rate_hz): (f64, f64),
        max_step: f64,
        duration: f64,
    ) -> Schedule {
        match sampling {
            Sampling::ZeroOrderHold => {
                let period = 1.0 / rate_hz;
                let steps_per_period = equal_steps(period, max_step);
                Schedule {
                    sampling,
                    period,
                    steps_per_period,
                    inner_ticks: 1,
                    step: period / steps_per_period as f64,
                    last_sample: (duration / period).round() as usize,
                }
            }
            Sampling::Continuous => {
                let steps = equal_steps(duration, max_step);
                let step = duration / steps as f64;
                Schedule {
                    sampling,
                    period: step,
                    steps_per_period: 1,
                    inner_ticks: 1,
                    step,
                    last_sample: steps,
                }
            }
            Sampling::MultiRate => {
                let period = 1.0 / rate_hz;
                let inner_ticks = inner_ticks(rate_hz, inner_rate_hz);
                let steps_per_inner = equal_steps(period / inner_ticks as f64, max_step);
                let steps_per_period = inner_ticks * steps_per_inner;
                Schedule {
                    sampling,
                    period,
                    steps_per_period,
                    inner_ticks,
                    step: period / steps_per_period as f64,
                    last_sample: (duration / period).round() as usize,
                }
            }
        }
    }

    /// Plant steps per joint loop tick.
    pub fn steps_per_inner_tick(&self) -> usize {
        self.steps_per_period / self.inner_ticks
    }

    /// Time of sample `index` [s].
    pub fn time(&self, index: usize) -> f64 {
        index as f64 * self.period
    }
}

/// The smallest whole number of equal steps not longer than `max_step` that make up `span`
/// (at least 1). A span that is a whole number of steps up to rounding keeps that number.
pub fn equal_steps(span: f64, max_step: f64) -> usize {
    const ROUNDING: f64 = 1e-9;
    ((span / max_step) * (1.0 - ROUNDING)).ceil().max(1.0) as usize
}

/// Joint loop ticks per whole-body period: `inner_rate_hz / rate_hz`, rounded (validation
/// requires a whole multiple, at least 1).
pub fn inner_ticks(rate_hz: f64, inner_rate_hz: f64) -> usize {
    (inner_rate_hz / rate_hz).round().max(1.0) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_rate_splits_the_period_into_inner_ticks_of_whole_steps() {
        let schedule = Schedule::new(Sampling::MultiRate, (100.0, 1000.0), 0.0004, 10.0);
        assert_eq!(schedule.period, 0.01);
        assert_eq!(schedule.inner_ticks, 10);
        assert_eq!(schedule.steps_per_inner_tick(), 3);
        assert_eq!(schedule.steps_per_period, 30);
        assert_eq!(schedule.last_sample, 1000);
        let schedule = Schedule::new(Sampling::MultiRate, (250.0, 2000.0), 0.0004, 10.0);
        assert_eq!(
            (schedule.inner_ticks, schedule.steps_per_inner_tick()),
            (8, 2)
        );
    }

    #[test]
    fn equal_steps_are_the_fewest_not_longer_than_the_bound() {
        assert_eq!(equal_steps(1e-3, 1e-3), 1);
        assert_eq!(equal_steps(1.0 / 1000.0, 0.5e-3), 2);
        assert_eq!(equal_steps(1.0 / 4000.0, 1e-3), 1);
        // 550 Hz with a 1 ms bound: 1.818... ms in 2 steps of 0.909 ms.
        assert_eq!(equal_steps(1.0 / 550.0, 1e-3), 2);
        assert_eq!(equal_steps(1.0 / 300.0, 1e-3), 4);
        assert_eq!(equal_steps(10.0, 1e-3), 10_000);
        assert_eq!(equal_steps(10.0, 0.3e-3), 33_334);
        for (span, bound) in [(1.0 / 550.0, 1e-3), (1.0 / 300.0, 1e-3), (10.0, 0.3e-3)] {
            let n = equal_steps(span, bound);
            assert!(span / n as f64 <= bound * (1.0 + 1e-9));
            assert!(span / (n - 1) as f64 > bound);
        }
    }
}
