//! Walking: the contact phases of a planned gait ([`crate::walking::Gait`]) in the momentum
//! controller. The controller keeps its two feet as its contacts throughout; at each tick
//! each foot is either on the ground or swinging ([`FootTask`]):
//!
//! - the torque map keeps every foot's rows in the constraint Jacobian. A foot on the ground
//!   is held (`J_c nudot + Jdot_c nu = 0`, the paper's eq:constraints_acc); a swinging foot's
//!   rows ask for the sole's desired acceleration instead,
//!   `J_c nudot + Jdot_c nu = a_c*` ([`swing_acceleration`]: the swing trajectory's
//!   acceleration plus a PD on the sole's pose and velocity errors), so the legs follow the
//!   feet and the postural task keeps acting on the rest only;
//! - single support: the swinging foot's wrench is zero and the stance foot's wrench solves
//!   the one-contact QP, `min |A_s f_s - b|^2` under its contact constraints (the paper's
//!   one-foot problem on the stance columns of `A`);
//! - double support: the paper's two-feet QP (`min |tau(f)|^2` s.t. `A f = b`) with each
//!   foot whose planned share of the load `sigma` is below one half penalised by
//!   `w (1 - 2 sigma) / sigma |f_c|^2` ([`share_penalty`]; `w` the mean diagonal of the
//!   torque-norm Hessian): zero standing (`sigma = 1/2`), unbounded as the share goes to zero,
//!   so a leaving foot's wrench goes to zero continuously before lift-off and a landing
//!   foot's rises from zero after touchdown: no jump of the planned wrenches at a switch
//!   (with `controller.contact.min_normal_force = 0`, which a walking scenario needs).
//!
//! Touchdown from the feet's force/torque sensors ([`MomentumController::set_foot_forces`],
//! the stack hands them over after each period): a swinging foot past its mid-swing
//! ([`crate::walking::Footstep::mid_swing`]) whose measured normal force exceeds
//! [`TOUCHDOWN_FORCE_FRACTION`] of the robot's weight has landed early: it is held while its
//! sensor reads it loaded (a foot on the ground with no planned load until the plan's double
//! support hands it some); one that bounces off before the plan lands it follows its swing
//! again until it is loaded again (docs/findings/stepping.md, "The touchdowns' infeasible
//! double supports"). A foot the plan has landed whose normal force has stayed below that
//! since its mid-swing is late: through that double support it keeps descending from its
//! landing pose at [`LATE_TOUCHDOWN_SPEED`], with no planned load, until the sensor sees it.
//! Once seen loaded it has landed, and a normal force chattering about the threshold
//! afterwards does not make it late again. So a sole that struck the ground before its
//! planned touchdown and bounced off follows its swing to the landing pose and is then held
//! where it is, the double support handing it its share while it may still be in the air
//! (docs/findings/stepping.md, "The planned and the delivered wrenches at each touchdown").
//! A foot counts as loaded (or unloaded) once its readings have said so for
//! `walking.touchdown_debounce` ([`DebouncedLoad`]), each reading standing for the period
//! before it: at 100 Hz every reading counts at once, at 1 kHz a touchdown's chattering force
//! does not toggle the foot's task every millisecond.

use super::step_adjustment::StepAdjusting;
use super::stepping::Stepping;
use super::touchdown_debounce::DebouncedLoad;
use super::MomentumController;
use crate::error::{Error, Result};
use crate::qp::{momentum_tracking_objective, Minimizer, QpCounters, QpStatus, WrenchQp};
use crate::references::ComSample;
use crate::walking::{FootTask, Gait, SwingSample, ToeOff, WalkingSettings};
use nalgebra::{DMatrix, DVector, Matrix3, Rotation3, Vector6};
use sea_dyn::spatial::{heading, Pose};

/// The measured normal force, as a fraction of the robot's weight, above which a foot is on
/// the ground (module doc).
pub const TOUCHDOWN_FORCE_FRACTION: f64 = 0.05;

/// How fast a late foot keeps descending after its planned touchdown [m/s] (module doc).
pub const LATE_TOUCHDOWN_SPEED: f64 = 0.1;

/// The walking state of a controller: the gait, this tick's foot tasks and the buffers of
/// the single-support QP.
pub(super) struct ContactPhases {
    /// The planned walk.
    pub(super) gait: Gait,
    /// How many times `gait` changed after the start: a step adjusted (and retimed), a
    /// recovery step planned, the settling after a recovery step's touchdown planned from the
    /// measured state ([`MomentumController::gait_revision`]).
    pub(super) gait_revision: u64,
    /// Position gain of the swing sole's PD [1/s^2].
    position_gain: f64,
    /// Velocity gain of the swing sole's PD [1/s].
    velocity_gain: f64,
    /// The gains (position [1/s^2], velocity [1/s]) of the PD that settles a foot on the
    /// ground flat ([`settle_acceleration`], `walking.settle_position_gain` and
    /// `walking.settle_velocity_gain`); `None` when both are zero: the paper's held contact.
    settle_gains: Option<(f64, f64)>,
    /// `walking.double_support_momentum_weight` (0: the paper's equality in double support).
    double_support_momentum_weight: f64,
    /// The two-feet QP without equalities of double support's momentum task in least
    /// squares (`qp_solve.rs`).
    pub(super) least_squares_qp: WrenchQp,
    /// Each contact's task at this tick.
    pub(super) tasks: [FootTask; 2],
    /// The one-contact QP of single support and its buffers.
    single: SingleSupportQp,
    /// Each contact's measured normal force of the last period (world z) [N]; `None` before
    /// the sensors were handed over (the plan's timing alone).
    pub(super) normal_forces: Option<[f64; 2]>,
    /// The normal force above which a foot is on the ground [N].
    pub(super) touchdown_force: f64,
    /// Whether the sensors move the touchdowns (`walking.sensed_touchdown`).
    sensed_touchdown: bool,
    /// `walking.touchdown_debounce` [s].
    touchdown_debounce: f64,
    /// Each contact's loaded state from its sensor, debounced.
    loads: [DebouncedLoad; 2],
    /// Touchdowns the sensors moved: early, late.
    pub(super) early_touchdowns: usize,
    pub(super) late_ticks: usize,
    /// Each contact's last tick with its measured normal force above `touchdown_force` [s]
    /// (`-inf` before any): a foot loaded since its mid-swing has landed and is not late.
    last_loaded_s: [f64; 2],
    /// Stepping to recover pushes (`walking.stepping`, `stepping.rs`); `None`: the gait as
    /// planned.
    pub(super) stepping: Option<Stepping>,
    /// Step adjustment while walking (`walking.step_adjustment`, `step_adjustment.rs`);
    /// `None`: the footsteps as planned.
    pub(super) adjusting: Option<StepAdjusting>,
    /// `walking.identification_settle` [s].
    identification_settle: f64,
    /// `walking.identification_single_support` [s].
    identification_single_support: Option<f64>,
    /// The time of the last tick [s].
    last_tick_s: f64,
    /// The last tick at which a foot's task changed between ground and air (the run's start
    /// before any) [s].
    last_contact_change_s: f64,
}

/// The one-contact wrench QP of single support, on the stance foot's wrench.
struct SingleSupportQp {
    qp: WrenchQp,
    minimizer: Minimizer,
    /// The stance columns of `A` (6 x 6).
    momentum_map: DMatrix<f64>,
    hessian: DMatrix<f64>,
    gradient: DVector<f64>,
    unconstrained: DVector<f64>,
    wrench: DVector<f64>,
}

/// The swing sole's desired classical acceleration `[a_origin; omegadot]` (world axes):
/// `a* = a_d + K_d (v_d - v) + K_p e`, with `e` the position error of the sole origin and
/// the rotation error `log(R_d R^T)` (world axes), `v` = `[v_origin; omega]` the sole's
/// measured velocity.
pub fn swing_acceleration(
    desired: &SwingSample,
    world_h_sole: &Pose,
    world_v_sole: &Vector6<f64>,
    position_gain: f64,
    velocity_gain: f64,
) -> Vector6<f64> {
    let position_error = desired.world_p_sole - world_h_sole.translation;
    let rotation_error = Rotation3::from_matrix_unchecked(
        desired.world_r_sole().matrix() * world_h_sole.rotation.transpose(),
    )
    .scaled_axis();
    let linear = desired.world_a_sole
        + (desired.world_v_sole - world_v_sole.fixed_rows::<3>(0)) * velocity_gain
        + position_error * position_gain;
    let angular = desired.world_omegadot_sole
        + (desired.world_omega_sole - world_v_sole.fixed_rows::<3>(3)) * velocity_gain
        + rotation_error * position_gain;
    Vector6::new(
        linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
    )
}

/// A foot on the ground's desired classical acceleration `[a_origin; omegadot]` (world
/// axes): a PD that settles the sole flat on the ground, `a* = K_p e - K_d v`, with `e` the
/// sole origin's height error to the ground `world_z_ground` (along z only) and the rotation
/// error `log(R_flat R^T)` to the sole turned flat about its own yaw, `v` its measured velocity
/// `[v_origin; omega]`. Zero on a sole at rest flat on the ground (the paper's held contact,
/// eq:constraints_acc); a landing sole that bounced or rocks onto an edge is pulled back down
/// and flat instead of being held where it is.
pub fn settle_acceleration(
    world_h_sole: &Pose,
    world_v_sole: &Vector6<f64>,
    world_z_ground: f64,
    position_gain: f64,
    velocity_gain: f64,
) -> Vector6<f64> {
    let yaw = heading(&world_h_sole.rotation);
    let world_r_flat = Rotation3::from_axis_angle(&nalgebra::Vector3::z_axis(), yaw);
    let rotation_error =
        Rotation3::from_matrix_unchecked(world_r_flat.matrix() * world_h_sole.rotation.transpose())
            .scaled_axis();
    let height_error = world_z_ground - world_h_sole.translation.z;
    let mut acceleration = -world_v_sole * velocity_gain;
    acceleration[2] += height_error * position_gain;
    for r in 0..3 {
        acceleration[3 + r] += rotation_error[r] * position_gain;
    }
    acceleration
}

/// The penalty weight on a foot's wrench in double support for its planned share of the
/// load `share` (module doc): `(1 - 2 share) / share` below one half, 0 above (times the
/// Hessian's scale); capped at [`MAX_SHARE_PENALTY`] (the share 0 of a foot just landed).
pub fn share_penalty(share: f64) -> f64 {
    if share >= 0.5 {
        0.0
    } else {
        ((1.0 - 2.0 * share) / share.max(1e-12)).min(MAX_SHARE_PENALTY)
    }
}

/// The largest [`share_penalty`]: a foot's wrench is then about 1e-4 of what the QP would
/// give it unpenalised (a few hundredths of a newton for the iCub), and the QP's Hessian
/// stays well conditioned.
pub const MAX_SHARE_PENALTY: f64 = 1e4;

/// What the feet's sensors make of a foot's planned task (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Touchdown {
    /// The plan stands.
    AsPlanned,
    /// A swinging foot loaded past its mid-swing: held on the ground at this tick.
    Early,
    /// A foot the plan has landed `since` [s] ago and the sensors have not seen loaded since
    /// its mid-swing: it keeps descending.
    Late {
        /// Time since the planned touchdown [s].
        since: f64,
    },
}

/// One foot's sensor reading at a tick.
#[derive(Clone, Copy, Debug)]
struct SensedFoot {
    /// Its measured normal force is above the touchdown force.
    loaded: bool,
    /// The last tick it was loaded [s] (`-inf` before any).
    last_loaded_s: f64,
}

/// The correction of a foot's `planned` task at `t` [s] in a gait phase ending at
/// `phase_end` [s] whose step is `landing` (`lands_here`: that step's foot is this one), by
/// what its sensor reads (`sensed`).
fn touchdown(
    planned: &FootTask,
    landing: &crate::walking::Footstep,
    lands_here: bool,
    sensed: SensedFoot,
    t: f64,
    phase_end: f64,
) -> Touchdown {
    match planned {
        FootTask::Swing(_) if sensed.loaded && t > landing.mid_swing() => Touchdown::Early,
        FootTask::Contact { share } if !sensed.loaded && *share < 0.5 && lands_here => {
            let since = t - landing.touchdown;
            let landed = sensed.last_loaded_s > landing.mid_swing();
            if !landed && since >= 0.0 && t < phase_end {
                Touchdown::Late { since }
            } else {
                Touchdown::AsPlanned
            }
        }
        _ => Touchdown::AsPlanned,
    }
}

impl ContactPhases {
    /// The phases of walking `gait` under `settings` for a robot of `weight` [N] standing at
    /// the start, with the single-support QP (one contact) and the two-feet QP of the double
    /// support's least squares (`[single, least_squares]`), without stepping or step
    /// adjustment.
    fn new(
        settings: &WalkingSettings,
        gait: Gait,
        weight: f64,
        [single_qp, least_squares_qp]: [WrenchQp; 2],
    ) -> Self {
        let settle = settings.settle_position_gain > 0.0 || settings.settle_velocity_gain > 0.0;
        Self {
            normal_forces: None,
            touchdown_force: TOUCHDOWN_FORCE_FRACTION * weight,
            sensed_touchdown: settings.sensed_touchdown,
            touchdown_debounce: settings.touchdown_debounce,
            loads: [DebouncedLoad::default(); 2],
            early_touchdowns: 0,
            late_ticks: 0,
            stepping: None,
            adjusting: None,
            tasks: gait.foot_tasks(0.0),
            identification_settle: settings.identification_settle,
            identification_single_support: settings.identification_single_support,
            last_tick_s: 0.0,
            last_loaded_s: [f64::NEG_INFINITY; 2],
            last_contact_change_s: 0.0,
            gait,
            gait_revision: 0,
            position_gain: settings.swing_position_gain,
            velocity_gain: settings.swing_velocity_gain,
            settle_gains: settle
                .then_some((settings.settle_position_gain, settings.settle_velocity_gain)),
            double_support_momentum_weight: settings.double_support_momentum_weight,
            least_squares_qp,
            single: SingleSupportQp {
                qp: single_qp,
                minimizer: Minimizer::new(6, 0),
                momentum_map: DMatrix::zeros(6, 6),
                hessian: DMatrix::zeros(6, 6),
                gradient: DVector::zeros(6),
                unconstrained: DVector::zeros(6),
                wrench: DVector::zeros(6),
            },
        }
    }

    /// The `planned` tasks at `t` corrected by the measured normal forces (module doc): an
    /// early touchdown holds the foot, a late one keeps it descending.
    fn sensed_tasks(&mut self, t: f64, planned: [FootTask; 2]) -> [FootTask; 2] {
        let Some(forces) = self.normal_forces.filter(|_| self.sensed_touchdown) else {
            return planned;
        };
        let mut tasks = planned;
        let phase = self.gait.footsteps.phase_at(t);
        let period = t - self.last_tick_s;
        for c in 0..2 {
            let reading_loaded = forces[c] > self.touchdown_force;
            let loaded = self.loads[c].update(reading_loaded, t, period, self.touchdown_debounce);
            if loaded {
                self.last_loaded_s[c] = t;
            }
            let Some(step) = phase.step else {
                continue;
            };
            let landing = &self.gait.footsteps.steps[step];
            let lands_here = self.gait.contact_of_foot(landing.foot) == c;
            let sensed = SensedFoot {
                loaded,
                last_loaded_s: self.last_loaded_s[c],
            };
            match touchdown(&planned[c], landing, lands_here, sensed, t, phase.end) {
                Touchdown::AsPlanned => {}
                Touchdown::Early => {
                    if !matches!(self.tasks[c], FootTask::Contact { .. }) {
                        self.early_touchdowns += 1;
                    }
                    tasks[c] = FootTask::Contact { share: 0.0 };
                }
                Touchdown::Late { since } => {
                    self.late_ticks += 1;
                    tasks[c] = FootTask::Swing(self.descent(step, since));
                }
            }
        }
        tasks
    }

    /// A late foot `since` [s] after step `step`'s planned touchdown: its landing pose,
    /// lowered at [`LATE_TOUCHDOWN_SPEED`].
    pub(super) fn descent(&self, step: usize, since: f64) -> SwingSample {
        let mut sample = self.gait.swings[step].sample(f64::INFINITY);
        sample.world_p_sole.z -= LATE_TOUCHDOWN_SPEED * since;
        sample.world_v_sole.z = -LATE_TOUCHDOWN_SPEED;
        sample
    }

    /// Double support: adds each foot's [`share_penalty`] to the two-feet QP's `hessian`
    /// (12 x 12), scaled by its mean diagonal.
    pub(super) fn add_share_penalties(&self, hessian: &mut DMatrix<f64>) {
        let scale = hessian.trace() / hessian.nrows() as f64;
        for (c, task) in self.tasks.iter().enumerate() {
            if let FootTask::Contact { share } = task {
                let weight = scale * share_penalty(*share);
                for r in 0..6 {
                    hessian[(6 * c + r, 6 * c + r)] += weight;
                }
            }
        }
    }
}

impl MomentumController {
    /// Makes the controller walk the gait of `settings` from the posture `q0` (the robot
    /// standing on its two contacts, where [`Self::new`] placed them), whose whole-body period
    /// is `whole_body_period` [s]: from then on [`Self::walking_reference`] gives each tick's
    /// CoM reference and contact phases. Errors name the key: the settings' check
    /// ([`WalkingSettings::validate`]), the footsteps', one contact
    /// (`controller.contacts`), a minimum normal force above zero
    /// (`controller.contact.min_normal_force`: a foot's wrench must reach zero to lift off).
    pub fn set_walking(
        &mut self,
        settings: &WalkingSettings,
        q0: &[f64],
        whole_body_period: f64,
    ) -> Result<()> {
        settings.validate(whole_body_period)?;
        if self.contact_frames.len() != 2 {
            return Err(Error::config(
                "walking",
                format!(
                    "walking needs two contacts (the feet) in controller.contacts, got {}",
                    self.contact_frames.len()
                ),
            ));
        }
        let min_normal_force = self.settings.constraints.min_normal_force;
        if min_normal_force != 0.0 {
            return Err(Error::invalid(
                "controller.contact.min_normal_force",
                "must be 0 when walking (a foot's wrench goes to zero before it lifts off)",
                min_normal_force,
            ));
        }
        let world_p_com = sea_dyn::centroidal::com(&self.model, &mut self.data, q0);
        let gravity = self.model.gravity.norm();
        let surface = self.settings.constraints.surface;
        let toe_off = ToeOff::of(settings, &surface);
        let gait = Gait::new(
            settings,
            &self.contact_references,
            world_p_com,
            gravity,
            toe_off,
        )?;
        let stepping = settings.stepping.then(|| {
            let stance = gait.footsteps.stances[0];
            Stepping::new(
                settings,
                gait.dcm.lip(),
                surface,
                stance,
                gait.world_z_ground,
            )
        });
        let adjusting = settings
            .step_adjustment
            .then(|| StepAdjusting::new(settings, surface));
        let (tuning, constraints) = (&self.settings.tuning, &self.settings.constraints);
        let mut single_qp = WrenchQp::new(1, 0, constraints);
        single_qp.unconstrained_first = tuning.qp_unconstrained_first;
        single_qp.solver = tuning.qp_solver;
        let mut least_squares_qp = WrenchQp::new(2, 0, constraints);
        least_squares_qp.solver = tuning.qp_solver;
        self.torque_map.desired_acceleration = Some(DVector::zeros(12));
        let qps = [single_qp, least_squares_qp];
        let mut phases = ContactPhases::new(settings, gait, self.mass * gravity, qps);
        phases.stepping = stepping;
        phases.adjusting = adjusting;
        self.walking = Some(phases);
        Ok(())
    }

    /// The gait the controller walks, if any.
    pub fn gait(&self) -> Option<&Gait> {
        self.walking.as_ref().map(|walking| &walking.gait)
    }

    /// How many times [`Self::gait`] changed since walking began (a step adjusted or
    /// retimed, a recovery step planned, the settling after a recovery step's touchdown
    /// planned from the measured state): a reader that kept a
    /// copy of the gait takes a new one when this moves. `None` when not walking.
    pub fn gait_revision(&self) -> Option<u64> {
        self.walking.as_ref().map(|walking| walking.gait_revision)
    }

    /// The foot tasks of the last [`Self::walking_reference`], in the order of the contacts
    /// (`None` when not walking).
    pub fn foot_tasks(&self) -> Option<&[FootTask; 2]> {
        self.walking.as_ref().map(|walking| &walking.tasks)
    }

    /// When walking: whether the stiffness identification may update from the last tick's
    /// samples: both feet on the ground since at least `walking.identification_settle`, or
    /// one foot alone since at least `walking.identification_single_support` when that is set
    /// (lift-offs, touchdowns and the run's start reopen the window); `None` when not
    /// walking (no contact changes: always).
    pub fn identification_settled(&self) -> Option<bool> {
        let walking = self.walking.as_ref()?;
        let on_ground = walking
            .tasks
            .iter()
            .filter(|task| matches!(task, FootTask::Contact { .. }))
            .count();
        let settle = match on_ground {
            2 => Some(walking.identification_settle),
            1 => walking.identification_single_support,
            _ => None,
        };
        let settled = walking.last_tick_s - walking.last_contact_change_s;
        Some(settle.is_some_and(|settle| settled >= settle - 1e-9))
    }

    /// When walking: sets the contact phases of the tick at time `t` [s] and returns the
    /// CoM reference the momentum task tracks then; `None` when not walking, or when stepping
    /// (`walking.stepping`) before any step (the caller's reference then, `stepping.rs`).
    pub fn walking_reference(&mut self, t: f64) -> Option<ComSample> {
        let walking = self.walking.as_mut()?;
        let mut planned = walking.gait.foot_tasks(t);
        let standing = walking.stepping.as_ref().is_some_and(|stepping| {
            walking.recovery_landing_tasks(t, &mut planned);
            !stepping.has_stepped()
        });
        let tasks = walking.sensed_tasks(t, planned);
        let on_ground = |task: &FootTask| matches!(task, FootTask::Contact { .. });
        if tasks
            .iter()
            .map(on_ground)
            .ne(walking.tasks.iter().map(on_ground))
        {
            walking.last_contact_change_s = t;
        }
        walking.tasks = tasks;
        walking.last_tick_s = t;
        if standing {
            return None;
        }
        Some(walking.gait.com_reference(t))
    }

    /// The feet's measured contact wrenches (6 per contact, the controller's order, world
    /// axes; the force/torque sensors at the end of the last period): the touchdowns of the
    /// next ticks follow them (module doc). Ignored when not walking.
    pub fn set_foot_forces(&mut self, contact_wrenches: &DVector<f64>) {
        if let Some(walking) = &mut self.walking {
            walking.normal_forces = Some([contact_wrenches[2], contact_wrenches[8]]);
        }
    }

    /// Walking: the touchdowns the sensors moved so far, early (feet held before their
    /// planned touchdown) and late (ticks of a foot still descending after it); `None` when
    /// not walking.
    pub fn touchdown_corrections(&self) -> Option<(usize, usize)> {
        let walking = self.walking.as_ref()?;
        Some((walking.early_touchdowns, walking.late_ticks))
    }

    /// When walking, contact `c`'s desired acceleration into the torque map (zero on the
    /// ground, [`swing_acceleration`] when swinging), at the sole placement `world_h_sole`,
    /// with the generalized velocity `nu`.
    pub(super) fn set_contact_acceleration(&mut self, c: usize, world_h_sole: &Pose, nu: &[f64]) {
        let Some(walking) = &self.walking else {
            return;
        };
        let map = &mut self.torque_map;
        let Some(desired) = map.desired_acceleration.as_mut() else {
            return;
        };
        let rows = map.jacobian.rows(6 * c, 6);
        let velocity =
            Vector6::from_fn(|r, _| rows.row(r).iter().zip(nu).map(|(j, v)| j * v).sum());
        // Stepping, before the first recovery step: the feet stand held (the paper's contact,
        // as standing without `[walking]`); settling them pulled down a foot that a sideways
        // push lifts and lowered the recovered pushes (docs/findings/stepping.md).
        let standing = walking
            .stepping
            .as_ref()
            .is_some_and(|stepping| !stepping.has_stepped());
        let settle_gains = walking.settle_gains.filter(|_| !standing);
        let acceleration = match &walking.tasks[c] {
            FootTask::Contact { .. } => match settle_gains {
                Some((kp, kd)) => settle_acceleration(
                    world_h_sole,
                    &velocity,
                    walking.gait.world_z_ground,
                    kp,
                    kd,
                ),
                None => Vector6::zeros(),
            },
            FootTask::Swing(sample) => {
                let (kp, kd) = (walking.position_gain, walking.velocity_gain);
                swing_acceleration(sample, world_h_sole, &velocity, kp, kd)
            }
        };
        desired.fixed_rows_mut::<6>(6 * c).copy_from(&acceleration);
    }

    /// Walking with `walking.double_support_momentum_weight` above zero: that weight (the
    /// double support's momentum task in least squares, `qp_solve.rs`); `None` otherwise (the
    /// paper's equality `A f = b`).
    pub(super) fn double_support_momentum_weight(&self) -> Option<f64> {
        let weight = self.walking.as_ref()?.double_support_momentum_weight;
        (weight > 0.0 && self.redundant.is_none()).then_some(weight)
    }

    /// The stance contact of single support (`None` in double support or when not walking).
    pub(super) fn stance_contact(&self) -> Option<usize> {
        let tasks = &self.walking.as_ref()?.tasks;
        match tasks {
            [FootTask::Contact { .. }, FootTask::Swing(_)] => Some(0),
            [FootTask::Swing(_), FootTask::Contact { .. }] => Some(1),
            _ => None,
        }
    }

    /// Single support on contact `stance`: the one-contact QP on the stance columns of the
    /// momentum task into `wrenches` (the swinging foot's wrench zero).
    pub(super) fn solve_single_support(
        &mut self,
        stance: usize,
        wrenches: &mut DVector<f64>,
    ) -> QpStatus {
        let walking = self
            .walking
            .as_mut()
            .expect("single support only when walking");
        let single = &mut walking.single;
        let terms = &self.terms;
        single
            .momentum_map
            .copy_from(&terms.momentum_map.columns(6 * stance, 6));
        momentum_tracking_objective(
            &single.momentum_map,
            &terms.momentum_target,
            self.settings.tuning.qp_regularization,
            &mut single.hessian,
            &mut single.gradient,
        );
        let found = single.minimizer.unconstrained(
            &single.hessian,
            &single.gradient,
            &mut single.unconstrained,
        );
        let rotation: [Matrix3<f64>; 1] = [terms.contact_rotations[stance]];
        let status = single.qp.solve(
            &single.hessian,
            &single.gradient,
            None,
            &rotation,
            found.then_some(&single.unconstrained),
            &mut single.wrench,
        );
        wrenches.fill(0.0);
        wrenches.rows_mut(6 * stance, 6).copy_from(&single.wrench);
        status
    }

    /// The counters of the walking QPs, single support's and double support's in least
    /// squares, summed (zero when not walking).
    pub(super) fn single_support_counters(&self) -> QpCounters {
        let Some(walking) = self.walking.as_ref() else {
            return QpCounters::default();
        };
        walking.single.qp.counters() + walking.least_squares_qp.counters()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walking::SwingSample;
    use nalgebra::Vector3;

    fn sample_at(p: Vector3<f64>) -> SwingSample {
        SwingSample {
            world_p_sole: p,
            world_v_sole: Vector3::zeros(),
            world_a_sole: Vector3::new(0.0, 0.0, 1.0),
            world_yaw_sole: 0.3,
            world_omega_sole: Vector3::zeros(),
            world_omegadot_sole: Vector3::zeros(),
            pitch: 0.0,
        }
    }

    /// Step lifting off at 1.0 s and landing at 1.3 s (mid-swing 1.15 s).
    fn landing() -> crate::walking::Footstep {
        crate::walking::Footstep {
            foot: crate::walking::Foot::Left,
            pose: crate::walking::SolePose::new(nalgebra::Vector2::new(0.1, 0.05), 0.0),
            lift_off: 1.0,
            touchdown: 1.3,
        }
    }

    fn sensed(loaded: bool, last_loaded_s: f64) -> SensedFoot {
        SensedFoot {
            loaded,
            last_loaded_s,
        }
    }

    #[test]
    fn a_swinging_foot_lands_early_only_when_loaded_past_its_mid_swing() {
        let swing = FootTask::Swing(sample_at(Vector3::zeros()));
        let step = landing();
        let loaded = sensed(true, 1.1);
        assert_eq!(
            touchdown(&swing, &step, true, loaded, 1.1, 1.3),
            Touchdown::AsPlanned
        );
        assert_eq!(
            touchdown(&swing, &step, true, loaded, 1.2, 1.3),
            Touchdown::Early
        );
        let unloaded = sensed(false, 0.9);
        assert_eq!(
            touchdown(&swing, &step, true, unloaded, 1.2, 1.3),
            Touchdown::AsPlanned
        );
        // Loaded at 1.2 s, bounced off by 1.22 s: its swing again until loaded again (holding
        // it from the first contact on lost walks, docs/findings/stepping.md).
        let bounced = sensed(false, 1.2);
        assert_eq!(
            touchdown(&swing, &step, true, bounced, 1.22, 1.3),
            Touchdown::AsPlanned
        );
    }

    #[test]
    fn a_landed_foot_is_late_unless_loaded_since_its_mid_swing() {
        let contact = FootTask::Contact { share: 0.2 };
        let step = landing();
        let late = |last_loaded_s| {
            touchdown(
                &contact,
                &step,
                true,
                sensed(false, last_loaded_s),
                1.35,
                1.4,
            )
        };
        // Never loaded, or loaded only at its lift-off (the last period's force of a foot
        // leaving the ground): late, descending.
        assert_eq!(
            late(f64::NEG_INFINITY),
            Touchdown::Late { since: 1.35 - 1.3 }
        );
        assert_eq!(late(1.0), Touchdown::Late { since: 1.35 - 1.3 });
        // Loaded once past mid-swing: landed, a chattering force does not make it late.
        assert_eq!(late(1.2), Touchdown::AsPlanned);
        // Not the landing foot, or a share already handed over, or the phase over: as planned.
        let other = touchdown(&contact, &step, false, sensed(false, 0.0), 1.35, 1.4);
        assert_eq!(other, Touchdown::AsPlanned);
        let loaded_share = FootTask::Contact { share: 0.6 };
        let handed = touchdown(&loaded_share, &step, true, sensed(false, 0.0), 1.35, 1.4);
        assert_eq!(handed, Touchdown::AsPlanned);
        let over = touchdown(&contact, &step, true, sensed(false, 0.0), 1.4, 1.4);
        assert_eq!(over, Touchdown::AsPlanned);
    }

    #[test]
    fn the_swing_pd_pulls_the_sole_towards_its_reference() {
        let desired = sample_at(Vector3::new(0.1, 0.0, 0.05));
        let mut pose = Pose {
            rotation: *desired.world_r_sole().matrix(),
            translation: desired.world_p_sole,
        };
        let at_rest = swing_acceleration(&desired, &pose, &Vector6::zeros(), 400.0, 40.0);
        assert!((at_rest - Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0)).norm() < 1e-12);
        // 1 cm too low and yawed 0.1 rad too far: pushed up, turned back.
        pose.translation.z -= 0.01;
        pose.rotation = *Rotation3::from_axis_angle(&Vector3::z_axis(), 0.4).matrix();
        let a = swing_acceleration(&desired, &pose, &Vector6::zeros(), 400.0, 40.0);
        assert!((a[2] - (1.0 + 4.0)).abs() < 1e-9);
        assert!((a[5] + 40.0).abs() < 1e-9);
        // Moving up at 0.1 m/s: damped.
        let v = Vector6::new(0.0, 0.0, 0.1, 0.0, 0.0, 0.0);
        let damped = swing_acceleration(&desired, &pose, &v, 400.0, 40.0);
        assert!((damped[2] - (a[2] - 4.0)).abs() < 1e-9);
    }

    #[test]
    fn the_settling_pd_pulls_a_foot_down_and_flat_and_leaves_a_resting_one_alone() {
        let yawed = *Rotation3::from_axis_angle(&Vector3::z_axis(), 0.3).matrix();
        let mut pose = Pose {
            rotation: yawed,
            translation: Vector3::new(0.2, 0.1, 0.01),
        };
        // Flat on the ground at 0.01 m, at rest: nothing asked (the paper's held contact).
        let rest = settle_acceleration(&pose, &Vector6::zeros(), 0.01, 100.0, 20.0);
        assert!(rest.norm() < 1e-12);
        // 5 mm up, pitched 0.1 rad about its own y axis, rising at 0.1 m/s: pushed down,
        // pitched back, damped; no horizontal pull, the yaw kept.
        pose.translation.z = 0.015;
        pose.rotation = yawed * Rotation3::from_axis_angle(&Vector3::y_axis(), 0.1).matrix();
        let v = Vector6::new(0.0, 0.0, 0.1, 0.0, 0.0, 0.0);
        let a = settle_acceleration(&pose, &v, 0.01, 100.0, 20.0);
        assert!((a[2] - (-0.5 - 2.0)).abs() < 1e-9, "{a}");
        assert!(a[0].abs() < 1e-12 && a[1].abs() < 1e-12);
        let pitch_axis = yawed * Vector3::y();
        let angular = a.fixed_rows::<3>(3).into_owned();
        assert!((angular + pitch_axis * 10.0).norm() < 1e-9, "{angular}");
    }

    #[test]
    fn the_share_penalty_vanishes_at_half_and_grows_without_bound_at_zero() {
        assert_eq!(share_penalty(0.5), 0.0);
        assert_eq!(share_penalty(1.0), 0.0);
        assert!((share_penalty(0.25) - 2.0).abs() < 1e-12);
        assert!(share_penalty(1e-3) > 900.0);
        assert_eq!(share_penalty(0.0), MAX_SHARE_PENALTY);
        // Continuous at one half, decreasing in the share.
        assert!(share_penalty(0.4999) < 1e-3);
        assert!(share_penalty(0.1) > share_penalty(0.2));
    }
}
