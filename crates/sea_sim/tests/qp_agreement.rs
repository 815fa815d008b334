//! The active-set QP solver (`sea_ctrl::qp::active_set`, Goldfarb-Idnani) agrees with Clarabel,
//! the reference (issue 12): on every tick of the paper's scenarios (shortened), with the QP
//! solver forced on every tick (`controller.qp_unconstrained_first = false`) and the
//! controller's cross-check on (Clarabel solves the same problem; `QpAgreement`), its wrenches
//! are Clarabel's within Clarabel's accuracy and satisfy the contact inequalities and the
//! momentum equalities to rounding. Cases where inequalities bind (small feet, a high minimum
//! normal force, low friction) make sure active constraints are exercised; and a property
//! test compares the two on random well-posed wrench QPs of the controller's shape.

use crate::support;

use nalgebra::{DMatrix, DVector, Matrix3, Rotation3, Vector3};
use proptest::prelude::*;
use sea_ctrl::qp::{
    momentum_tracking_objective, torque_norm_objective, ContactConstraints, QpAgreement,
    QpCounters, QpSolver, QpStatus, WrenchQp, CLARABEL_TOLERANCE,
};
use sea_dyn::sample::Lcg;
use sea_sim::closed_loop::{build, run_setup_with_sinks};
use sea_sim::scenario::icub;
use sea_sim::scenario::Scenario;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// The bound on `|f_active - f_clarabel|_2 / sqrt(1 + |J_clarabel|)` (`J` the QP objective,
/// `QpAgreement::max_scaled_difference`) that Clarabel's tolerance implies: it stops at a
/// duality gap of `eps (1 + |J|)` (`eps` = `CLARABEL_TOLERANCE`, absolute and relative), and
/// the objective's Hessian is at least `lambda_min = 2 reg` (the regulariser, `P = 2 (S^T S +
/// reg I)`), so a feasible point `eps (1 + |J|)` above the optimum is within
/// `sqrt(2 eps (1 + |J|) / lambda_min)` of it (strong convexity and the optimum's first-order
/// condition). The active set is exact to rounding: the differences measure Clarabel's error.
/// Twice the bound, as Clarabel's point is feasible only to `eps` too.
fn scaled_difference_bound(regularization: f64) -> f64 {
    2.0 * (2.0 * CLARABEL_TOLERANCE / (2.0 * regularization)).sqrt()
}

/// The active set's KKT stationarity residual (relative, `QpAgreement::
/// max_stationarity_residual`): rounding only. With its feasibility (below) and
/// complementarity (by construction) it certifies the active set's optimum independently of
/// Clarabel, whose objective can lie below the optimum as its point is feasible only to
/// `eps` (so the objectives are reported, not compared).
const STATIONARITY_TOLERANCE: f64 = 1e-9;

/// Constraint violations of the active set's wrenches relative to the largest force (or the
/// largest equality target): rounding only (its own feasibility tolerance is 1e-10).
const VIOLATION_TOLERANCE: f64 = 1e-8;

/// Shortened duration of every run [s]: covers the posture steps at 0.5 s and the first
/// seconds of the saturation experiment (springs at rest, the largest transients).
const DURATION_S: &str = "1.2";

/// The figures of one cross-checked run.
struct CrossChecked {
    name: String,
    status: String,
    solves: QpCounters,
    active_set_failures: usize,
    agreement: QpAgreement,
}

/// Runs `scenarios/paper/<file>` with `overrides`, the QP solver on every tick, the default
/// solver (the active set) and the cross-check on.
fn cross_checked(name: &str, file: &str, overrides: &[(&str, &str)]) -> CrossChecked {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/paper")
        .join(file);
    let mut pairs = vec![
        ("simulation.duration_s", DURATION_S),
        ("controller.qp_unconstrained_first", "false"),
        // The solvers' agreement, on the model's bilateral contacts: with a 1.2 cm foot the
        // plant's wrench leaves the sole (a real foot would tip) while the QP's stays on it.
        ("simulation.stop_on_fall", "false"),
    ];
    pairs.extend_from_slice(overrides);
    let pairs: Vec<(String, String)> = pairs
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let scenario = Scenario::from_file(&path, &pairs).unwrap();
    assert_eq!(scenario.controller.tuning.qp_solver, QpSolver::ActiveSet);
    let mut setup = build(&scenario).unwrap();
    setup.controller.set_qp_cross_check(true);
    let cancel = AtomicBool::new(false);
    let summary = run_setup_with_sinks(&scenario, &mut setup, &mut [], &cancel, |_, _| {}).unwrap();
    let checked = CrossChecked {
        name: name.to_string(),
        status: summary.status,
        solves: setup.controller.qp_solves(),
        active_set_failures: setup.controller.qp_active_set_failures().0,
        agreement: setup.controller.qp_agreement().clone(),
    };
    let a = &checked.agreement;
    println!(
        "{name}: {} ticks, {} with active inequalities (at most {}), |df| {:.2e} of |f| {:.1} \
         (scaled {:.2e}, objective excess {:.2e}, KKT {:.2e}), violation {:.2e} (Clarabel {:.2e}), \
         |Af - b| {:.2e} of |b| {:.1}; solves {:?}, active-set failures {}",
        a.ticks,
        a.ticks_with_active_inequalities,
        a.max_active_inequalities,
        a.max_wrench_difference,
        a.max_wrench,
        a.max_scaled_difference,
        a.max_objective_excess,
        a.max_stationarity_residual,
        a.max_inequality_violation,
        a.reference_max_inequality_violation,
        a.max_equality_residual,
        a.max_equality_target,
        checked.solves,
        checked.active_set_failures,
    );
    checked
}

/// What is wrong with a cross-checked run (empty when nothing): not completed, a tick not
/// solved by the active set, or a tick whose wrenches disagree with Clarabel's or violate
/// the constraints.
fn problems(run: &CrossChecked) -> Vec<String> {
    let (a, name) = (&run.agreement, &run.name);
    let mut problems = Vec::new();
    if run.status != "completed" {
        problems.push(format!("{name}: run {}", run.status));
    }
    if run.active_set_failures > 0 || run.solves.unconstrained > 0 || run.solves.clarabel > 0 {
        problems.push(format!(
            "{name}: not every tick solved by the active set: {:?}, {} failures",
            run.solves, run.active_set_failures
        ));
    }
    if a.ticks == 0 || a.ticks != run.solves.active_set || a.reference_failures > 0 {
        problems.push(format!(
            "{name}: {} ticks compared of {} ({} Clarabel failures)",
            a.ticks, run.solves.active_set, a.reference_failures
        ));
    }
    problems.extend(agreement_problems(name, a));
    problems
}

/// What is wrong with the cross-check figures `a` of `name` (empty when nothing): wrenches
/// farther from Clarabel's than its tolerance allows, a KKT residual above rounding, or
/// violated constraints.
fn agreement_problems(name: &str, a: &QpAgreement) -> Vec<String> {
    let mut problems = Vec::new();
    let scale = a.max_wrench.max(1.0);
    let bound = scaled_difference_bound(icub().qp_regularization);
    if a.max_scaled_difference > bound {
        problems.push(format!(
            "{name}: wrenches differ by {:.2e} sqrt(1 + |J|), bound {bound:.2e}",
            a.max_scaled_difference
        ));
    }
    if a.max_stationarity_residual > STATIONARITY_TOLERANCE {
        problems.push(format!(
            "{name}: KKT stationarity residual {:.2e}",
            a.max_stationarity_residual
        ));
    }
    if a.max_inequality_violation > VIOLATION_TOLERANCE * scale {
        problems.push(format!(
            "{name}: inequalities violated by {:.2e}",
            a.max_inequality_violation
        ));
    }
    if a.max_equality_residual > VIOLATION_TOLERANCE * a.max_equality_target.max(1.0) {
        problems.push(format!(
            "{name}: equalities violated by {:.2e}",
            a.max_equality_residual
        ));
    }
    problems
}

#[test]
fn the_active_set_agrees_with_clarabel_on_every_tick_of_the_paper_scenarios() {
    let mut runs: Vec<CrossChecked> = ["tracking", "saturation", "step_sea", "step_rigid"]
        .iter()
        .map(|name| cross_checked(name, &format!("{name}.toml"), &[]))
        .collect();
    runs.push(cross_checked(
        "tracking, two feet",
        "tracking.toml",
        &support::TWO_FEET,
    ));
    let all: Vec<String> = runs.iter().flat_map(problems).collect();
    assert!(all.is_empty(), "{}", all.join("\n"));
}

#[test]
fn the_active_set_agrees_with_clarabel_when_inequalities_bind() {
    // The paper's scenarios never reach the contact limits (the previous test counts no
    // active inequality); here they are tightened until they bind: the minimum normal force
    // of two feet at 160 N of the robot's 324 N (the load shifts between the feet with the
    // CoM), and the centre of pressure of the stance foot in a 1.2 cm square during the
    // posture step and the saturation experiment's spring loading.
    let two_feet = support::TWO_FEET;
    let minimum = [("controller.contact.min_normal_force", "160.0")];
    let small_foot = [
        ("controller.contact.foot_x", "[-0.006, 0.006]"),
        ("controller.contact.foot_y", "[-0.006, 0.006]"),
    ];
    let runs = [
        cross_checked(
            "two feet, 160 N minimum normal force",
            "tracking.toml",
            &[&two_feet[..], &minimum].concat(),
        ),
        cross_checked("step_sea, 1.2 cm foot", "step_sea.toml", &small_foot),
        cross_checked("saturation, 1.2 cm foot", "saturation.toml", &small_foot),
    ];
    let mut all: Vec<String> = runs.iter().flat_map(problems).collect();
    for run in &runs {
        if run.agreement.ticks_with_active_inequalities == 0 {
            all.push(format!("{}: no tick with an active inequality", run.name));
        }
    }
    assert!(all.is_empty(), "{}", all.join("\n"));
}

/// A strictly feasible sole wrench `[F; n]` of `constraints`: normal force in
/// `[min + 20, min + 400]` N, tangential force, torsion and centre of pressure at most half
/// their limits.
fn feasible_sole_wrench(constraints: &ContactConstraints, rng: &mut Lcg) -> [f64; 6] {
    let surface = &constraints.surface;
    let uniform = |rng: &mut Lcg| 0.5 * (rng.next_signed() + 1.0);
    let f_z = constraints.min_normal_force + 20.0 + 380.0 * uniform(rng);
    let inscribed = surface.friction * (std::f64::consts::PI / constraints.facets as f64).cos();
    let angle = std::f64::consts::PI * rng.next_signed();
    let tangential = 0.5 * inscribed * f_z * uniform(rng);
    let centre = |range: [f64; 2], rng: &mut Lcg| {
        let middle = 0.5 * (range[0] + range[1]);
        middle + 0.25 * (range[1] - range[0]) * rng.next_signed()
    };
    let (cop_x, cop_y) = (centre(surface.foot_x, rng), centre(surface.foot_y, rng));
    [
        tangential * angle.cos(),
        tangential * angle.sin(),
        f_z,
        cop_y * f_z,
        -cop_x * f_z,
        0.5 * surface.torsional_friction * f_z * rng.next_signed(),
    ]
}

/// A random wrench QP of the controller's shape from `seed`: sole rotations tilted up to
/// 0.3 rad; two feet: the torque-norm objective of a random `Sigma` (25 x 12) and
/// `tau_bias` under random momentum equalities `A f = b` met by strictly feasible wrenches;
/// one foot: momentum tracking towards a random (often infeasible) target. Returns `(P, c,
/// equality, rotations)`.
type RandomQp = (
    DMatrix<f64>,
    DVector<f64>,
    Option<(DMatrix<f64>, DVector<f64>)>,
    Vec<Matrix3<f64>>,
);

fn random_wrench_qp(seed: u64, two_feet: bool) -> RandomQp {
    let constraints = &ContactConstraints::default();
    let mut rng = Lcg::new(seed);
    let contacts = if two_feet { 2 } else { 1 };
    let k = 6 * contacts;
    let rotations: Vec<Matrix3<f64>> = (0..contacts)
        .map(|_| {
            let axis = Vector3::new(rng.next_signed(), rng.next_signed(), rng.next_signed());
            *Rotation3::from_scaled_axis(0.3 * axis).matrix()
        })
        .collect();
    let mut feasible = DVector::zeros(k);
    for (c, rotation) in rotations.iter().enumerate() {
        let w = feasible_sole_wrench(constraints, &mut rng);
        let force = rotation * Vector3::new(w[0], w[1], w[2]);
        let moment = rotation * Vector3::new(w[3], w[4], w[5]);
        feasible.fixed_rows_mut::<3>(6 * c).copy_from(&force);
        feasible.fixed_rows_mut::<3>(6 * c + 3).copy_from(&moment);
    }
    // Momentum-map-like: identity blocks per contact plus random lever arms and noise.
    let momentum_map = DMatrix::from_fn(6, k, |i, j| {
        f64::from(u8::from(i == j % 6)) + 0.3 * rng.next_signed()
    });
    let (mut p, mut c) = (DMatrix::zeros(k, k), DVector::zeros(k));
    if two_feet {
        let sigma = DMatrix::from_fn(25, k, |_, _| 0.3 * rng.next_signed());
        let tau_bias = DVector::from_fn(25, |_, _| 50.0 * rng.next_signed());
        torque_norm_objective(&sigma, &tau_bias, icub().qp_regularization, &mut p, &mut c);
        let b = &momentum_map * &feasible;
        (p, c, Some((momentum_map, b)), rotations)
    } else {
        let target = DVector::from_fn(6, |_, _| 200.0 * rng.next_signed());
        let regularization = icub().qp_regularization;
        momentum_tracking_objective(&momentum_map, &target, regularization, &mut p, &mut c);
        (p, c, None, rotations)
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_wrench_qps_agree_with_clarabel(seed in any::<u64>(), two_feet in any::<bool>()) {
        let (p, c, equality, rotations) = random_wrench_qp(seed, two_feet);
        let contacts = if two_feet { 2 } else { 1 };
        let mut qp = WrenchQp::new(
            contacts,
            if two_feet { 6 } else { 0 },
            &ContactConstraints::default(),
        );
        qp.unconstrained_first = false;
        qp.cross_check = true;
        let mut wrenches = DVector::zeros(6 * contacts);
        let equality = equality.as_ref().map(|(a, b)| (a, b));
        let status = qp.solve(&p, &c, equality, &rotations, None, &mut wrenches);
        prop_assert_eq!(status, QpStatus::Solved);
        prop_assert_eq!(qp.counters().active_set, 1, "the active set failed");
        prop_assert_eq!(qp.agreement.ticks, 1, "Clarabel failed");
        let problems = agreement_problems("random QP", &qp.agreement);
        prop_assert!(problems.is_empty(), "{}", problems.join("; "));
    }
}
