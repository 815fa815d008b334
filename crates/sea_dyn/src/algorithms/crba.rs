//! Composite rigid body algorithm: the joint-space inertia matrix `M(q)` (nv x nv, full and
//! symmetric), with `0.5 nu^T M nu` the kinetic energy in the mixed velocity `nu`.
//!
//! Composite inertias at `O`: `Ic_i = I_i + sum_{children c} Ic_c`. With every quantity at the
//! same point no transform is needed along the tree: `F_i = Ic_i S_i`,
//! `M[i, j] = S_j . F_i` for every `j` on the path from `i` to the base, `M[base, i] = F_i`
//! (the base columns are the identity at `O`), `M[base, base] = Ic_0` as a 6x6 matrix.

use crate::data::Data;
use crate::kinematics::forward_kinematics;
use crate::model::Model;
use crate::spatial::SpatialInertia;
use nalgebra::DMatrix;

/// Body inertias, composite inertias and `F_i = Ic_i S_i` at `O` after forward kinematics.
pub(crate) fn composite_inertias(model: &Model, data: &mut Data) {
    for i in 0..model.n_bodies() {
        data.body_inertia[i] = SpatialInertia::from_body(
            &model.body_inertias[i],
            &data.world_r_body[i],
            &data.p_body_rel[i],
        );
    }
    composite_inertias_from_bodies(model, data);
}

/// Composite inertias and `F_i = Ic_i S_i` from the body inertias at `O` already in `data`.
fn composite_inertias_from_bodies(model: &Model, data: &mut Data) {
    data.composite_inertia.copy_from_slice(&data.body_inertia);
    for i in (1..model.n_bodies()).rev() {
        let composite = data.composite_inertia[i];
        data.composite_inertia[model.parent(i)] += composite;
        data.composite_column[i] = composite.mul_motion(&data.motion_subspace[i]);
    }
}

/// Joint-space inertia matrix `M(q)` into `data.mass_matrix`; `q` has size nq.
pub fn crba<'a>(model: &Model, data: &'a mut Data, q: &[f64]) -> &'a DMatrix<f64> {
    forward_kinematics(model, data, q);
    crba_from_kinematics(model, data)
}

/// `M(q)` from the placements already in `data` (after any forward kinematics pass).
pub fn crba_from_kinematics<'a>(model: &Model, data: &'a mut Data) -> &'a DMatrix<f64> {
    composite_inertias(model, data);
    mass_matrix_from_composites(model, data)
}

/// `M(q)` right after RNEA (`rnea`, `bias_forces` or `gravity_forces`) at the same `q`: reuses
/// the body inertias at `O` that RNEA left in `data` instead of transforming them again.
pub fn crba_after_rnea<'a>(model: &Model, data: &'a mut Data) -> &'a DMatrix<f64> {
    composite_inertias_from_bodies(model, data);
    mass_matrix_from_composites(model, data)
}

/// Fills `data.mass_matrix` from the composite inertias and `F_i`.
fn mass_matrix_from_composites<'a>(model: &Model, data: &'a mut Data) -> &'a DMatrix<f64> {
    let m = &mut data.mass_matrix;
    m.fixed_view_mut::<6, 6>(0, 0)
        .copy_from(&data.composite_inertia[0].to_matrix());
    for i in 1..model.n_bodies() {
        let column = data.composite_column[i];
        let vi = model.velocity_index(i);
        let base_column = column.to_vector();
        m.fixed_view_mut::<6, 1>(0, vi).copy_from(&base_column);
        m.fixed_view_mut::<1, 6>(vi, 0)
            .copy_from(&base_column.transpose());
        for j in model.support(i) {
            let vj = model.velocity_index(j);
            let value = data.motion_subspace[j].dot(&column);
            m[(vj, vi)] = value;
            m[(vi, vj)] = value;
        }
    }
    // Entries of joints on different branches are structurally zero: `Data::new` zeroed them
    // and no call ever writes them, so they need no clearing here.
    &data.mass_matrix
}
