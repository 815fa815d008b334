//! The state manifold: retraction `x (+) dx` and the derivative of the state vector itself.

use crate::plant::Plant;
use nalgebra::DVector;

/// `x_out = x (+) scale * dx` on the state manifold (quaternion stays unit).
pub fn retract(plant: &Plant, x: &[f64], dx: &DVector<f64>, scale: f64, x_out: &mut [f64]) {
    let layout = plant.layout();
    let dx = layout.tangent().split(dx.as_slice());
    sea_dyn::configuration::integrate(&plant.model, layout.q(x), dx.dq, scale, layout.q_mut(x_out));
    axpy_into(layout.theta_mut(x_out), layout.theta(x), scale, dx.dtheta);
    axpy_into(layout.nu_mut(x_out), layout.nu(x), scale, dx.dnu);
    axpy_into(
        layout.thetadot_mut(x_out),
        layout.thetadot(x),
        scale,
        dx.dthetadot,
    );
}

/// `out = start + scale * d`, entry by entry (the Euclidean blocks of the retraction).
fn axpy_into(out: &mut [f64], start: &[f64], scale: f64, d: &[f64]) {
    for ((o, &s), &d) in out.iter_mut().zip(start).zip(d) {
        *o = s + scale * d;
    }
}

/// Time derivative of the state vector itself (nx), for external integrators: the quaternion
/// rate is `0.5 [0; omega] * quat` (world angular velocity, left product).
pub fn state_derivative(plant: &Plant, x: &[f64], xdot_tangent: &DVector<f64>, out: &mut [f64]) {
    let layout = plant.layout();
    let xdot = layout.tangent().split(xdot_tangent.as_slice());
    let nu = xdot.dq;
    let omega = [nu[3], nu[4], nu[5]];
    out[..3].copy_from_slice(&nu[..3]);
    let rate = sea_dyn::configuration::quaternion_multiply(
        [0.0, omega[0], omega[1], omega[2]],
        [x[3], x[4], x[5], x[6]],
    );
    for c in 0..4 {
        out[3 + c] = 0.5 * rate[c];
    }
    out[7..layout.nq].copy_from_slice(&nu[6..]);
    layout.theta_mut(out).copy_from_slice(xdot.dtheta);
    layout.nu_mut(out).copy_from_slice(xdot.dnu);
    layout.thetadot_mut(out).copy_from_slice(xdot.dthetadot);
}
