//! Series elastic actuation, per elastic joint (paper section "Series elastic actuators"):
//! the elastic coupling (eq:alpha), the motor dynamics (eq:motors) and the motor velocity loop
//! (eq:tauMotors) with the motor torque limit.
//!
//! All quantities are scalars of one joint: `theta`, `thetadot` motor side [rad, rad/s];
//! `s`, `sdot` joint side; `tau` joint side [Nm]; `tau_m` motor side [Nm].

use sea_dyn::ElasticParameters;

/// Elastic coupling, paper eq:alpha: the joint torque transmitted by the spring-damper,
/// `tau = K_S (Gamma theta - s) + K_D (Gamma thetadot - sdot)` [Nm, joint side].
pub fn elastic_joint_torque(
    p: &ElasticParameters,
    theta: f64,
    thetadot: f64,
    s: f64,
    sdot: f64,
) -> f64 {
    p.stiffness * (p.ratio * theta - s) + p.damping * (p.ratio * thetadot - sdot)
}

/// Motor velocity loop, paper eq:tauMotors: `tau_m = -I_m K_m (thetadot - thetadot_d) + Gamma
/// tau`, the torque that makes the motor track `thetadot_d` with rate `K_m` [1/s] while
/// compensating the spring torque `tau` seen through the transmission.
pub fn motor_velocity_loop(
    p: &ElasticParameters,
    gain: f64,
    thetadot: f64,
    thetadot_desired: f64,
    tau: f64,
) -> f64 {
    -p.motor_inertia * gain * (thetadot - thetadot_desired) + p.ratio * tau
}

/// The motor torque after the actuator's limit `|tau_m| <= torque_limit`, and whether it
/// saturated.
pub fn saturate(p: &ElasticParameters, demanded: f64) -> (f64, bool) {
    match p.torque_limit {
        Some(limit) if demanded.abs() > limit => (demanded.signum() * limit, true),
        _ => (demanded, false),
    }
}

/// Motor dynamics, paper eq:motors: `I_m thetaddot = tau_m - Gamma tau`, solved for the motor
/// acceleration [rad/s^2].
pub fn motor_acceleration(p: &ElasticParameters, motor_torque: f64, joint_torque: f64) -> f64 {
    (motor_torque - p.ratio * joint_torque) / p.motor_inertia
}
