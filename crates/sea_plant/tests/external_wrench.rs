//! External wrenches (pushes) enter the dynamics as `J^T w`: checked against the centroidal
//! momentum balance written from its definition, not against the Jacobian that computes them.
//! On the free-floating robot without gravity, at rest, a wrench `[f; n]` (world axes) at a
//! link's origin `p` changes the centroidal momentum at the rate
//! `Hdot = A_G(q) nudot = [f; (p - p_com) x f + n]`, whatever the internal joint torques.

use crate::support;

use nalgebra::Vector3;
use sea_dyn::centroidal::{centroidal_momentum_matrix, com};
use sea_dyn::kinematics::{forward_kinematics, frame_placement};
use sea_dyn::sample::Lcg;
use sea_dyn::Data;
use sea_plant::{evaluate, ExternalWrench, PlantOutputs, Workspace};
use support::*;

#[test]
fn a_link_wrench_changes_the_centroidal_momentum_by_newton_and_euler() {
    let model = shipped("icub25.urdf");
    let plant = weightless(
        model.clone(),
        all_elastic(&model, sea(350.0, 1.0, 1e-5, 0.01)),
    );
    let mut rng = Lcg::new(19);
    let q = random_q(&model, 0.5, &mut rng);
    let x = random_state(&plant, &q, 0.0, 0.01, &mut rng);
    let u = vec![0.0; model.n_joints()];
    let layout = plant.layout();
    for link in ["root_link", "l_hand", "r_foot"] {
        let frame = model.frame_id(link).unwrap();
        let wrench = [30.0, -20.0, 10.0, 1.0, -2.0, 0.5];
        let mut ws = Workspace::new(&plant);
        ws.external.push(ExternalWrench {
            frame,
            wrench,
            active: true,
        });
        let mut out = PlantOutputs::new(&plant);
        evaluate(&plant, &mut ws, &x, &u, &mut out).unwrap();
        let nudot = nalgebra::DVector::from_column_slice(layout.tangent().dnu(out.xdot.as_slice()));
        let mut data = Data::new(&model);
        let hdot = centroidal_momentum_matrix(&model, &mut data, &q) * nudot;
        forward_kinematics(&model, &mut data, &q);
        let p = frame_placement(&model, &data, frame).translation;
        let p_com = com(&model, &mut data, &q);
        let f = Vector3::new(wrench[0], wrench[1], wrench[2]);
        let n = Vector3::new(wrench[3], wrench[4], wrench[5]);
        let expected_moment = (p - p_com).cross(&f) + n;
        for k in 0..3 {
            assert!((hdot[k] - f[k]).abs() < 1e-8, "{link}: {hdot} vs f {f}");
            let error = (hdot[3 + k] - expected_moment[k]).abs();
            assert!(error < 1e-8, "{link}: {hdot} vs moment {expected_moment}");
        }
        // Switched off, it does nothing: the momentum of the internal torques is constant.
        ws.external[0].active = false;
        evaluate(&plant, &mut ws, &x, &u, &mut out).unwrap();
        let nudot = nalgebra::DVector::from_column_slice(layout.tangent().dnu(out.xdot.as_slice()));
        let hdot = centroidal_momentum_matrix(&model, &mut data, &q) * nudot;
        assert!(hdot.norm() < 1e-8, "{link}: {hdot}");
    }
}
