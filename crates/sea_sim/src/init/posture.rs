//! A standing posture on two feet, found by damped least-squares inverse kinematics on sea_dyn's
//! frame and CoM Jacobians: both soles flat on the ground (z up, their yaw kept), the CoM above
//! the middle of the two foot rectangles' centres (or of their centres along the feet, see
//! [`standing_posture`]), the base upright and lowered by
//! [`LOWERING`] of its height above the soles with straight legs (so the knees bend away from
//! the singular straight leg), every joint inside its limits by [`LIMIT_MARGIN`]. Only the
//! base and the joints of the two legs move; the others stay at 0 (clamped into their limits).
//! The knee of each leg (its middle joint whose axis is horizontal, bent towards its larger
//! limit) starts bent by [`KNEE_SEED`], so the iterations start away from the singularity.

use crate::error::{Error, Result};
use crate::scenario::robots::FootRectangle;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use sea_dyn::{Data, FrameId, Model};

/// The base is lowered by this fraction of its height above the soles with straight legs.
pub const LOWERING: f64 = 0.07;
/// Every joint stays this far inside its limits [rad or m].
pub const LIMIT_MARGIN: f64 = 0.02;
/// The knees' first guess [rad].
pub const KNEE_SEED: f64 = 0.4;
/// Damping of the least-squares steps.
const DAMPING: f64 = 1e-3;
/// The solution's largest task error (position [m], orientation [rad]).
pub const TOLERANCE: f64 = 1e-6;
/// Iterations before giving up.
const MAX_ITERATIONS: usize = 500;

/// What the posture achieves: the joint angles and what they were asked for.
#[derive(Clone, Debug)]
pub struct Standing {
    /// Joint angles `s` (model order).
    pub joints: Vec<f64>,
    /// How much the base was lowered [m].
    pub lowering_m: f64,
    /// The largest task error left [m or rad].
    pub residual: f64,
    /// Iterations used.
    pub iterations: usize,
    /// How far the CoM stands from above the middle of the rectangles' centres [m]: 0, or the
    /// lateral offset dropped for legs that cannot shift it sideways.
    pub com_offset_m: f64,
}

/// The standing posture of `model` on the contacts `feet` with their `rectangles`: the CoM
/// above the middle of the rectangles' centres, else (legs of five joints, no hip yaw: bent at
/// the hips, they yaw their feet when they shift the CoM sideways, so a rectangle off-centre
/// sideways leaves no posture) above the middle of their centres along the feet, the lateral
/// offsets dropped ([`Standing::com_offset_m`]).
pub fn standing_posture(
    model: &Model,
    feet: [FrameId; 2],
    rectangles: [FootRectangle; 2],
) -> Result<Standing> {
    let mut data = Data::new(model);
    let straight = model.neutral();
    sea_dyn::forward_kinematics(model, &mut data, &straight);
    let soles = feet.map(|f| sea_dyn::frame_placement(model, &data, f));
    let ground = soles[0].translation.z.min(soles[1].translation.z);
    let lowering = -ground * LOWERING;
    let targets: [(Vector3<f64>, Matrix3<f64>); 2] = [0, 1].map(|k| {
        let mut position = soles[k].translation;
        position.z = ground;
        (position, yaw_only(&soles[k].rotation))
    });
    let middle = |lateral: f64| {
        [0, 1]
            .map(|k| {
                let centre = rectangle_centre(&rectangles[k]);
                let centre = Vector3::new(centre.x, lateral * centre.y, 0.0);
                targets[k].0 + targets[k].1 * centre
            })
            .iter()
            .sum::<Vector3<f64>>()
            / 2.0
    };
    // The second point only when it is another one (a rectangle off-centre sideways).
    let mut centres = vec![middle(1.0)];
    if middle(0.0) != centres[0] {
        centres.push(middle(0.0));
    }
    let mut residual = f64::INFINITY;
    for centre in centres {
        let goal = Goal {
            feet,
            targets,
            centre,
            base_height: -lowering,
        };
        match solve(model, &goal) {
            Ok((joints, left, iterations)) => {
                return Ok(Standing {
                    joints,
                    lowering_m: lowering,
                    residual: left,
                    iterations,
                    com_offset_m: (centre - middle(1.0)).norm(),
                })
            }
            Err(left) => residual = residual.min(left),
        }
    }
    Err(Error::config(
        "robot.contacts",
        format!(
            "the robot cannot stand on these two contacts: no posture with both soles flat on \
             the ground and the CoM between them (task error {residual:.2e} after \
             {MAX_ITERATIONS} iterations)"
        ),
    ))
}

/// What the posture is asked: the two soles' targets, the CoM's point on the ground and the
/// base's height.
struct Goal {
    feet: [FrameId; 2],
    /// Each sole's position and orientation.
    targets: [(Vector3<f64>, Matrix3<f64>); 2],
    /// The point the CoM stands above.
    centre: Vector3<f64>,
    /// The base's height [m].
    base_height: f64,
}

/// Damped least-squares iterations towards `goal`: the joint angles, the task error left and
/// the iterations used, or the task error left after [`MAX_ITERATIONS`].
fn solve(model: &Model, goal: &Goal) -> std::result::Result<(Vec<f64>, f64, usize), f64> {
    let mut data = Data::new(model);
    let moving = leg_columns(model, goal.feet);
    let mut q = seed(model, goal.feet);
    let mut residual = f64::INFINITY;
    for iteration in 0..MAX_ITERATIONS {
        let (error, jacobian) = tasks(model, &mut data, &q, goal);
        residual = error.amax();
        if residual < TOLERANCE {
            return Ok((q[7..].to_vec(), residual, iteration));
        }
        let step = damped_step(&jacobian, &error, &moving);
        let mut next = q.clone();
        sea_dyn::integrate(model, &q, step.as_slice(), 1.0, &mut next);
        clamp_to_limits(model, &mut next);
        q = next;
    }
    Err(residual)
}

/// The rotation about world z closest to `rotation` (its x axis projected on the ground).
fn yaw_only(rotation: &Matrix3<f64>) -> Matrix3<f64> {
    let yaw = sea_dyn::spatial::heading(rotation);
    sea_dyn::spatial::rotation_from_rpy(0.0, 0.0, yaw)
}

/// The rectangle's centre in the contact frame.
fn rectangle_centre(rectangle: &FootRectangle) -> Vector3<f64> {
    let mid = |r: [f64; 2]| 0.5 * (r[0] + r[1]);
    Vector3::new(mid(rectangle.x), mid(rectangle.y), 0.0)
}

/// Which velocity columns move: the base's and the joints on the legs of `feet`.
fn leg_columns(model: &Model, feet: [FrameId; 2]) -> Vec<bool> {
    let mut moving = vec![false; model.nv()];
    moving[..6].fill(true);
    for foot in feet {
        for &body in model.support_path(model.frames[foot].body) {
            moving[model.velocity_index(body)] = true;
        }
    }
    moving
}

/// The first guess: base at the origin, joints at 0 clamped into their limits, each leg's
/// knee bent by [`KNEE_SEED`] towards its larger limit.
fn seed(model: &Model, feet: [FrameId; 2]) -> Vec<f64> {
    let mut q = model.neutral();
    for foot in feet {
        if let Some(knee) = knee_of(model, model.frames[foot].body) {
            let joint = &model.joints[knee - 1];
            let [lower, upper] = joint.position_limits;
            let toward = if upper.abs() >= lower.abs() {
                1.0
            } else {
                -1.0
            };
            q[7 + joint.coordinate] = toward * KNEE_SEED;
        }
    }
    clamp_to_limits(model, &mut q);
    q
}

/// The knee of the leg ending at `body`: among the joints of its support path whose axis is
/// horizontal at the zero posture (within 30 degrees), the middle one, when there are at
/// least three (hip, knee, ankle).
fn knee_of(model: &Model, body: usize) -> Option<usize> {
    let mut data = Data::new(model);
    sea_dyn::forward_kinematics(model, &mut data, &model.neutral());
    let pitch: Vec<usize> = model
        .support_path(body)
        .iter()
        .copied()
        .filter(|&b| {
            let axis = data.world_r_body[b] * model.joints[b - 1].axis;
            axis.z.abs() < 0.5 && axis.y.abs() > axis.x.abs()
        })
        .collect();
    (pitch.len() >= 3).then(|| pitch[pitch.len() / 2])
}

/// Every joint inside its limits by [`LIMIT_MARGIN`] (or at their middle when they are closer).
fn clamp_to_limits(model: &Model, q: &mut [f64]) {
    for joint in &model.joints {
        let [lower, upper] = joint.position_limits;
        let value = &mut q[7 + joint.coordinate];
        if upper - lower <= 2.0 * LIMIT_MARGIN {
            *value = 0.5 * (lower + upper);
        } else {
            *value = value.clamp(lower + LIMIT_MARGIN, upper - LIMIT_MARGIN);
        }
    }
}

/// The stacked task errors and Jacobians: each sole's position and orientation (6 + 6), the
/// CoM's x, y (2), the base's orientation (3, upright) and height (1).
fn tasks(model: &Model, data: &mut Data, q: &[f64], goal: &Goal) -> (DVector<f64>, DMatrix<f64>) {
    let nv = model.nv();
    let mut error = DVector::zeros(18);
    let mut jacobian = DMatrix::zeros(18, nv);
    for (k, &foot) in goal.feet.iter().enumerate() {
        let frame_jacobian = sea_dyn::frame_jacobian(model, data, q, foot).clone();
        sea_dyn::forward_kinematics(model, data, q);
        let placement = sea_dyn::frame_placement(model, data, foot);
        let (position, rotation) = &goal.targets[k];
        error
            .rows_mut(6 * k, 3)
            .copy_from(&(position - placement.translation));
        let angle = rotation_error(&(rotation * placement.rotation.transpose()));
        error.rows_mut(6 * k + 3, 3).copy_from(&angle);
        jacobian.rows_mut(6 * k, 6).copy_from(&frame_jacobian);
    }
    let com = sea_dyn::com(model, data, q);
    error[12] = goal.centre.x - com.x;
    error[13] = goal.centre.y - com.y;
    let com_jacobian = sea_dyn::centroidal::com_jacobian(model, data, q);
    jacobian.rows_mut(12, 2).copy_from(&com_jacobian.rows(0, 2));
    sea_dyn::forward_kinematics(model, data, q);
    let upright = rotation_error(&data.world_r_body[0].transpose());
    error.rows_mut(14, 3).copy_from(&upright);
    error[17] = goal.base_height - q[2];
    for k in 0..3 {
        jacobian[(14 + k, 3 + k)] = 1.0;
    }
    jacobian[(17, 2)] = 1.0;
    (error, jacobian)
}

/// The rotation vector (axis times angle, world axes) of the rotation `error`.
fn rotation_error(error: &Matrix3<f64>) -> Vector3<f64> {
    let skew = Vector3::new(
        error[(2, 1)] - error[(1, 2)],
        error[(0, 2)] - error[(2, 0)],
        error[(1, 0)] - error[(0, 1)],
    );
    let sin = 0.5 * skew.norm();
    let cos = 0.5 * (error.trace() - 1.0);
    let angle = sin.atan2(cos);
    if sin < 1e-9 {
        0.5 * skew
    } else {
        skew * (angle / (2.0 * sin))
    }
}

/// The damped least-squares step `J^T (J J^T + d^2 I)^-1 e` over the `moving` columns.
fn damped_step(jacobian: &DMatrix<f64>, error: &DVector<f64>, moving: &[bool]) -> DVector<f64> {
    let mut masked = jacobian.clone();
    for (column, &moves) in moving.iter().enumerate() {
        if !moves {
            masked.column_mut(column).fill(0.0);
        }
    }
    let mut gram = &masked * masked.transpose();
    for k in 0..gram.nrows() {
        gram[(k, k)] += DAMPING * DAMPING;
    }
    let solved = gram
        .cholesky()
        .map(|c| c.solve(error))
        .unwrap_or_else(|| DVector::zeros(error.len()));
    masked.transpose() * solved
}
