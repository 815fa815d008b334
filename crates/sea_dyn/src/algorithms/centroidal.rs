//! Centre of mass and centroidal momentum: `H = [m pdot_com; L_com] = A_G(q) nu` (world axes,
//! angular momentum about the CoM), its bias `Adot_G nu`, the CoM and its Jacobian.
//!
//! The spatial momentum at `O` is `h_O = sum_i I_i v_i = Ic_0 v_0 + sum_i F_i sdot_i`
//! (composite inertias, see [`crate::crba()`]), so the columns of `A_G` at `O` are `Ic_0` (base)
//! and `F_i` (joints); moving the moment to the CoM `c` gives `L_com = L_O - c x P`.
//! `J_com = A_G[0:3, :] / m`. The rate `Hdot = [Pdot; Ldot_O - c x Pdot]` (`cdot x P = 0`), with
//! `[Pdot; Ldot_O] = sum_i (I_i a_i + v_i x* I_i v_i)`, the gravity-free RNEA base force; at
//! `nudot = 0` it is `Adot_G nu`. Sizes: q (nq), nu (nv), A_G (6 x nv), J_com (3 x nv).

use crate::crba::composite_inertias;
use crate::data::Data;
use crate::kinematics::{forward_kinematics, forward_velocities};
use crate::model::Model;
use crate::rnea::{rnea_passes, RneaTerms};
use crate::spatial::{Force, SpatialInertia};
use nalgebra::{DMatrix, Vector3, Vector6};

/// Centre of mass in world [m]; also stores it relative to `O` in `data.p_com_rel`.
pub fn com(model: &Model, data: &mut Data, q: &[f64]) -> Vector3<f64> {
    forward_kinematics(model, data, q);
    let mut total = SpatialInertia::zero();
    for i in 0..model.n_bodies() {
        let body = &model.body_inertias[i];
        total.mass += body.mass;
        total.first_moment += (data.p_body_rel[i] + data.world_r_body[i] * body.com) * body.mass;
    }
    data.p_com_rel = total.com();
    data.p_base_world + data.p_com_rel
}

/// Centroidal momentum matrix `A_G(q)` into `data.centroidal_matrix` (6 x nv).
pub fn centroidal_momentum_matrix<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
) -> &'a DMatrix<f64> {
    forward_kinematics(model, data, q);
    composite_inertias(model, data);
    let total = data.composite_inertia[0];
    let c = total.com();
    data.p_com_rel = c;
    let a = &mut data.centroidal_matrix;
    let base = total.to_matrix();
    for k in 0..6 {
        let column = Force::new(
            Vector3::new(base[(0, k)], base[(1, k)], base[(2, k)]),
            Vector3::new(base[(3, k)], base[(4, k)], base[(5, k)]),
        );
        a.fixed_view_mut::<6, 1>(0, k)
            .copy_from(&column.moment_about(&c).to_vector());
    }
    for i in 1..model.n_bodies() {
        let column = data.composite_column[i].moment_about(&c).to_vector();
        a.fixed_view_mut::<6, 1>(0, model.velocity_index(i))
            .copy_from(&column);
    }
    &data.centroidal_matrix
}

/// CoM Jacobian `J_com(q)` into `data.com_jacobian` (3 x nv): `pdot_com = J_com nu`.
pub fn com_jacobian<'a>(model: &Model, data: &'a mut Data, q: &[f64]) -> &'a DMatrix<f64> {
    centroidal_momentum_matrix(model, data, q);
    let mass = data.composite_inertia[0].mass;
    data.com_jacobian
        .copy_from(&data.centroidal_matrix.rows(0, 3));
    data.com_jacobian.scale_mut(1.0 / mass);
    &data.com_jacobian
}

/// Centroidal momentum `H = [m pdot_com; L_com]` (6); leaves the body velocities and inertias
/// in `data`.
pub fn centroidal_momentum(model: &Model, data: &mut Data, q: &[f64], nu: &[f64]) -> Vector6<f64> {
    forward_velocities(model, data, q, nu);
    for i in 0..model.n_bodies() {
        data.body_inertia[i] = SpatialInertia::from_body(
            &model.body_inertias[i],
            &data.world_r_body[i],
            &data.p_body_rel[i],
        );
    }
    centroidal_momentum_from_dynamics(data)
}

/// Centroidal momentum `H` (6) from what a dynamics pass left in `data`: the body velocities
/// (forward velocities) and the body inertias at `O` (set by RNEA, the bias or gravity forces,
/// and CRBA). Also sets `data.p_com_rel`. Saves the kinematic pass of
/// [`centroidal_momentum`] when the bias forces at the same state were just computed.
pub fn centroidal_momentum_from_dynamics(data: &mut Data) -> Vector6<f64> {
    let mut momentum = Force::zero();
    let mut total = SpatialInertia::zero();
    for (inertia, velocity) in data.body_inertia.iter().zip(&data.body_velocity) {
        momentum += inertia.mul_motion(velocity);
        total += *inertia;
    }
    data.p_com_rel = total.com();
    momentum.moment_about(&data.p_com_rel).to_vector()
}

/// `Adot_G(q, nu) nu`, the rate of the centroidal momentum at `nudot = 0` (6).
pub fn centroidal_momentum_bias(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    nu: &[f64],
) -> Vector6<f64> {
    forward_velocities(model, data, q, nu);
    rnea_passes(model, data, None, RneaTerms { gravity: false });
    let mut total = SpatialInertia::zero();
    data.body_inertia.iter().for_each(|i| total += *i);
    data.p_com_rel = total.com();
    // After the backward pass body_force[0] holds the rate of the whole robot's momentum at O.
    data.body_force[0].moment_about(&data.p_com_rel).to_vector()
}
