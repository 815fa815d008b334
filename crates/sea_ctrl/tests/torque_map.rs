//! The torque map (tree-sparse solves, N applied to vectors) against the paper's formulas
//! evaluated densely: `Lambda = J M^-1 B`, `Lambda^+ = Lambda^T (Lambda Lambda^T + d^2 I)^-1`,
//! `N = I - Lambda^+ Lambda`, `Mbar = M_j - M_jb M_b^-1 M_bj`, ... on the iCub at random states.

use nalgebra::{DMatrix, DVector};
use sea_ctrl::torque_map::{PosturalTask, TorqueMap};
use sea_dyn::sample::{random_configuration, random_velocity, Lcg};
use sea_dyn::{Data, LoadOptions, Model};
use std::path::Path;

fn icub() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../urdf/icub25.urdf");
    Model::from_urdf_file(&path, &LoadOptions::default()).unwrap()
}

/// `tau_bias` and `Sigma` by the dense formulas.
#[allow(clippy::too_many_arguments)]
fn dense_reference(
    m: &DMatrix<f64>,
    h: &DVector<f64>,
    j: &DMatrix<f64>,
    jdot_nu: &DVector<f64>,
    posture: &PosturalTask,
    d: f64,
) -> (DVector<f64>, DMatrix<f64>) {
    let (k, nv) = j.shape();
    let n = nv - 6;
    let m_inv = m.clone().try_inverse().unwrap();
    let lambda = j * m_inv.columns(6, n);
    let gram = &lambda * lambda.transpose() + DMatrix::identity(k, k) * d * d;
    let pinv = lambda.transpose() * gram.try_inverse().unwrap();
    let null = DMatrix::identity(n, n) - &pinv * &lambda;
    let m_b_inv = m.view((0, 0), (6, 6)).into_owned().try_inverse().unwrap();
    let m_jb = m.view((6, 0), (n, 6));
    let mbar = m.view((6, 6), (n, n)) - m_jb * &m_b_inv * m.view((0, 6), (6, n));
    let jbar_t = j.columns(6, n).transpose() - m_jb * &m_b_inv * j.columns(0, 6).transpose();
    let hbar = h.rows(6, n) - m_jb * &m_b_inv * h.rows(0, 6);
    let stiff = &null * &mbar * DVector::from_column_slice(posture.error);
    let damp = &null * &mbar * DVector::from_column_slice(posture.velocity);
    let u0 = DVector::from_fn(n, |i, _| {
        -posture.stiffness[i] * stiff[i] - posture.damping[i] * damp[i]
    });
    let tau_bias = &pinv * (j * &m_inv * h - jdot_nu) + &null * (hbar + u0);
    let sigma = -(&pinv * j * &m_inv * j.transpose() + &null * jbar_t);
    (tau_bias, sigma)
}

#[test]
fn torque_map_matches_the_dense_formulas() {
    let model = icub();
    let (nv, n) = (model.nv(), model.n_joints());
    let frames = [
        model.frame_id("l_sole").unwrap(),
        model.frame_id("r_sole").unwrap(),
    ];
    let mut rng = Lcg::new(3);
    let mut data = Data::new(&model);
    for trial in 0..5 {
        let contacts = &frames[..1 + trial % 2];
        let k = 6 * contacts.len();
        let q = random_configuration(&model, &mut rng);
        let nu = random_velocity(&model, &mut rng);
        let mut map = TorqueMap::new(&model, k);
        map.bias
            .copy_from(sea_dyn::bias_forces(&model, &mut data, &q, &nu));
        for (i, value) in map.diagonal.iter_mut().enumerate().skip(6) {
            *value = 0.05 + 0.01 * i as f64;
        }
        for (c, &frame) in contacts.iter().enumerate() {
            sea_dyn::jacobian::frame_jacobian_from_kinematics(&model, &mut data, frame);
            map.jacobian
                .rows_mut(6 * c, 6)
                .copy_from(&data.frame_jacobian);
            let bias = sea_dyn::jacobian::frame_bias_acceleration(&model, &mut data, frame);
            map.jdot_nu.rows_mut(6 * c, 6).copy_from(&bias);
        }
        let mass_matrix = sea_dyn::crba_from_kinematics(&model, &mut data).clone();
        let error: Vec<f64> = (0..n).map(|_| 0.1 * rng.next_signed()).collect();
        let stiffness: Vec<f64> = (0..n).map(|_| 10.0 + 5.0 * rng.next_signed()).collect();
        let damping: Vec<f64> = stiffness.iter().map(|s| 2.0 * s.sqrt()).collect();
        let posture = PosturalTask {
            error: &error,
            velocity: &nu[6..],
            stiffness: &stiffness,
            damping: &damping,
        };
        let pinv_damping = 5e-4;
        map.compute(&mass_matrix, &posture, pinv_damping).unwrap();
        let regularised =
            &mass_matrix + DMatrix::from_diagonal(&DVector::from_vec(map.diagonal.clone()));
        let (tau_bias, sigma) = dense_reference(
            &regularised,
            &map.bias,
            &map.jacobian,
            &map.jdot_nu,
            &posture,
            pinv_damping,
        );
        let tau_error = (&map.tau_bias - &tau_bias).amax() / tau_bias.amax();
        let sigma_error = (&map.sigma - &sigma).amax() / sigma.amax();
        println!(
            "trial {trial} (k = {k}, nv = {nv}): tau_bias {tau_error:.1e}, Sigma {sigma_error:.1e}"
        );
        assert!(tau_error < 1e-9, "tau_bias relative error {tau_error}");
        assert!(sigma_error < 1e-9, "Sigma relative error {sigma_error}");
    }
}
