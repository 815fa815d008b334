//! The push of the push studies ([`super::push`]): where, when and how long it acts, and the
//! checks of those options against a scenario before any run.

use crate::error::Result;
use sea_dyn::error::check_positive;
use sea_loop::disturbance_schedule::whole_steps_of;
use sea_scenario::{build, Scenario};

/// The push: where, when, how long, and the bisection's resolution.
#[derive(Clone, Debug)]
pub struct PushOptions {
    /// The pushed link (its origin).
    pub link: String,
    /// Start of the push [s] (a whole number of plant steps).
    pub start_s: f64,
    /// Length of the push [s] (a whole number of plant steps).
    pub duration_s: f64,
    /// The bisection stops when the bracket is narrower than this [N s].
    pub tolerance_n_s: f64,
}

impl Default for PushOptions {
    /// 0.1 s on the iCub's pelvis (`root_link`) at 1 s, to 0.1 N s.
    fn default() -> Self {
        Self {
            link: "root_link".into(),
            start_s: 1.0,
            duration_s: 0.1,
            tolerance_n_s: 0.1,
        }
    }
}

impl PushOptions {
    /// Checks the options before any run: `duration_s` and `tolerance_n_s` finite and positive
    /// (a zero duration is an infinite force; a zero tolerance a bisection that never ends),
    /// `start_s` finite and non-negative.
    ///
    /// Errors: [`sea_dyn::Error::InvalidArgument`] naming the field and the value.
    pub fn check(&self) -> Result<()> {
        check_positive("PushOptions.duration_s", self.duration_s)?;
        check_positive("PushOptions.tolerance_n_s", self.tolerance_n_s)?;
        if !(self.start_s.is_finite() && self.start_s >= 0.0) {
            let expected = "a finite, non-negative time [s]";
            return Err(
                sea_dyn::Error::invalid("PushOptions.start_s", expected, self.start_s).into(),
            );
        }
        Ok(())
    }

    /// Checks the options against the scenario they push: `link` names a link of its robot,
    /// and the push ends within the run (`start_s + duration_s` at most
    /// `simulation.duration_s`; a push after the run's end would be "recovered" at any size).
    ///
    /// Errors: [`sea_dyn::Error::InvalidArgument`] naming `PushOptions.link` or
    /// `PushOptions.start_s`, and the scenario's.
    pub fn check_against(&self, scenario: &Scenario) -> Result<()> {
        check_pushed_link(scenario, &self.link)?;
        self.check_within_run(scenario)
    }

    /// The push ends within the `scenario`'s run (the half of [`Self::check_against`] that
    /// loads nothing).
    ///
    /// Its start and length are whole numbers of the scenario's plant steps.
    ///
    /// Errors: [`sea_dyn::Error::InvalidArgument`] naming `PushOptions.start_s` or
    /// `PushOptions.duration_s`.
    pub fn check_within_run(&self, scenario: &Scenario) -> Result<()> {
        let step = scenario.plant.dt;
        for (key, time) in [
            ("PushOptions.start_s", self.start_s),
            ("PushOptions.duration_s", self.duration_s),
        ] {
            if whole_steps_of(time, step).is_none() {
                let expected = format!("a whole number of plant steps of {step} s");
                return Err(sea_dyn::Error::invalid(key, expected, time).into());
            }
        }
        let run = scenario.simulation.duration_s;
        if self.start_s + self.duration_s > run {
            let expected = format!("a push that ends within the run's {run} s (start + duration)");
            return Err(
                sea_dyn::Error::invalid("PushOptions.start_s", expected, self.start_s).into(),
            );
        }
        Ok(())
    }

    /// A warning when the `scenario`'s run ends less than [`SETTLE_AFTER_PUSH_S`] after the
    /// push: a push that fells the robot may then end the run before the fall, and read as
    /// recovered. `None` when the run leaves that long, or when the push ends after the run
    /// (an error of [`Self::check_within_run`]).
    pub fn short_run_warning(&self, scenario: &Scenario) -> Option<String> {
        let after = scenario.simulation.duration_s - (self.start_s + self.duration_s);
        (0.0..SETTLE_AFTER_PUSH_S).contains(&after).then(|| {
            format!(
                "the run ends {after:.3} s after the push (simulation.duration_s {}): a push \
                 that fells the robot can take about {SETTLE_AFTER_PUSH_S} s to show as a fall, \
                 so a push may read as recovered that is not",
                scenario.simulation.duration_s
            )
        })
    }
}

/// How long a run should go on after a push's end for a push that fells the robot to show as
/// a fall [s]: the iCub's lost standing pushes tip its base past 60 degrees 0.96 to 1.09 s
/// after the push ends (docs/findings/stepping.md, "The legs at their reach" and "With the
/// knees bent").
pub const SETTLE_AFTER_PUSH_S: f64 = 1.0;

/// `link` names a link of the `scenario`'s robot (its model loaded, nothing run).
///
/// Errors: [`sea_dyn::Error::InvalidArgument`] naming `PushOptions.link`, and the scenario's
/// (a key's with its file and line).
pub fn check_pushed_link(scenario: &Scenario, link: &str) -> Result<()> {
    let model = build::load_model(scenario).map_err(|e| scenario.origin.locate(e))?;
    if model.frame_id(link).is_err() {
        let expected = "a link of the scenario's robot";
        return Err(sea_dyn::Error::invalid("PushOptions.link", expected, link).into());
    }
    Ok(())
}
