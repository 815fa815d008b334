//! Rigid contacts: held frames, their Baumgarte-stabilised acceleration constraint (paper
//! eq:constraints_acc) and the margins of the simulated wrenches.

use nalgebra::{Matrix3, Vector3};
use sea_dyn::model::FrameId;
use sea_dyn::spatial::Pose;

/// Friction and foot-size limits used to report the margins of the simulated wrenches: the
/// contact surface shared with the controller's constraints (defaults:
/// docs/references.md#original-study-contact-wrench-qp).
pub type ContactLimits = sea_dyn::ContactSurface;

/// A rigid contact: the frame is held at its reference pose.
#[derive(Clone, Debug)]
pub struct Contact {
    /// Frame name.
    pub name: String,
    /// Frame index.
    pub frame: FrameId,
    /// Desired pose of the frame, `world_H_frame`, where the contact holds it.
    pub world_h_frame_desired: Pose,
}

impl Contact {
    /// The pose error of the frame at `pose` from its reference, world axes: the position
    /// error `p - p_ref` [m] and the rotation error ([`rotation_error`], [rad]).
    pub fn pose_error(&self, pose: &Pose) -> (Vector3<f64>, Vector3<f64>) {
        let position_error = pose.translation - self.world_h_frame_desired.translation;
        let rotation_err = rotation_error(&pose.rotation, &self.world_h_frame_desired.rotation);
        (position_error, rotation_err)
    }
}

/// Rotation error `vee(R R_ref^T - R_ref R^T) / 2` (the rotation vector for small errors).
pub fn rotation_error(r: &Matrix3<f64>, r_ref: &Matrix3<f64>) -> Vector3<f64> {
    let d = r * r_ref.transpose();
    Vector3::new(
        d[(2, 1)] - d[(1, 2)],
        d[(0, 2)] - d[(2, 0)],
        d[(1, 0)] - d[(0, 1)],
    ) * 0.5
}

/// Margins of one simulated contact wrench (sole frame), negative when violated.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WrenchMargins {
    /// Normal force [N] (negative: the foot pulls on the ground).
    pub normal_force: f64,
    /// `mu f_z - |f_xy|` [N].
    pub friction: f64,
    /// Distance of the centre of pressure inside the foot rectangle [m] (negative: outside).
    pub center_of_pressure: f64,
}

/// Margins of a wrench `[force; moment about the sole origin]` given in the sole frame.
pub fn sole_margins(
    force: &Vector3<f64>,
    moment: &Vector3<f64>,
    limits: &ContactLimits,
) -> WrenchMargins {
    let fz = force.z;
    let friction = limits.friction * fz - force.xy().norm();
    let center_of_pressure = if fz > 0.0 {
        let (cop_x, cop_y) = (-moment.y / fz, moment.x / fz);
        (cop_x - limits.foot_x[0])
            .min(limits.foot_x[1] - cop_x)
            .min(cop_y - limits.foot_y[0])
            .min(limits.foot_y[1] - cop_y)
    } else {
        f64::NEG_INFINITY
    };
    WrenchMargins {
        normal_force: fz,
        friction,
        center_of_pressure,
    }
}

/// The contact constraint, paper eq:constraints_acc `J nudot + Jdot nu = 0`, Baumgarte
/// stabilised: returns the target of one row of `J nudot`,
/// `-(Jdot nu + K_d J nu + K_p e)`, from that row's `Jdot nu` (`jdot_nu`), `J nu` (`j_nu`) and
/// pose error `e` (position [m] or rotation vector [rad], world axes). The gains pull the drift
/// of the numerically integrated constraint back to zero.
pub fn constraint_acceleration(jdot_nu: f64, j_nu: f64, error: f64, kd: f64, kp: f64) -> f64 {
    -(jdot_nu + kd * j_nu + kp * error)
}
