//! Every scenario value checked against its meaning before anything is built. Names, types
//! and the bounds of single values (numbers, the entries of arrays and tables) are the
//! schema's, checked by serde when the file is read ([`super::bounded`]); here: the rules
//! between keys and feasibility where it is cheap. Each failure is an
//! [`Error::Scenario`] naming the dotted key, the rule and the value, so a typo or a value
//! outside the physics is reported before a run instead of surfacing as failing QPs, a
//! divergence at t = 0 or a feature silently switched off.
//!
//! [`scenario`] checks what the file alone decides; [`against_model`] what needs the robot
//! (a minimum normal force the robot's weight cannot supply).

use super::{
    ActuatorConfig, ActuatorKind, ControllerConfig, ControllerKind, ExternalWrench, PlantConfig,
    Sampling, Scenario, Setting, SimulationConfig,
};
use crate::error::{Error, Result};
use sea_loop::inner_ticks;

/// The bounds of `controller.contact.facets` (declared by the contact constraints).
pub use sea_ctrl::qp::{MAX_FRICTION_FACETS, MIN_FRICTION_FACETS};

/// Largest number of plant steps (or controller samples) of one run: about a day of wall
/// time; more is a typo (a step of 1e-300 s, a rate of 1e300 Hz) that would hang the run.
pub const MAX_RUN_STEPS: f64 = 1e10;

/// Shortest plant step a run takes [s]: the impact report keeps the last 50 ms of steps, so a
/// step of 1 ps would ask for hundreds of GB; the scenarios step at 0.25 to 1 ms with an
/// L-stable integrator.
pub const MIN_PLANT_STEP_S: f64 = 1e-6;

/// Checks every value of `scenario` that does not need the robot model.
pub fn scenario(scenario: &Scenario) -> Result<()> {
    robot(scenario)?;
    actuators(scenario)?;
    // Before the controller's checks, which derive bounds from the rates.
    plant_step(scenario)?;
    controller(scenario)?;
    super::disturbances::validate(&scenario.disturbances)?;
    sensing(scenario)?;
    walking(scenario)?;
    run_length(scenario)
}

/// The plant step the run takes, at most `plant.dt` and one per joint-loop tick (multi-rate)
/// or per whole-body tick (sampled), must be at least [`MIN_PLANT_STEP_S`]; the key named is
/// the one that sets the step. A value that gives no positive finite step is left to its own
/// check.
fn plant_step(scenario: &Scenario) -> Result<()> {
    let c = &scenario.controller;
    let mut candidates = vec![("plant.dt", scenario.plant.dt, scenario.plant.dt)];
    match c.sampling {
        Sampling::MultiRate => candidates.push((
            "controller.inner_rate_hz",
            c.inner_rate_hz,
            1.0 / c.inner_rate_hz,
        )),
        Sampling::ZeroOrderHold => {
            candidates.push(("controller.rate_hz", c.rate_hz(), 1.0 / c.rate_hz()))
        }
        Sampling::Continuous => {}
    }
    let shortest = candidates
        .into_iter()
        .filter(|&(_, _, step)| step > 0.0 && step.is_finite())
        .min_by(|a, b| a.2.total_cmp(&b.2));
    let Some((key, value, step)) = shortest.filter(|&(_, _, step)| step < MIN_PLANT_STEP_S) else {
        return Ok(());
    };
    let rule = format!(
        "must give plant steps of {MIN_PLANT_STEP_S:e} s or more (the plant steps at least \
         once per tick; this gives {step:.3e} s)"
    );
    Err(Error::invalid(key, rule, shown(value)))
}

/// `[walking]`: two feet on unilateral contacts whose wrench may reach zero, and the
/// walking settings' own rules for the whole-body period (`WalkingSettings::validate`: no
/// phase shorter than one period, the widths, the command).
fn walking(scenario: &Scenario) -> Result<()> {
    let Some(walking) = &scenario.walking else {
        return Ok(());
    };
    let contacts = &scenario.robot.contacts;
    if contacts.len() != 2 {
        return Err(Error::invalid(
            "walking",
            "needs two contacts (the feet) in robot.contacts",
            format!("{contacts:?}"),
        ));
    }
    if scenario.plant.contact_model != crate::ground::ContactModelKind::Unilateral {
        return Err(Error::invalid(
            "walking",
            "needs plant.contact_model = \"unilateral\" (held contacts cannot lift a foot)",
            "plant.contact_model = \"bilateral\"",
        ));
    }
    let min_normal_force = scenario.controller.contact.min_normal_force;
    if min_normal_force != 0.0 {
        return Err(Error::invalid(
            "controller.contact.min_normal_force",
            "must be 0 under [walking] (a foot's wrench goes to zero before it lifts off)",
            min_normal_force,
        ));
    }
    walking.validate(scenario.schedule().period)?;
    Ok(())
}

/// Checks what needs the robot: with `mass_kg` and gravity `gravity_m_s2` (magnitude), the
/// contacts must be able to carry `controller.contact.min_normal_force` each (the QP is
/// infeasible at rest otherwise: the contacts would push the robot up).
pub fn against_model(scenario: &Scenario, mass_kg: f64, gravity_m_s2: f64) -> Result<()> {
    let min_normal_force = scenario.controller.contact.min_normal_force;
    let contacts = scenario.robot.contacts.len() as f64;
    let weight = mass_kg * gravity_m_s2;
    if contacts * min_normal_force > weight {
        return Err(Error::invalid(
            "controller.contact.min_normal_force",
            format!(
                "must be at most the robot's weight {weight:.1} N shared by its {contacts} \
                 contact(s) (infeasible at rest)"
            ),
            min_normal_force,
        ));
    }
    Ok(())
}

/// `value` as written in a message (`sea_dyn::bounded::shown`).
pub(crate) use sea_dyn::bounded::shown;

/// `[robot]`: a URDF named, one or two distinct contact frames.
fn robot(scenario: &Scenario) -> Result<()> {
    if scenario.robot.urdf.trim().is_empty() {
        let rule = "must name a URDF file (a path or a package:// URI)";
        return Err(Error::invalid("robot.urdf", rule, "\"\""));
    }
    let contacts = &scenario.robot.contacts;
    if contacts.is_empty() || contacts.len() > 2 {
        return Err(Error::invalid(
            "robot.contacts",
            "one or two contact frames",
            format!("{contacts:?}"),
        ));
    }
    if contacts.len() == 2 && contacts[0] == contacts[1] {
        return Err(Error::invalid(
            "robot.contacts",
            "the contact frames must be distinct",
            format!("{contacts:?}"),
        ));
    }
    Ok(())
}

/// `[actuators]` and every `[actuators.overrides.NAME]`.
fn actuators(scenario: &Scenario) -> Result<()> {
    let sea = scenario.controller.kind == ControllerKind::Sea;
    actuator("actuators", &scenario.actuators.default, sea)?;
    for (name, config) in &scenario.actuators.overrides {
        actuator(&format!("actuators.overrides.{name}"), config, sea)?;
    }
    Ok(())
}

/// One actuator table (`table` is its dotted name): an elastic actuator's damping must be
/// positive under the SEA controller, which divides by it (the bounds of each parameter are
/// read with the file: `sea_dyn::ElasticParameters`).
fn actuator(table: &str, config: &ActuatorConfig, sea_controller: bool) -> Result<()> {
    let damping = config.parameters.damping;
    if config.kind == ActuatorKind::Rigid || !sea_controller || damping > 0.0 {
        return Ok(());
    }
    Err(Error::invalid(
        format!("{table}.damping"),
        "must be positive and finite with the SEA controller (it divides by the damping; use \
         controller.kind = \"rigid\" for an undamped spring)",
        damping,
    ))
}

/// `[controller]`: the rules between its keys (and `plant.motor_velocity_gain`).
fn controller(scenario: &Scenario) -> Result<()> {
    let c = &scenario.controller;
    joint_loop_rates(c)?;
    torque_bandwidth_limit(c, scenario.plant.motor_velocity_gain)?;
    external_wrench(c)
}

/// `controller.external_wrench`: observed only with sampled control (the observer runs once
/// per whole-body period).
fn external_wrench(c: &ControllerConfig) -> Result<()> {
    let observer = c.wrench_observer.kind;
    if observer != ExternalWrench::None && c.sampling == Sampling::Continuous {
        return Err(Error::invalid(
            "controller.external_wrench",
            "needs controller.sampling = \"zero_order_hold\" or \"multi_rate\" (the \
             observer runs once per whole-body period)",
            observer.name(),
        ));
    }
    Ok(())
}

/// `[sensing]`: unless sensing is perfect, a sampled controller
/// (not "continuous") whose measurement delay is at most one whole-body period (the inner
/// ticks of one period; one with "zero_order_hold"). Also checked when a run starts (a
/// scenario built in code).
pub fn sensing(scenario: &Scenario) -> Result<()> {
    let sensing = &scenario.sensing;
    let delay = sensing.delay_inner_periods;
    let controller = &scenario.controller;
    let inner_ticks = match controller.sampling {
        Sampling::MultiRate => inner_ticks(controller.rate_hz(), controller.inner_rate_hz),
        Sampling::ZeroOrderHold => 1,
        Sampling::Continuous if sensing.is_perfect() => return Ok(()),
        Sampling::Continuous => {
            let (key, value) = sensing
                .noise()
                .into_iter()
                .find(|&(_, std)| std != 0.0)
                .map(|(name, std)| (name, std.to_string()))
                .unwrap_or(("delay_inner_periods", delay.to_string()));
            return Err(Error::invalid(
                format!("sensing.{key}"),
                "must be 0 with controller.sampling = \"continuous\" (noise and delay need a \
                 sampled controller: \"zero_order_hold\" or \"multi_rate\")",
                value,
            ));
        }
    };
    if delay > inner_ticks {
        return Err(Error::invalid(
            "sensing.delay_inner_periods",
            format!(
                "must be at most one whole-body period, {inner_ticks} inner period(s) with \
                 controller.sampling = \"{}\"",
                controller.sampling.name()
            ),
            delay,
        ));
    }
    let observer = controller.wrench_observer.kind;
    if delay > 0 && observer != ExternalWrench::None {
        // The observer pairs the measured state's momentum with the feet's wrenches at the
        // sample: a delay of the one and not the other would show as an external wrench.
        return Err(Error::invalid(
            "sensing.delay_inner_periods",
            format!(
                "must be 0 with controller.external_wrench = \"{}\" (the contact wrenches \
                 are not delayed)",
                observer.name()
            ),
            delay,
        ));
    }
    Ok(())
}

/// The joint loops of `multi_rate`: an inner rate that is a whole multiple (at least 1) of `controller.rate_hz`, and what only the joint loops run (the
/// stiffness identification, its excitation) refused under another sampling.
fn joint_loop_rates(c: &ControllerConfig) -> Result<()> {
    if c.sampling != Sampling::MultiRate {
        if c.stiffness_identification {
            return Err(Error::invalid(
                "controller.stiffness_identification",
                "needs controller.sampling = \"multi_rate\" (it feeds the joint loops)",
                true,
            ));
        }
        if !c.excitation.amplitudes_nm.is_empty() {
            let joints: Vec<_> = c.excitation.amplitudes_nm.keys().cloned().collect();
            return Err(Error::invalid(
                "controller.identification_excitation_nm",
                "needs controller.sampling = \"multi_rate\" (it is added in the joint loops)",
                format!("{{ {} }}", joints.join(", ")),
            ));
        }
        return Ok(());
    }
    let ratio = c.inner_rate_hz / c.rate_hz();
    if ratio < 1.0 - 1e-9 {
        return Err(Error::invalid(
            "controller.inner_rate_hz",
            format!("must be at least controller.rate_hz ({} Hz)", c.rate_hz()),
            c.inner_rate_hz,
        ));
    }
    if (ratio - ratio.round()).abs() > 1e-9 * ratio {
        return Err(Error::invalid(
            "controller.inner_rate_hz",
            format!(
                "must be a whole multiple of controller.rate_hz ({} Hz)",
                c.rate_hz()
            ),
            c.inner_rate_hz,
        ));
    }
    Ok(())
}

/// `multi_rate` with `torque_bandwidth_hz` (not the paper's law): a bandwidth the joint loops
/// can hold at `inner_rate_hz` on the motor velocity loop of gain `motor_velocity_gain`, below
/// [`sea_ctrl::joint_loop::max_stable_bandwidth`] (where the sampled loop's poles leave the
/// unit circle; beyond it the run diverges).
fn torque_bandwidth_limit(c: &ControllerConfig, motor_velocity_gain: f64) -> Result<()> {
    if c.sampling != Sampling::MultiRate || c.joint_loops.paper_law {
        return Ok(());
    }
    let period = 1.0 / c.inner_rate_hz;
    let bound = sea_ctrl::joint_loop::max_stable_bandwidth(motor_velocity_gain, period);
    let bound_hz = bound / (2.0 * std::f64::consts::PI);
    if !bound_hz.is_finite() || c.joint_loops.torque_bandwidth_hz < bound_hz {
        return Ok(()); // a bad gain or rate is reported by its own check
    }
    Err(Error::invalid(
        "controller.torque_bandwidth_hz",
        format!(
            "must be in (0, {bound_hz:.1}) Hz: the joint torque loops at controller.inner_rate_hz \
             = {} Hz on plant.motor_velocity_gain = {motor_velocity_gain} 1/s are unstable from \
             {bound_hz:.1} Hz on (their sampled poles leave the unit circle); useful bandwidths \
             are well below it (default 20 Hz)",
            c.inner_rate_hz
        ),
        c.joint_loops.torque_bandwidth_hz,
    ))
}

/// The error of a sampled controller whose period is longer than the run, naming the run's
/// length when it is shorter than the default rate's period, else the rate.
fn no_tick_in_the_run(scenario: &Scenario) -> Error {
    let (duration, rate) = (
        scenario.simulation.duration_s,
        scenario.controller.rate_hz(),
    );
    if duration * scenario.controller.sampling.default_rate_hz() < 1.0 {
        let rule = format!(
            "must last one whole-body period at least (controller.rate_hz {})",
            shown(rate)
        );
        Error::invalid("simulation.duration_s", rule, shown(duration))
    } else {
        let rule = format!(
            "must give one whole-body tick within the run at least (simulation.duration_s {} s)",
            shown(duration)
        );
        Error::invalid("controller.rate_hz", rule, shown(rate))
    }
}

/// The run's plant steps (or controller samples, whichever are more) must not exceed
/// [`MAX_RUN_STEPS`]; the key named is the one that makes the count huge. A sampled
/// controller ticks at least once within the run: a period longer than the run would run no
/// tick and report the run completed.
fn run_length(scenario: &Scenario) -> Result<()> {
    let duration = scenario.simulation.duration_s;
    // The joint loops tick on plant steps: a faster inner rate shortens the step below plant.dt.
    let inner_rate_hz = match scenario.controller.sampling {
        Sampling::MultiRate => scenario.controller.inner_rate_hz,
        _ => 0.0,
    };
    let plant_steps = duration * (1.0 / scenario.plant.dt).max(inner_rate_hz);
    let samples = match scenario.controller.sampling {
        Sampling::Continuous => 0.0,
        Sampling::ZeroOrderHold | Sampling::MultiRate => duration * scenario.controller.rate_hz(),
    };
    let sampled = scenario.controller.sampling != Sampling::Continuous;
    if sampled && samples < 1.0 - 1e-9 {
        return Err(no_tick_in_the_run(scenario));
    }
    if plant_steps.max(samples) <= MAX_RUN_STEPS {
        return Ok(());
    }
    // Name the value furthest from its default (10 s, 1 ms, 1 kHz): that is the typo.
    let defaults = (SimulationConfig::default(), PlantConfig::default());
    let default_rate = scenario.controller.sampling.default_rate_hz();
    let candidates = [
        (
            "simulation.duration_s",
            duration,
            duration / defaults.0.duration_s,
        ),
        (
            "plant.dt",
            scenario.plant.dt,
            defaults.1.dt / scenario.plant.dt,
        ),
        (
            "controller.rate_hz",
            scenario.controller.rate_hz(),
            samples / duration / default_rate,
        ),
        (
            "controller.inner_rate_hz",
            inner_rate_hz,
            inner_rate_hz * defaults.1.dt,
        ),
    ];
    let key = candidates
        .iter()
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .map(|&(key, value, _)| (key, value))
        .unwrap_or(("simulation.duration_s", duration));
    Err(Error::invalid(
        key.0,
        format!(
            "with simulation.duration_s = {} the run would take {:.3e} steps, more \
             than {MAX_RUN_STEPS:e}",
            shown(duration),
            plant_steps.max(samples)
        ),
        shown(key.1),
    ))
}

#[cfg(test)]
mod tests;
