//! Frame Jacobians and `Jdot nu`.
//!
//! `J_F(q)` (6 x nv) maps `nu` to `[velocity of the frame origin; angular velocity]`, world
//! axes. With `x` the frame origin relative to `O`: base columns `[[I, -[x]x], [0, I]]`; the
//! column of joint `j` on the frame's support is `[S_j,lin + S_j,ang x x; S_j,ang]` (the body
//! velocity at `O` moved to `x`); other columns are zero.
//! `Jdot_nu` is the frame's classical acceleration at `nudot = 0`: with the body's spatial
//! velocity `v` and acceleration `a` at `O`,
//! `pddot_x = a_lin + a_ang x x + omega x (v_lin + omega x x)`, `omegadot = a_ang`.

use crate::data::Data;
use crate::kinematics::{forward_kinematics_path, forward_velocities_path, frame_position_rel};
use crate::model::{FrameId, Model};
use crate::spatial::{skew, Motion};
use nalgebra::{DMatrix, Matrix3, Vector6};

/// Frame Jacobian into `data.frame_jacobian` (6 x nv); q has size nq.
pub fn frame_jacobian<'a>(
    model: &Model,
    data: &'a mut Data,
    q: &[f64],
    frame: FrameId,
) -> &'a DMatrix<f64> {
    forward_kinematics_path(model, data, q, model.frames[frame].body);
    frame_jacobian_from_kinematics(model, data, frame);
    &data.frame_jacobian
}

/// Frame Jacobian from the placements already in `data` (after forward kinematics, at least
/// along the frame's support).
pub fn frame_jacobian_from_kinematics(model: &Model, data: &mut Data, frame: FrameId) {
    let x = frame_position_rel(model, data, frame);
    let jac = &mut data.frame_jacobian;
    jac.as_mut_slice().fill(0.0);
    jac.fixed_view_mut::<3, 3>(0, 0)
        .copy_from(&Matrix3::identity());
    jac.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-skew(&x)));
    jac.fixed_view_mut::<3, 3>(3, 3)
        .copy_from(&Matrix3::identity());
    for j in model.support(model.frames[frame].body) {
        let s = &data.motion_subspace[j];
        let column = Motion::new(s.point_velocity(&x), s.ang).to_vector();
        jac.fixed_view_mut::<6, 1>(0, model.velocity_index(j))
            .copy_from(&column);
    }
}

/// `Jdot_F(q, nu) nu` for `frame` (6): classical acceleration of the frame at `nudot = 0`.
pub fn frame_jacobian_dot_v(
    model: &Model,
    data: &mut Data,
    q: &[f64],
    nu: &[f64],
    frame: FrameId,
) -> Vector6<f64> {
    forward_velocities_path(model, data, q, nu, model.frames[frame].body);
    frame_bias_acceleration(model, data, frame)
}

/// `Jdot_F nu` from the velocities already in `data` (after forward velocities, at least along
/// the frame's support); computes the
/// gravity-free bias accelerations only along the frame's support.
pub fn frame_bias_acceleration(model: &Model, data: &mut Data, frame: FrameId) -> Vector6<f64> {
    let body = model.frames[frame].body;
    let v0 = data.body_velocity[0];
    // a_0 at nudot = 0: the base origin moves while O is fixed (see rnea.rs).
    let mut acceleration = Motion::new(-v0.ang.cross(&v0.lin), nalgebra::Vector3::zeros());
    // a_body = a_0 + sum over the support of v_k x (S_k sdot_k): a sum, so leaf-to-root order
    // is as good as any.
    for i in model.support(body) {
        let v = data.body_velocity[i];
        let joint_velocity = v - data.body_velocity[model.parent(i)];
        acceleration = acceleration + v.cross_motion(&joint_velocity);
    }
    classical_frame_acceleration(model, data, frame, &acceleration)
}

/// [`frame_bias_acceleration`] right after [`crate::rnea::bias_forces`] at the same state:
/// RNEA at `nudot = 0` left every body's acceleration at `O` in `data`, which is the bias
/// acceleration plus gravity's uniform `[-g; 0]` (it enters at the base and propagates
/// unchanged), so no pass over the support is needed.
pub fn frame_bias_acceleration_after_bias_forces(
    model: &Model,
    data: &Data,
    frame: FrameId,
) -> Vector6<f64> {
    let mut acceleration = data.body_acceleration[model.frames[frame].body];
    acceleration.lin += model.gravity;
    classical_frame_acceleration(model, data, frame, &acceleration)
}

/// The classical acceleration `[pddot_x; omegadot]` of `frame` from its body's spatial
/// acceleration at `O` (`acceleration`) and the velocities in `data`.
fn classical_frame_acceleration(
    model: &Model,
    data: &Data,
    frame: FrameId,
    acceleration: &Motion,
) -> Vector6<f64> {
    let v = data.body_velocity[model.frames[frame].body];
    let x = frame_position_rel(model, data, frame);
    let velocity_x = v.point_velocity(&x);
    let linear = acceleration.point_velocity(&x) + v.ang.cross(&velocity_x);
    Vector6::new(
        linear.x,
        linear.y,
        linear.z,
        acceleration.ang.x,
        acceleration.ang.y,
        acceleration.ang.z,
    )
}
