//! One sample period of the closed loop: the feedback law's evaluation at a state
//! ([`FeedbackLaw`] of `sea_ctrl`, with the hand-over of its model terms to the plant), the
//! divergence bounds ([`super::bounds`]), and the plant's advance to the next sample with the input held
//! (zero-order hold) or the law at every integrator stage (continuous).

use super::bounds::bound_crossed;
use super::contact_check::{ContactCheck, ContactCheckEvent, ViolationEpisodes, WrenchCheck};
use super::fall_check::{Fall, FallCheck};
use super::impacts::{Impact, ImpactDetector};
use super::record::{RunInfo, Sample};
use super::sampling::{Sampling, Schedule};
use super::sensing::Sensor;
use super::statistics::{Divergence, RunEnd};
use crate::disturbance_schedule::DisturbanceSchedule;
use crate::error::Result;
use crate::settings::{LoopSettings, Setup};
use nalgebra::DVector;
use sea_ctrl::feedback::{FeedbackLaw, Observation};
use sea_ctrl::robot::{ForceReadings, PeriodSensors, RobotController, StackParts};
use sea_ctrl::walking::footstep::wrap_angle;
use sea_ctrl::walking::Gait;
use sea_ctrl::MomentumController;
use sea_dyn::{Data, Model};
use sea_plant::integrator::step_with_feedback;
use sea_plant::{Method, Plant, PlantData, PlantOutputs, StateLayout, Workspace};
use std::sync::atomic::AtomicBool;

/// The loop's feedback law: the setup's controller, borrowed (its counters are read after the
/// run), with clones of its references.
pub(super) type Law<'a> = FeedbackLaw<&'a mut MomentumController>;

/// The robot's controller stack of the loop, around the borrowed controller.
pub(super) type Robot<'a> = RobotController<&'a mut MomentumController>;

/// The hand-over of the law's model terms to the plant: whether the controller's model is
/// the plant's, so that the model terms of a tick (kinematics, `h`, `M` at the tick's state)
/// can be handed to the plant's evaluation at the same state instead of being computed twice.
#[derive(Clone, Copy)]
struct HandOver {
    share_model_terms: bool,
}

impl HandOver {
    /// After the law's evaluation at `x`: hands the controller's model terms, and its contact
    /// terms when its diagonal and contacts are the plant's, to the plant's next evaluation
    /// (used only if that evaluation is at `x`'s `q` and `nu`; see
    /// [`Workspace::adopt_model_terms`] and [`Workspace::adopt_contact_terms`]). Results are
    /// bitwise those without it.
    fn give(self, law: &Law<'_>, plant: &Plant, ws: &mut Workspace, x: &[f64]) {
        if self.share_model_terms {
            let controller = law.controller();
            ws.adopt_model_terms(controller.model_data(), &law.layout(), x);
            ws.adopt_contact_terms(plant, &controller.factored_contacts());
        }
    }
}

/// What a walking robot walked ([`Engine::walked`]).
pub struct Walked {
    /// The planned steps whose touchdown time the run reached.
    pub steps: usize,
    /// The horizontal distance between the feet's mid-points at the start and the end [m].
    pub distance_m: f64,
    /// The distance over the time from the first lift-off to the last touchdown (or the
    /// run's end) [m/s]; `None` before the first lift-off.
    pub speed_m_s: Option<f64>,
    /// The yaw the feet turned: the walking frame's yaw (the soles' mean heading) at the end
    /// minus at the start, counter-clockwise positive, wrapped into (-pi, pi] [rad].
    pub turned_rad: f64,
}

/// What one sample period gave (the evaluation at its start is the law's last observation):
/// when the run stops there, how it ended.
pub(super) struct Period {
    /// `Some` when the run ends at this sample.
    pub end: Option<RunEnd>,
}

/// Which state and outputs start a plant step ([`PlantSide::observe_impacts`]).
#[derive(Clone, Copy)]
enum Step<'x> {
    /// A step with the input held: `x_step` and `pd.outputs`.
    Held,
    /// A continuous step from this state, with the sample's outputs.
    Continuous(&'x [f64]),
}

/// The plant side of the loop: the plant, its workspace and the state buffers, apart from the
/// law so that the plant can advance with the law's output borrowed.
struct PlantSide<'a> {
    plant: &'a Plant,
    method: Method,
    pd: PlantData,
    x_next: Vec<f64>,
    x_step: Vec<f64>,
    /// The law's output buffer of a continuous step.
    u: Vec<f64>,
    /// The plant's outputs at the state of the current sample.
    outputs: PlantOutputs,
    /// The contact wrenches (6 per contact) and joint torques (n) the sensors read at the
    /// period's start, after its command took effect. Under unilateral contacts the wrenches
    /// delivered over the period's first plant step ([`PlantOutputs::step_contact_wrench`]): a
    /// stiff contact's force follows a new command within a step, so the wrench evaluated at
    /// the command's instant still holds the old one's. Under bilateral contacts the
    /// multipliers at the first step's start already follow it, and these are unused (the
    /// sample's outputs are read).
    period_start_wrench: DVector<f64>,
    /// See `period_start_wrench`.
    period_start_joint_torque: DVector<f64>,
    /// The contact wrenches at the start of the period's last plant step, the period's input
    /// still held (6 per contact; under unilateral contacts those delivered over that step):
    /// what the feet's sensors read at the period's end.
    period_end_wrench: DVector<f64>,
    /// The joint torques (n) at the start of the period's last plant step: what the joint
    /// torque sensors read at the period's end.
    period_end_joint_torque: DVector<f64>,
    /// The contact wrenches (6 per contact) averaged over the period's plant steps (under
    /// unilateral contacts those delivered over each step): the sensors' mean reading.
    period_mean_wrench: DVector<f64>,
    /// `[[disturbances]]`: which external wrench acts at each plant step.
    disturbances: DisturbanceSchedule,
    /// The disturbances' wrenches at the current sample (6 per disturbance), for the record.
    disturbance_wrenches: Vec<f64>,
    /// Touchdowns and joint stops at every plant step (`None`: nothing can strike).
    impacts: Option<ImpactDetector>,
    /// Impacts already handed to the sinks.
    impacts_emitted: usize,
}

impl PlantSide<'_> {
    /// What the robot's force sensors read over the period that just ran: the plant's contact
    /// wrenches and joint torques at its start (the sample) and at the start of its last step.
    fn period_sensors(&self) -> PeriodSensors<'_> {
        let start = if self.plant.unilateral().is_some() {
            ForceReadings {
                contact_wrench: &self.period_start_wrench,
                joint_torque: &self.period_start_joint_torque,
            }
        } else {
            ForceReadings {
                contact_wrench: &self.outputs.contact_wrench,
                joint_torque: &self.outputs.joint_torque,
            }
        };
        PeriodSensors {
            start,
            end: ForceReadings {
                contact_wrench: &self.period_end_wrench,
                joint_torque: &self.period_end_joint_torque,
            },
            mean_contact_wrench: Some(&self.period_mean_wrench),
        }
    }

    /// Evaluates the plant at `x` (time `time`) with the law's last input, for the record.
    fn evaluate_at(
        &mut self,
        law: &Law<'_>,
        hand_over: HandOver,
        x: &[f64],
        time: f64,
    ) -> std::result::Result<(), Divergence> {
        self.disturbances.apply(&mut self.pd.workspace, time);
        hand_over.give(law, self.plant, &mut self.pd.workspace, x);
        let u = &law.last().output.input;
        let result =
            sea_plant::evaluate(self.plant, &mut self.pd.workspace, x, u, &mut self.outputs);
        result.map_err(|e| Divergence::PlantFailed(e.to_string()))
    }

    /// Evaluates the plant at `x` with `robot`'s command (n), for the record (the multi-rate
    /// loop's input at the sample).
    fn evaluate_input(
        &mut self,
        robot: &Robot<'_>,
        hand_over: HandOver,
        (x, time): (&[f64], f64),
    ) -> std::result::Result<(), Divergence> {
        self.disturbances.apply(&mut self.pd.workspace, time);
        hand_over.give(robot.law(), self.plant, &mut self.pd.workspace, x);
        let u = robot.command();
        let result =
            sea_plant::evaluate(self.plant, &mut self.pd.workspace, x, u, &mut self.outputs);
        result.map_err(|e| Divergence::PlantFailed(e.to_string()))
    }

    /// Step `k` of the period that starts at `time`: the plant from `x_step` with input `u`
    /// (n) and the disturbances of the step's start, the result swapped into `x_step`; the
    /// first step's start evaluation gives the outputs of the sample.
    fn step(
        &mut self,
        k: usize,
        (time, schedule): (f64, &Schedule),
        u: &[f64],
    ) -> std::result::Result<(), Divergence> {
        let step_start = time + k as f64 * schedule.step;
        self.disturbances.apply(&mut self.pd.workspace, step_start);
        let result = sea_plant::step(
            self.plant,
            &mut self.pd,
            &self.x_step,
            u,
            schedule.step,
            self.method,
            &mut self.x_next,
        );
        if k == 0 {
            let outputs = &self.pd.outputs;
            self.outputs.copy_from(outputs);
            self.period_start_wrench
                .copy_from(&outputs.step_contact_wrench);
            self.period_start_joint_torque
                .copy_from(&outputs.joint_torque);
            self.period_mean_wrench.fill(0.0);
        }
        let wrenches = match self.plant.unilateral() {
            Some(_) => &self.pd.outputs.step_contact_wrench,
            None => &self.pd.outputs.contact_wrench,
        };
        self.period_mean_wrench
            .axpy(1.0 / schedule.steps_per_period as f64, wrenches, 1.0);
        if k + 1 == schedule.steps_per_period {
            self.period_end_wrench.copy_from(wrenches);
            let torques = &self.pd.outputs.joint_torque;
            self.period_end_joint_torque.copy_from(torques);
        }
        result.map_err(|e| Divergence::PlantStepFailed(e.to_string()))?;
        if self.x_next.iter().any(|v| !v.is_finite()) {
            return Err(Divergence::NonFiniteState);
        }
        self.observe_impacts(step_start, Step::Held);
        std::mem::swap(&mut self.x_step, &mut self.x_next);
        Ok(())
    }

    /// Hands the start of the plant step at `time` to the impact detector: the state
    /// `x_step` with the step's outputs (`pd.outputs`) when held, the sample's state `x` with
    /// the sample's outputs (`outputs`) in continuous mode.
    fn observe_impacts(&mut self, time: f64, step: Step<'_>) {
        let Some(detector) = &mut self.impacts else {
            return;
        };
        let plant = (self.plant, self.plant.layout());
        match step {
            Step::Held => detector.observe(plant, time, &self.x_step, &self.pd.outputs),
            Step::Continuous(x) => detector.observe(plant, time, x, &self.outputs),
        }
    }

    /// Multi-rate: the plant over one whole-body period from `x` into `x_next`, the law's
    /// desired joint torques held in `robot`'s joint loops (already held and ticked at `x`);
    /// every `schedule.steps_per_inner_tick()` steps the joint loops tick again at the
    /// measured state (`sensor`'s measurement, the true state without one). The first step's
    /// start evaluation gives the outputs at `x`.
    fn advance_multi_rate(
        &mut self,
        (robot, hand_over): (&mut Robot<'_>, HandOver),
        x: &[f64],
        (time, schedule): (f64, &Schedule),
        mut sensor: Option<&mut Sensor>,
    ) -> std::result::Result<(), Divergence> {
        self.x_step.copy_from_slice(x);
        hand_over.give(
            robot.law(),
            self.plant,
            &mut self.pd.workspace,
            &self.x_step,
        );
        let steps_per_inner = schedule.steps_per_inner_tick();
        for k in 0..schedule.steps_per_period {
            if k > 0 && k % steps_per_inner == 0 {
                let measured = match sensor.as_deref_mut() {
                    Some(sensor) => sensor.measure(&self.x_step),
                    None => &self.x_step,
                };
                robot.joint_tick(measured);
            }
            self.step(k, (time, schedule), robot.command())?;
        }
        self.x_next.copy_from_slice(&self.x_step);
        Ok(())
    }

    /// Zero-order hold: the plant steps over one control period from `x` (time `time`) with
    /// the law's last input held, into `x_next`; the first step's start evaluation gives the
    /// outputs at `x`.
    fn advance_held(
        &mut self,
        law: &Law<'_>,
        hand_over: HandOver,
        x: &[f64],
        (time, schedule): (f64, &Schedule),
    ) -> std::result::Result<(), Divergence> {
        let u = &law.last().output.input;
        self.x_step.copy_from_slice(x);
        // The first step starts where the controller just ticked.
        hand_over.give(law, self.plant, &mut self.pd.workspace, &self.x_step);
        for k in 0..schedule.steps_per_period {
            self.step(k, (time, schedule), u)?;
        }
        self.x_next.copy_from_slice(&self.x_step);
        Ok(())
    }
}

/// Under unilateral contacts: the samples whose delivered wrenches the bilateral contacts'
/// wrench check ([`super::contact_check`]) would have called a fall (a foot lifted, tipping
/// or slipping), and the first one's time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactCheckCount {
    /// Samples.
    pub violations: usize,
    /// Time of the first [s].
    pub first_s: Option<f64>,
}

/// The loop's state between samples: the law, the plant side, the schedule and the buffers,
/// all allocated once.
pub(super) struct Engine<'a> {
    settings: &'a LoopSettings,
    /// The link of each disturbance (what the sinks name).
    disturbance_links: Vec<String>,
    /// Points per contact under unilateral contacts (what the sinks draw); empty otherwise.
    contact_points: Vec<usize>,
    model: &'a Model,
    elastic_names: &'a [String],
    /// The robot's controller stack; its law's last observation is the evaluation at the
    /// current sample.
    pub robot: Robot<'a>,
    hand_over: HandOver,
    /// The time grid.
    pub schedule: Schedule,
    layout: StateLayout,
    side: PlantSide<'a>,
    /// The state at the current sample.
    x: Vec<f64>,
    /// The evaluations at the later integrator stages (continuous sampling), not recorded.
    stage: Observation,
    /// Fall detection on the plant's outputs at each sample (bilateral contacts).
    contact_check: ContactCheck,
    /// Falls as physics (unilateral contacts; `None` under bilateral ones).
    fall_check: Option<FallCheck>,
    /// Under unilateral contacts, the wrench check as a diagnostic.
    contact_check_count: ContactCheckCount,
    /// Under unilateral contacts, each foot's check at the current sample (empty when the
    /// check did not run there: bilateral contacts, `stop_on_fall` off, a diverged sample).
    contact_checks: Vec<WrenchCheck>,
    /// Under unilateral contacts, each foot's open violation.
    violation_episodes: ViolationEpisodes,
    /// The check's verdict changes not yet handed to the sinks.
    contact_check_events: Vec<ContactCheckEvent>,
    /// `[sensing]`: the controller's measurements (`None`: it reads the true state).
    sensor: Option<Sensor>,
    /// Without a sensor, when the controller's model is not the plant's (mass estimates): the
    /// plant model's buffers for the true CoM that is recorded and checked.
    truth: Option<Data>,
}

impl<'a> Engine<'a> {
    /// The loop of `setup` and the controller stack's `parts` with `settings`, at the
    /// initial state.
    pub fn new(
        settings: &'a LoopSettings,
        setup: &'a mut Setup,
        parts: StackParts,
    ) -> Result<Engine<'a>> {
        let schedule = settings.schedule;
        let method = settings.method;
        let Setup {
            model,
            plant,
            controller,
            x0,
            com_reference,
            posture,
            elastic_names,
            warnings: _,
        } = setup;
        let layout = plant.layout();
        let sensor = Sensor::new(&settings.sensing, &plant.model, layout, x0);
        // The law's model terms are a measured state's when there is a sensor.
        let same_model = controller.model() == &plant.model;
        let hand_over = HandOver {
            share_model_terms: same_model && sensor.is_none(),
        };
        let truth = (!same_model && sensor.is_none()).then(|| Data::new(&plant.model));
        let mut pd = settings.plant_data(plant);
        let disturbances = DisturbanceSchedule::new(
            &settings.disturbances,
            &plant.model,
            schedule.step,
            &mut pd.workspace,
        )?;
        let law = FeedbackLaw::new(controller, com_reference.clone(), posture.clone(), layout);
        let robot = RobotController::new(law, parts, schedule.period);
        let impacts = ImpactDetector::new(plant, &settings.scene.contacts, schedule.step);
        let contact_points = plant.contact_point_counts();
        Ok(Engine {
            contact_points,
            disturbance_links: settings.disturbance_links(),
            settings,
            model,
            elastic_names,
            stage: robot.law().new_observation(),
            robot,
            hand_over,
            schedule,
            layout,
            side: PlantSide {
                plant,
                method,
                pd,
                x_next: x0.clone(),
                x_step: x0.clone(),
                u: vec![0.0; model.n_joints()],
                outputs: PlantOutputs::new(plant),
                period_start_wrench: PlantOutputs::new(plant).contact_wrench,
                period_start_joint_torque: PlantOutputs::new(plant).joint_torque,
                period_end_wrench: PlantOutputs::new(plant).contact_wrench,
                period_end_joint_torque: PlantOutputs::new(plant).joint_torque,
                period_mean_wrench: PlantOutputs::new(plant).contact_wrench,
                disturbance_wrenches: vec![0.0; 6 * disturbances.len()],
                disturbances,
                impacts,
                impacts_emitted: 0,
            },
            x: x0.clone(),
            contact_check: ContactCheck::new(plant),
            contact_check_count: ContactCheckCount::default(),
            contact_checks: Vec::with_capacity(plant.contacts.len()),
            violation_episodes: ViolationEpisodes::default(),
            contact_check_events: Vec::new(),
            fall_check: FallCheck::new(plant, x0, settings.fall_bounds),
            sensor,
            truth,
        })
    }

    /// What the sinks learn before the first sample (`cancel`: the run's flag).
    pub fn info<'s>(&'s self, cancel: &'s AtomicBool) -> RunInfo<'s> {
        RunInfo {
            model: self.model,
            layout: self.layout,
            elastic_joints: self.elastic_names,
            contacts: &self.settings.scene.contacts,
            scene: &self.settings.scene,
            disturbance_links: &self.disturbance_links,
            contact_points: &self.contact_points,
            walking: self.robot.controller().gait(),
            cancel,
        }
    }

    /// `[walking]`: the walk the controller follows now; `None` when the robot does not walk.
    pub fn gait(&self) -> Option<&Gait> {
        self.robot.controller().gait()
    }

    /// `[walking]`: how many times the controller's walk changed
    /// ([`sea_ctrl::MomentumController::gait_revision`]); `None` when the robot does not walk.
    pub fn gait_revision(&self) -> Option<u64> {
        self.robot.controller().gait_revision()
    }

    /// The impacts complete since the last call (each handed out once).
    pub fn new_impacts(&mut self) -> &[Impact] {
        let side = &mut self.side;
        let Some(detector) = &side.impacts else {
            return &[];
        };
        let start = side.impacts_emitted;
        side.impacts_emitted = detector.impacts().len();
        &detector.impacts()[start..]
    }

    /// Closes the windows of the impacts still open (the run ended); they are new impacts.
    pub fn close_impacts(&mut self) {
        if let Some(detector) = &mut self.side.impacts {
            detector.close_all();
        }
    }

    /// Every complete impact of the run, in the order they closed.
    pub fn impacts(&self) -> &[Impact] {
        self.side
            .impacts
            .as_ref()
            .map_or(&[], ImpactDetector::impacts)
    }

    /// Record every this many samples (`simulation.record_every`, at least 1).
    pub fn record_every(&self) -> usize {
        self.settings.record_every.max(1)
    }

    /// The simulated duration asked for (`simulation.duration_s`) [s].
    pub fn duration(&self) -> f64 {
        self.settings.duration_s
    }

    /// The state layout.
    pub fn layout(&self) -> StateLayout {
        self.layout
    }

    /// Runs the period that starts at sample `index`: evaluates the law there, stops
    /// (evaluating the plant for the record) when a bound is crossed, `interrupted` is set or
    /// the run is over, and otherwise advances the plant to the next sample (see
    /// [`Engine::commit`]). `Err` carries the reason when the controller fails at the sample
    /// itself (then there is nothing to record). A foot whose wrench at the sample violates
    /// a contact constraint ends the run as [`RunEnd::Fell`] (unless it diverged there).
    pub fn period(
        &mut self,
        index: usize,
        interrupted: bool,
    ) -> std::result::Result<Period, Divergence> {
        self.contact_checks.clear();
        let mut period = self.period_unchecked(index, interrupted)?;
        let check = self.settings.stop_on_fall;
        if check && !matches!(period.end, Some(RunEnd::Diverged { .. })) {
            let at_s = self.schedule.time(index);
            if let Some(fall) = self.fall(&self.x.clone(), at_s) {
                period.end = Some(RunEnd::Fell { at_s, fall });
            }
        }
        Ok(period)
    }

    /// The fall at state `x`: the robot on the ground under unilateral contacts, a foot's
    /// wrench outside a unilateral contact under bilateral ones.
    /// Under unilateral contacts the wrench check stays a diagnostic: the samples whose
    /// delivered wrenches it would have called a fall are counted ([`ContactCheckCount`]),
    /// each foot's check is kept for the sample ([`Engine::sample`]) and a foot's verdict
    /// changes are queued for the sinks ([`Engine::new_contact_check_events`]).
    fn fall(&mut self, x: &[f64], time: f64) -> Option<Fall> {
        let (plant, outputs) = (self.side.plant, &self.side.outputs);
        match &mut self.fall_check {
            Some(check) => {
                let checks = &mut self.contact_checks;
                self.contact_check.check_all(plant, x, outputs, checks);
                if checks.iter().any(|check| check.violated.is_some()) {
                    self.contact_check_count.violations += 1;
                    self.contact_check_count.first_s.get_or_insert(time);
                }
                let names = |c: usize| plant.contacts[c].name.clone();
                let events = &mut self.contact_check_events;
                self.violation_episodes.update(time, checks, names, events);
                check.fall(plant, x).map(Fall::Physical)
            }
            None => self.contact_check.fall(plant, x, outputs).map(Fall::Wrench),
        }
    }

    /// Under unilateral contacts, the samples the wrench check would have called a fall.
    pub fn contact_check_count(&self) -> ContactCheckCount {
        self.contact_check_count
    }

    /// Under unilateral contacts, the feet's verdict changes since the last call (each
    /// handed out once; the buffer is kept).
    pub fn new_contact_check_events(&mut self) -> std::vec::Drain<'_, ContactCheckEvent> {
        self.contact_check_events.drain(..)
    }

    /// [`Engine::period`] without the fall check.
    fn period_unchecked(
        &mut self,
        index: usize,
        interrupted: bool,
    ) -> std::result::Result<Period, Divergence> {
        let time = self.schedule.time(index);
        let side = &mut self.side;
        side.disturbances
            .wrenches_at(time, &mut side.disturbance_wrenches);
        let last = index == self.schedule.last_sample;
        if self.schedule.sampling == Sampling::Continuous && !(last || interrupted) {
            return self.continuous_period(time);
        }
        self.tick_law(time)?;
        let state = (self.model, self.layout.s(&self.x));
        let stop = match bound_crossed(self.robot.last(), state, &self.settings.bounds) {
            Some(reason) => Some(RunEnd::Diverged { at_s: time, reason }),
            None if interrupted => Some(RunEnd::Interrupted),
            None if last => Some(RunEnd::Completed),
            None => None,
        };
        let (hand_over, x) = (self.hand_over, &self.x);
        let measured = self.sensor.as_ref().map_or(x.as_slice(), Sensor::last);
        self.robot.hold(time, measured);
        let robot = &mut self.robot;
        let joint_loops = robot.joint_loop().is_some();
        let failure = match (&stop, joint_loops) {
            (Some(_), false) => self.side.evaluate_at(robot.law(), hand_over, x, time),
            (Some(_), true) => self.side.evaluate_input(robot, hand_over, (x, time)),
            (None, false) => {
                let schedule = &self.schedule;
                self.side
                    .advance_held(robot.law(), hand_over, x, (time, schedule))
            }
            (None, true) => {
                let (schedule, sensor) = (&self.schedule, self.sensor.as_mut());
                self.side
                    .advance_multi_rate((robot, hand_over), x, (time, schedule), sensor)
            }
        };
        let end = match failure {
            Err(reason) => Some(RunEnd::Diverged { at_s: time, reason }),
            Ok(()) => stop,
        };
        if end.is_none() {
            self.robot.end_period(self.side.period_sensors());
        }
        Ok(Period { end })
    }

    /// Multi-rate sampling: the joint loops' stiffness estimates [Nm/rad] by elastic joint
    /// name (identified or not); empty otherwise.
    pub fn stiffness_estimates(&self) -> Vec<(String, f64)> {
        let Some(joint_loop) = self.robot.joint_loop() else {
            return Vec::new();
        };
        let estimates = joint_loop.estimates().iter();
        let names = self.elastic_names.iter().cloned();
        names.zip(estimates.map(|e| e.stiffness)).collect()
    }

    /// Without a sensor, when the controller's model is not the plant's: puts the plant's CoM
    /// (the true one; the controller's is its model's) into the law's observation of the
    /// current sample, which is recorded and checked.
    fn observe_true_com(&mut self) {
        if let Some(data) = &mut self.truth {
            let (model, q) = (&self.side.plant.model, self.layout.q(&self.x));
            let com = sea_dyn::centroidal::com(model, data, q);
            let law = self.robot.law_mut();
            law.observe_truth(com, self.layout.s(&self.x));
        }
    }

    /// The law's tick at sample time `time`: at the true state, or with a sensor at its
    /// measurement of it (the observation then carries the true CoM and errors).
    fn tick_law(&mut self, time: f64) -> std::result::Result<(), Divergence> {
        let failed = |e: sea_ctrl::Error| Divergence::ControllerFailed(e.to_string());
        let Some(sensor) = &mut self.sensor else {
            self.robot.law_mut().tick(time, &self.x).map_err(failed)?;
            self.observe_true_com();
            return Ok(());
        };
        let law = self.robot.law_mut();
        law.tick(time, sensor.measure(&self.x)).map_err(failed)?;
        sensor.observe_truth(law, &self.side.plant.model, &self.x);
        Ok(())
    }

    /// Continuous sampling: one plant step with the law at every stage, into `x_next`. The
    /// first stage is the law's tick at `(time, x)`: it is the sample's observation, so the
    /// controller runs no extra time for the record. When that observation crosses a bound,
    /// the step's result is dropped and the run ends at `time`.
    fn continuous_period(&mut self, time: f64) -> std::result::Result<Period, Divergence> {
        let mut observed = false;
        let (law, stage, hand_over) = (self.robot.law_mut(), &mut self.stage, self.hand_over);
        let side = &mut self.side;
        side.disturbances.apply(&mut side.pd.workspace, time);
        let plant = side.plant;
        let mut feedback = |t: f64, x: &[f64], u: &mut [f64], ws: &mut Workspace| -> Result<()> {
            let input = if observed {
                law.observe(t, x, stage)?;
                &stage.output.input
            } else {
                &law.tick(t, x)?.output.input
            };
            u.copy_from_slice(input);
            hand_over.give(law, plant, ws, x);
            observed = true;
            Ok(())
        };
        let result = step_with_feedback(
            plant,
            &mut side.pd,
            &self.x,
            time,
            self.schedule.step,
            side.method,
            &mut feedback,
            &mut side.u,
            &mut side.x_next,
        );
        side.outputs.copy_from(&side.pd.outputs);
        if result.is_ok() {
            side.observe_impacts(time, Step::Continuous(&self.x));
        }
        if !observed {
            // Only the law fails before the first stage's observation exists.
            return Err(Divergence::ControllerFailed(match result {
                Err(e) => e.to_string(),
                Ok(()) => "not evaluated".into(),
            }));
        }
        self.observe_true_com();
        let state = (self.model, self.layout.s(&self.x));
        let failure = match (
            bound_crossed(self.robot.last(), state, &self.settings.bounds),
            result,
        ) {
            (Some(reason), _) => Some(reason),
            (None, Err(e)) => Some(Divergence::StepFailed(e.to_string())),
            (None, Ok(())) if self.side.x_next.iter().any(|v| !v.is_finite()) => {
                Some(Divergence::NonFiniteState)
            }
            (None, Ok(())) => None,
        };
        let end = failure.map(|reason| RunEnd::Diverged { at_s: time, reason });
        Ok(Period { end })
    }

    /// Moves to the next sample (after a period that did not end the run).
    pub fn commit(&mut self) {
        std::mem::swap(&mut self.x, &mut self.side.x_next);
    }

    /// The current state.
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// `[walking]`: what the robot walked by time `end_s` [s] (the current state's feet
    /// against the gait's initial ones); `None` when it does not walk.
    pub fn walked(&self, end_s: f64) -> Option<Walked> {
        let controller = self.robot.controller();
        let gait = controller.gait()?;
        let model = &self.side.plant.model;
        let frames = controller.contact_frames();
        let mut data = Data::new(model);
        sea_dyn::forward_kinematics(model, &mut data, self.layout.q(&self.x));
        let [a, b] = [0, 1].map(|c| sea_dyn::frame_placement(model, &data, frames[c]));
        let end = (a.translation + b.translation).xy() * 0.5;
        // The feet where the walk started (the initial posture's soles; a re-planned gait,
        // as stepping makes, starts elsewhere).
        let start_frame = controller.initial_stance()?.mid_frame();
        let distance_m = (end - start_frame.world_p_sole).norm();
        // The soles' mean heading (the sum of their x axes' ground projections).
        let heading = a.rotation.column(0) + b.rotation.column(0);
        let end_yaw = heading.y.atan2(heading.x);
        let turned_rad = wrap_angle(end_yaw - start_frame.world_yaw_sole);
        let first_lift_off = gait.footsteps.steps.first().map(|s| s.lift_off);
        let walking_end = gait
            .footsteps
            .steps
            .last()
            .map_or(end_s, |s| s.touchdown.min(end_s));
        let speed_m_s = first_lift_off
            .filter(|&t0| walking_end > t0)
            .map(|t0| distance_m / (walking_end - t0));
        Some(Walked {
            steps: controller.steps_landed(end_s)?,
            distance_m,
            speed_m_s,
            turned_rad,
        })
    }

    /// The law's evaluation at the current sample (after [`Engine::period`]).
    pub fn observation(&self) -> &Observation {
        self.robot.last()
    }

    /// The record of [`Engine::observation`], taken at the current state.
    pub fn sample(&self) -> Sample<'_> {
        let observation = self.robot.last();
        let output = &observation.output;
        let m = &output.momentum;
        let outputs = &self.side.outputs;
        Sample {
            time_s: observation.time,
            state: &self.x,
            layout: self.layout,
            thetadot_desired: &output.thetadot_desired,
            com: [output.com.x, output.com.y, output.com.z],
            com_reference: observation.reference.position.into(),
            momentum: [m[0], m[1], m[2], m[3], m[4], m[5]],
            external_wrench: output.external_wrench.into(),
            contact_wrenches: outputs.step_contact_wrench.as_slice(),
            planned_wrenches: output.wrenches.as_slice(),
            contact_point_positions: outputs.contact_point_position.as_slice(),
            contact_point_forces: outputs.contact_point_force.as_slice(),
            contact_point_active: &outputs.contact_point_active,
            contact_checks: &self.contact_checks,
            motor_torques: outputs.motor_torque.as_slice(),
            joint_torques: outputs.joint_torque.as_slice(),
            disturbance_wrenches: &self.side.disturbance_wrenches,
            com_error_norm: observation.com_error,
            joint_error_norm: observation.joint_error,
            qp_status: &output.qp_status,
            qp_failures: self.robot.controller().qp_failures(),
        }
    }
}
