//! Step adjustment while walking (`walking.step_adjustment = true`): at each whole-body tick
//! of a swing ([`MomentumController::adjust_steps`]), the measured DCM is compared with the
//! gait's plan; when they differ by more than `walking.step_adjustment_threshold` the swing's
//! landing and the later footsteps move, the DCM plan is made again from the measured state
//! and the swing re-aimed in flight ([`adjust_step`], docs/explanation/walking.md). Not in
//! double support, nor once the swing foot is on the ground (an early touchdown).

use super::MomentumController;
use crate::walking::{adjust_step, FootTask, StepAdjustment, Support, WalkingSettings};
use sea_dyn::{ContactSurface, StateLayout};

/// The step adjustment state of a walking controller (module doc).
pub(super) struct StepAdjusting {
    /// The walking settings (the step limits and the threshold).
    settings: WalkingSettings,
    /// The soles' rectangle (where the stance's centre of pressure may be).
    surface: ContactSurface,
    /// Every adjustment made.
    made: Vec<StepAdjustment>,
}

impl StepAdjusting {
    /// Step adjustment with `settings` on soles of `surface`.
    pub(super) fn new(settings: &WalkingSettings, surface: ContactSurface) -> Self {
        Self {
            settings: settings.clone(),
            surface,
            made: Vec::new(),
        }
    }
}

impl MomentumController {
    /// Step adjustment (module doc) at the whole-body tick at time `t` [s] and the measured
    /// state `x` (layout `layout`). Does nothing when the controller does not adjust its
    /// steps (`walking.step_adjustment` off or not walking) or no foot swings.
    pub fn adjust_steps(&mut self, t: f64, x: &[f64], layout: &StateLayout) {
        let Some(index) = self.step_to_adjust(t) else {
            return;
        };
        let measured = self.measured_com(t, x, layout);
        let walking = self.walking.as_mut().expect("walking");
        let adjusting = walking.adjusting.as_mut().expect("step adjustment");
        let (settings, surface) = (&adjusting.settings, &adjusting.surface);
        if let Some(made) = adjust_step(&mut walking.gait, settings, surface, index, measured) {
            adjusting.made.push(made);
            walking.gait_revision += 1;
        }
    }

    /// The step to adjust at `t` [s] when the controller adjusts its steps: the step swinging
    /// while its foot is still in the air at the last tick.
    fn step_to_adjust(&self, t: f64) -> Option<usize> {
        let walking = self.walking.as_ref()?;
        walking.adjusting.as_ref()?;
        let phase = walking.gait.footsteps.phase_at(t);
        let (Support::Single { .. }, Some(index)) = (phase.support, phase.step) else {
            return None;
        };
        let foot = walking.gait.footsteps.steps[index].foot;
        let contact = walking.gait.contact_of_foot(foot);
        let landed =
            matches!(walking.tasks[contact], FootTask::Contact { .. }) && phase.fraction > 0.5;
        (!landed).then_some(index)
    }

    /// Step adjustment: every adjustment made so far (empty when the controller does not
    /// adjust its steps).
    pub fn step_adjustments(&self) -> &[StepAdjustment] {
        self.walking
            .as_ref()
            .and_then(|walking| walking.adjusting.as_ref())
            .map_or(&[], |adjusting| &adjusting.made)
    }
}
