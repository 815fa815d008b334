//! Forward kinematics: body placements, joint motion subspaces, body velocities, frame
//! placements.
//!
//! For body `i` moved by joint `i` with parent `p`:
//! `world_R_joint = world_R_p * p_R_joint`, `r_joint = r_p + world_R_p p_t_joint`,
//! `a = world_R_joint axis`; revolute: `world_R_i = world_R_joint Rot(axis, s_i)`, `r_i = r_joint`,
//! `S_i = [r_joint x a; a]`; prismatic: `world_R_i = world_R_joint`, `r_i = r_joint + a s_i`,
//! `S_i = [a; 0]`. Velocities: `v_0 = [pdot_B; omega_B]` (the mixed base velocity is the base's
//! spatial velocity at `O`), `v_i = v_p + S_i sdot_i`. Positions `r` are relative to `O`, the base
//! origin, world axes.

use crate::data::Data;
use crate::model::{FrameId, JointKind, Model};
use crate::spatial::{
    mat_mul, mat_vec_add, rotation_about_axis, rotation_from_quaternion, Motion, Pose,
};
use nalgebra::Vector3;

/// Placements `world_R_body`, `p_body_rel` and motion subspaces `S_i` from `q` (size nq).
pub fn forward_kinematics(model: &Model, data: &mut Data, q: &[f64]) {
    base_placement(data, q);
    for i in 1..model.n_bodies() {
        body_placement(model, data, q, i);
    }
}

/// Forward kinematics of the base and of the bodies supporting `body` only (what a frame
/// Jacobian needs); other bodies keep stale values.
pub fn forward_kinematics_path(model: &Model, data: &mut Data, q: &[f64], body: usize) {
    base_placement(data, q);
    for &i in model.support_path(body) {
        body_placement(model, data, q, i);
    }
}

#[inline]
fn base_placement(data: &mut Data, q: &[f64]) {
    data.p_base_world = Vector3::new(q[0], q[1], q[2]);
    data.world_r_body[0] = rotation_from_quaternion(q[3], q[4], q[5], q[6]);
    data.p_body_rel[0] = Vector3::zeros();
}

/// Placement and motion subspace of body `i`, its parent's being up to date.
#[inline]
fn body_placement(model: &Model, data: &mut Data, q: &[f64], i: usize) {
    {
        let joint = &model.joints[i - 1];
        let p = joint.parent;
        let world_r_parent = data.world_r_body[p];
        let world_r_joint = mat_mul(&world_r_parent, &joint.parent_h_joint.rotation);
        let r_joint = mat_vec_add(
            &world_r_parent,
            &joint.parent_h_joint.translation,
            data.p_body_rel[p],
        );
        let axis_world = mat_vec_add(&world_r_joint, &joint.axis, Vector3::zeros());
        let s = q[7 + joint.coordinate];
        match joint.kind {
            JointKind::Revolute => {
                data.world_r_body[i] =
                    mat_mul(&world_r_joint, &rotation_about_axis(&joint.axis, s));
                data.p_body_rel[i] = r_joint;
                data.motion_subspace[i] = Motion::new(r_joint.cross(&axis_world), axis_world);
            }
            JointKind::Prismatic => {
                data.world_r_body[i] = world_r_joint;
                data.p_body_rel[i] = r_joint + axis_world * s;
                data.motion_subspace[i] = Motion::new(axis_world, Vector3::zeros());
            }
        }
    }
}

/// Forward kinematics along the support of `body` plus the velocities of those bodies.
pub fn forward_velocities_path(model: &Model, data: &mut Data, q: &[f64], nu: &[f64], body: usize) {
    forward_kinematics_path(model, data, q, body);
    data.body_velocity[0] = base_motion(nu);
    for &i in model.support_path(body) {
        let sdot = nu[model.velocity_index(i)];
        data.body_velocity[i] =
            data.body_velocity[model.parent(i)] + data.motion_subspace[i].scale(sdot);
    }
}

/// Forward kinematics plus body velocities `v_i` at `O` from `nu` (size nv).
pub fn forward_velocities(model: &Model, data: &mut Data, q: &[f64], nu: &[f64]) {
    forward_kinematics(model, data, q);
    data.body_velocity[0] = base_motion(nu);
    for i in 1..model.n_bodies() {
        let sdot = nu[model.velocity_index(i)];
        data.body_velocity[i] =
            data.body_velocity[model.parent(i)] + data.motion_subspace[i].scale(sdot);
    }
}

/// The first six entries of a velocity-sized vector as a spatial motion at `O`.
#[inline]
pub(crate) fn base_motion(v: &[f64]) -> Motion {
    Motion::new(
        Vector3::new(v[0], v[1], v[2]),
        Vector3::new(v[3], v[4], v[5]),
    )
}

/// Position of a frame origin relative to `O` (world axes), after forward kinematics.
#[inline]
pub fn frame_position_rel(model: &Model, data: &Data, frame: FrameId) -> Vector3<f64> {
    let f = &model.frames[frame];
    data.p_body_rel[f.body] + data.world_r_body[f.body] * f.body_h_frame.translation
}

/// `world_H_frame` after forward kinematics.
pub fn frame_placement(model: &Model, data: &Data, frame: FrameId) -> Pose {
    let f = &model.frames[frame];
    let body = f.body;
    Pose {
        rotation: data.world_r_body[body] * f.body_h_frame.rotation,
        translation: data.p_base_world + frame_position_rel(model, data, frame),
    }
}
