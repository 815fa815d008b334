//! Gain conventions shared by the plant, the controller and the scenarios.

/// Critical damping of a unit-mass second-order loop with stiffness `kp`: `kd = 2 sqrt(kp)`
/// (`e'' + kd e' + kp e = 0` with a double pole). The original study (docs/references.md) sets the
/// Baumgarte velocity gain, the momentum proportional gains and the postural damping this way.
/// A negative `kp` is clamped to zero (no damping) rather than giving NaN.
pub fn critical_damping(kp: f64) -> f64 {
    2.0 * kp.max(0.0).sqrt()
}
