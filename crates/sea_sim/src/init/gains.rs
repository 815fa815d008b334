//! The controller's gains for a new robot. The momentum gains act per unit of momentum (the
//! CoM error obeys `xddot + K_p xdot + K_i x = 0` whatever the mass), so the paper's iCub
//! gains on two feet carry over unchanged; the postural stiffness of each joint is its
//! inertia in the standing posture (the diagonal of `M`) times [`POSTURAL_FREQUENCY`] squared,
//! so every joint's postural task has the same bandwidth; the joint inertia regularisation
//! scales with the robot's mass from the iCub's (0.1 kg m^2 for 33 kg), and so does the QP's
//! minimum normal force for a robot lighter than the iCub (10 N for 33 kg: a 1.7 kg robot
//! weighs 16.7 N, and two feet could not carry 10 N each at rest).

use crate::scenario::robots::icub;
use sea_dyn::{Data, Model};

/// Natural frequency of each joint's postural task [rad/s].
pub const POSTURAL_FREQUENCY: f64 = 3.0;
/// The mass of the paper's iCub, `urdf/icub25.urdf` [kg], from which the regularisation is
/// scaled (docs/references.md#robots-set-up-by-sea-sim-init).
pub const ICUB_MASS: f64 = 33.06;

/// The postural stiffness of each joint at the configuration `q` [Nm/rad].
///
/// Errors: a joint whose inertia (with the regularisation) is not positive, naming it: a link
/// it moves has a negative principal inertia (a model warning), and its gain would be too.
pub fn postural_stiffness(
    model: &Model,
    q: &[f64],
    regularization: f64,
) -> sea_dyn::Result<Vec<f64>> {
    let mut data = Data::new(model);
    let mass_matrix = sea_dyn::crba(model, &mut data, q);
    let omega2 = POSTURAL_FREQUENCY * POSTURAL_FREQUENCY;
    (0..model.n_joints())
        .map(|k| {
            let inertia = mass_matrix[(6 + k, 6 + k)] + regularization;
            if inertia > 0.0 {
                return Ok((omega2 * inertia * 1e3).round() / 1e3);
            }
            Err(sea_dyn::Error::model(
                format!("joint '{}'", model.joint_names[k]),
                format!(
                    "its inertia standing is {inertia:.4} kg m^2: a link it moves has a \
                     negative principal inertia (see the warnings), and its postural gain \
                     would be negative"
                ),
            ))
        })
        .collect()
}

/// The joint inertia regularisation of a robot of `mass` [kg m^2].
pub fn joint_inertia_regularization(mass: f64) -> f64 {
    let scaled = icub().joint_inertia_regularization * mass / ICUB_MASS;
    (scaled * 1e3).round() / 1e3
}

/// The QP's minimum normal force per contact for a robot of `mass` [N]: the default (the
/// original study's 10 N, for the iCub) scaled down with the mass for a lighter robot, kept for
/// a heavier one; `None` when it is the default.
pub fn min_normal_force(mass: f64) -> Option<f64> {
    let default = sea_ctrl::qp::ContactConstraints::default().min_normal_force;
    let scaled = (default * mass / ICUB_MASS * 100.0).floor() / 100.0;
    (scaled < default).then_some(scaled.max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_minimum_normal_force_scales_down_for_a_lighter_robot_only() {
        assert_eq!(
            min_normal_force(ICUB_MASS),
            None,
            "the iCub keeps the default"
        );
        assert_eq!(min_normal_force(90.0), None, "Talos keeps the default");
        let light = min_normal_force(1.7).expect("scaled");
        assert!((light - 10.0 * 1.7 / ICUB_MASS).abs() < 0.01, "{light}");
        assert_eq!(min_normal_force(0.0), Some(0.0));
    }
}
