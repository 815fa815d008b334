//! The redundant two-feet contact set (`sea_ctrl::redundant_contacts`) on the mini biped, whose
//! legs have 5 joints, standing still: the equalities' wrenches are ones the joints produce
//! (eq:torques is consistent for them), the paper's `A f = b` wrenches are not; on the iCub (legs
//! of 6 joints) nothing is redundant.

use nalgebra::{DMatrix, DVector, Vector3};
use sea_ctrl::momentum::{momentum_map_identity_blocks, set_momentum_map_contact};
use sea_ctrl::redundant_contacts::RedundantContacts;
use sea_ctrl::torque_map::{PosturalTask, TorqueMap};
use sea_dyn::{Data, LoadOptions, Model};
use std::path::Path;

fn model(file: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../urdf")
        .join(file);
    Model::from_urdf_file(&path, &LoadOptions::default()).unwrap()
}

/// The torque map and momentum map of `model` standing still at `joints` on its two soles.
fn standing_terms(model: &Model, joints: &[f64]) -> (TorqueMap, DMatrix<f64>) {
    let (nv, n) = (model.nv(), model.n_joints());
    let mut q = model.neutral();
    q[7..].copy_from_slice(joints);
    let nu = vec![0.0; nv];
    let mut data = Data::new(model);
    let mut map = TorqueMap::new(model, 12);
    map.bias
        .copy_from(sea_dyn::bias_forces(model, &mut data, &q, &nu));
    for value in map.diagonal.iter_mut().skip(6) {
        *value = 0.026;
    }
    let com = sea_dyn::com(model, &mut data, &q);
    let mut momentum_map = momentum_map_identity_blocks(2);
    for (c, name) in ["l_sole", "r_sole"].iter().enumerate() {
        let frame = model.frame_id(name).unwrap();
        let jacobian = sea_dyn::frame_jacobian(model, &mut data, &q, frame);
        map.jacobian.rows_mut(6 * c, 6).copy_from(jacobian);
        let pose = sea_dyn::frame_placement(model, &data, frame);
        set_momentum_map_contact(&mut momentum_map, c, &pose.translation, &com);
    }
    let mass_matrix = sea_dyn::crba(model, &mut data, &q).clone();
    let zeros = vec![0.0; n];
    let posture = PosturalTask {
        error: &zeros,
        velocity: &zeros,
        stiffness: &zeros,
        damping: &zeros,
    };
    map.compute(&mass_matrix, &posture, 5e-4).unwrap();
    (map, momentum_map)
}

/// `|(I - Lambda Lambda^+) (J M^-1 h - Jdot nu - J M^-1 J^T f)|`: how far eq:torques is from
/// being solvable for `f` (zero: some torque produces `f`).
fn inconsistency(map: &TorqueMap, f: &DVector<f64>) -> f64 {
    let lambda = map.lambda_t().transpose();
    let rhs = map.task_bias() - map.contact_schur() * f;
    let pinv = lambda.clone().pseudo_inverse(1e-9).unwrap();
    (&rhs - &lambda * (pinv * &rhs)).norm()
}

#[test]
fn the_equalities_keep_the_wrenches_to_those_the_joints_produce() {
    let model = model("mini_biped.urdf");
    let (hip, knee, ankle) = (-0.409, 0.835, -0.426);
    let joints = [0.0, hip, 0.0, knee, ankle, 0.0, hip, 0.0, knee, ankle, 0.0];
    let (map, momentum_map) = standing_terms(&model, &joints);
    let mut redundant =
        RedundantContacts::detect(map.lambda_t(), map.contact_schur(), &momentum_map)
            .expect("legs of 5 joints: Lambda has rank 10, J rank 11");
    assert_eq!(
        redundant.n_rows(),
        6,
        "5 momentum directions and 1 consistency row"
    );
    // The weight on the feet and a momentum rate with every component.
    let weight = model.total_mass() * 9.81;
    let target = DVector::from_column_slice(&[1.0, -2.0, weight, 0.3, -0.2, 0.5]);
    redundant.update(
        map.lambda_t(),
        map.contact_schur(),
        map.task_bias(),
        &momentum_map,
        &target,
    );
    let pinv = |m: &DMatrix<f64>| m.clone().pseudo_inverse(1e-12).unwrap();
    let f = pinv(&redundant.equality) * &redundant.target;
    let paper = pinv(&momentum_map) * &target;
    // The size of eq:torques' right-hand side: J M^-1 h (the weight) and J M^-1 J^T f.
    let scale = map.task_bias().norm();
    let residual = (&redundant.equality * &f - &redundant.target).norm();
    assert!(residual < 1e-9 * redundant.target.norm(), "{residual}");
    let (ours, papers) = (inconsistency(&map, &f), inconsistency(&map, &paper));
    // Measured: 3e-13 (the equalities) and 2.9 (A f = b) of a right-hand side of 13.9.
    assert!(ours < 1e-9 * scale, "{ours}");
    assert!(papers > 1e-2 * scale, "{papers}");
    // The momentum rate follows the target but in one direction (mostly the yaw moment).
    let miss = &momentum_map * &f - &target;
    let yaw = Vector3::new(miss[3], miss[4], miss[5]).normalize().z.abs();
    assert!(yaw > 0.9, "{miss}");
}

#[test]
fn legs_of_six_joints_are_not_redundant() {
    let model = model("icub25.urdf");
    let mut joints = vec![0.0; model.n_joints()];
    for (name, angle) in [("hip_pitch", 0.4), ("knee", -0.8), ("ankle_pitch", 0.4)] {
        for side in ["l_", "r_"] {
            let joint = model
                .joint_names
                .iter()
                .position(|j| *j == format!("{side}{name}"));
            joints[joint.unwrap()] = angle;
        }
    }
    let (map, momentum_map) = standing_terms(&model, &joints);
    assert!(
        RedundantContacts::detect(map.lambda_t(), map.contact_schur(), &momentum_map).is_none()
    );
}
