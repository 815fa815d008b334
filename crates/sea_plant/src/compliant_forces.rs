//! Stage 3 of an evaluation under unilateral contacts and joint stops: the forces of the
//! compliant laws ([`crate::unilateral`], [`crate::joint_stops`]) at the evaluated state, added
//! to the generalised forces, with their linearisation kept for the implicit step.
//!
//! Per contact: the sole's pose `(o, R)` and velocity `[v; omega]` (world axes) from the
//! kinematics, each point at `p = o + R r` moving at `v + omega x (R r)`, its force from
//! [`point_contact`], the foot's wrench at the sole origin `w = sum [f; (R r) x f]`, and the
//! generalised force `J^T w` with `J` the sole's Jacobian (kept in the workspace's contact
//! Jacobian rows for `W`).

use crate::plant::Plant;
use crate::unilateral::{foot_stiffness, point_contact, UnilateralContacts};
use crate::workspace::{PlantOutputs, Workspace};
use nalgebra::{Matrix6, Vector3, Vector6};
use sea_dyn::jacobian::{frame_jacobian_into_rows, frame_velocity_from_kinematics};
use sea_dyn::kinematics::frame_placement;

/// Adds each foot's contact wrench as `J^T w` to `ws.acceleration` (nv, the generalised
/// forces at this stage) and writes the wrenches (`out.contact_wrench`, at the sole origins,
/// world axes), the points' forces, positions and activity into `out`. `ws.data` holds the
/// kinematics and body velocities at the state; the sole Jacobians go to the workspace's
/// contact Jacobian rows.
pub(crate) fn add_contact_forces(
    plant: &Plant,
    unilateral: &UnilateralContacts,
    ws: &mut Workspace,
    out: &mut PlantOutputs,
) {
    let model = &plant.model;
    let ground = &unilateral.ground;
    let jacobian = &mut ws.contact.jacobian;
    let mut point = 0;
    for (c, (contact, points)) in plant.contacts.iter().zip(&unilateral.points).enumerate() {
        frame_jacobian_into_rows(model, &ws.data, contact.frame, jacobian, 6 * c);
        let pose = frame_placement(model, &ws.data, contact.frame);
        let velocity = frame_velocity_from_kinematics(model, &ws.data, contact.frame);
        let (linear, angular) = (velocity.fixed_rows::<3>(0), velocity.fixed_rows::<3>(3));
        let mut wrench = Vector6::zeros();
        for r in points {
            let offset = pose.rotation * r;
            let position = pose.translation + offset;
            let point_velocity = linear + angular.cross(&offset);
            let contact = point_contact(ground, &unilateral.law, &position, &point_velocity);
            ws.compliance.points[point] = contact;
            ws.compliance.point_offsets[point] = offset;
            let moment = offset.cross(&contact.force);
            wrench += Vector6::new(
                contact.force.x,
                contact.force.y,
                contact.force.z,
                moment.x,
                moment.y,
                moment.z,
            );
            write_point(out, point, &position, &contact.force, contact.active);
            point += 1;
        }
        out.contact_wrench
            .fixed_rows_mut::<6>(6 * c)
            .copy_from(&wrench);
        add_transposed_rows(jacobian, 6 * c, &wrench, ws.acceleration.as_mut_slice());
    }
}

/// Contact `c`'s stiffness and damping of its wrench at the sole origin (6 x 6, `[v; omega]`,
/// world axes; [`foot_stiffness`]) from the points' contacts of the last evaluation in `ws`:
/// the sum over its points that carry a force.
pub(crate) fn foot_matrices(
    unilateral: &UnilateralContacts,
    ws: &Workspace,
    c: usize,
    stiffness: &mut Matrix6<f64>,
    damping: &mut Matrix6<f64>,
) {
    let first: usize = unilateral.points[..c].iter().map(Vec::len).sum();
    let points = first..first + unilateral.points[c].len();
    stiffness.fill(0.0);
    damping.fill(0.0);
    let terms = &ws.compliance;
    for (contact, offset) in terms.points[points.clone()]
        .iter()
        .zip(&terms.point_offsets[points])
    {
        if contact.active {
            foot_stiffness(
                contact,
                &unilateral.ground.normal,
                offset,
                stiffness,
                damping,
            );
        }
    }
}

/// Point `i`'s position, force and activity into `out`.
fn write_point(
    out: &mut PlantOutputs,
    i: usize,
    position: &Vector3<f64>,
    force: &Vector3<f64>,
    active: bool,
) {
    out.contact_point_position
        .fixed_rows_mut::<3>(3 * i)
        .copy_from(position);
    out.contact_point_force
        .fixed_rows_mut::<3>(3 * i)
        .copy_from(force);
    out.contact_point_active[i] = active;
}

/// `generalized += J[rows..rows + 6]^T w`.
fn add_transposed_rows(
    jacobian: &nalgebra::DMatrix<f64>,
    rows: usize,
    wrench: &Vector6<f64>,
    generalized: &mut [f64],
) {
    for (v, g) in generalized.iter_mut().enumerate() {
        let column = jacobian.column(v);
        *g += (0..6).map(|r| column[rows + r] * wrench[r]).sum::<f64>();
    }
}

/// Adds each joint's stop torque to `ws.acceleration` (nv, the generalised forces at this
/// stage; joint rows) at `q`, `nu` (outputs and terms indexed by coordinate), writing the torques and activity into `out` and the
/// linearisation into the workspace. Without stops the outputs stay zero.
pub(crate) fn add_stop_torques(
    plant: &Plant,
    ws: &mut Workspace,
    q: &[f64],
    nu: &[f64],
    out: &mut PlantOutputs,
) {
    let terms = &mut ws.compliance;
    let generalized = ws.acceleration.as_mut_slice();
    let Some(stops) = &plant.joint_stops else {
        return;
    };
    for joint in &plant.model.joints {
        let j = joint.coordinate;
        let stop = stops.torque(q[7 + j], nu[6 + j], joint.position_limits);
        out.joint_stop_torque[j] = stop.torque;
        out.joint_stop_active[j] = stop.stiffness > 0.0;
        terms.stop_stiffness[j] = stop.stiffness;
        terms.stop_damping[j] = stop.damping;
        generalized[6 + j] += stop.torque;
    }
}

/// `matrix += g J_c^T C J_c` (nv x nv) for the contact rows `rows..rows + 6` of `jacobian`
/// (`J_c`) and a foot's combined stiffness `C = g K + D`; `scratch` (6 x nv) holds `C J_c`.
pub(crate) fn add_foot_to_matrix(
    jacobian: &nalgebra::DMatrix<f64>,
    rows: usize,
    combined: &Matrix6<f64>,
    g: f64,
    scratch: &mut nalgebra::DMatrix<f64>,
    matrix: &mut nalgebra::DMatrix<f64>,
) {
    let foot = jacobian.fixed_rows::<6>(rows);
    // Column by column (6 x 6 times a 6-vector): a general `gemm` would allocate its packing
    // buffers on every call.
    for (column, mut out) in foot.column_iter().zip(scratch.column_iter_mut()) {
        out.copy_from(&(combined * column));
    }
    matrix.gemm_tr(g, &foot, scratch, 1.0);
}
