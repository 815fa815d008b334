//! The feedback law of the closed loop, `(t, x) -> plant input + observation`: the
//! controller ([`MomentumController`]) with its CoM reference ([`ComTrajectory`]) and postural
//! reference ([`PostureReference`]), and what it holds between evaluations (the postural
//! reference `s_d(t)` and the last [`Observation`]). The native closed loop (`sea_sim`) and
//! Python's `Controller.tick` both evaluate it, so a Python loop of `Controller.tick` and
//! `Plant.step` computes what the native loop computes.
//!
//! An evaluation at `(t, x)`: `p_d(t)` and `s_d(t)` from the references (`p_d` from the
//! controller's gait when it walks, [`MomentumController::walking_reference`]), the controller's tick
//! ([`MomentumController::compute_into`]) at `x` with them, and the tracking errors
//! `|p_com - p_com_d|` and `|s - s_d|`. [`FeedbackLaw::tick`] evaluates into the held
//! observation ([`FeedbackLaw::last`]); [`FeedbackLaw::observe`] into a caller's (e.g. the
//! later integrator stages of a step, whose evaluations are not recorded). Both allocate
//! nothing (the controller's tick aside, see there).

use crate::controller::{ControlOutput, MomentumController};
use crate::error::Result;
use crate::references::{ComSample, ComTrajectory, PostureReference};
use nalgebra::Vector3;
use sea_dyn::StateLayout;
use std::borrow::BorrowMut;

/// The feedback law's evaluation at one state.
#[derive(Clone, Debug)]
pub struct Observation {
    /// Time [s].
    pub time: f64,
    /// Controller output (plant input, CoM, momentum, QP status).
    pub output: ControlOutput,
    /// CoM reference at `time`.
    pub reference: ComSample,
    /// `|p_com - p_com_d|` [m].
    pub com_error: f64,
    /// `|s - s_d|` [rad].
    pub joint_error: f64,
}

/// The controller with its references: the closed loop's feedback law. `C` is the controller
/// owned (`MomentumController`, the default) or borrowed (`&mut MomentumController`, e.g. a
/// controller whose counters its owner reads after the run).
#[derive(Debug)]
pub struct FeedbackLaw<C = MomentumController> {
    controller: C,
    com_reference: ComTrajectory,
    posture: PostureReference,
    /// Layout of the plant states evaluated.
    layout: StateLayout,
    /// Postural reference `s_d(t)` of the last evaluation (n).
    s_desired: Vec<f64>,
    /// The evaluation of the last [`FeedbackLaw::tick`].
    last: Observation,
}

impl<C: BorrowMut<MomentumController>> FeedbackLaw<C> {
    /// The law of `controller` tracking `com_reference` and `posture`, at plant states of
    /// `layout`. Until the first tick, the held observation is zero and `s_d` is the initial
    /// posture.
    pub fn new(
        controller: C,
        com_reference: ComTrajectory,
        posture: PostureReference,
        layout: StateLayout,
    ) -> Self {
        let last = zero_observation(controller.borrow());
        Self {
            s_desired: posture.initial.clone(),
            controller,
            com_reference,
            posture,
            layout,
            last,
        }
    }

    /// The controller.
    pub fn controller(&self) -> &MomentumController {
        self.controller.borrow()
    }

    /// The controller, to set what it holds between ticks (e.g. its external wrench).
    pub fn controller_mut(&mut self) -> &mut MomentumController {
        self.controller.borrow_mut()
    }

    /// The CoM reference.
    pub fn com_reference(&self) -> &ComTrajectory {
        &self.com_reference
    }

    /// The postural reference.
    pub fn posture(&self) -> &PostureReference {
        &self.posture
    }

    /// Layout of the plant states the law reads.
    pub fn layout(&self) -> StateLayout {
        self.layout
    }

    /// The postural reference `s_d` of the last evaluation (n).
    pub fn s_desired(&self) -> &[f64] {
        &self.s_desired
    }

    /// The evaluation of the last [`Self::tick`] (zero before the first).
    pub fn last(&self) -> &Observation {
        &self.last
    }

    /// A zeroed observation sized for the controller, for [`Self::observe`].
    pub fn new_observation(&self) -> Observation {
        zero_observation(self.controller.borrow())
    }

    /// Evaluates the law at time `time` [s] and plant state `x` (nx) into the held
    /// observation, and returns it. On `Err` (the controller failed) the held observation's
    /// contents are unspecified.
    pub fn tick(&mut self, time: f64, x: &[f64]) -> Result<&Observation> {
        self.evaluate(time, x, None)?;
        Ok(&self.last)
    }

    /// Evaluates the law at `(time, x)` into `observation` (allocation-free when it comes from
    /// [`Self::new_observation`]); the held observation is left as it is. On `Err` the
    /// contents of `observation` are unspecified.
    pub fn observe(&mut self, time: f64, x: &[f64], observation: &mut Observation) -> Result<()> {
        self.evaluate(time, x, Some(observation))
    }

    /// After a [`Self::tick`] at a measurement of the state (noisy, delayed): replaces the held
    /// observation's CoM and tracking errors with the true state's, `com` its CoM [m] and `s`
    /// its joint positions (n), so that what is recorded and checked against the divergence
    /// bounds is the truth. The rest of the output (the plant input, the momentum) stays the
    /// measured state's.
    pub fn observe_truth(&mut self, com: Vector3<f64>, s: &[f64]) {
        let last = &mut self.last;
        last.output.com = com;
        last.com_error = (com - last.reference.position).norm();
        last.joint_error = joint_error_norm(s, &self.s_desired);
    }

    /// One evaluation into `target`, or into the held observation when `None`.
    fn evaluate(&mut self, time: f64, x: &[f64], target: Option<&mut Observation>) -> Result<()> {
        let observation = match target {
            Some(observation) => observation,
            None => &mut self.last,
        };
        // Walking: the gait's CoM reference, and the contact phases of the tick set (after a
        // recovery step is planned when the measured DCM needs one, `walking.stepping`, and
        // the footsteps adjusted to the measured DCM, `walking.step_adjustment`).
        let controller = self.controller.borrow_mut();
        controller.watch_capture_point(time, x, &self.layout);
        controller.adjust_steps(time, x, &self.layout);
        let reference = match controller.walking_reference(time) {
            Some(reference) => reference,
            None => self.com_reference.sample(time),
        };
        self.posture.at(time, &mut self.s_desired);
        let output = &mut observation.output;
        self.controller.borrow_mut().compute_into(
            x,
            &self.layout,
            &reference,
            &self.s_desired,
            output,
        )?;
        observation.com_error = (output.com - reference.position).norm();
        observation.joint_error = joint_error_norm(self.layout.s(x), &self.s_desired);
        observation.time = time;
        observation.reference = reference;
        Ok(())
    }
}

/// `|s - s_d|`, the Euclidean norm of the joint error [rad].
fn joint_error_norm(s: &[f64], s_desired: &[f64]) -> f64 {
    s.iter()
        .zip(s_desired)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

/// A zeroed observation sized for `controller`.
fn zero_observation(controller: &MomentumController) -> Observation {
    let zero = Vector3::zeros();
    Observation {
        time: 0.0,
        output: controller.new_output(),
        reference: ComSample {
            position: zero,
            velocity: zero,
            acceleration: zero,
        },
        com_error: 0.0,
        joint_error: 0.0,
    }
}
