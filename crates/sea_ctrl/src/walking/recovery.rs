//! The walk of one push-recovery step ([`recovery_gait`]), planned at the whole-body tick at
//! which the measured DCM needs a step ([`super::needs_step`]; `controller::stepping` watches
//! it). Forwards from the measured state, the VRP (centre of pressure) where the feet can
//! hold it:
//!
//! 1. a double support of `walking.recovery_transfer_duration` (re-planned at each tick of
//!    it from the measured state, the lift-off kept, `controller::stepping`) that hands the swing foot's
//!    load to the stance foot: the VRP moves linearly from the point of the two-feet polygon
//!    closest to the measured DCM `xi0` to the point `p_s` of the stance sole closest to the
//!    DCM at lift-off, `xi_lift` (the exact solution of `xidot = omega (xi - p)` for a linear
//!    VRP);
//! 2. the swing of [`super::recovery_step`] from `xi_lift`: at least
//!    `walking.min_swing_duration`, the VRP held at `p_s`, the swing sole aimed
//!    `walking.recovery_step_offset` beyond the DCM at touchdown
//!    `xi_td = p_s + (xi_lift - p_s) e^(omega T)`, clipped to the step limits;
//! 3. after touchdown, over `walking.transfer_duration`, a cubic DCM from rest at `xi_td`
//!    (the VRP jumps onto the DCM: the landing foot takes the load at once, both feet then
//!    free to carry it, `controller::stepping`) to rest over the new mid-feet point; then
//!    standing there. At the first tick after touchdown this part is planned again from the
//!    measured DCM and CoM ([`settle_from`]).
//!
//! The CoM reference ([`DcmPlan`]) starts at the measured CoM, so it starts where the robot
//! is and moving as it moves (the DCM's velocity `omega (xi0 - p)`), and follows the DCM the
//! feet can produce rather than the one a walk from rest would plan.

use super::capture::{recovery_step_beyond, RecoveryStep, StepRequest};
use super::dcm::DcmPlan;
use super::footstep::{Foot, Footstep, FootstepPlan, Stance};
use super::gait::Gait;
use super::lip::Lip;
use super::polygon::SupportPolygon;
use super::segment::{Cubic, DcmSegment};
use super::settings::WalkingSettings;
use super::swing::{SwingTrajectory, ToeOff};
use nalgebra::Vector2;
use sea_dyn::ContactSurface;

/// The measured state a recovery step is planned from (world x, y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasuredCom {
    /// The time of the measurement: the recovery plan's start [s].
    pub time: f64,
    /// The CoM's ground projection [m].
    pub world_p_com: Vector2<f64>,
    /// The CoM's horizontal velocity [m/s].
    pub world_v_com: Vector2<f64>,
    /// The CoM's height [m].
    pub world_z_com: f64,
}

/// Where a recovery gait stands and how its CoM reference is placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecoveryFrame {
    /// Both feet on the ground when the push is detected.
    pub stance: Stance,
    /// The ground's height [m].
    pub world_z_ground: f64,
    /// The CoM height the recovery lowers the CoM reference to [m].
    pub world_z_com: f64,
    /// The CoM reference's height at the recovery's start [m].
    pub world_z_com_start: f64,
    /// Which contact index each foot is (left, right), as [`Gait::contact_of`].
    pub contact_of: [usize; 2],
}

/// The gait of one recovery step of `swing_foot` from `frame.stance` at the `measured` state
/// (module doc), its first double support from `start_s` [s] (the load hand-over's start)
/// to the lift-off at `lift_off` [s] (`walking.recovery_transfer_duration` after the
/// decision; kept when re-planned before it), and the step as [`super::capture::recovery_step`] planned it.
pub fn recovery_gait(
    settings: &WalkingSettings,
    lip: &Lip,
    surface: &ContactSurface,
    frame: &RecoveryFrame,
    (swing_foot, start_s, lift_off): (Foot, f64, f64),
    measured: MeasuredCom,
) -> (Gait, RecoveryStep) {
    let transfer = lift_off - measured.time;
    let world_xi = lip.dcm(measured.world_p_com, measured.world_v_com);
    let world_p_cop = SupportPolygon::of_stance(&frame.stance, surface).closest_point(world_xi);
    let stance_sole = SupportPolygon::of_sole(frame.stance.get(swing_foot.other()), surface);
    // The stance's centre of pressure at lift-off: closest to the DCM then (one refinement
    // from the current DCM's closest point).
    let first_guess = stance_sole.closest_point(world_xi);
    let guess_lift_off = transfer_dcm(lip, world_xi, (world_p_cop, first_guess), transfer);
    let world_p_stance = stance_sole.closest_point(guess_lift_off);
    let world_xi_lift_off = transfer_dcm(lip, world_xi, (world_p_cop, world_p_stance), transfer);
    let request = StepRequest {
        world_xi: world_xi_lift_off,
        stance: frame.stance.get(swing_foot.other()),
        swing_foot,
        swing_duration: settings.min_swing_duration,
    };
    let offset = settings.recovery_step_offset;
    let step = recovery_step_beyond(settings, lip, surface, request, offset);
    let touchdown = lift_off + step.swing_duration;
    let mut after = frame.stance;
    after.set(swing_foot, step.pose);
    let footsteps = FootstepPlan {
        steps: vec![Footstep {
            foot: swing_foot,
            pose: step.pose,
            lift_off,
            touchdown,
        }],
        stances: vec![frame.stance, after],
        transfer_duration: settings.transfer_duration,
        start_s,
    };
    let omega = lip.omega;
    let rest_point = after.mid_frame().world_p_sole;
    let settle = settings.transfer_duration;
    let mut segments = vec![
        DcmSegment::linear_vrp(
            omega,
            measured.time,
            transfer,
            (world_p_cop, world_p_stance),
            world_xi_lift_off,
        ),
        DcmSegment::linear_vrp(
            omega,
            lift_off,
            step.swing_duration,
            (step.stance_cop, step.stance_cop),
            step.dcm_at_touchdown,
        ),
    ];
    segments.extend(settling_segments(
        touchdown,
        settle,
        step.dcm_at_touchdown,
        rest_point,
    ));
    let dcm = DcmPlan::from_segments(*lip, segments, measured.world_p_com, frame.world_z_ground);
    let swings = vec![SwingTrajectory::of_step(
        &footsteps,
        0,
        (settings.swing_height, ToeOff::of(settings, surface)),
        frame.world_z_ground,
    )];
    let gait = Gait {
        footsteps,
        dcm,
        swings,
        world_z_com: frame.world_z_com,
        world_z_com_start: frame.world_z_com_start,
        contact_of: frame.contact_of,
        world_z_ground: frame.world_z_ground,
    };
    (gait, step)
}

/// The DCM after a recovery step's touchdown at `start` [s]: held at `xi_start` (the VRP
/// moves onto it: the landing foot takes the load at once), then a cubic to rest at
/// `rest_point` over `duration` [s], standing there after.
fn settling_segments(
    start: f64,
    duration: f64,
    xi_start: Vector2<f64>,
    rest_point: Vector2<f64>,
) -> [DcmSegment; 2] {
    [
        DcmSegment::polynomial(
            start,
            duration,
            Cubic::hermite(
                (xi_start, Vector2::zeros()),
                (rest_point, Vector2::zeros()),
                duration,
            ),
        ),
        DcmSegment::at_rest(start + duration, rest_point),
    ]
}

/// `gait` after its recovery step's touchdown, its DCM plan from the `measured` state on
/// (`settling_segments` from the measured DCM to rest over the new mid-feet point by the
/// gait's end, or over `walking.transfer_duration` when past it): the CoM reference starts
/// where the robot landed.
pub fn settle_from(gait: &mut Gait, settings: &WalkingSettings, measured: MeasuredCom) {
    let lip = gait.dcm.lip();
    let world_xi = lip.dcm(measured.world_p_com, measured.world_v_com);
    let rest_point = gait.footsteps.final_stance().mid_frame().world_p_sole;
    let remaining = gait.end_time() - measured.time;
    let duration = if remaining > 0.5 * settings.transfer_duration {
        remaining
    } else {
        settings.transfer_duration
    };
    let segments = settling_segments(measured.time, duration, world_xi, rest_point).to_vec();
    let world_z_ground = gait.dcm.world_z_com() - lip.com_height;
    gait.dcm = DcmPlan::from_segments(lip, segments, measured.world_p_com, world_z_ground);
}

/// The DCM after `duration` [s] from `xi0` with the VRP moving linearly from `p0` to `p1`:
/// `xi(T) = p1 + pdot / omega + (xi0 - p0 - pdot / omega) e^(omega T)`.
fn transfer_dcm(
    lip: &Lip,
    xi0: Vector2<f64>,
    (p0, p1): (Vector2<f64>, Vector2<f64>),
    duration: f64,
) -> Vector2<f64> {
    let pdot_over_omega = (p1 - p0) / (duration * lip.omega);
    p1 + pdot_over_omega + (xi0 - p0 - pdot_over_omega) * (lip.omega * duration).exp()
}
