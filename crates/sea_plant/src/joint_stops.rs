//! Joint stops: the URDF's position limits as unilateral joint constraints, with the same
//! compliant law as the contacts ([`crate::unilateral`]) on the joint coordinate. Past a limit
//! by `delta` (rad or m) moving further in at `deltadot`, the stop pushes back with
//! `max(0, k delta (1 + d deltadot))`: no torque jump when a joint reaches its stop, and an
//! inelastic impact (the joint leaves its stop only faster than `1 / d`). The stop acts
//! between the link and its parent, beside the actuator, so a joint torque sensor (the spring's
//! torque) does not read it. Its stiffness and damping enter the implicit step's `W` on the
//! joint's diagonal.

use crate::error::Result;
use sea_dyn::error::{check_non_negative, check_positive};

/// The stops' law (the same for every joint).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointStops {
    /// Stiffness `k` [N m/rad, or N/m for a prismatic joint].
    pub stiffness: f64,
    /// Hunt-Crossley dissipation `d` [s/rad, or s/m].
    pub dissipation: f64,
}

impl Default for JointStops {
    /// `k` = 2000 N m/rad (a joint carrying 20 N m rests 0.01 rad past its stop), `d` = 10
    /// s/rad (it leaves the stop only faster than 0.1 rad/s).
    fn default() -> Self {
        Self {
            stiffness: 2000.0,
            dissipation: 10.0,
        }
    }
}

/// One joint's stop at a state: its torque and linearisation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StopTorque {
    /// Torque on the joint [N m] (positive pushes the coordinate up).
    pub torque: f64,
    /// `-d torque / d s` [N m/rad].
    pub stiffness: f64,
    /// `-d torque / d sdot` [N m s/rad].
    pub damping: f64,
}

impl JointStops {
    /// Checks the law; errors name the key.
    pub fn validate(&self) -> Result<()> {
        check_positive("plant.joint_stop_stiffness", self.stiffness)?;
        check_non_negative("plant.joint_stop_dissipation", self.dissipation)
    }

    /// The stop torque of a joint at position `s`, velocity `sdot`, with limits `[lower,
    /// upper]` (infinite: no stop).
    pub fn torque(&self, s: f64, sdot: f64, [lower, upper]: [f64; 2]) -> StopTorque {
        // `sign` is the direction the stop pushes.
        let (depth, depth_rate, sign) = if s > upper {
            (s - upper, sdot, -1.0)
        } else if s < lower {
            (lower - s, -sdot, 1.0)
        } else {
            return StopTorque::default();
        };
        let magnitude = self.stiffness * depth * (1.0 + self.dissipation * depth_rate);
        if magnitude <= 0.0 {
            return StopTorque::default();
        }
        StopTorque {
            torque: sign * magnitude,
            stiffness: self.stiffness * (1.0 + self.dissipation * depth_rate),
            damping: self.stiffness * depth * self.dissipation,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_pushes_back_only_past_its_limit() {
        let stops = JointStops::default();
        let limits = [-1.0, 1.0];
        assert_eq!(stops.torque(0.5, 3.0, limits), StopTorque::default());
        let upper = stops.torque(1.01, 0.0, limits);
        assert!((upper.torque + 2000.0 * 0.01).abs() < 1e-9);
        let lower = stops.torque(-1.01, 0.0, limits);
        assert!((lower.torque - 2000.0 * 0.01).abs() < 1e-9);
        // Leaving faster than 1 / d: no pull.
        assert_eq!(stops.torque(1.01, -0.2, limits).torque, 0.0);
        let unlimited = [f64::NEG_INFINITY, f64::INFINITY];
        assert_eq!(stops.torque(1e3, 1.0, unlimited), StopTorque::default());
    }

    #[test]
    fn the_linearisation_is_the_derivative() {
        let stops = JointStops::default();
        let limits = [-1.0, 1.0];
        let (s, sdot, h) = (1.02, 0.03, 1e-7);
        let at = stops.torque(s, sdot, limits);
        let ds = (stops.torque(s + h, sdot, limits).torque - at.torque) / h;
        let dsdot = (stops.torque(s, sdot + h, limits).torque - at.torque) / h;
        assert!((ds + at.stiffness).abs() < 1e-3 * at.stiffness);
        assert!((dsdot + at.damping).abs() < 1e-3 * at.damping);
        let (s, sdot) = (-1.02, -0.03);
        let at = stops.torque(s, sdot, limits);
        let ds = (stops.torque(s + h, sdot, limits).torque - at.torque) / h;
        assert!((ds + at.stiffness).abs() < 1e-3 * at.stiffness);
    }
}
