//! The `run` conveniences: a scenario built and handed to the closed loop (`sea_loop`), which
//! knows no scenario file: the loop's plain settings ([`Scenario::loop_settings`]) and the
//! controller stack's parts ([`super::ControllerConfig::stack_parts`]) come from here.

use super::{build, validate, Scenario, Setup};
use crate::error::Result;
use sea_loop::{
    DivergenceBounds, LoopSettings, RecordSink, RunRecord, RunScene, Sampling, Schedule, Summary,
};
use std::sync::atomic::AtomicBool;

impl Scenario {
    /// The time grid of the run (`controller.sampling`, `controller.rate_hz`,
    /// `controller.inner_rate_hz`, `plant.dt`, `simulation.duration_s`).
    pub fn schedule(&self) -> Schedule {
        let controller = &self.controller;
        let rates = (controller.rate_hz(), controller.inner_rate_hz);
        let simulation = &self.simulation;
        Schedule::new(
            controller.sampling,
            rates,
            self.plant.dt,
            simulation.duration_s,
        )
    }

    /// The loop's plain settings of this scenario: `[simulation]`, `[sensing]`,
    /// `[[disturbances]]`, the plant's integrator, and what the logs draw. The cross-field
    /// rules of `[sensing]` are checked here ([`validate::sensing`]).
    pub fn loop_settings(&self) -> Result<LoopSettings> {
        validate::sensing(self)?;
        let simulation = &self.simulation;
        let surface = &self.controller.contact.surface;
        Ok(LoopSettings {
            schedule: self.schedule(),
            method: self.plant.method,
            w_refresh_steps: self.plant.w_refresh_steps,
            duration_s: simulation.duration_s,
            record_every: simulation.record_every,
            bounds: DivergenceBounds {
                com_error_m: simulation.divergence_com_error_m,
                joint_error_rad: simulation.divergence_joint_error_rad,
                stop_at_joint_limits: simulation.stop_at_joint_limits,
            },
            stop_on_fall: simulation.stop_on_fall,
            fall_bounds: sea_loop::FallBounds {
                base_height_fraction: simulation.fall_base_height_fraction,
                tilt_rad: simulation.fall_tilt_rad,
            },
            sensing: self.sensing.clone(),
            disturbances: self.disturbances.clone(),
            scene: RunScene {
                urdf: self.urdf_path(),
                contacts: self.robot.contacts.clone(),
                foot: Some((surface.foot_x, surface.foot_y)),
            },
        })
    }
}

/// Runs a scenario into an in-memory record; `progress(t, duration)` is called about once per
/// simulated second. Not cancellable, no other sink (an MCAP log, the live view): see
/// [`run_with_sinks`].
pub fn run(scenario: &Scenario, progress: impl FnMut(f64, f64)) -> Result<(RunRecord, Summary)> {
    let mut record = RunRecord::default();
    let summary = run_with_sinks(
        scenario,
        &mut [&mut record],
        &AtomicBool::new(false),
        progress,
    )?;
    Ok((record, summary))
}

/// [`run`] that also hands back the setup as the run leaves it (its controller's gait,
/// counters and estimates readable; the plant's parameters beside them).
pub fn run_keeping_setup(scenario: &Scenario) -> Result<(RunRecord, Summary, Setup)> {
    let mut setup = build(scenario)?;
    let mut record = RunRecord::default();
    let cancel = AtomicBool::new(false);
    let summary =
        run_setup_with_sinks(scenario, &mut setup, &mut [&mut record], &cancel, |_, _| ())?;
    Ok((record, summary, setup))
}

/// Runs a scenario, handing every recorded sample to each of `sinks` (none: only the
/// summary, in constant memory); see [`sea_loop::run_setup_with_sinks`] for `cancel`,
/// `progress` and how the sinks are finished.
pub fn run_with_sinks(
    scenario: &Scenario,
    sinks: &mut [&mut dyn RecordSink],
    cancel: &AtomicBool,
    progress: impl FnMut(f64, f64),
) -> Result<Summary> {
    let mut setup = build(scenario)?;
    run_setup_with_sinks(scenario, &mut setup, sinks, cancel, progress)
}

/// [`run_with_sinks`] on `setup`, already built from `scenario` (and possibly adjusted, e.g.
/// a controller with its QP cross-check on); the setup is left as the run ends (its
/// controller's counters readable).
pub fn run_setup_with_sinks(
    scenario: &Scenario,
    setup: &mut Setup,
    sinks: &mut [&mut dyn RecordSink],
    cancel: &AtomicBool,
    progress: impl FnMut(f64, f64),
) -> Result<Summary> {
    let located = |e| scenario.origin.locate(e);
    let settings = scenario.loop_settings().map_err(located)?;
    let multi_rate = settings.schedule.sampling == Sampling::MultiRate;
    let period = settings.schedule.period;
    let parts = scenario
        .controller
        .stack_parts(&setup.controller, period, multi_rate)
        .map_err(located)?;
    sea_loop::run_setup_with_sinks((&settings, setup, parts), sinks, cancel, progress)
        .map_err(located)
}
