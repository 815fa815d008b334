//! A planned walk as the controller follows it ([`Gait`]): the footsteps, the DCM plan and
//! the swing of every step, built once from the settings and the robot's standing feet, and
//! sampled at each whole-body tick into the CoM reference the momentum task tracks
//! ([`Gait::com_reference`]) and one task per foot ([`Gait::foot_tasks`]): a foot on the
//! ground with its planned share of the load, or a swinging foot with its sole's pose,
//! velocity and acceleration.

use super::command::footsteps_from_settings;
use super::dcm::DcmPlan;
use super::footstep::{Foot, FootstepPlan, SolePose, Stance};
use super::phase::Support;
use super::settings::WalkingSettings;
use super::swing::{SwingSample, SwingTrajectory, ToeOff};
use crate::error::{Error, Result};
use crate::references::ComSample;
use nalgebra::{Vector2, Vector3};
use sea_dyn::spatial::{heading, Pose};

/// What one foot does at a tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FootTask {
    /// On the ground, held in place, carrying at most its planned `share` of the load in
    /// [0, 1] (the wrench QP hands the load over with it, `controller::contact_phase`).
    Contact {
        /// The planned share of the robot's load on this foot.
        share: f64,
    },
    /// In the air: the sole tracks this sample of its swing; its wrench is zero.
    Swing(SwingSample),
}

/// A planned walk (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Gait {
    /// The footsteps and the contact schedule.
    pub footsteps: FootstepPlan,
    /// The DCM and CoM reference over them.
    pub dcm: DcmPlan,
    /// The swing of each step, in the order of `footsteps.steps`.
    pub swings: Vec<SwingTrajectory>,
    /// The CoM height the momentum task holds while walking, in world [m]: the ground plus
    /// the pendulum's height (`walking.com_height`), so that the plan's `omega` is the
    /// robot's.
    pub world_z_com: f64,
    /// The robot's CoM height at the start, in world [m]: the reference moves from it to
    /// [`Self::world_z_com`] over the initial transfer ([`Self::com_reference`]).
    pub world_z_com_start: f64,
    /// Which contact index (in the controller's order of contacts) each foot is: left, right.
    pub contact_of: [usize; 2],
    /// The ground's height in world [m]: the standing soles' mean.
    pub world_z_ground: f64,
}

impl Gait {
    /// The walk of `settings` from the robot standing on the soles `world_h_soles` (the
    /// controller's two contacts, in its order; the one further along world +y is the left
    /// foot) with its CoM at `world_p_com`, under gravity of magnitude `gravity`; the ground
    /// is at the soles' mean height. Errors: fewer or more than two soles
    /// (`controller.contacts`), the settings' and the footsteps' checks.
    pub fn new(
        settings: &WalkingSettings,
        world_h_soles: &[Pose],
        world_p_com: Vector3<f64>,
        gravity: f64,
        toe_off: ToeOff,
    ) -> Result<Self> {
        let [first, second] = world_h_soles else {
            return Err(Error::config(
                "controller.contacts",
                format!(
                    "walking needs two contacts (the feet), got {}",
                    world_h_soles.len()
                ),
            ));
        };
        let contact_of = if first.translation.y >= second.translation.y {
            [0, 1]
        } else {
            [1, 0]
        };
        let stance = Stance {
            left: sole_pose(&world_h_soles[contact_of[0]]),
            right: sole_pose(&world_h_soles[contact_of[1]]),
        };
        let world_z_ground = 0.5 * (first.translation.z + second.translation.z);
        let footsteps = footsteps_from_settings(settings, stance)?;
        let lip = settings.lip(gravity)?;
        let world_p_com0 = Vector2::new(world_p_com.x, world_p_com.y);
        let dcm = DcmPlan::new(&footsteps, lip, world_p_com0, world_z_ground);
        let swings = (0..footsteps.steps.len())
            .map(|i| {
                let shape = (settings.swing_height, toe_off);
                SwingTrajectory::of_step(&footsteps, i, shape, world_z_ground)
            })
            .collect();
        Ok(Self {
            footsteps,
            dcm,
            swings,
            world_z_com: world_z_ground + settings.com_height,
            world_z_com_start: world_p_com.z,
            contact_of,
            world_z_ground,
        })
    }

    /// The CoM reference at `t` [s]: the DCM plan's horizontal CoM; its height goes from
    /// [`Self::world_z_com_start`] to [`Self::world_z_com`] over the initial transfer by
    /// `10 u^3 - 15 u^4 + 6 u^5` of the transfer's fraction `u` (zero velocity and
    /// acceleration at both ends), and is held after.
    pub fn com_reference(&self, t: f64) -> ComSample {
        let mut com = self.dcm.sample(t).com;
        let duration = self.footsteps.transfer_duration;
        let u = ((t - self.footsteps.start_s) / duration).clamp(0.0, 1.0);
        let (u2, u3) = (u * u, u * u * u);
        let blend = u3 * (10.0 - 15.0 * u + 6.0 * u2);
        let rate = 30.0 * u2 * (1.0 - 2.0 * u + u2) / duration;
        let curvature = 60.0 * u * (1.0 - 3.0 * u + 2.0 * u2) / (duration * duration);
        let drop = self.world_z_com - self.world_z_com_start;
        com.position.z = self.world_z_com_start + drop * blend;
        com.velocity.z = drop * rate;
        com.acceleration.z = drop * curvature;
        com
    }

    /// Each foot's task at `t` [s], in the controller's order of contacts.
    pub fn foot_tasks(&self, t: f64) -> [FootTask; 2] {
        let phase = self.footsteps.phase_at(t);
        let left_share = self.footsteps.left_load_share(t);
        let mut tasks = [FootTask::Contact { share: 0.0 }; 2];
        for foot in [Foot::Left, Foot::Right] {
            let share = match foot {
                Foot::Left => left_share,
                Foot::Right => 1.0 - left_share,
            };
            let task = match (phase.support, phase.step) {
                (Support::Single { stance }, Some(step)) if stance != foot => {
                    FootTask::Swing(self.swings[step].sample(t))
                }
                _ => FootTask::Contact { share },
            };
            tasks[self.contact_of_foot(foot)] = task;
        }
        tasks
    }

    /// The contact (the scenario's order) that `foot` stands on: `contact_of`'s entry.
    pub fn contact_of_foot(&self, foot: Foot) -> usize {
        match foot {
            Foot::Left => self.contact_of[0],
            Foot::Right => self.contact_of[1],
        }
    }

    /// The steps whose touchdown is at or before `t` [s].
    pub fn steps_landed(&self, t: f64) -> usize {
        self.footsteps
            .steps
            .iter()
            .filter(|step| step.touchdown <= t)
            .count()
    }

    /// Moves the touchdown of step `index`, in flight at `t` [s], to `touchdown` [s] (after
    /// `t`), and every later lift-off and touchdown by as much: the swing is retimed in flight
    /// ([`SwingTrajectory::retime`]), the later swings move with their steps. The DCM plan is
    /// the caller's to make again over the new times ([`super::adjust_step`]).
    pub fn retime_step(&mut self, index: usize, t: f64, touchdown: f64) {
        let shift = touchdown - self.footsteps.steps[index].touchdown;
        self.footsteps.steps[index].touchdown = touchdown;
        for later in &mut self.footsteps.steps[index + 1..] {
            later.lift_off += shift;
            later.touchdown += shift;
        }
        self.swings[index].retime(t, touchdown);
        for later in &mut self.swings[index + 1..] {
            later.start += shift;
        }
    }

    /// The time the walk ends standing [s].
    pub fn end_time(&self) -> f64 {
        self.footsteps.end_time()
    }
}

/// A sole's placement as a pose on flat ground: its origin's x, y and its yaw (the heading
/// of its x axis in the world's x-y plane).
fn sole_pose(world_h_sole: &Pose) -> SolePose {
    SolePose::new(
        Vector2::new(world_h_sole.translation.x, world_h_sole.translation.y),
        heading(&world_h_sole.rotation),
    )
}
