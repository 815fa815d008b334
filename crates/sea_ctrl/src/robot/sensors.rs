//! What the robot's sensors hand to the controller stack ([`super::RobotController`]) after a
//! whole-body period: the feet's force/torque sensors and the joint torques, read at the
//! period's start (just after the stack's command took effect) and at its end (the last joint
//! tick of the period).
//!
//! The measured state (encoders of the joints and motors, the base's pose and velocity from
//! the estimator) is handed at each tick instead ([`super::RobotController::tick`],
//! [`super::RobotController::joint_tick`]).

use nalgebra::DVector;

/// The force readings at one instant.
#[derive(Clone, Copy, Debug)]
pub struct ForceReadings<'a> {
    /// The contact wrenches the feet's force/torque sensors read (6 per contact, the
    /// controller's contact order; force then moment, at the contact frame's origin, world
    /// axes) [N, Nm].
    pub contact_wrench: &'a DVector<f64>,
    /// The joint torques (n, joint order) [Nm]: a rigid joint's motor torque; an elastic
    /// joint's entry is not read (the stack senses it from the spring's deflection through its
    /// own estimates).
    pub joint_torque: &'a DVector<f64>,
}

/// The readings of one whole-body period, handed to [`super::RobotController::end_period`].
#[derive(Clone, Copy, Debug)]
pub struct PeriodSensors<'a> {
    /// At the period's start, after the tick's command took effect.
    pub start: ForceReadings<'a>,
    /// At the period's end, before the next tick (the last joint tick's command acting).
    pub end: ForceReadings<'a>,
    /// The contact wrenches (6 per contact) averaged over the period, when the sensors are
    /// read at the joint loop's rate and the stack can average them: the external wrench
    /// observer then takes this mean instead of the trapezoid of `start` and `end`
    /// (`crate::external_wrench`). `None`: only the two instants are read.
    pub mean_contact_wrench: Option<&'a DVector<f64>>,
}
