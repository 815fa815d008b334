//! Control sampling (`controller.sampling`) and the time grid it gives a run.
//!
//! - Zero-order hold: the controller runs at `controller.rate_hz` and its input is held over
//!   the control period, which is split into the smallest whole number of equal plant steps
//!   not longer than `plant.dt` (so any rate works with any step bound).
//! - Continuous: the controller is evaluated at every stage of every plant step, as in the
//!   paper, whose controller runs inside ode15s's right-hand side; the run is split into equal
//!   steps not longer than `plant.dt` and `controller.rate_hz` is not used.

use crate::error::Result;
/// The setting, typed in the scenario schema.
pub use crate::scenario::Sampling;
use crate::scenario::Scenario;

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
    /// Plant step [s], at most `plant.dt`.
    pub step: f64,
    /// Index of the last sample (the end of the run).
    pub last_sample: usize,
}

impl Schedule {
    /// The grid of `scenario` (`controller.sampling`, `controller.rate_hz`, `plant.dt`,
    /// `simulation.duration_s`).
    pub fn of(scenario: &Scenario) -> Result<Schedule> {
        let sampling = scenario.controller.sampling;
        let (duration, max_step) = (scenario.simulation.duration_s, scenario.plant.dt);
        Ok(match sampling {
            Sampling::ZeroOrderHold => {
                let period = 1.0 / scenario.controller.rate_hz;
                let steps_per_period = equal_steps(period, max_step);
                Schedule {
                    sampling,
                    period,
                    steps_per_period,
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
                    step,
                    last_sample: steps,
                }
            }
        })
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

#[cfg(test)]
mod tests {
    use super::*;

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
