//! Stepping to recover a push (`walking.stepping = true`, docs/explanation/walking.md): the
//! robot stands, and at each whole-body tick ([`MomentumController::watch_capture_point`])
//! the measured DCM `xi = x + xdot / omega` (the CoM and its velocity at the measured state)
//! is checked against the support polygon of the feet ([`needs_step`], within
//! `walking.capture_margin` of its edge in the DCM's direction, [`stance_margin`], or
//! outside). When it needs a step, the controller
//! replaces its gait with the walk of one recovery step planned from the measured state
//! ([`recovery_gait`]: a short transfer of the load, the swing aimed at the DCM predicted at
//! touchdown, the transfer back to standing over the new feet), walked through the contact
//! phases like any step (`contact_phase.rs`). Checked again after its touchdown: when the
//! step did not capture the DCM, a further step, up to `walking.max_recovery_steps` in a row.
//! Until a step lifts off, it is planned again at each tick from the measured state (the
//! push may still be acting when the step is first needed), with the same foot and lift-off.
//!
//! The swing foot: for the first step the one on the side of the mid-feet line the DCM lies
//! ([`swing_foot_for`]); for a further step the foot that stood (the feet alternate).
//!
//! Until the first step the CoM reference is the scenario's (`[reference]`; the controller
//! stands as without `[walking]`, both feet with half the load each and held, zero desired
//! acceleration, not settled by `walking.settle_position_gain`'s PD); from the first step on
//! the recovery gait's, which ends at rest over the new mid-feet point, and the feet on the
//! ground are settled flat as in a walk.

use super::contact_phase::ContactPhases;
use super::MomentumController;
use crate::walking::{
    needs_step, recovery_gait, settle_from, stance_margin, swing_foot_for, FootTask, Lip,
    MeasuredCom, RecoveryFrame, RecoveryStep, Stance, SupportPolygon, WalkingSettings,
};
use nalgebra::Vector2;
use sea_dyn::{ContactSurface, StateLayout};

/// What the tick does about stepping.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Decision {
    /// Before the lift-off of a planned recovery step: plan it again from the measured state,
    /// lifting off at the same time.
    Replan {
        /// The planned lift-off [s].
        lift_off: f64,
    },
    /// Both feet down after the last touchdown: a step when the DCM needs one (the
    /// `sequence_steps`-th of the sequence).
    Watch {
        /// Recovery steps already taken in this sequence.
        sequence_steps: usize,
    },
}

/// The stepping state of a walking controller (module doc).
pub(super) struct Stepping {
    /// The walking settings (the recovery step's limits and timing).
    settings: WalkingSettings,
    /// The pendulum of `walking.com_height`.
    lip: Lip,
    /// The soles' rectangle.
    surface: ContactSurface,
    /// The ground's height [m] (the initial soles' mean).
    world_z_ground: f64,
    /// Recovery steps planned in the current sequence (reset once a recovery ends standing).
    sequence_steps: usize,
    /// Steps landed in the gaits before the current one.
    earlier_steps: usize,
    /// The feet before any step.
    initial_stance: Stance,
    /// Every recovery step planned: the time of the decision [s] and the step.
    planned: Vec<(f64, RecoveryStep)>,
    /// Whether the current recovery gait's DCM plan was made again from the measured state
    /// after its touchdown ([`settle_from`]).
    settled: bool,
}

impl Stepping {
    /// Stepping from `initial_stance` on ground at `world_z_ground` [m].
    pub(super) fn new(
        settings: &WalkingSettings,
        lip: Lip,
        surface: ContactSurface,
        initial_stance: Stance,
        world_z_ground: f64,
    ) -> Self {
        Self {
            settings: settings.clone(),
            lip,
            surface,
            world_z_ground,
            sequence_steps: 0,
            earlier_steps: 0,
            initial_stance,
            planned: Vec::new(),
            settled: true,
        }
    }

    /// Whether a recovery step was planned: the gait's CoM reference is followed from then on.
    pub(super) fn has_stepped(&self) -> bool {
        !self.planned.is_empty()
    }
}

impl ContactPhases {
    /// After a recovery step's planned touchdown (the gait's last step, at or before `t`
    /// [s]): until the feet's sensors load the landing foot, it keeps descending from its
    /// landing pose (`LATE_TOUCHDOWN_SPEED`) and the other foot stands alone (single
    /// support); once loaded, both feet carry what the QP gives them (share 1/2, no
    /// penalty): the landing foot takes the load at once instead of over the planned
    /// hand-over (module doc).
    pub(super) fn recovery_landing_tasks(&self, t: f64, tasks: &mut [FootTask; 2]) {
        let Some(stepping) = &self.stepping else {
            return;
        };
        let steps = &self.gait.footsteps.steps;
        let Some(index) = steps.len().checked_sub(1) else {
            return;
        };
        let step = &steps[index];
        if !stepping.has_stepped() || t < step.touchdown {
            return;
        }
        let landing = self.gait.contact_of_foot(step.foot);
        let since = t - step.touchdown;
        let unloaded = self
            .normal_forces
            .is_some_and(|forces| forces[landing] <= self.touchdown_force);
        if unloaded && since < self.gait.footsteps.transfer_duration {
            tasks[landing] = FootTask::Swing(self.descent(index, since));
            tasks[1 - landing] = FootTask::Contact { share: 1.0 };
            return;
        }
        for task in tasks.iter_mut() {
            if let FootTask::Contact { share } = task {
                *share = 0.5;
            }
        }
    }
}

impl MomentumController {
    /// Stepping (module doc): at the whole-body tick at time `t` [s] and the measured state
    /// `x` (layout `layout`), plans a recovery step when the measured DCM needs one and the
    /// feet are both on the ground after the last planned touchdown. Does nothing when the
    /// controller does not step (`walking.stepping` off or not walking).
    pub fn watch_capture_point(&mut self, t: f64, x: &[f64], layout: &StateLayout) {
        let Some(decision) = self.stepping_decision(t) else {
            return;
        };
        let measured = self.measured_com(t, x, layout);
        let walking = self.walking.as_mut().expect("walking");
        let stepping = walking.stepping.as_mut().expect("stepping");
        if let (Decision::Watch { .. }, false) = (decision, stepping.settled) {
            settle_from(&mut walking.gait, &stepping.settings, measured);
            walking.gait_revision += 1;
            stepping.settled = true;
        }
        let gait = &walking.gait;
        let (stance, timing) = match decision {
            Decision::Replan { lift_off } => {
                let step = &gait.footsteps.steps[0];
                let start_s = gait.footsteps.start_s;
                (gait.footsteps.stances[0], (step.foot, start_s, lift_off))
            }
            Decision::Watch { sequence_steps } => {
                stepping.sequence_steps = sequence_steps;
                let stance = gait.footsteps.final_stance();
                let world_xi = stepping.lip.dcm(measured.world_p_com, measured.world_v_com);
                let support = SupportPolygon::of_stance(&stance, &stepping.surface);
                let margin = stance_margin(&stepping.settings.capture_margin, &stance, world_xi);
                if !needs_step(&support, world_xi, margin) {
                    return;
                }
                let swing_foot = match (sequence_steps, gait.footsteps.steps.last()) {
                    (1.., Some(last)) => last.foot.other(),
                    _ => swing_foot_for(&stance, world_xi),
                };
                let lift_off = t + stepping.settings.recovery_transfer_duration;
                (stance, (swing_foot, t, lift_off))
            }
        };
        let frame = RecoveryFrame {
            stance,
            world_z_ground: stepping.world_z_ground,
            world_z_com: gait.world_z_com,
            world_z_com_start: match decision {
                Decision::Replan { .. } => gait.world_z_com_start,
                Decision::Watch { .. } if stepping.has_stepped() => {
                    gait.com_reference(t).position.z
                }
                Decision::Watch { .. } => measured.world_z_com,
            },
            contact_of: gait.contact_of,
        };
        let (recovery, step) = recovery_gait(
            &stepping.settings,
            &stepping.lip,
            &stepping.surface,
            &frame,
            timing,
            measured,
        );
        if let Decision::Replan { .. } = decision {
            stepping.planned.pop();
        } else {
            stepping.earlier_steps += gait.steps_landed(t);
            stepping.sequence_steps += 1;
        }
        stepping.planned.push((t, step));
        stepping.settled = false;
        walking.gait = recovery;
        walking.gait_revision += 1;
    }

    /// What stepping does at `t` [s] (`None`: nothing, the controller does not step or a
    /// swing is under way or the sequence has its steps).
    fn stepping_decision(&self, t: f64) -> Option<Decision> {
        let walking = self.walking.as_ref()?;
        let stepping = walking.stepping.as_ref()?;
        let steps = &walking.gait.footsteps.steps;
        if let (true, Some(step)) = (stepping.has_stepped(), steps.first()) {
            if t < step.lift_off {
                return Some(Decision::Replan {
                    lift_off: step.lift_off,
                });
            }
        }
        let last_touchdown = steps
            .last()
            .map_or(f64::NEG_INFINITY, |step| step.touchdown);
        // A landing foot still descending (`recovery_landing_tasks`): not yet.
        if walking
            .tasks
            .iter()
            .any(|task| matches!(task, FootTask::Swing(_)))
        {
            return None;
        }
        let sequence_steps = if t >= walking.gait.end_time() {
            0
        } else {
            stepping.sequence_steps
        };
        (t >= last_touchdown && sequence_steps < stepping.settings.max_recovery_steps)
            .then_some(Decision::Watch { sequence_steps })
    }

    /// The CoM's ground projection and horizontal velocity at `x` (the controller's model;
    /// `self.data` is scratch until the tick recomputes it).
    pub(super) fn measured_com(&mut self, t: f64, x: &[f64], layout: &StateLayout) -> MeasuredCom {
        let (q, nu) = (layout.q(x), layout.nu(x));
        let momentum = sea_dyn::centroidal::centroidal_momentum(&self.model, &mut self.data, q, nu);
        let world_p_com = self.data.p_base_world + self.data.p_com_rel;
        MeasuredCom {
            time: t,
            world_p_com: world_p_com.xy(),
            world_v_com: Vector2::new(momentum[0], momentum[1]) / self.mass,
            world_z_com: world_p_com.z,
        }
    }

    /// Stepping: the recovery steps planned so far, each with the time it was planned [s]
    /// (empty when the controller does not step).
    pub fn recovery_steps(&self) -> &[(f64, RecoveryStep)] {
        self.walking
            .as_ref()
            .and_then(|walking| walking.stepping.as_ref())
            .map_or(&[], |stepping| &stepping.planned)
    }

    /// Walking: the steps landed by time `t` [s] over every gait walked (a stepping
    /// controller's recovery steps included); `None` when not walking.
    pub fn steps_landed(&self, t: f64) -> Option<usize> {
        let walking = self.walking.as_ref()?;
        let earlier = walking
            .stepping
            .as_ref()
            .map_or(0, |stepping| stepping.earlier_steps);
        Some(earlier + walking.gait.steps_landed(t))
    }

    /// Walking: the feet before the first step (the first gait's initial stance); `None`
    /// when not walking.
    pub fn initial_stance(&self) -> Option<Stance> {
        let walking = self.walking.as_ref()?;
        Some(match &walking.stepping {
            Some(stepping) => stepping.initial_stance,
            None => walking.gait.footsteps.stances[0],
        })
    }
}
