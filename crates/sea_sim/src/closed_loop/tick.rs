//! One sample period of the closed loop: the controller's evaluation at a state
//! ([`Law::observe`]), the divergence bounds, and the plant's advance to the next sample with
//! the input held (zero-order hold) or the controller at every integrator stage (continuous).

use super::record::{RunInfo, Sample};
use super::sampling::{Sampling, Schedule};
use super::statistics::RunEnd;
use crate::error::Result;
use crate::scenario::{Scenario, Setup};
use sea_ctrl::controller::{ControlOutput, MomentumController};
use sea_ctrl::references::{ComSample, ComTrajectory, PostureReference};
use sea_dyn::Model;
use sea_plant::integrator::step_with_feedback;
use sea_plant::{Method, Plant, PlantData, StateLayout, Workspace};

/// The controller with its references: the feedback law `(t, x) -> plant input`.
pub(super) struct Law<'a> {
    /// The controller.
    pub controller: &'a mut MomentumController,
    com_reference: &'a ComTrajectory,
    posture: &'a PostureReference,
    layout: StateLayout,
    /// Postural reference `s_d(t)` of the last evaluation (n).
    s_desired: Vec<f64>,
    /// Whether the controller's model equals the plant's, so that the model terms of a tick
    /// (kinematics, `h`, `M` at the tick's state) can be handed to the plant's evaluation
    /// at the same state instead of being computed twice.
    share_model_terms: bool,
}

/// The controller's evaluation at one state; [`Law::new_observation`] makes one that
/// [`Law::observe`] then refills without allocating.
pub(super) struct Observation {
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

impl Observation {
    /// The bound this observation crosses, as the reason of a divergence: the quantity, its
    /// value and the bound. A NaN error counts as crossing.
    fn bound_crossed(&self, scenario: &Scenario) -> Option<String> {
        let simulation = &scenario.simulation;
        let (com_bound, joint_bound) = (
            simulation.divergence_com_error_m,
            simulation.divergence_joint_error_rad,
        );
        if exceeds(self.com_error, com_bound) {
            Some(format!(
                "CoM error {:.4} m over the bound {com_bound} m",
                self.com_error
            ))
        } else if exceeds(self.joint_error, joint_bound) {
            Some(format!(
                "joint error norm {:.4} rad over the bound {joint_bound} rad",
                self.joint_error
            ))
        } else {
            None
        }
    }
}

/// `value > bound`, and NaN (an undefined error) counts as over.
fn exceeds(value: f64, bound: f64) -> bool {
    value > bound || value.is_nan()
}

impl Law<'_> {
    /// A zeroed observation sized for the controller, to be filled by [`Law::observe`].
    pub fn new_observation(&self) -> Observation {
        let zero = nalgebra::Vector3::zeros();
        Observation {
            time: 0.0,
            output: self.controller.new_output(),
            reference: ComSample {
                position: zero,
                velocity: zero,
                acceleration: zero,
            },
            com_error: 0.0,
            joint_error: 0.0,
        }
    }

    /// After a tick at `x`: hands the controller's model terms, and its contact terms when
    /// its diagonal and contacts are the plant's, to the plant's next evaluation (used only if
    /// that evaluation is at `x`'s `q` and `nu`; see [`Workspace::adopt_model_terms`] and
    /// [`Workspace::adopt_contact_terms`]). Results are bitwise those without it.
    fn hand_over_model_terms(&self, plant: &Plant, ws: &mut Workspace, x: &[f64]) {
        if self.share_model_terms {
            ws.adopt_model_terms(self.controller.model_data(), &self.layout, x);
            ws.adopt_contact_terms(plant, &self.controller.factored_contacts());
        }
    }

    /// Evaluates the controller at `(time, x)` into `observation` (allocation-free when it
    /// comes from [`Law::new_observation`]). On `Err` its contents are unspecified.
    pub fn observe(&mut self, time: f64, x: &[f64], observation: &mut Observation) -> Result<()> {
        let reference = self.com_reference.sample(time);
        self.posture.at(time, &mut self.s_desired);
        let output = &mut observation.output;
        self.controller
            .compute_into(x, &self.layout, &reference, &self.s_desired, output)?;
        observation.com_error = (output.com - reference.position).norm();
        observation.joint_error = self
            .layout
            .s(x)
            .iter()
            .zip(&self.s_desired)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt();
        observation.time = time;
        observation.reference = reference;
        Ok(())
    }
}

/// Plant outputs at the state of a sample (copied out of `PlantData`).
#[derive(Default)]
struct PlantOutputs {
    wrench: Vec<f64>,
    motor_torque: Vec<f64>,
    joint_torque: Vec<f64>,
}

impl PlantOutputs {
    fn copy_from(&mut self, pd: &PlantData) {
        for (target, source) in [
            (&mut self.wrench, &pd.outputs.contact_wrench),
            (&mut self.motor_torque, &pd.outputs.motor_torque),
            (&mut self.joint_torque, &pd.outputs.joint_torque),
        ] {
            target.clear();
            target.extend_from_slice(source.as_slice());
        }
    }
}

/// What one sample period gave (the evaluation at its start is [`Engine::observation`]):
/// when the run stops there, how it ended.
pub(super) struct Period {
    /// `Some` when the run ends at this sample.
    pub end: Option<RunEnd>,
}

/// The loop's state between samples: the plant, the law, the schedule and the buffers, all
/// allocated once.
pub(super) struct Engine<'a> {
    scenario: &'a Scenario,
    model: &'a Model,
    elastic_names: &'a [String],
    plant: &'a Plant,
    /// The feedback law.
    pub law: Law<'a>,
    /// The time grid.
    pub schedule: Schedule,
    method: Method,
    layout: StateLayout,
    pd: PlantData,
    x: Vec<f64>,
    x_next: Vec<f64>,
    x_step: Vec<f64>,
    u: Vec<f64>,
    outputs: PlantOutputs,
    /// The controller's evaluation at the current sample.
    observation: Observation,
    /// The evaluations at the later integrator stages (continuous sampling), not recorded.
    stage: Observation,
}

impl<'a> Engine<'a> {
    /// The loop of `setup` on the grid of `scenario`, at the initial state.
    pub fn new(scenario: &'a Scenario, setup: &'a mut Setup) -> Result<Engine<'a>> {
        let schedule = Schedule::of(scenario)?;
        let method = scenario.plant.method;
        let Setup {
            model,
            plant,
            controller,
            x0,
            com_reference,
            posture,
            elastic_names,
        } = setup;
        let layout = plant.layout();
        let n = model.n_joints();
        let share_model_terms = controller.model() == &plant.model;
        let law = Law {
            controller,
            com_reference,
            posture,
            layout,
            s_desired: vec![0.0; n],
            share_model_terms,
        };
        Ok(Engine {
            scenario,
            model,
            elastic_names,
            plant,
            observation: law.new_observation(),
            stage: law.new_observation(),
            law,
            schedule,
            method,
            layout,
            pd: PlantData::new(plant),
            x: x0.clone(),
            x_next: x0.clone(),
            x_step: x0.clone(),
            u: vec![0.0; n],
            outputs: PlantOutputs::default(),
        })
    }

    /// What the sinks learn before the first sample.
    pub fn info(&self) -> RunInfo<'_> {
        RunInfo {
            model: self.model,
            layout: self.layout,
            elastic_joints: self.elastic_names,
            contacts: &self.scenario.robot.contacts,
            scenario: self.scenario,
        }
    }

    /// Record every this many samples (`simulation.record_every`, at least 1).
    pub fn record_every(&self) -> usize {
        self.scenario.simulation.record_every.max(1)
    }

    /// The simulated duration asked for (`simulation.duration_s`) [s].
    pub fn duration(&self) -> f64 {
        self.scenario.simulation.duration_s
    }

    /// The state layout.
    pub fn layout(&self) -> StateLayout {
        self.layout
    }

    /// Runs the period that starts at sample `index`: evaluates the controller there, stops
    /// (evaluating the plant for the record) when a bound is crossed, `interrupted` is set or
    /// the run is over, and otherwise advances the plant to the next sample (see
    /// [`Engine::commit`]). `Err` carries the reason when the controller fails at the sample
    /// itself (then there is nothing to record).
    pub fn period(
        &mut self,
        index: usize,
        interrupted: bool,
    ) -> std::result::Result<Period, String> {
        let time = self.schedule.time(index);
        let last = index == self.schedule.last_sample;
        if self.schedule.sampling == Sampling::Continuous && !(last || interrupted) {
            return self.continuous_period(time);
        }
        self.law
            .observe(time, &self.x, &mut self.observation)
            .map_err(|e| format!("controller: {e}"))?;
        let stop = match self.observation.bound_crossed(self.scenario) {
            Some(reason) => Some(RunEnd::Diverged { at_s: time, reason }),
            None if interrupted => Some(RunEnd::Interrupted),
            None if last => Some(RunEnd::Completed),
            None => None,
        };
        // The input is moved out for the plant and back, so the plant can borrow the engine.
        let input = std::mem::take(&mut self.observation.output.input);
        let failure = match stop {
            Some(_) => self.evaluate_here(&input),
            None => self.advance_held(&input),
        };
        self.observation.output.input = input;
        let end = match failure {
            Err(reason) => Some(RunEnd::Diverged { at_s: time, reason }),
            Ok(()) => stop,
        };
        Ok(Period { end })
    }

    /// Evaluates the plant at the current state with input `u`, for the record.
    fn evaluate_here(&mut self, u: &[f64]) -> std::result::Result<(), String> {
        self.law
            .hand_over_model_terms(self.plant, &mut self.pd.workspace, &self.x);
        let pd = &mut self.pd;
        let result =
            sea_plant::evaluate(self.plant, &mut pd.workspace, &self.x, u, &mut pd.outputs);
        self.outputs.copy_from(&self.pd);
        result.map_err(|e| format!("plant: {e}"))
    }

    /// Zero-order hold: the plant steps over one control period with `u` held, into `x_next`;
    /// the first step's start evaluation gives the outputs at the current state.
    fn advance_held(&mut self, u: &[f64]) -> std::result::Result<(), String> {
        let steps = self.schedule.steps_per_period;
        self.x_step.copy_from_slice(&self.x);
        // The first step starts where the controller just ticked.
        self.law
            .hand_over_model_terms(self.plant, &mut self.pd.workspace, &self.x_step);
        for k in 0..steps {
            let result = sea_plant::step(
                self.plant,
                &mut self.pd,
                &self.x_step,
                u,
                self.schedule.step,
                self.method,
                &mut self.x_next,
            );
            if k == 0 {
                self.outputs.copy_from(&self.pd);
            }
            result.map_err(|e| format!("plant step: {e}"))?;
            if self.x_next.iter().any(|v| !v.is_finite()) {
                return Err("non-finite state".into());
            }
            std::mem::swap(&mut self.x_step, &mut self.x_next);
        }
        self.x_next.copy_from_slice(&self.x_step);
        Ok(())
    }

    /// Continuous sampling: one plant step with the controller at every stage, into `x_next`.
    /// The first stage is the evaluation at `(time, x)`: it is the sample's observation, so
    /// the controller runs no extra time for the record. When that observation crosses a
    /// bound, the step's result is dropped and the run ends at `time`.
    fn continuous_period(&mut self, time: f64) -> std::result::Result<Period, String> {
        let mut observed = false;
        let (law, first, stage) = (&mut self.law, &mut self.observation, &mut self.stage);
        let plant = self.plant;
        let mut feedback = |t: f64, x: &[f64], u: &mut [f64], ws: &mut Workspace| -> Result<()> {
            let observation = if observed { &mut *stage } else { &mut *first };
            law.observe(t, x, observation)?;
            law.hand_over_model_terms(plant, ws, x);
            u.copy_from_slice(&observation.output.input);
            observed = true;
            Ok(())
        };
        let result = step_with_feedback(
            self.plant,
            &mut self.pd,
            &self.x,
            time,
            self.schedule.step,
            self.method,
            &mut feedback,
            &mut self.u,
            &mut self.x_next,
        );
        self.outputs.copy_from(&self.pd);
        if !observed {
            // Only the law fails before the first stage's observation exists.
            return Err(match result {
                Err(e) => format!("controller: {e}"),
                Ok(()) => "controller: not evaluated".into(),
            });
        }
        let failure = match (self.observation.bound_crossed(self.scenario), result) {
            (Some(reason), _) => Some(reason),
            (None, Err(e)) => Some(format!("step: {e}")),
            (None, Ok(())) if self.x_next.iter().any(|v| !v.is_finite()) => {
                Some("non-finite state".into())
            }
            (None, Ok(())) => None,
        };
        let end = failure.map(|reason| RunEnd::Diverged { at_s: time, reason });
        Ok(Period { end })
    }

    /// Moves to the next sample (after a period that did not end the run).
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.x, &mut self.x_next);
    }

    /// The current state.
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// The controller's evaluation at the current sample (after [`Engine::period`]).
    pub fn observation(&self) -> &Observation {
        &self.observation
    }

    /// The record of [`Engine::observation`], taken at the current state.
    pub fn sample(&self) -> Sample<'_> {
        let observation = &self.observation;
        let output = &observation.output;
        let m = &output.momentum;
        Sample {
            time_s: observation.time,
            state: &self.x,
            layout: self.layout,
            thetadot_desired: &output.thetadot_desired,
            com: [output.com.x, output.com.y, output.com.z],
            com_reference: observation.reference.position.into(),
            momentum: [m[0], m[1], m[2], m[3], m[4], m[5]],
            contact_wrenches: &self.outputs.wrench,
            motor_torques: &self.outputs.motor_torque,
            joint_torques: &self.outputs.joint_torque,
            com_error_norm: observation.com_error,
            joint_error_norm: observation.joint_error,
            qp_status: &output.qp_status,
            qp_failures: self.law.controller.qp_failures(),
        }
    }
}
