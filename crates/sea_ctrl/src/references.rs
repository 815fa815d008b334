//! References: the CoM trajectory and the postural reference.
//!
//! CoM (the original study, docs/references.md#original-study-com-reference):
//! `p_d(t) = p_0 + (1 - exp(-t / T_s)) A sin(2 pi f t) d`,
//! with amplitude `A`, frequency `f`, unit direction `d` and smooth-start time constant `T_s`
//! (a constant reference when `A = 0`). Velocity and acceleration are its exact derivatives.
//! Posture: `s_d(t) = s_0 + step` for `t >= t_step` on the chosen joints, `s_0` before.

use nalgebra::Vector3;

/// A CoM trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct ComTrajectory {
    /// Initial reference `p_0` in world [m].
    pub origin: Vector3<f64>,
    /// Amplitude `A` [m].
    pub amplitude: f64,
    /// Frequency `f` [Hz].
    pub frequency: f64,
    /// Unit direction `d` (world).
    pub direction: Vector3<f64>,
    /// Smooth-start time constant `T_s` [s] (0: no smoothing).
    pub smooth_start: f64,
}

/// Position, velocity and acceleration of a reference at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComSample {
    /// Position [m].
    pub position: Vector3<f64>,
    /// Velocity [m/s].
    pub velocity: Vector3<f64>,
    /// Acceleration [m/s^2].
    pub acceleration: Vector3<f64>,
}

impl ComTrajectory {
    /// A constant reference at `origin`.
    pub fn constant(origin: Vector3<f64>) -> Self {
        Self {
            origin,
            amplitude: 0.0,
            frequency: 0.0,
            direction: Vector3::y(),
            smooth_start: 0.0,
        }
    }

    /// The reference at time `t` [s]; before the start (`t < 0`) it rests at `origin`.
    pub fn sample(&self, t: f64) -> ComSample {
        if t < 0.0 {
            return ComSample {
                position: self.origin,
                velocity: Vector3::zeros(),
                acceleration: Vector3::zeros(),
            };
        }
        let w = 2.0 * std::f64::consts::PI * self.frequency;
        let (sin, cos) = (w * t).sin_cos();
        // Envelope e(t) = 1 - exp(-t/T) and its derivatives.
        let (e, de, dde) = if self.smooth_start > 0.0 {
            let decay = (-t / self.smooth_start).exp();
            let tau = self.smooth_start;
            (1.0 - decay, decay / tau, -decay / (tau * tau))
        } else {
            (1.0, 0.0, 0.0)
        };
        let a = self.amplitude;
        let g = a * e * sin;
        let dg = a * (de * sin + e * w * cos);
        let ddg = a * (dde * sin + 2.0 * de * w * cos - e * w * w * sin);
        ComSample {
            position: self.origin + self.direction * g,
            velocity: self.direction * dg,
            acceleration: self.direction * ddg,
        }
    }
}

/// A postural reference with a step on some joints.
#[derive(Clone, Debug, PartialEq)]
pub struct PostureReference {
    /// Posture before the step (n) [rad].
    pub initial: Vec<f64>,
    /// Step added to each joint (n) [rad] (zero for joints without a step).
    pub step: Vec<f64>,
    /// Time of the step [s].
    pub step_time: f64,
}

impl PostureReference {
    /// The desired posture at `t`.
    pub fn at(&self, t: f64, out: &mut [f64]) {
        let stepped = t >= self.step_time;
        for (k, value) in out.iter_mut().enumerate() {
            *value = self.initial[k] + if stepped { self.step[k] } else { 0.0 };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 cm lateral sway at 0.2 Hz with a 1 s smooth start.
    fn sway() -> ComTrajectory {
        ComTrajectory {
            origin: Vector3::new(0.1, 0.0, 0.5),
            amplitude: 0.01,
            frequency: 0.2,
            direction: Vector3::y(),
            smooth_start: 1.0,
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let traj = sway();
        let eps = 1e-6;
        // Central differences away from t = 0 (the envelope starts there).
        for &t in &[0.3, 1.7, 4.0] {
            let (a, b) = (traj.sample(t + eps), traj.sample(t - eps));
            let s = traj.sample(t);
            assert!(((a.position - b.position) / (2.0 * eps) - s.velocity).norm() < 1e-8);
            assert!(((a.velocity - b.velocity) / (2.0 * eps) - s.acceleration).norm() < 1e-7);
        }
        // One-sided at the start: first-order accurate.
        let (a, s) = (traj.sample(eps), traj.sample(0.0));
        assert!(((a.position - s.position) / eps - s.velocity).norm() < 1e-6);
        assert!(((a.velocity - s.velocity) / eps - s.acceleration).norm() < 1e-4);
        assert!((traj.sample(0.0).position - traj.origin).norm() < 1e-15);
    }

    #[test]
    fn before_the_start_the_reference_rests_at_its_origin() {
        let traj = sway();
        // The envelope 1 - exp(-t / T) grows without bound for t < 0 (NaN at -1e3 s).
        for t in [-1e-9, -1.25, -1e3, -1e9, f64::NEG_INFINITY] {
            let s = traj.sample(t);
            assert_eq!(s.position, traj.origin, "t = {t}");
            assert_eq!(s.velocity, Vector3::zeros(), "t = {t}");
            assert_eq!(s.acceleration, Vector3::zeros(), "t = {t}");
        }
    }
}
