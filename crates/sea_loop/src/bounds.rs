//! The divergence bounds of a sample: the observed CoM and joint errors against their bounds
//! and, optionally, the true joint positions against the URDF's limits.

use super::statistics::Divergence;
use crate::settings::DivergenceBounds;
use sea_ctrl::feedback::Observation;
use sea_dyn::Model;

/// The bound the sample crosses, as the reason of a divergence: the law's `observation`'s
/// errors (the quantity, its value and the bound; a NaN error counts as crossing), then, with
/// `bounds.stop_at_joint_limits`, the true joint positions `s` (n) against `model`'s
/// limits.
pub(super) fn bound_crossed(
    observation: &Observation,
    (model, s): (&Model, &[f64]),
    bounds: &DivergenceBounds,
) -> Option<Divergence> {
    let (com_bound, joint_bound) = (bounds.com_error_m, bounds.joint_error_rad);
    if exceeds(observation.com_error, com_bound) {
        Some(Divergence::ComErrorOverBound {
            value: observation.com_error,
            bound: com_bound,
        })
    } else if exceeds(observation.joint_error, joint_bound) {
        Some(Divergence::JointErrorOverBound {
            value: observation.joint_error,
            bound: joint_bound,
        })
    } else if bounds.stop_at_joint_limits {
        joint_limit_crossed(model, s)
    } else {
        None
    }
}

/// The first joint (model order) whose position in `s` (n) lies outside its URDF limits.
fn joint_limit_crossed(model: &Model, s: &[f64]) -> Option<Divergence> {
    model.joints.iter().find_map(|joint| {
        let value = s[joint.coordinate];
        let [lower, upper] = joint.position_limits;
        let limit = if value < lower {
            lower
        } else if value > upper {
            upper
        } else {
            return None;
        };
        Some(Divergence::JointOutsideLimits {
            joint: joint.name.clone(),
            value,
            limit,
        })
    })
}

/// `value > bound`, and NaN (an undefined error) counts as over.
fn exceeds(value: f64, bound: f64) -> bool {
    value > bound || value.is_nan()
}
