//! A series elastic actuator on every joint, scaled to the robot from the paper's iCub SEA
//! ([`ElasticParameters::paper_icub`]): the stiffness so that the spring's static deflection
//! under gravity in the standing posture is [`STATIC_DEFLECTION`] (joints carrying less than
//! [`TORQUE_FLOOR`] of the largest static torque are sized for that floor); the motor inertia
//! so that the spring-motor mode (joint held, `sqrt(K_S Gamma^2 / I_m)`) keeps the paper's
//! frequency; the damping so that the spring's time constant `K_D / K_S` keeps the paper's;
//! the paper's transmission ratio. The motor torque limit is the URDF's effort through that
//! ratio: the scenario sets `actuators.torque_limit_from_urdf`, and [`effort_warnings`] names
//! the joints whose effort is below what standing needs.

use super::posture::Standing;
use sea_dyn::{ElasticParameters, FrameId, Model};

/// Static spring deflection under gravity in the standing posture [rad].
pub const STATIC_DEFLECTION: f64 = 0.05;
/// The smallest static torque a spring is sized for, as a fraction of the largest.
pub const TORQUE_FLOOR: f64 = 0.1;

/// The elastic actuator of each joint, for the static joint torques `torques` [Nm].
pub fn scaled_actuators(torques: &[f64]) -> Vec<ElasticParameters> {
    let paper = ElasticParameters::paper_icub();
    let largest = torques.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let mode_squared = paper.stiffness * paper.ratio * paper.ratio / paper.motor_inertia;
    let time_constant = paper.damping / paper.stiffness;
    torques
        .iter()
        .map(|torque| {
            let sized_for = torque.abs().max(TORQUE_FLOOR * largest).max(1e-3);
            let stiffness = round(sized_for / STATIC_DEFLECTION);
            ElasticParameters {
                stiffness,
                motor_inertia: stiffness * paper.ratio * paper.ratio / mode_squared,
                damping: stiffness * time_constant,
                ..paper
            }
        })
        .collect()
}

/// The joint torques [Nm] (n) that hold the robot `standing` on its two `feet` at rest
/// (`sea_plant::equilibrium::static_torques`), which the springs are sized for.
pub fn standing_torques(model: &Model, feet: [FrameId; 2], standing: &Standing) -> Vec<f64> {
    let mut q = model.neutral();
    q[7..].copy_from_slice(&standing.joints);
    sea_plant::equilibrium::static_torques(model, &q, &feet)
}

/// A warning per joint (body order) whose URDF effort limit is below the torque `torques`
/// (coordinate order) it holds standing: under `actuators.torque_limit_from_urdf` its motor saturates
/// before the robot stands.
pub fn effort_warnings(model: &Model, torques: &[f64]) -> Vec<String> {
    model
        .joints
        .iter()
        .filter_map(|joint| {
            let (torque, effort) = (torques[joint.coordinate].abs(), joint.effort_limit);
            (torque > effort).then(|| {
                format!(
                    "joint '{}' holds {torque:.3} Nm standing, above its URDF effort limit \
                     {effort} Nm: its motor saturates (actuators.torque_limit_from_urdf)",
                    joint.name
                )
            })
        })
        .collect()
}

/// `value` to 3 significant digits (the file stays readable).
fn round(value: f64) -> f64 {
    let magnitude = 10f64.powi(value.abs().log10().floor() as i32 - 2);
    (value / magnitude).round() * magnitude
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_papers_torque_gives_the_papers_sea() {
        let paper = ElasticParameters::paper_icub();
        let torque = paper.stiffness * STATIC_DEFLECTION;
        let scaled = scaled_actuators(&[torque, 0.0]);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
        assert!(close(scaled[0].stiffness, paper.stiffness));
        assert!(close(scaled[0].motor_inertia, paper.motor_inertia));
        assert!(close(scaled[0].damping, paper.damping));
        assert!(close(scaled[1].stiffness, TORQUE_FLOOR * paper.stiffness));
    }
}
