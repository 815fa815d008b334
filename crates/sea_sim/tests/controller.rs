//! Controller checks on the iCub: static consistency with the plant, QP constraints, Lemma 1.

use crate::support;

use sea_ctrl::qp::QpCounters;
use sea_sim::closed_loop::build;
use sea_sim::scenario::Scenario;
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
        let mut pd = sea_plant::PlantData::new(&setup.plant);
        sea_plant::evaluate(
            &setup.plant,
            &mut pd.workspace,
            &setup.x0,
            &out.input,
            &mut pd.outputs,
        )
        .unwrap();
        let nudot = pd.outputs.xdot.rows(layout.nv, layout.nv);
        let wrench_error = (&pd.outputs.contact_wrench - &out.wrenches).amax();
        println!(
            "{contacts}: qp {:?}, |nudot| {:.3e}, wrench error {:.3e}",
            out.qp_status,
            nudot.amax(),
            wrench_error
        );
        println!(
            "  qp f {:?}\n  plant f {:?}",
            out.wrenches.as_slice(),
            pd.outputs.contact_wrench.as_slice()
        );
        assert!(
            nudot.amax() < 1e-4,
            "joint accelerations at rest: {}",
            nudot.amax()
        );
        assert!(wrench_error < 1e-6 * setup.model.total_mass() * 9.81);
    }
}

fn two_feet(extra: &[(&str, &str)]) -> sea_sim::closed_loop::Setup {
    let mut overrides = support::TWO_FEET.to_vec();
    overrides.extend_from_slice(extra);
    build(&scenario(&overrides)).unwrap()
}

#[test]
fn qp_wrenches_satisfy_the_constraints_and_the_momentum_task() {
    // A moving reference and a perturbed velocity, so the task is not trivial.
    let (mut setup, x, reference, s_d) = two_feet_tick(&[], 0.02);
    let layout = setup.plant.layout();
    let out = setup
        .controller
        .compute(&x, &layout, &reference, &s_d)
        .unwrap();
    assert_eq!(out.qp_status, sea_ctrl::qp::QpStatus::Solved);
    let terms = setup
        .controller
        .torque_map(&x, &layout, &reference, &s_d)
        .unwrap();
    let residual = (&terms.momentum_map * &out.wrenches - &terms.momentum_target).amax();
    assert!(
        residual < 1e-5 * terms.momentum_target.amax(),
        "A f - b = {residual}"
    );
    let qp = sea_ctrl::qp::WrenchQp::new(2, 6, &sea_ctrl::qp::ContactConstraints::default());
    let (c, b) = qp.inequalities(&terms.contact_rotations);
    let violation = (&c * &out.wrenches - b).max();
    assert!(violation < 1e-6, "C f - b max {violation}");
    // The command is tau(f) of the reported wrenches.
    let tau = &terms.tau_bias + &terms.sigma * &out.wrenches;
    assert!((tau - nalgebra::DVector::from_vec(out.joint_command.clone())).amax() < 1e-9);
}

/// Paper, Lemma 1: with Lambda of full row rank, the closed-loop joint accelerations do not
/// depend on the wrench redundancy f0 (f = f1 + N_b f0 with A N_b = 0).
#[test]
fn lemma_1_joint_accelerations_do_not_depend_on_the_wrench_redundancy() {
    let mut setup = two_feet(&[
        ("actuators.kind", "rigid"),
        ("controller.kind", "rigid"),
        ("controller.pinv_damping", "1e-12"),
    ]);
    let layout = setup.plant.layout();
    let mut s_d = vec![0.0; setup.model.n_joints()];
    setup.posture.at(0.0, &mut s_d);
    let x = setup.x0.clone();
    let reference = setup.com_reference.sample(0.8);
    let terms = setup
        .controller
        .torque_map(&x, &layout, &reference, &s_d)
        .unwrap();
    let a = &terms.momentum_map;
    let f1 = a.clone().pseudo_inverse(1e-12).unwrap() * &terms.momentum_target;
    let null = nalgebra::DMatrix::identity(12, 12) - a.clone().pseudo_inverse(1e-12).unwrap() * a;
    let f0 = nalgebra::DVector::from_fn(12, |i, _| 5.0 * ((i as f64) * 1.3).cos());
    let f2 = &f1 + &null * f0;
    assert!((a * &f2 - a * &f1).amax() < 1e-8);
    assert!((&f2 - &f1).amax() > 1.0);
    let mut joint_accelerations = Vec::new();
    for f in [&f1, &f2] {
        let tau = &terms.tau_bias + &terms.sigma * f;
        let mut pd = sea_plant::PlantData::new(&setup.plant);
        sea_plant::evaluate(
            &setup.plant,
            &mut pd.workspace,
            &x,
            tau.as_slice(),
            &mut pd.outputs,
        )
        .unwrap();
        joint_accelerations.push(
            pd.outputs
                .xdot
                .rows(layout.nv + 6, setup.model.n_joints())
                .into_owned(),
        );
    }
    let difference = (&joint_accelerations[0] - &joint_accelerations[1]).amax();
    println!(
        "Lemma 1: |sddot(f1) - sddot(f1 + N f0)| = {difference:.2e}, |sddot| = {:.2e}",
        joint_accelerations[0].amax()
    );
    assert!(difference < 1e-6 * joint_accelerations[0].amax().max(1.0));
}

/// A two-feet tick with a moving reference and velocities perturbed by `velocity` [rad/s].
fn two_feet_tick(
    extra: &[(&str, &str)],
    velocity: f64,
) -> (
    sea_sim::closed_loop::Setup,
    Vec<f64>,
    sea_ctrl::references::ComSample,
    Vec<f64>,
) {
    let setup = two_feet(extra);
    let layout = setup.plant.layout();
    let mut s_d = vec![0.0; setup.model.n_joints()];
    setup.posture.at(0.0, &mut s_d);
    let mut x = setup.x0.clone();
    for (k, v) in x[layout.nu_offset()..layout.nu_offset() + layout.nv]
        .iter_mut()
        .enumerate()
    {
        *v = velocity * ((k as f64) * 0.7).sin();
    }
    let reference = setup.com_reference.sample(1.3);
    (setup, x, reference, s_d)
}

/// When no inequality binds, the minimiser without inequalities (accepted without calling
/// Clarabel) is the QP's optimum: Clarabel, forced, finds the same wrenches.
#[test]
fn skipping_clarabel_when_no_constraint_binds_gives_clarabel_s_optimum() {
    let mut wrenches = Vec::new();
    let skipped = QpCounters {
        unconstrained: 1,
        ..Default::default()
    };
    let by_clarabel = QpCounters {
        clarabel: 1,
        ..Default::default()
    };
    for (unconstrained_first, solves) in [("true", skipped), ("false", by_clarabel)] {
        let (mut setup, x, reference, s_d) = two_feet_tick(
            &[
                ("controller.qp_unconstrained_first", unconstrained_first),
                ("controller.qp_solver", "\"clarabel\""),
                ("reference.com_amplitude", "0.005"),
            ],
            0.002,
        );
        let layout = setup.plant.layout();
        let out = setup
            .controller
            .compute(&x, &layout, &reference, &s_d)
            .unwrap();
        assert_eq!(out.qp_status, sea_ctrl::qp::QpStatus::Solved);
        assert_eq!(setup.controller.qp_solves(), solves);
        wrenches.push(out.wrenches);
    }
    let difference = (&wrenches[0] - &wrenches[1]).amax();
    println!(
        "|f_skip - f_clarabel| = {difference:.2e}, |f| = {:.1}",
        wrenches[0].amax()
    );
    assert!(difference < 1e-5 * wrenches[0].amax(), "{difference}");
}

/// When a constraint binds (a 2 cm square foot for the centre of pressure), the minimiser
/// without inequalities violates it, Clarabel is called, and its wrenches satisfy it.
#[test]
fn a_binding_constraint_goes_to_clarabel() {
    let (mut setup, x, reference, s_d) = two_feet_tick(
        &[
            ("controller.contact.foot_x", "[-0.01, 0.01]"),
            ("controller.contact.foot_y", "[-0.01, 0.01]"),
            ("controller.qp_solver", "\"clarabel\""),
        ],
        0.002,
    );
    let layout = setup.plant.layout();
    let out = setup
        .controller
        .compute(&x, &layout, &reference, &s_d)
        .unwrap();
    assert_eq!(out.qp_status, sea_ctrl::qp::QpStatus::Solved);
    let by_clarabel = QpCounters {
        clarabel: 1,
        ..Default::default()
    };
    assert_eq!(setup.controller.qp_solves(), by_clarabel);
    let terms = setup
        .controller
        .torque_map(&x, &layout, &reference, &s_d)
        .unwrap();
    let qp = sea_ctrl::qp::WrenchQp::new(2, 6, &setup.controller.settings().constraints);
    let (c, b) = qp.inequalities(&terms.contact_rotations);
    let violation = (&c * &out.wrenches - b).max();
    assert!(violation < 1e-6, "C f - b max {violation}");
}
