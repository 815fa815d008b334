//! Recursive Newton-Euler algorithm: `tau = M(q) nudot + h(q, nu)`, and its special cases
//! `h = C(q, nu) nu + G(q)` (bias forces, `nudot = 0`) and `G(q)` (gravity, `nu = nudot = 0`).
//!
//! Forward pass (all at `O`, world axes): `a_0 = [pddot_B - omega x pdot_B; omegadot] - [g; 0]`
//! (the base term `-omega x pdot_B` because `O` is fixed in space while the base origin moves;
//! gravity as a fictitious base acceleration), `a_i = a_p + S_i sddot_i + v_i x (S_i sdot_i)`,
//! `f_i = I_i a_i + v_i x* (I_i v_i)`. Backward pass: `f_p += f_i`, `tau_i = S_i . f_i`, and the
//! base rows of `tau` are `f_0` = [force; moment about the base origin], the generalised force
//! conjugate to the mixed base velocity. Sizes: q (nq), nu and nudot (nv), result (nv).

use crate::data::Data;
use crate::kinematics::{base_motion, forward_velocities};
use crate::model::Model;
use crate::spatial::{Motion, SpatialInertia};
use nalgebra::DVector;

/// Which terms RNEA includes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct RneaTerms {
    /// Include gravity.
    pub gravity: bool,
}

/// Inverse dynamics `tau = M nudot + h` into `data.tau`.
pub fn rnea<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    nu: &[f64],
    nudot: &[f64],
) -> &'a DVector<f64> {
    forward_velocities(model, data, q, nu);
    rnea_passes(model, data, Some(nudot), RneaTerms { gravity: true });
    &data.tau
}

/// Bias forces `h(q, nu) = C nu + G` into `data.tau`.
pub fn bias_forces<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    nu: &[f64],
) -> &'a DVector<f64> {
    forward_velocities(model, data, q, nu);
    rnea_passes(model, data, None, RneaTerms { gravity: true });
    &data.tau
}

/// Gravity forces `G(q)` into `data.tau`.
pub fn gravity_forces<'a>(model: &Model, data: &'a mut Data, q: &[f64]) -> &'a DVector<f64> {
    crate::kinematics::forward_kinematics(model, data, q);
    data.body_velocity
        .iter_mut()
        .for_each(|v| *v = Motion::zero());
    rnea_passes(model, data, None, RneaTerms { gravity: true });
    &data.tau
}

/// The two passes of RNEA after `forward_velocities` (body velocities set); `nudot = None`
/// means zero. Only the base velocity `v_0` is read from `data`.
pub(crate) fn rnea_passes(model: &Model, data: &mut Data, nudot: Option<&[f64]>, terms: RneaTerms) {
    let v0 = data.body_velocity[0];
    let mut a0 = match nudot {
        Some(a) => base_motion(a),
        None => Motion::zero(),
    };
    a0.lin -= v0.ang.cross(&v0.lin);
    if terms.gravity {
        a0.lin -= model.gravity;
    }
    data.body_acceleration[0] = a0;
    let base = SpatialInertia::from_body(
        &model.body_inertias[0],
        &data.world_r_body[0],
        &data.p_body_rel[0],
    );
    data.body_inertia[0] = base;
    data.body_force[0] = base.mul_motion(&a0) + v0.cross_force(&base.mul_motion(&v0));
    for i in 1..model.n_bodies() {
        let vi = model.velocity_index(i);
        let s = data.motion_subspace[i];
        let v = data.body_velocity[i];
        let sddot = nudot.map_or(0.0, |a| a[vi]);
        // S_i sdot_i is the velocity the joint adds to its parent's.
        let sdot_s = v - data.body_velocity[model.parent(i)];
        let a = data.body_acceleration[model.parent(i)] + s.scale(sddot) + v.cross_motion(&sdot_s);
        data.body_acceleration[i] = a;
        let inertia = SpatialInertia::from_body(
            &model.body_inertias[i],
            &data.world_r_body[i],
            &data.p_body_rel[i],
        );
        data.body_inertia[i] = inertia;
        data.body_force[i] = inertia.mul_motion(&a) + v.cross_force(&inertia.mul_motion(&v));
    }
    for i in (1..model.n_bodies()).rev() {
        let f = data.body_force[i];
        data.tau[model.velocity_index(i)] = data.motion_subspace[i].dot(&f);
        data.body_force[model.parent(i)] += f;
    }
    let f0 = data.body_force[0];
    data.tau.fixed_rows_mut::<6>(0).copy_from(&f0.to_vector());
}
