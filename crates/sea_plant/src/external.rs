//! External wrenches on links (pushes, disturbances): a wrench `w = [f; n]` in world axes
//! at a link frame's origin enters the dynamics `M nudot + h = B tau + J^T f_c + J_w^T w` as the
//! generalised force `J_w^T w`, with `J_w` the frame's Jacobian (`[v; omega]` of the frame
//! origin in world axes, [`sea_dyn::jacobian::frame_jacobian_from_kinematics`]), so that the
//! wrench's power is `w . J_w nu`.

use sea_dyn::data::Data;
use sea_dyn::jacobian::frame_jacobian_from_kinematics;
use sea_dyn::model::{FrameId, Model};

/// One external wrench, applied while `active` (the caller switches it per step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExternalWrench {
    /// The frame whose origin it acts at.
    pub frame: FrameId,
    /// `[force (N); moment (N m)]`, world axes, at the frame origin.
    pub wrench: [f64; 6],
    /// Whether it acts now.
    pub active: bool,
}

/// Adds `J_w^T w` of every active wrench to `generalized` (nv), with the kinematics already in
/// `data` (uses `data.frame_jacobian` as scratch); allocation-free.
pub fn add_generalized_force(
    model: &Model,
    data: &mut Data,
    wrenches: &[ExternalWrench],
    generalized: &mut [f64],
) {
    for external in wrenches.iter().filter(|w| w.active) {
        frame_jacobian_from_kinematics(model, data, external.frame);
        let jacobian = &data.frame_jacobian;
        for (v, g) in generalized.iter_mut().enumerate() {
            *g += (0..6)
                .map(|r| jacobian[(r, v)] * external.wrench[r])
                .sum::<f64>();
        }
    }
}
