//! Controller checks on the iCub: static consistency with the plant, QP constraints, Lemma 1.

use sea_ctrl::closed_loop::build;
use sea_ctrl::scenario::Scenario;
use std::path::Path;

fn scenario(extra: &[(&str, &str)]) -> Scenario {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper");
    let overrides: Vec<(String, String)> = extra
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_file(&dir.join("tracking.toml"), &overrides).unwrap()
}

#[test]
fn rigid_controller_at_rest_keeps_the_rigid_robot_at_rest() {
    for contacts in ["[\"l_sole\"]", "[\"l_sole\", \"r_sole\"]"] {
        let posture = if contacts.contains("r_sole") {
            "two_feet"
        } else {
            "left_stance"
        };
        let s = scenario(&[
            ("actuators.kind", "rigid"),
            ("controller.kind", "rigid"),
            ("reference.com_amplitude", "0"),
            ("reference.com_origin", "initial"),
            ("robot.contacts", contacts),
            ("robot.initial_posture", posture),
            // Without the Hessian regulariser the QP's wrenches balance gravity exactly.
            ("controller.qp_regularization", "1e-12"),
        ]);
        let mut setup = build(&s).unwrap();
        let layout = setup.plant.layout();
        let reference = setup.com_reference.sample(0.0);
        let mut s_d = vec![0.0; setup.model.n_joints()];
        setup.posture.at(0.0, &mut s_d);
        let out = setup
            .controller
            .compute(&setup.x0, &layout, &reference, &s_d)
            .unwrap();
        let mut pd = sea_dyn::PlantData::new(&setup.plant);
        sea_dyn::evaluate(&setup.plant, &mut pd, &setup.x0, &out.input).unwrap();
        let nudot = pd.xdot.rows(layout.nv, layout.nv);
        let wrench_error = (&pd.contact_wrench - &out.wrenches).amax();
        println!(
            "{contacts}: qp {:?}, |nudot| {:.3e}, wrench error {:.3e}",
            out.qp_status,
            nudot.amax(),
            wrench_error
        );
        println!(
            "  qp f {:?}\n  plant f {:?}",
            out.wrenches.as_slice(),
            pd.contact_wrench.as_slice()
        );
        assert!(
            nudot.amax() < 1e-4,
            "joint accelerations at rest: {}",
            nudot.amax()
        );
        assert!(wrench_error < 1e-6 * setup.model.total_mass() * 9.81);
    }
}
