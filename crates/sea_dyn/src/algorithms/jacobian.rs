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
use nalgebra::{DMatrix, Vector6};

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
    let mut jacobian = std::mem::replace(&mut data.frame_jacobian, DMatrix::zeros(0, 0));
    frame_jacobian_into_rows(model, data, frame, &mut jacobian, 0);
    data.frame_jacobian = jacobian;
}

/// The frame Jacobian (as [`frame_jacobian_from_kinematics`]) written straight into rows
/// `first_row..first_row + 6` of `stacked` (k x nv, e.g. the stacked Jacobian of several
/// contacts); its other rows are left as they are. Panics if the rows do not fit or `stacked`
/// does not have nv columns.
pub fn frame_jacobian_into_rows(
    model: &Model,
    data: &Data,
    frame: FrameId,
    stacked: &mut DMatrix<f64>,
    first_row: usize,
) {
    let k = stacked.nrows();
    assert!(
        first_row + 6 <= k && stacked.ncols() == model.nv(),
        "frame_jacobian_into_rows: sizes"
    );
    let x = frame_position_rel(model, data, frame);
    let columns = stacked.as_mut_slice();
    let mut set_column = |index: usize, column: &Vector6<f64>| {
        let start = index * k + first_row;
        columns[start..start + 6].copy_from_slice(column.as_slice());
    };
    // Base columns [[I, -[x]x], [0, I]]; joint columns off the support are zero.
    let minus_x_cross = -skew(&x);
    for c in 0..3 {
        set_column(c, &Vector6::ith(c, 1.0));
        let mut angular = Vector6::ith(3 + c, 1.0);
        angular
            .fixed_rows_mut::<3>(0)
            .copy_from(&minus_x_cross.column(c));
        set_column(3 + c, &angular);
    }
    for j in 6..model.nv() {
        set_column(j, &Vector6::zeros());
    }
    for j in model.support(model.frames[frame].body) {
        let s = &data.motion_subspace[j];
        let column = Motion::new(s.point_velocity(&x), s.ang).to_vector();
        set_column(model.velocity_index(j), &column);
    }
}

/// `J_F nu` for `frame` (6): the frame's velocity `[velocity of its origin; angular velocity]`
/// from the body velocities already in `data` (after forward velocities, at least along the
/// frame's support), without forming `J_F`.
pub fn frame_velocity_from_kinematics(model: &Model, data: &Data, frame: FrameId) -> Vector6<f64> {
    let v = data.body_velocity[model.frames[frame].body];
    let x = frame_position_rel(model, data, frame);
    Motion::new(v.point_velocity(&x), v.ang).to_vector()
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
