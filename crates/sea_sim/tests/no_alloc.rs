//! The hot paths of one closed-loop tick allocate nothing after a warm-up call
//! (docs/explanation/architecture.md#rules: no allocation on per-tick or per-step paths): the plant's
//! right-hand side (`sea_plant::evaluate`), one step of each integrator, the torque map and the
//! controller tick, on the SEA iCub of `scenarios/paper/tracking.toml`. The counting global
//! allocator shared with sea_dyn's test (`crates/sea_dyn/tests/counting/mod.rs`, per thread,
//! so the harness's other test threads do not interfere) counts the allocations of the call
//! after the warm-up, made at a different state.

#[path = "../../sea_dyn/tests/counting/mod.rs"]
mod counting;
mod support;

use counting::allocations;
use nalgebra::DMatrix;
use sea_ctrl::feedback::FeedbackLaw;
use sea_ctrl::qp::QpCounters;
use sea_ctrl::torque_map::{PosturalTask, TorqueMap};
use sea_dyn::sample::Lcg;
use sea_dyn::Data;
use sea_plant::{evaluate, step, Method, MotorInput, PlantData};
use sea_sim::scenario::{build, Scenario, Setup};
use std::path::Path;

/// The paper's tracking scenario with `overrides`.
fn setup(overrides: &[(&str, &str)]) -> Setup {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/paper/tracking.toml");
    let overrides: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    build(&Scenario::from_file(&path, &overrides).unwrap()).unwrap()
}

/// The SEA iCub on both feet (SEA controller, motor velocity loop).
fn two_feet(extra: &[(&str, &str)]) -> Setup {
    let mut overrides = support::TWO_FEET.to_vec();
    overrides.extend_from_slice(extra);
    setup(&overrides)
}

/// `x0` with base and joint velocities and motor velocities perturbed by up to `size`.
fn perturbed(setup: &Setup, size: f64, rng: &mut Lcg) -> Vec<f64> {
    let layout = setup.plant.layout();
    let mut x = setup.x0.clone();
    let velocities = layout.nu_offset()..layout.nx();
    for v in &mut x[velocities] {
        *v += size * rng.next_signed();
    }
    x
}

#[test]
fn the_counting_allocator_is_active() {
    assert!(allocations(|| vec![1u8; 16]) >= 1);
}

#[test]
fn plant_evaluate_and_one_step_of_each_method_allocate_nothing() {
    let welded = two_feet(&[]);
    let on_ground = two_feet(&[("plant.contact_model", "unilateral")]);
    for (contacts, base) in [("welded", &welded), ("on the ground", &on_ground)] {
        let offenders = plant_allocations(base);
        assert!(
            offenders.is_empty(),
            "{contacts}: allocations: {offenders:?}"
        );
    }
}

/// `(what, allocations)` of every plant evaluation and step of `base`'s plant that allocates
/// (after a warm-up call), driven by the motor velocity loop and by torques.
fn plant_allocations(base: &Setup) -> Vec<(String, usize)> {
    let mut torque_driven = base.plant.clone();
    torque_driven.motor_input = MotorInput::Torque;
    let mut rng = Lcg::new(3);
    let states = [
        perturbed(base, 0.01, &mut rng),
        perturbed(base, 0.01, &mut rng),
    ];
    let n = base.model.n_joints();
    let u: Vec<f64> = (0..n).map(|_| rng.next_signed()).collect();
    let mut offenders = Vec::new();
    for (input, plant) in [("velocity loop", &base.plant), ("torque", &torque_driven)] {
        let mut pd = PlantData::new(plant);
        let mut x_next = states[0].clone();
        let mut count = |what: String, f: &mut dyn FnMut(&[f64]) -> bool| {
            assert!(f(&states[0]), "{what}: warm-up call failed");
            let mut ok = false;
            let counted = allocations(|| ok = f(&states[1]));
            assert!(ok, "{what}: counted call failed");
            if counted > 0 {
                offenders.push((what, counted));
            }
        };
        count(format!("evaluate ({input})"), &mut |x| {
            evaluate(plant, &mut pd.workspace, x, &u, &mut pd.outputs).is_ok()
        });
        for method in [Method::Ros2, Method::LinearlyImplicitEuler, Method::Rk4] {
            count(format!("step {method:?} ({input})"), &mut |x| {
                step(plant, &mut pd, x, &u, 1e-3, method, &mut x_next).is_ok()
            });
        }
    }
    offenders
}

#[test]
fn torque_map_allocates_nothing() {
    let setup = two_feet(&[]);
    let model = &setup.model;
    let (nv, n) = (model.nv(), model.n_joints());
    let contacts = [
        model.frame_id("l_sole").unwrap(),
        model.frame_id("r_sole").unwrap(),
    ];
    let mut map = TorqueMap::new(model, 6 * contacts.len());
    map.diagonal[6..].fill(0.1);
    let mut data = Data::new(model);
    let mut rng = Lcg::new(9);
    let stiffness = vec![10.0; n];
    let damping = vec![6.0; n];
    let mut counts = Vec::new();
    for _ in 0..2 {
        // Inputs at a new state, filled outside the counted call.
        let x = perturbed(&setup, 0.05, &mut rng);
        let layout = setup.plant.layout();
        let (q, nu) = (layout.q(&x), layout.nu(&x));
        map.bias
            .copy_from(sea_dyn::bias_forces(model, &mut data, q, nu));
        for (c, &frame) in contacts.iter().enumerate() {
            sea_dyn::jacobian::frame_jacobian_from_kinematics(model, &mut data, frame);
            map.jacobian
                .rows_mut(6 * c, 6)
                .copy_from(&data.frame_jacobian);
            let bias = sea_dyn::jacobian::frame_bias_acceleration(model, &mut data, frame);
            map.jdot_nu.rows_mut(6 * c, 6).copy_from(&bias);
        }
        let mass_matrix: DMatrix<f64> = sea_dyn::crba_from_kinematics(model, &mut data).clone();
        let error: Vec<f64> = (0..n).map(|_| 0.1 * rng.next_signed()).collect();
        let posture = PosturalTask {
            error: &error,
            velocity: &nu[6..],
            stiffness: &stiffness,
            damping: &damping,
        };
        counts.push(allocations(|| {
            map.compute(&mass_matrix, &posture, 1e-3).unwrap();
        }));
        assert_eq!(map.tau_bias.len(), n);
        assert_eq!(map.sigma.ncols(), 12);
        assert_eq!(mass_matrix.nrows(), nv);
    }
    assert_eq!(
        counts[1], 0,
        "TorqueMap::compute allocates after warm-up: {counts:?}"
    );
}

/// Allocations of `ticks` controller ticks after one warm-up tick, at perturbed states; also
/// returns the controller's QP solves by path during the counted ticks.
fn tick_allocations(setup: &mut Setup, ticks: usize) -> (Vec<usize>, QpCounters) {
    let layout = setup.plant.layout();
    let mut s_desired = vec![0.0; setup.model.n_joints()];
    setup.posture.at(0.0, &mut s_desired);
    let reference = setup.com_reference.sample(1.3);
    let mut out = setup.controller.new_output();
    let mut rng = Lcg::new(17);
    let states: Vec<Vec<f64>> = (0..=ticks)
        .map(|_| perturbed(setup, 0.01, &mut rng))
        .collect();
    setup
        .controller
        .compute_into(&states[0], &layout, &reference, &s_desired, &mut out)
        .unwrap();
    let before = setup.controller.qp_solves();
    let counts = states[1..]
        .iter()
        .map(|x| {
            allocations(|| {
                setup
                    .controller
                    .compute_into(x, &layout, &reference, &s_desired, &mut out)
                    .unwrap()
            })
        })
        .collect();
    let after = setup.controller.qp_solves();
    let solves = QpCounters {
        unconstrained: after.unconstrained - before.unconstrained,
        active_set: after.active_set - before.active_set,
        clarabel: after.clarabel - before.clarabel,
        ..QpCounters::default()
    };
    (counts, solves)
}

/// The QP path every counted tick must take.
#[derive(Clone, Copy, Debug)]
enum QpPath {
    /// The minimiser without inequalities is feasible: no solver runs.
    Unconstrained,
    /// The active-set solver.
    ActiveSet,
    /// Clarabel.
    Clarabel,
}

impl QpPath {
    /// The solve counts of `ticks` ticks all on this path.
    fn counts(self, ticks: usize) -> QpCounters {
        let mut counts = QpCounters::default();
        match self {
            QpPath::Unconstrained => counts.unconstrained = ticks,
            QpPath::ActiveSet => counts.active_set = ticks,
            QpPath::Clarabel => counts.clarabel = ticks,
        }
        counts
    }
}

/// Allocations of one `DefaultSolver::solve` after a warm-up solve, on a one-variable QP
/// (`min x^2 - x` s.t. `x <= 0.25`, the bound active). clarabel 0.11.1 resets its "solve" timer
/// at every solve, which drops the nested timer maps; re-inserting the "IP iteration" sub-timers
/// allocates (src/timers/timers.rs, `SubTimersMap::start_subtimer`). This is Clarabel's own
/// allocation, independent of the problem, and our API cannot avoid it.
fn bare_clarabel_allocations_per_solve() -> usize {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SupportedConeT};
    let p = CscMatrix::new(1, 1, vec![0, 1], vec![0], vec![2.0]);
    let a = CscMatrix::new(1, 1, vec![0, 1], vec![0], vec![1.0]);
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .build()
        .unwrap();
    let cones = [SupportedConeT::NonnegativeConeT(1)];
    let mut solver = DefaultSolver::new(&p, &[-1.0], &a, &[0.25], &cones, settings).unwrap();
    solver.solve();
    let counts: Vec<usize> = (0..3).map(|_| allocations(|| solver.solve())).collect();
    assert!(
        counts.iter().all(|&c| c == counts[0]),
        "a bare Clarabel solve allocates a varying amount: {counts:?}"
    );
    counts[0]
}

/// Ticks of each case: `(name, overrides)`; returns the cases whose ticks allocate more than
/// `allowed_per_tick`. Panics if a case does not take the expected QP `path` on every tick:
/// the test would then not measure what it claims.
fn allocating_ticks(
    cases: &[(&str, Vec<(&str, &str)>)],
    path: QpPath,
    allowed_per_tick: usize,
) -> Vec<String> {
    const TICKS: usize = 5;
    let mut offenders = Vec::new();
    for (name, overrides) in cases {
        let mut setup = two_feet(overrides);
        let (counts, solves) = tick_allocations(&mut setup, TICKS);
        println!("{name}: allocations per tick {counts:?}, QP solves {solves:?}");
        assert_eq!(
            solves,
            path.counts(TICKS),
            "{name}: not the intended QP path"
        );
        if counts.iter().any(|&c| c > allowed_per_tick) {
            offenders.push(format!("{name}: {counts:?}"));
        }
    }
    offenders
}

#[test]
fn controller_tick_allocates_nothing_when_the_qp_skips_clarabel() {
    // One foot: the QP's minimiser without inequalities is feasible at these states.
    let one_foot = [
        ("robot.contacts", "[\"l_sole\"]"),
        ("robot.initial_posture", "left_stance"),
    ];
    let rigid = [("actuators.kind", "rigid"), ("controller.kind", "rigid")];
    let cases = [
        ("SEA, one foot", one_foot.to_vec()),
        ("rigid, one foot", [one_foot, rigid].concat()),
    ];
    let offenders = allocating_ticks(&cases, QpPath::Unconstrained, 0);
    assert!(
        offenders.is_empty(),
        "controller ticks allocate: {offenders:?}"
    );
}

#[test]
fn controller_tick_allocates_nothing_beyond_clarabels_own_when_clarabel_solves_the_qp() {
    // Two feet with Clarabel forced: the tick may allocate exactly what a bare Clarabel solve
    // allocates (its timers, see `bare_clarabel_allocations_per_solve`), nothing of ours.
    let clarabel_own = bare_clarabel_allocations_per_solve();
    println!("a bare Clarabel solve allocates {clarabel_own} time(s)");
    let forced = ("controller.qp_unconstrained_first", "false");
    let clarabel = ("controller.qp_solver", "\"clarabel\"");
    let cases = [
        ("SEA, two feet", vec![forced, clarabel]),
        (
            "rigid, two feet",
            vec![
                forced,
                clarabel,
                ("actuators.kind", "rigid"),
                ("controller.kind", "rigid"),
            ],
        ),
    ];
    let offenders = allocating_ticks(&cases, QpPath::Clarabel, clarabel_own);
    assert!(
        offenders.is_empty(),
        "controller ticks allocate: {offenders:?}"
    );
}

#[test]
fn controller_tick_allocates_nothing_when_the_active_set_solves_the_qp() {
    // The QP solver forced on every tick with the default solver (the active set): two feet
    // (six equalities), and one foot with a 1.2 cm square sole, where the centre-of-pressure
    // rows bind (tests/qp_agreement.rs counts such ticks), so the active set's add and drop
    // paths are part of what is counted.
    let forced = ("controller.qp_unconstrained_first", "false");
    let one_foot_small_sole = [
        forced,
        ("robot.contacts", "[\"l_sole\"]"),
        ("robot.initial_posture", "left_stance"),
        ("controller.contact.foot_x", "[-0.006, 0.006]"),
        ("controller.contact.foot_y", "[-0.006, 0.006]"),
    ];
    let rigid = [("actuators.kind", "rigid"), ("controller.kind", "rigid")];
    let cases = [
        ("SEA, two feet", vec![forced]),
        ("rigid, two feet", [&[forced][..], &rigid].concat()),
        ("SEA, one foot, 1.2 cm sole", one_foot_small_sole.to_vec()),
    ];
    let offenders = allocating_ticks(&cases, QpPath::ActiveSet, 0);
    assert!(
        offenders.is_empty(),
        "controller ticks allocate: {offenders:?}"
    );
}

#[test]
fn the_feedback_law_allocates_nothing_after_a_warm_up() {
    // The closed loop's law (`sea_ctrl::feedback`): references, the controller's tick and the
    // tracking errors, into the held observation (`tick`) and into a caller's (`observe`);
    // two feet, the QP solved by the active set at every tick.
    let mut setup = two_feet(&[("controller.qp_unconstrained_first", "false")]);
    let mut rng = Lcg::new(23);
    let states: Vec<Vec<f64>> = (0..3).map(|_| perturbed(&setup, 0.01, &mut rng)).collect();
    let layout = setup.plant.layout();
    let (com_reference, posture) = (setup.com_reference.clone(), setup.posture.clone());
    let mut law = FeedbackLaw::new(&mut setup.controller, com_reference, posture, layout);
    let mut stage = law.new_observation();
    law.tick(1.0, &states[0]).unwrap();
    law.observe(1.0, &states[0], &mut stage).unwrap();
    let ticked = allocations(|| {
        law.tick(1.2, &states[1]).unwrap();
    });
    let observed = allocations(|| law.observe(1.3, &states[2], &mut stage).unwrap());
    assert_eq!((ticked, observed), (0, 0), "allocations of tick, observe");
    assert_eq!(law.last().time, 1.2);
    assert_eq!(stage.time, 1.3);
}

/// The joint torque loops of `multi_rate` (the inner tick on the hot path, 10 per whole-body
/// tick, and the hold after each whole-body tick) allocate nothing.
#[test]
fn joint_torque_loop_hold_and_tick_allocate_nothing() {
    let mut setup = setup(&[
        ("controller.sampling", "multi_rate"),
        ("controller.kind", "rigid"),
        ("controller.joint_stiffness", "10"),
    ]);
    let layout = setup.plant.layout();
    let mut rng = Lcg::new(7);
    let states: Vec<Vec<f64>> = (0..3).map(|_| perturbed(&setup, 0.01, &mut rng)).collect();
    let s_desired = setup.posture.initial.clone();
    let output = setup
        .controller
        .compute(
            &states[0],
            &layout,
            &setup.com_reference.sample(0.0),
            &s_desired,
        )
        .unwrap();
    let mut joint_loop = sea_ctrl::joint_loop::JointTorqueLoop::new(&setup.controller, Some(125.0))
        .with_joint_stiffness(10.0);
    let counts: Vec<usize> = states
        .iter()
        .map(|x| {
            allocations(|| {
                joint_loop.hold(&output, &layout, x, &s_desired);
                joint_loop.tick(&layout, x);
            })
        })
        .collect();
    assert_eq!(counts[1..], [0, 0], "{counts:?}");
    assert!(joint_loop.input().iter().all(|v| v.is_finite()));
}
