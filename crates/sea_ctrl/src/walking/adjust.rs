//! Step adjustment while walking ([`adjust_step`], `walking.step_adjustment`): the classic
//! DCM step adjustment (Englsberger et al. 2015; Khadiv et al. 2016, docs/references.md#walking).
//!
//! During the swing of step `i` the VRP is held at the stance sole `p`, so a DCM error `e0 =
//! xi_measured - xi_planned` now grows to `e0 e^(omega t_remaining)` by touchdown. Moving the
//! landing of step `i`, and every later footstep with it, by that much moves the whole DCM
//! plan after touchdown by the same vector (the backward recursion is equivariant under a
//! common shift of the footsteps), so the plan made again over the moved footsteps starts at
//! the measured DCM: the walk goes on from where the push left it, on a shifted line.
//!
//! The move is clipped in the stance sole's frame to the reach (`max_step_length`) and to
//! `min_step_width`..`max_step_width` on the swing foot's own side (the feet never cross), the
//! yaw kept. What the clipping leaves is taken by the stance's centre of pressure: the VRP
//! held over the rest of the swing is the point `p'` with `p' + (xi_measured - p')
//! e^(omega t_remaining)` the plan's DCM at touchdown, `p'` moved into the stance sole (the
//! ankle strategy); when it has to be moved, the plan's DCM now differs from the measured one
//! and the next step is adjusted in its turn.
//!
//! With `walking.step_timing` the touchdown may also come earlier, when the landing wished
//! for lies beyond the step limits ([`super::step_timing`]): the later steps' times move with
//! it, the swing is retimed in flight ([`Gait::retime_step`]) and the DCM plan made again over
//! the new times.
//!
//! Only until `step_adjustment_end_phase` of the swing (0.8 by default): as the foot meets
//! the ground the measured DCM error jumps (impacts), and a landing moved in the last
//! periods asks the swing foot for accelerations it cannot follow.
//!
//! The CoM reference starts at the measured CoM (the plan follows the robot, as a recovery
//! step's does, `walking::recovery`).

use super::dcm::{backward_recursion, DcmPlan};
use super::footstep::{Footstep, SolePose};
use super::gait::Gait;
use super::polygon::SupportPolygon;
use super::recovery::MeasuredCom;
use super::segment::DcmSegment;
use super::settings::WalkingSettings;
use super::step_timing::{remaining_swing, SwingInFlight, TIMING_GRID_S};
use super::swing::SwingTrajectory;
use nalgebra::Vector2;
use sea_dyn::ContactSurface;

/// What one adjustment did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepAdjustment {
    /// The time of the adjustment [s].
    pub time: f64,
    /// The step whose landing moved (index in the plan).
    pub step: usize,
    /// The DCM error now, measured minus planned (world x, y) [m].
    pub world_dcm_error: Vector2<f64>,
    /// How far the landing (and every later footstep) moved (world x, y) [m].
    pub world_shift: Vector2<f64>,
    /// Whether the move was clipped to the step limits.
    pub clipped: bool,
    /// The step's touchdown after the adjustment [s]: earlier than planned when the timing
    /// moved (`walking.step_timing`, [`super::step_timing`]).
    pub touchdown: f64,
}

/// Adjusts `gait` during the swing of its step `index` at the `measured` state (module doc):
/// moves that step's landing and every later footstep, makes the DCM plan again from the
/// measured state over them and re-aims the swing in flight. Nothing is done (`None`) when the
/// DCM error is at most `walking.step_adjustment_threshold`, the step is not in flight, or
/// its swing is past `walking.step_adjustment_end_phase` (module doc).
pub fn adjust_step(
    gait: &mut Gait,
    settings: &WalkingSettings,
    surface: &ContactSurface,
    index: usize,
    measured: MeasuredCom,
) -> Option<StepAdjustment> {
    let lip = gait.dcm.lip();
    let t = measured.time;
    let step = gait.footsteps.steps[index];
    let remaining = step.touchdown - t;
    let world_xi = lip.dcm(measured.world_p_com, measured.world_v_com);
    let world_xi_plan_now = gait.dcm.sample(t).world_xi.xy();
    let world_dcm_error = world_xi - world_xi_plan_now;
    let phase = step.swing_fraction(t);
    let adjustable = phase >= 0.0 && phase < settings.step_adjustment_end_phase && remaining > 1e-6;
    if !adjustable || world_dcm_error.norm() <= settings.step_adjustment_threshold {
        return None;
    }
    let stance = gait.footsteps.stance_sole(index);
    let side = step.foot.side();
    let clip = |world_p| clip_landing(settings, stance, side, world_p);
    let swing = SwingInFlight {
        remaining,
        earliest: earliest_touchdown(settings, &step, t),
        omega: lip.omega,
        world_xi,
        world_xi_plan: [
            world_xi_plan_now,
            gait.dcm.sample(step.touchdown).world_xi.xy(),
        ],
        world_p_landing: step.pose.world_p_sole,
        stance,
    };
    let tau = remaining_swing(&swing, settings.step_timing, clip);
    let wished = if tau < remaining {
        gait.retime_step(index, t, t + tau);
        swing.wished_landing(tau)
    } else {
        step.pose.world_p_sole + world_dcm_error * (lip.omega * remaining).exp()
    };
    let landing = clip(wished);
    let world_shift = landing - step.pose.world_p_sole;
    shift_footsteps(gait, index, world_shift);
    replan_in_swing(gait, surface, index, measured, world_xi);
    gait.swings[index].reaim(t, landing);
    Some(StepAdjustment {
        time: t,
        step: index,
        world_dcm_error,
        world_shift,
        clipped: (landing - wished).norm() > 1e-12,
        touchdown: gait.footsteps.steps[index].touchdown,
    })
}

/// The earliest time from `t` [s] to the touchdown of `step`, in flight, that the timing
/// adaptation may choose (`walking.step_timing`): the swing lasts at least
/// `walking.min_adjusted_swing_duration` from its lift-off, and the rest of it goes at most
/// `swing / min_adjusted_swing_duration` times faster than now (`swing` its duration as now
/// timed), so a foot late in its swing is not brought down from its apex in a few periods;
/// never sooner than one step of the timing's grid.
fn earliest_touchdown(settings: &WalkingSettings, step: &Footstep, t: f64) -> f64 {
    let shortest = settings.min_adjusted_swing_duration;
    let remaining = step.touchdown - t;
    let pace = shortest / (step.touchdown - step.lift_off);
    (step.lift_off + shortest - t)
        .max(remaining * pace)
        .max(TIMING_GRID_S)
}

/// `world_p` moved, in the `stance` sole's frame, into the reach and onto the swing foot's
/// own side (`side` +1 left, -1 right) `min_step_width`..`max_step_width` from it.
pub(super) fn clip_landing(
    settings: &WalkingSettings,
    stance: SolePose,
    side: f64,
    world_p: Vector2<f64>,
) -> Vector2<f64> {
    let aim = stance.to_sole(world_p);
    let reach = settings.max_step_length;
    let lateral = (side * aim.y).clamp(settings.min_step_width, settings.max_step_width);
    stance.to_world(Vector2::new(aim.x.clamp(-reach, reach), side * lateral))
}

/// Moves the landing of step `index` and of every later step by `world_shift`, the feet
/// before each later step with them, and rebuilds the later steps' swings (their lift-off
/// poses moved).
fn shift_footsteps(gait: &mut Gait, index: usize, world_shift: Vector2<f64>) {
    let plan = &mut gait.footsteps;
    for step in &mut plan.steps[index..] {
        step.pose.world_p_sole += world_shift;
    }
    for next in index..plan.steps.len() {
        let step = plan.steps[next];
        let mut feet = plan.stances[next];
        feet.set(step.foot, step.pose);
        plan.stances[next + 1] = feet;
    }
    let shape = (gait.swings[index].height, gait.swings[index].toe_off);
    for later in index + 1..plan.steps.len() {
        gait.swings[later] = SwingTrajectory::of_step(plan, later, shape, gait.world_z_ground);
    }
}

/// The DCM plan of `gait` made again at `measured.time`, in the swing of step `index`: the
/// backward recursion over its (moved) footsteps from that step's touchdown on, and before
/// it the rest of the swing with the stance's centre of pressure at the point that joins the
/// measured DCM `world_xi` to the recursion's DCM at touchdown, moved into the stance sole
/// (module doc); the CoM from the measured one.
fn replan_in_swing(
    gait: &mut Gait,
    surface: &ContactSurface,
    index: usize,
    measured: MeasuredCom,
    world_xi: Vector2<f64>,
) {
    let lip = gait.dcm.lip();
    let omega = lip.omega;
    let touchdown = gait.footsteps.steps[index].touchdown;
    let remaining = touchdown - measured.time;
    let mut later = backward_recursion(&gait.footsteps, omega).split_off(2 * index + 1);
    let xi_touchdown = later[0].dcm(omega, 0.0).0;
    let growth = (omega * remaining).exp();
    let joining = (xi_touchdown - world_xi * growth) / (1.0 - growth);
    let stance = SupportPolygon::of_sole(gait.footsteps.stance_sole(index), surface);
    let world_p_cop = stance.closest_point(joining);
    let swing_rest = DcmSegment::linear_vrp(
        omega,
        measured.time,
        remaining,
        (world_p_cop, world_p_cop),
        xi_touchdown,
    );
    later.insert(0, swing_rest);
    let world_z_ground = gait.dcm.world_z_com() - lip.com_height;
    gait.dcm = DcmPlan::from_segments(lip, later, measured.world_p_com, world_z_ground);
}
