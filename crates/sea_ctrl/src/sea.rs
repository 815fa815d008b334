//! The SEA-specific terms of the controller (paper section "The balancing control for series
//! elastic actuators") and the rigid controller's motor torque on an SEA robot (remark1).
//!
//! Per elastic joint, scalars: `theta`, `thetadot` motor side [rad, rad/s]; `s`, `sdot` joint
//! side; torques joint side [Nm] unless said otherwise. The parameters are the controller's
//! own estimates ([`controller_estimates`]), not the plant's, so that the paper's mismatch
//! study (scaled `K_S`, `K_D`) changes only the controller.
//!
//! With the fictitious input `beta = K_D Gamma thetadot`, the joint dynamics become
//! newJointDynamics `M_j sddot = J_j^T f - hbar_j + beta`: the rigid controller's QP
//! (inputTorquesSOT) solved with `h_j -> hbar_j = h_j - p` and `tau -> beta` is the SEA QP
//! (inputTorquesSOTu), and `beta*` maps to desired motor velocities (inputDesMotVel). Mixed
//! actuation: rigid joints keep `tau` and `p = 0`.

use nalgebra::DVector;
use sea_dyn::{Actuation, ElasticParameters};

/// The controller's estimates of the elastic parameters, one per elastic joint (order of
/// `actuation.elastic`): the true stiffness `K_S` and damping `K_D` times the given scales,
/// the other parameters unchanged; the stiffness of joint `j` (coordinate index) also times
/// `joint_stiffness_scales[j]` when given (empty: none).
pub fn controller_estimates(
    actuation: &Actuation,
    stiffness_scale: f64,
    damping_scale: f64,
    joint_stiffness_scales: &[f64],
) -> Vec<ElasticParameters> {
    let joint_scale = |j: usize| joint_stiffness_scales.get(j).copied().unwrap_or(1.0);
    actuation
        .elastic
        .iter()
        .zip(&actuation.elastic_joints)
        .map(|(p, &j)| ElasticParameters {
            stiffness: p.stiffness * stiffness_scale * joint_scale(j),
            damping: p.damping * damping_scale,
            ..*p
        })
        .collect()
}

/// Paper label `p`: the part of the spring-damper torque eq:alpha that does not depend on the
/// motor velocity, `p = K_S (Gamma theta - s) - K_D sdot` [Nm, joint side], for one joint.
pub fn spring_torque_without_motor_velocity(
    estimate: &ElasticParameters,
    theta: f64,
    s: f64,
    sdot: f64,
) -> f64 {
    estimate.stiffness * (estimate.ratio * theta - s) - estimate.damping * sdot
}

/// The spring-damper torque eq:alpha `K_S (Gamma theta - s) + K_D (Gamma thetadot - sdot)`
/// [Nm, joint side] of one joint as the robot senses it: its deflection and deflection rate
/// (encoders) through the parameters `estimate` (label `p` plus the motor velocity term).
pub fn sensed_spring_torque(
    estimate: &ElasticParameters,
    (theta, thetadot): (f64, f64),
    (s, sdot): (f64, f64),
) -> f64 {
    spring_torque_without_motor_velocity(estimate, theta, s, sdot)
        + estimate.damping * estimate.ratio * thetadot
}

/// Paper label hjBar: `hbar_j = h_j - p` (label `p`), in place on the joint rows of the bias
/// forces `h` (nv = 6 + n, `h = [h_b; h_j]`) for the elastic joints `elastic_joints`
/// (coordinate indices, n_e) with `estimates` (n_e), motor angles `theta` (n_e), joint
/// positions `s` (n) and velocities `sdot` (n). Rigid joints keep `h_j` (`p = 0`).
pub fn subtract_spring_torque(
    bias: &mut DVector<f64>,
    elastic_joints: &[usize],
    estimates: &[ElasticParameters],
    theta: &[f64],
    s: &[f64],
    sdot: &[f64],
) {
    for (e, (&j, estimate)) in elastic_joints.iter().zip(estimates).enumerate() {
        bias[6 + j] -= spring_torque_without_motor_velocity(estimate, theta[e], s[j], sdot[j]);
    }
}

/// Paper label inputDesMotVel: the desired motor velocity `thetadot_d = Gamma^-1 K_D^-1 beta*`
/// [rad/s, motor side] of one joint, from its optimal `beta*` [Nm, joint side].
pub fn desired_motor_velocity(estimate: &ElasticParameters, beta: f64) -> f64 {
    beta / (estimate.ratio * estimate.damping)
}

/// Rigid controller on an elastic joint, paper remark1 (eq:equivJoints
/// `(M_j + Gamma^-1 I_m Gamma^-1) sddot = ... + Gamma^-1 tau_m`): the motor torque
/// `tau_m = Gamma tau*` [Nm, motor side] that realises the joint torque `tau*` [Nm] when the
/// transmission is taken as rigid.
pub fn rigid_motor_torque(parameters: &ElasticParameters, joint_torque: f64) -> f64 {
    parameters.ratio * joint_torque
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint() -> ElasticParameters {
        ElasticParameters {
            ratio: 0.01,
            motor_inertia: 1e-5,
            stiffness: 350.0,
            damping: 0.25,
            torque_limit: None,
        }
    }

    /// With `thetadot = thetadot_d` (inputDesMotVel), the spring-damper torque eq:alpha equals
    /// `p + beta*`: the substitution of newJointDynamics is exact.
    #[test]
    fn desired_motor_velocity_realises_beta_through_the_spring() {
        let p = joint();
        let (theta, s, sdot, beta) = (12.0, 0.1, -0.3, 4.5);
        let thetadot = desired_motor_velocity(&p, beta);
        let alpha = p.stiffness * (p.ratio * theta - s) + p.damping * (p.ratio * thetadot - sdot);
        let expected = spring_torque_without_motor_velocity(&p, theta, s, sdot) + beta;
        assert!((alpha - expected).abs() < 1e-12 * expected.abs());
    }

    #[test]
    fn hj_bar_touches_only_elastic_joint_rows() {
        let p = joint();
        let mut bias = DVector::from_element(6 + 3, 1.0);
        let (theta, s, sdot) = ([10.0], [0.0, 0.05, 0.0], [0.0, 0.2, 0.0]);
        subtract_spring_torque(&mut bias, &[1], &[p], &theta, &s, &sdot);
        let p1 = spring_torque_without_motor_velocity(&p, 10.0, 0.05, 0.2);
        assert_eq!(bias[7], 1.0 - p1);
        assert!(bias.iter().enumerate().all(|(i, v)| i == 7 || *v == 1.0));
    }

    #[test]
    fn estimates_scale_only_stiffness_and_damping() {
        let estimate = ElasticParameters {
            stiffness: 700.0,
            damping: 0.125,
            ..joint()
        };
        let actuation = Actuation {
            actuators: vec![sea_dyn::Actuator::Elastic(joint())],
            elastic_joints: vec![0],
            elastic: vec![joint()],
        };
        assert_eq!(
            controller_estimates(&actuation, 2.0, 0.5, &[]),
            vec![estimate]
        );
    }
}
