//! The state manifold: retraction `x (+) dx` and the derivative of the state vector itself.

use crate::plant::Plant;
use nalgebra::DVector;

/// `x_out = x (+) scale * dx` on the state manifold (quaternion stays unit).
pub fn retract(plant: &Plant, x: &[f64], dx: &DVector<f64>, scale: f64, x_out: &mut [f64]) {
    let layout = plant.layout();
    let (nq, nv, ne) = (layout.nq, layout.nv, layout.ne);
    sea_dyn::configuration::integrate(
        &plant.model,
        &x[..nq],
        &dx.as_slice()[..nv],
        scale,
        &mut x_out[..nq],
    );
    for e in 0..ne {
        x_out[nq + e] = x[nq + e] + scale * dx[nv + e];
    }
    for i in 0..nv + ne {
        x_out[nq + ne + i] = x[nq + ne + i] + scale * dx[nv + ne + i];
    }
}

/// Time derivative of the state vector itself (nx), for external integrators: the quaternion
/// rate is `0.5 [0; omega] * quat` (world angular velocity, left product).
pub fn state_derivative(plant: &Plant, x: &[f64], xdot_tangent: &DVector<f64>, out: &mut [f64]) {
    let layout = plant.layout();
    let (nq, nv, ne) = (layout.nq, layout.nv, layout.ne);
    let omega = [xdot_tangent[3], xdot_tangent[4], xdot_tangent[5]];
    out[..3].copy_from_slice(&xdot_tangent.as_slice()[..3]);
    let rate = sea_dyn::configuration::quaternion_multiply(
        [0.0, omega[0], omega[1], omega[2]],
        [x[3], x[4], x[5], x[6]],
    );
    for c in 0..4 {
        out[3 + c] = 0.5 * rate[c];
    }
    out[7..nq].copy_from_slice(&xdot_tangent.as_slice()[6..nv]);
    out[nq..].copy_from_slice(&xdot_tangent.as_slice()[nv..nv + ne + nv + ne]);
}
