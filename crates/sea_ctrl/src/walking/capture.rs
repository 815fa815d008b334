//! Stepping to recover a push, from the capture point (docs/references.md#walking: Pratt et
//! al. 2006; Koolen et al. 2012).
//!
//! A step is needed when the measured DCM `xi0` is outside the support polygon or closer to
//! its edge than `walking.capture_margin` in its direction ([`needs_step`],
//! [`stance_margin`]). During the swing of duration `T`
//! the stance foot's centre of pressure is best held at the point `p` of its sole closest to
//! the DCM, so the DCM at touchdown is `xi(T) = p + (xi0 - p) e^(omega T)`; the swing sole is
//! aimed there ([`recovery_step`]), so that the new foot's centre of pressure can hold the
//! DCM (one-step capture). The aim is clipped in the stance sole's frame to the reach
//! (`max_step_length`, `max_step_width`) and to no crossing (`min_step_width` on the swing
//! foot's own side), the yaw kept; `T` is at least `walking.min_swing_duration`. Whether the
//! clipped step still captures the DCM (its touchdown DCM inside the new sole) is reported:
//! when it does not, the robot needs more steps (N-step capturability).

use super::footstep::{Foot, SolePose, Stance};
use super::lip::Lip;
use super::polygon::SupportPolygon;
use super::settings::{CaptureMargin, WalkingSettings};
use nalgebra::Vector2;
use sea_dyn::ContactSurface;

/// What a push-recovery step starts from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepRequest {
    /// The measured DCM `xi0` (world x, y) [m].
    pub world_xi: Vector2<f64>,
    /// The sole that stays on the ground.
    pub stance: SolePose,
    /// The foot that steps (the other one).
    pub swing_foot: Foot,
    /// The wished swing duration [s] (raised to `walking.min_swing_duration`).
    pub swing_duration: f64,
}

/// A push-recovery step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecoveryStep {
    /// The swing foot.
    pub foot: Foot,
    /// Its landing pose (the stance sole's yaw).
    pub pose: SolePose,
    /// The swing's duration [s].
    pub swing_duration: f64,
    /// The DCM predicted at touchdown, `xi(T)` [m].
    pub dcm_at_touchdown: Vector2<f64>,
    /// The stance's centre of pressure assumed during the swing [m].
    pub stance_cop: Vector2<f64>,
    /// Whether the aim was clipped to the step limits.
    pub clipped: bool,
    /// Whether the DCM at touchdown is inside the landing sole (captured in this step).
    pub captures: bool,
}

/// Whether the DCM `xi` needs a step: outside `support` or within `margin` [m] of its edge.
pub fn needs_step(support: &SupportPolygon, xi: Vector2<f64>, margin: f64) -> bool {
    support.signed_margin(xi) < margin
}

/// The margin of `margins` for the DCM `world_xi` standing on `stance`: by its direction
/// from the mid-feet point in the mid-feet frame ([`CaptureMargin::toward`]) [m].
pub fn stance_margin(margins: &CaptureMargin, stance: &Stance, world_xi: Vector2<f64>) -> f64 {
    margins.toward(stance.mid_frame().to_sole(world_xi))
}

/// On two feet, the foot to step with: the one on the side the DCM lies, in the walking
/// frame (left when it is on the left of the mid-feet line or on it).
pub fn swing_foot_for(stance: &Stance, xi: Vector2<f64>) -> Foot {
    if stance.mid_frame().to_sole(xi).y >= 0.0 {
        Foot::Left
    } else {
        Foot::Right
    }
}

/// The step of `request.swing_foot` that recovers the DCM `request.world_xi` while the other
/// foot, at `request.stance`, holds (module doc); `surface` gives the soles' rectangle.
pub fn recovery_step(
    settings: &WalkingSettings,
    lip: &Lip,
    surface: &ContactSurface,
    request: StepRequest,
) -> RecoveryStep {
    recovery_step_beyond(settings, lip, surface, request, 0.0)
}

/// [`recovery_step`] with the swing sole aimed `offset` [m] beyond the DCM at touchdown,
/// along the DCM's motion away from the stance's centre of pressure (`xi(T) - p`): the DCM
/// then lands inside the new sole on the stance's side, with room for the landing foot's
/// centre of pressure to stop it (`walking.recovery_step_offset`).
pub fn recovery_step_beyond(
    settings: &WalkingSettings,
    lip: &Lip,
    surface: &ContactSurface,
    request: StepRequest,
    offset: f64,
) -> RecoveryStep {
    let StepRequest {
        world_xi: xi0,
        stance,
        swing_foot,
        swing_duration,
    } = request;
    let duration = swing_duration.max(settings.min_swing_duration);
    let stance_cop = SupportPolygon::of_sole(stance, surface).closest_point(xi0);
    let dcm_at_touchdown = lip.dcm_after(stance_cop, xi0, duration);
    let away = dcm_at_touchdown - stance_cop;
    let beyond = if away.norm() > 1e-9 {
        away * (offset / away.norm())
    } else {
        Vector2::zeros()
    };
    let aim = stance.to_sole(dcm_at_touchdown + beyond);
    let side = swing_foot.side();
    let reach = settings.max_step_length;
    let clipped_aim = Vector2::new(
        aim.x.clamp(-reach, reach),
        side * (side * aim.y).clamp(settings.min_step_width, settings.max_step_width),
    );
    let pose = SolePose::new(stance.to_world(clipped_aim), stance.world_yaw_sole);
    let captures = SupportPolygon::of_sole(pose, surface).signed_margin(dcm_at_touchdown) >= 0.0;
    RecoveryStep {
        foot: swing_foot,
        pose,
        swing_duration: duration,
        dcm_at_touchdown,
        stance_cop,
        clipped: (clipped_aim - aim).norm() > 1e-12,
        captures,
    }
}
