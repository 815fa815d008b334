//! The robot's controller as one stack: the whole-body law ([`FeedbackLaw`], the momentum
//! controller with its references) at its rate, the joint torque loops
//! ([`JointTorqueLoop`]) at theirs, the online stiffness identification
//! ([`StiffnessIdentifier`]) with its excitation ([`IdentificationExcitation`]), and the
//! observers of what the model misses ([`ExternalWrenchObserver`],
//! [`DisturbanceObserverLoop`]). The simulator's loop, Python's `Controller` and a robot's
//! loop all run this stack.
//!
//! # The per-tick contract
//!
//! With a whole-body period `T` (e.g. 10 ms) and, with joint loops, an inner period `T / m`
//! (e.g. 1 ms):
//!
//! 1. At the whole-body tick, time `t`: [`RobotController::tick`]`(t, x)` with the measured
//!    state `x = (q, theta, nu, thetadot)` (the base's pose and velocity from the estimator,
//!    the joints' and motors' encoders). It evaluates the whole-body law, holds its desired
//!    joint torques in the joint loops (plus the identification's excitation), runs their
//!    first tick, and returns the motor command (n, joint order): a rigid joint's motor
//!    torque [Nm], an elastic joint's desired motor velocity [rad/s, motor side] for its
//!    motor velocity loop (eq:tauMotors).
//! 2. At each later joint tick of the period (with joint loops): [`RobotController::joint_tick`]
//!    with the freshly measured state returns the new command. Without joint loops the
//!    command is held.
//! 3. After the period, before the next tick: [`RobotController::end_period`] with the force
//!    readings of the period ([`PeriodSensors`]: the feet's force/torque sensors and the joint
//!    torques at its start and at its end). The identification updates the joint loops'
//!    stiffness estimates (walking: only when both feet have been on the ground for
//!    `walking.identification_settle`, [`MomentumController::identification_settled`];
//!    otherwise the estimates are held and only the period's velocity is kept) and the
//!    observers hand their estimates to the controller; both take effect from the next tick
//!    on. A walking controller also takes the feet's normal forces
//!    for its touchdowns ([`MomentumController::set_foot_forces`]).
//!
//! A tick that fails (the QP and its fallback fail, a non-finite measurement) returns the
//! error; the command of the last successful tick is still [`RobotController::command`], and
//! a robot's loop should hold it or stop the robot. A missed [`RobotController::end_period`]
//! skips one update of the estimators (the identification's filters see a longer period as
//! the next update's `T`, which the stack does not know: call it once per period).
//!
//! Every step allocates nothing after [`RobotController::new`] (the controller's tick aside,
//! see [`MomentumController::compute_into`]).

mod disturbance_loop;
mod sensors;

pub use disturbance_loop::DisturbanceObserverLoop;
pub use sensors::{ForceReadings, PeriodSensors};

use crate::error::Result;
use crate::excitation::IdentificationExcitation;
use crate::external_wrench::ExternalWrenchObserver;
use crate::feedback::{FeedbackLaw, Observation};
use crate::joint_loop::JointTorqueLoop;
use crate::stiffness_id::{IdentificationWrenches, StiffnessIdentifier};
use crate::walking::FootTask;
use crate::MomentumController;
use sea_dyn::{ElasticParameters, StateLayout};
use std::borrow::BorrowMut;

/// The parts of the stack besides the whole-body law, each optional.
#[derive(Clone, Debug, Default)]
pub struct StackParts {
    /// The joint torque loops of the elastic joints (the multi-rate design); `None`: the
    /// whole-body law's input is the command, held over the period.
    pub joint_loop: Option<JointTorqueLoop>,
    /// The stiffness identification feeding the joint loops (needs them), with the contact
    /// wrenches it takes.
    pub identifier: Option<(StiffnessIdentifier, IdentificationWrenches)>,
    /// The sinusoid added to the joint loops' held torques (needs them).
    pub excitation: Option<IdentificationExcitation>,
    /// `external_wrench = "observed"`: the centroidal observer of an external wrench.
    pub external_wrench_observer: Option<ExternalWrenchObserver>,
    /// `external_wrench = "generalized"`: the generalized disturbance observer.
    pub disturbance_observer: Option<DisturbanceObserverLoop>,
}

/// The robot's controller stack (module doc). `C` is the momentum controller owned
/// (`MomentumController`, the default) or borrowed (`&mut MomentumController`).
#[derive(Debug)]
pub struct RobotController<C = MomentumController> {
    law: FeedbackLaw<C>,
    parts: StackParts,
    /// The whole-body period `T` [s] (the estimators' sampling period).
    period: f64,
    /// The measured state of the last tick (nx), which the estimators read after the period.
    measured_at_tick: Vec<f64>,
    /// Without joint loops, the last held tick's motor command (n): a tick that fails leaves
    /// it, while the law's own output is the failed evaluation's.
    held_input: Vec<f64>,
}

impl<C: BorrowMut<MomentumController>> RobotController<C> {
    /// The stack of `law` and `parts` ticking every `period` [s].
    ///
    /// # Panics
    /// When the identification or the excitation is given without joint loops (they act
    /// through them).
    pub fn new(law: FeedbackLaw<C>, parts: StackParts, period: f64) -> Self {
        assert!(
            parts.joint_loop.is_some()
                || (parts.identifier.is_none() && parts.excitation.is_none()),
            "the stiffness identification and its excitation need the joint loops"
        );
        let nx = law.layout().nx();
        let held_input = law.last().output.input.clone();
        Self {
            law,
            parts,
            period,
            measured_at_tick: vec![0.0; nx],
            held_input,
        }
    }

    /// The whole-body law (the momentum controller with its references and last evaluation).
    pub fn law(&self) -> &FeedbackLaw<C> {
        &self.law
    }

    /// The whole-body law, e.g. to evaluate it at the stages of an integrator (continuous
    /// sampling, a simulator's setting) or to put the true state's errors into its last
    /// observation.
    pub fn law_mut(&mut self) -> &mut FeedbackLaw<C> {
        &mut self.law
    }

    /// The momentum controller.
    pub fn controller(&self) -> &MomentumController {
        self.law.controller()
    }

    /// The state layout the stack reads.
    pub fn layout(&self) -> StateLayout {
        self.law.layout()
    }

    /// The whole-body period `T` [s].
    pub fn period(&self) -> f64 {
        self.period
    }

    /// The joint torque loops, when the stack has them.
    pub fn joint_loop(&self) -> Option<&JointTorqueLoop> {
        self.parts.joint_loop.as_ref()
    }

    /// The joint loops, e.g. to give each joint its own estimate.
    pub fn joint_loop_mut(&mut self) -> Option<&mut JointTorqueLoop> {
        self.parts.joint_loop.as_mut()
    }

    /// The stiffness identification, when on.
    pub fn identifier(&self) -> Option<&StiffnessIdentifier> {
        self.parts
            .identifier
            .as_ref()
            .map(|(identifier, _)| identifier)
    }

    /// The whole-body law's last evaluation.
    pub fn last(&self) -> &Observation {
        self.law.last()
    }

    /// The elastic estimates the stack works with (n_e): the joint loops' (identified or not),
    /// or without them the controller's.
    pub fn estimates(&self) -> &[ElasticParameters] {
        match &self.parts.joint_loop {
            Some(joint_loop) => joint_loop.estimates(),
            None => self.law.controller().estimates(),
        }
    }

    /// The motor command (n): the joint loops' last, or the whole-body law's input at the last
    /// tick held (a tick that failed is not).
    pub fn command(&self) -> &[f64] {
        match &self.parts.joint_loop {
            Some(joint_loop) => joint_loop.input(),
            None => &self.held_input,
        }
    }

    /// The whole-body tick at time `time` [s] and measured state `measured` (nx): returns the
    /// motor command (n) (module doc, step 1). On `Err` nothing is held from this tick: a law
    /// that fails, or a command with an entry that is not finite (an
    /// [`sea_dyn::Error::Numerical`]; the joint loops keep the last torques).
    pub fn tick(&mut self, time: f64, measured: &[f64]) -> Result<&[f64]> {
        self.law.tick(time, measured)?;
        let input = &self.law.last().output.input;
        if let Some(k) = input.iter().position(|u| !u.is_finite()) {
            let detail = format!("the command is not finite (entry {k}) at t = {time} s");
            return Err(sea_dyn::Error::numerical("the whole-body tick", detail).into());
        }
        self.hold(time, measured);
        Ok(self.command())
    }

    /// After the whole-body law's tick at `(time, measured)` (by [`Self::tick`], or by the
    /// caller through [`Self::law_mut`]): holds its torques in the joint loops, adds the
    /// excitation and runs their first tick; keeps `measured` for the estimators.
    pub fn hold(&mut self, time: f64, measured: &[f64]) {
        let layout = self.law.layout();
        if let Some(joint_loop) = &mut self.parts.joint_loop {
            let output = &self.law.last().output;
            joint_loop.hold(output, &layout, measured, self.law.s_desired());
            if let Some(excitation) = &self.parts.excitation {
                joint_loop.excite(excitation, time);
            }
            joint_loop.tick(&layout, measured);
        } else {
            self.held_input.clone_from(&self.law.last().output.input);
        }
        self.measured_at_tick.copy_from_slice(measured);
    }

    /// A joint tick between two whole-body ticks at the measured state `measured` (nx):
    /// returns the motor command (n) (module doc, step 2).
    pub fn joint_tick(&mut self, measured: &[f64]) -> &[f64] {
        let layout = self.law.layout();
        match &mut self.parts.joint_loop {
            Some(joint_loop) => joint_loop.tick(&layout, measured),
            None => &self.held_input,
        }
    }

    /// After the period that began at the last tick: the estimators' updates with the
    /// period's force readings (module doc, step 3).
    pub fn end_period(&mut self, sensors: PeriodSensors<'_>) {
        // Walking: the touchdowns of the next ticks follow the feet's sensors.
        self.law
            .controller_mut()
            .set_foot_forces(sensors.end.contact_wrench);
        self.identify(&sensors);
        self.observe_external_wrench(&sensors);
        self.observe_generalized_disturbance(sensors);
    }

    /// The stiffness identification's update at the last tick's measured state, with the
    /// contact wrenches it takes (the sensors' at the period's start, or the commanded `f*`);
    /// the joint loops take the estimates from the next tick on.
    fn identify(&mut self, sensors: &PeriodSensors<'_>) {
        let (Some((identifier, source)), Some(joint_loop)) =
            (&mut self.parts.identifier, &mut self.parts.joint_loop)
        else {
            return;
        };
        // Walking: a foot in the air carries no load (its zero wrench is kept).
        let controller = self.law.controller();
        if let Some(tasks) = controller.foot_tasks() {
            let loaded = tasks.map(|task| matches!(task, FootTask::Contact { .. }));
            identifier.set_loaded_contacts(&loaded);
        }
        // Walking: learn only on both feet settled (`walking.identification_settle`).
        if controller.identification_settled() == Some(false) {
            identifier.hold_sample(&self.law.layout(), &self.measured_at_tick);
            return;
        }
        let wrenches = match source {
            IdentificationWrenches::Measured => sensors.start.contact_wrench,
            IdentificationWrenches::Commanded => &self.law.last().output.wrenches,
        };
        identifier.update(
            &self.law.layout(),
            &self.measured_at_tick,
            self.period,
            wrenches,
            joint_loop.estimates_mut(),
        );
    }

    /// `external_wrench = "observed"`: one update with the tick's momentum and momentum map
    /// and the feet's wrenches over the period: their mean when the sensors give it, else
    /// those at the period's start and end.
    fn observe_external_wrench(&mut self, sensors: &PeriodSensors<'_>) {
        let Some(observer) = &mut self.parts.external_wrench_observer else {
            return;
        };
        let controller = self.law.controller();
        let tick = (&self.law.last().output.momentum, controller.momentum_map());
        let model = (controller.mass(), &controller.model().gravity);
        // The trapezoid of the period's mean with itself is that mean (module doc of
        // `external_wrench`).
        let (start, end) = match sensors.mean_contact_wrench {
            Some(mean) => (mean, mean),
            None => (sensors.start.contact_wrench, sensors.end.contact_wrench),
        };
        let estimate = *observer.update(tick, start, end, model);
        self.law.controller_mut().set_external_wrench(&estimate);
    }

    /// `external_wrench = "generalized"`: one update with the last tick's measured state and
    /// the period's force readings.
    fn observe_generalized_disturbance(&mut self, sensors: PeriodSensors<'_>) {
        let Some(observer) = &mut self.parts.disturbance_observer else {
            return;
        };
        let layout = self.law.layout();
        let measured = (&layout, self.measured_at_tick.as_slice());
        let controller = self.law.controller_mut();
        match &self.parts.joint_loop {
            Some(joint_loop) => {
                observer.observe(controller, measured, joint_loop.estimates(), sensors)
            }
            None => {
                let estimates = controller.estimates().to_vec();
                observer.observe(controller, measured, &estimates, sensors)
            }
        }
    }
}
