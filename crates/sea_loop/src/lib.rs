//! `sea_loop`: the closed loop of a plant and the robot's controller stack, knowing no file
//! format. Built objects ([`Setup`], the stack's parts) and plain settings
//! ([`LoopSettings`]) in; samples to [`RecordSink`]s and a [`Summary`] out.
//!
//! The controller sampled with zero-order hold at its rate, continuously (at every integrator
//! stage) or multi-rate (the whole-body law over joint loops, `sea_ctrl::robot`); the plant
//! with its motor velocity loop; divergence detection; recording into sinks; online summary
//! statistics; cancellation.
//!
//! - `tick`: one sample period (the stack's tick, the bounds, the plant's advance);
//! - [`sampling`]: the sampling and the run's time grid ([`Schedule`]);
//! - [`sensing`]: the measurement model (noise and delay of the controller's state);
//! - [`disturbance_schedule`]: external wrenches on links over time windows;
//! - [`record`]: [`Sample`], the [`RecordSink`] trait and the in-memory [`RunRecord`];
//! - [`contact_check`]: fall detection under bilateral contacts, each foot's wrench against
//!   a unilateral contact with friction;
//! - [`fall_check`]: falls as physics under unilateral contacts (base height, tilt, a link on
//!   the ground), and [`Fall`], either kind;
//! - [`impacts`]: touchdowns of the feet and joints reaching their stops at plant-step
//!   resolution, with the velocity jump and the actuators' peaks around each ([`Impact`]);
//! - [`statistics`]: running statistics, how a run ended ([`RunEnd`], [`Divergence`]) and the
//!   [`Summary`];
//! - [`settings`]: [`Setup`] and [`LoopSettings`];
//! - [`error`]: the one error type of the application crates.
//!
//! The loop knows its outputs only as [`RecordSink`]s: the MCAP log and the live view are
//! sinks above it (`sea_viz`).
//!
//! A run stops as "diverged" when the controller or a plant step fails, the state is not
//! finite, the CoM error or the joint error norm exceeds its bound ([`DivergenceBounds`]); the
//! sample that crossed a bound is the last one recorded, and the reason ([`Divergence`])
//! names the quantity, its value and the bound. A raised cancellation flag stops the run at
//! the next sample with status "interrupted". A foot whose simulated contact wrench has a
//! non-positive normal force, leaves the friction cone or puts its centre of pressure outside
//! the sole ends the run as "fell" under bilateral contacts (checked at every sample whose
//! plant evaluation succeeded; [`contact_check`]); under unilateral contacts the feet may
//! lift, tip and slip, and the run falls when the robot reaches the ground ([`fall_check`]).
//! Either way the sinks are finished.

#![forbid(unsafe_code)]

mod bounds;
pub mod contact_check;
pub mod disturbance_schedule;
pub mod error;
pub mod fall_check;
pub mod impacts;
pub mod record;
pub mod sampling;
pub mod sensing;
pub mod settings;
pub mod statistics;
mod tick;

pub use contact_check::{
    ContactCheckEvent, ContactConstraint, VerdictChange, WrenchCheck, WrenchFall,
};
pub use disturbance_schedule::{DisturbanceConfig, DisturbanceSchedule};
pub use error::{Error, Result};
pub use fall_check::{Fall, FallBounds, PhysicalFall};
pub use impacts::{Impact, ImpactKind};
pub use record::{OwnedSample, RecordSink, RunInfo, RunRecord, Sample};
pub use sampling::{equal_steps, inner_ticks, Sampling, Schedule};
pub use sensing::SensingConfig;
pub use settings::{DivergenceBounds, LoopSettings, RunScene, Setup};
pub use statistics::{
    Divergence, FallSummary, RunEnd, RunTotals, RunningStatistics, Summary, NON_SCALAR_FIELDS,
};

use sea_ctrl::robot::StackParts;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use tick::Engine;

/// Runs `setup` with the controller stack's `parts` under `settings`, handing every recorded
/// sample to each of `sinks` (none: only the summary, in constant memory); the setup is left
/// as the run ends (its controller's counters readable). `cancel` is read at every sample:
/// once it is `true` the run records the current sample and ends with status "interrupted"
/// at the time reached. `progress(t, duration)` is called about once per simulated second.
/// The sinks are finished however the run ends; a sink error ends the run and is returned
/// (after finishing the others).
pub fn run_setup_with_sinks(
    (settings, setup, parts): (&LoopSettings, &mut Setup, StackParts),
    sinks: &mut [&mut dyn RecordSink],
    cancel: &AtomicBool,
    mut progress: impl FnMut(f64, f64),
) -> Result<Summary> {
    let start = Instant::now();
    let mut engine = Engine::new(settings, setup, parts)?;
    let mut statistics = RunningStatistics::default();
    let info = engine.info(cancel);
    let outcome = sinks
        .iter_mut()
        .try_for_each(|sink| sink.begin(&info))
        .and_then(|()| drive(&mut engine, sinks, &mut statistics, cancel, &mut progress));
    // The impacts still open end with the run: the sinks get them before the end.
    engine.close_impacts();
    let outcome = outcome.and_then(|ended| deliver_impacts(&mut engine, sinks).map(|()| ended));
    // Each sink learns how the run ended (when it did not fail), then every sink finishes.
    let outcome = outcome.and_then(|(end, duration_s)| {
        sinks
            .iter_mut()
            .try_for_each(|sink| sink.end(&end))
            .map(|()| (end, duration_s))
    });
    let finished = sinks
        .iter_mut()
        .map(|sink| sink.finish())
        .fold(Ok(()), Result::and);
    let (end, duration_s) = outcome?;
    finished?;
    let controller = engine.robot.controller();
    let solves = controller.qp_solves();
    let totals = RunTotals {
        duration_s,
        qp_failures: controller.qp_failures(),
        qp_relaxed_solves: controller.qp_relaxations(),
        qp_active_set_solves: solves.active_set,
        qp_clarabel_solves: solves.clarabel,
        wall_time_s: start.elapsed().as_secs_f64(),
    };
    let sampling = engine.schedule.sampling.name();
    let mut summary = Summary::new(&end, sampling, &statistics, totals);
    summary.stiffness_estimates = engine.stiffness_estimates();
    summary.add_impacts(engine.impacts());
    let check = engine.contact_check_count();
    summary.contact_check_violations = check.violations;
    summary.contact_check_first_s = check.first_s;
    if let Some(walked) = engine.walked(duration_s) {
        summary.steps_taken = Some(walked.steps);
        summary.distance_walked_m = Some(walked.distance_m);
        summary.walking_speed_m_s = walked.speed_m_s;
        summary.turned_rad = Some(walked.turned_rad);
    }
    Ok(summary)
}

/// Hands the impacts complete since the last call to every sink.
fn deliver_impacts(engine: &mut Engine<'_>, sinks: &mut [&mut dyn RecordSink]) -> Result<()> {
    for impact in engine.new_impacts() {
        for sink in sinks.iter_mut() {
            sink.impact(impact)?;
        }
    }
    Ok(())
}

/// Hands the controller's walk to every sink when it changed since `revision` (which it
/// updates; [`sea_ctrl::MomentumController::gait_revision`]).
fn deliver_walking(
    engine: &Engine<'_>,
    sinks: &mut [&mut dyn RecordSink],
    revision: &mut Option<u64>,
) -> Result<()> {
    let now = engine.gait_revision();
    if now == *revision {
        return Ok(());
    }
    *revision = now;
    if let Some(gait) = engine.gait() {
        for sink in sinks.iter_mut() {
            sink.walking(gait)?;
        }
    }
    Ok(())
}

/// Hands the contact check's verdict changes since the last call to every sink.
fn deliver_contact_checks(
    engine: &mut Engine<'_>,
    sinks: &mut [&mut dyn RecordSink],
) -> Result<()> {
    for event in engine.new_contact_check_events() {
        for sink in sinks.iter_mut() {
            sink.contact_check(&event)?;
        }
    }
    Ok(())
}

/// The loop over samples: each period's observation goes to the statistics and, every
/// `simulation.record_every` samples and at the last one, to the sinks. Returns how the run
/// ended and the time reached.
fn drive(
    engine: &mut Engine<'_>,
    sinks: &mut [&mut dyn RecordSink],
    statistics: &mut RunningStatistics,
    cancel: &AtomicBool,
    progress: &mut impl FnMut(f64, f64),
) -> Result<(RunEnd, f64)> {
    let record_every = engine.record_every();
    let duration = engine.duration();
    let mut last_progress = 0.0;
    let mut gait_revision = engine.gait_revision();
    for index in 0..=engine.schedule.last_sample {
        let time = engine.schedule.time(index);
        let period = match engine.period(index, cancel.load(Ordering::Relaxed)) {
            Ok(period) => period,
            Err(reason) => return Ok((RunEnd::Diverged { at_s: time, reason }, time)),
        };
        let observation = engine.observation();
        let lateral = observation.output.com.y - observation.reference.position.y;
        let thetadot = engine.layout().thetadot(engine.state());
        statistics.add(
            time,
            observation.com_error,
            lateral,
            observation.joint_error,
            thetadot,
        );
        // Every change of the walk, not only the last before a sample: a drawing that splices
        // a swing re-aimed at each tick needs each re-aim.
        deliver_walking(engine, sinks, &mut gait_revision)?;
        if index % record_every == 0 || period.end.is_some() {
            let sample = engine.sample();
            for sink in sinks.iter_mut() {
                sink.record(&sample)?;
            }
        }
        deliver_contact_checks(engine, sinks)?;
        deliver_impacts(engine, sinks)?;
        if let Some(end) = period.end {
            return Ok((end, time));
        }
        engine.commit();
        if time - last_progress >= 1.0 {
            last_progress = time;
            progress(time, duration);
        }
    }
    // The last sample always ends the run (Engine::period); kept total for the compiler.
    let last = engine.schedule.last_sample;
    Ok((RunEnd::Completed, engine.schedule.time(last)))
}
