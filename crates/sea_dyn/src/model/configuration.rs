//! Configuration-space operations on `q = [p_B; quaternion (w, x, y, z); s]`.
//!
//! `integrate`: `p_B += pdot_B dt`, `R_B <- exp([omega_B dt]x) R_B` (world-axes angular velocity
//! acts on the left; the quaternion stays unit), `s += sdot dt`. This is the exponential map of
//! the mixed velocity held constant over `dt` for the orientation and the joints, and first order
//! in the base translation.

use crate::model::Model;

/// Quaternion product `a * b`, both (w, x, y, z).
#[inline]
pub fn quaternion_multiply(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// Unit quaternion (w, x, y, z) of the rotation vector `phi` (axis times angle).
pub fn quaternion_exp(phi: [f64; 3]) -> [f64; 4] {
    let angle = (phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]).sqrt();
    // sin(angle/2)/angle, by its series near zero to keep full precision.
    let half_sinc = if angle < 1e-6 {
        0.5 - angle * angle / 48.0
    } else {
        (0.5 * angle).sin() / angle
    };
    [
        (0.5 * angle).cos(),
        phi[0] * half_sinc,
        phi[1] * half_sinc,
        phi[2] * half_sinc,
    ]
}

/// Writes `q_out = q (+) nu dt` (sizes nq, nv, nq).
pub fn integrate(model: &Model, q: &[f64], nu: &[f64], dt: f64, q_out: &mut [f64]) {
    for k in 0..3 {
        q_out[k] = q[k] + nu[k] * dt;
    }
    let delta = quaternion_exp([nu[3] * dt, nu[4] * dt, nu[5] * dt]);
    let rotated = quaternion_multiply(delta, [q[3], q[4], q[5], q[6]]);
    let norm = rotated.iter().map(|c| c * c).sum::<f64>().sqrt();
    for k in 0..4 {
        q_out[3 + k] = rotated[k] / norm;
    }
    for k in 0..model.n_joints() {
        q_out[7 + k] = q[7 + k] + nu[6 + k] * dt;
    }
}
