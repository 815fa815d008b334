//! The workspace of the algorithms (Pinocchio's `Data`): every buffer, sized once by
//! [`Data::new`], so the in-place algorithms allocate nothing.
//!
//! Frames: every spatial quantity is in world-aligned axes at the reference point `O`, the base
//! origin at the current configuration (see [`crate::spatial`]). Positions marked `_rel` are
//! relative to `O`; add [`Data::p_base_world`] for world positions.

use crate::dense::copy_contiguous;
use crate::model::Model;
use crate::spatial::{Force, Motion, SpatialInertia};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Buffers of all algorithms for one [`Model`].
#[derive(Clone, Debug)]
pub struct Data {
    /// Base origin in world [m] (the reference point `O`).
    pub p_base_world: Vector3<f64>,
    /// `world_R_body` for each body (n + 1).
    pub world_r_body: Vec<Matrix3<f64>>,
    /// Body frame origins relative to `O`, world axes (n + 1) [m].
    pub p_body_rel: Vec<Vector3<f64>>,
    /// Joint motion subspace `S_i` of body `i >= 1` at `O` (index 0 unused) (n + 1).
    pub motion_subspace: Vec<Motion>,
    /// Spatial velocity of each body at `O` (n + 1).
    pub body_velocity: Vec<Motion>,
    /// Spatial acceleration of each body at `O` (n + 1); includes `-g` after RNEA with gravity.
    pub body_acceleration: Vec<Motion>,
    /// Net spatial force on each subtree at `O` after RNEA's backward pass (n + 1).
    pub body_force: Vec<Force>,
    /// Spatial inertia of each body at `O` (n + 1).
    pub body_inertia: Vec<SpatialInertia>,
    /// Composite (subtree) spatial inertia of each body at `O` (n + 1).
    pub composite_inertia: Vec<SpatialInertia>,
    /// `F_i = Ic_i S_i`, momentum of the subtree of body `i` per unit joint velocity (n + 1).
    pub composite_column: Vec<Force>,
    /// Generalised forces of RNEA, bias or gravity (nv).
    pub tau: DVector<f64>,
    /// Joint-space inertia matrix `M(q)`, full and symmetric (nv x nv).
    pub mass_matrix: DMatrix<f64>,
    /// Centroidal momentum matrix `A_G(q)`, world axes, about the CoM (6 x nv).
    pub centroidal_matrix: DMatrix<f64>,
    /// Last frame Jacobian, `[v_origin; omega]`, world axes (6 x nv).
    pub frame_jacobian: DMatrix<f64>,
    /// Centre-of-mass Jacobian, world axes (3 x nv).
    pub com_jacobian: DMatrix<f64>,
    /// Centre of mass relative to `O` [m] (set by the centroidal and CoM algorithms).
    pub p_com_rel: Vector3<f64>,
}

impl Data {
    /// Copies from `other` (a workspace of the same model) what an algorithm run at the same
    /// state after `bias_forces` and [`crate::crba_after_rnea`] leaves for later use: base
    /// position, placements, motion subspaces, body velocities, accelerations (RNEA's, which
    /// give `Jdot nu`) and inertias, the bias forces in `tau` and `M`. Allocates nothing. Lets a second user of the same state (the plant after
    /// the controller) skip the kinematics, RNEA and CRBA.
    pub fn copy_model_terms_from(&mut self, other: &Data) {
        self.p_base_world = other.p_base_world;
        self.world_r_body.copy_from_slice(&other.world_r_body);
        self.p_body_rel.copy_from_slice(&other.p_body_rel);
        self.motion_subspace.copy_from_slice(&other.motion_subspace);
        self.body_velocity.copy_from_slice(&other.body_velocity);
        self.body_acceleration
            .copy_from_slice(&other.body_acceleration);
        self.body_inertia.copy_from_slice(&other.body_inertia);
        copy_contiguous(&mut self.tau, &other.tau);
        copy_contiguous(&mut self.mass_matrix, &other.mass_matrix);
    }

    /// Allocates every buffer for `model`.
    pub fn new(model: &Model) -> Self {
        let nb = model.n_bodies();
        let nv = model.nv();
        Self {
            p_base_world: Vector3::zeros(),
            world_r_body: vec![Matrix3::identity(); nb],
            p_body_rel: vec![Vector3::zeros(); nb],
            motion_subspace: vec![Motion::zero(); nb],
            body_velocity: vec![Motion::zero(); nb],
            body_acceleration: vec![Motion::zero(); nb],
            body_force: vec![Force::zero(); nb],
            body_inertia: vec![SpatialInertia::zero(); nb],
            composite_inertia: vec![SpatialInertia::zero(); nb],
            composite_column: vec![Force::zero(); nb],
            tau: DVector::zeros(nv),
            mass_matrix: DMatrix::zeros(nv, nv),
            centroidal_matrix: DMatrix::zeros(6, nv),
            frame_jacobian: DMatrix::zeros(6, nv),
            com_jacobian: DMatrix::zeros(3, nv),
            p_com_rel: Vector3::zeros(),
        }
    }
}
