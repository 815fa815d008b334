//! Criterion benches of the dynamics algorithms on the iCub (`urdf/icub25.urdf`, nv = 31):
//! RNEA, CRBA and the centroidal momentum matrix, cycling through seeded random states (the
//! states of `sea-sim bench`), and the tree-sparse factorisation of `M` with the two feet's
//! Schur complement `J M^-1 J^T` (the plant's and the controller's linear algebra). Run `cargo bench -p sea_dyn --bench dynamics`; criterion
//! compares each run with the previous one.
#![allow(
    missing_docs,
    reason = "criterion_group! defines an undocumented function"
)]

use criterion::{criterion_group, criterion_main, Criterion};
use sea_dyn::sample::{random_configuration, random_velocity, Lcg};
use sea_dyn::{Data, LoadOptions, Model};
use std::hint::black_box;

/// Random states cycled through (as in `sea_sim::bench`).
const STATES: usize = 64;

/// The iCub model shipped with the repository.
fn icub() -> Model {
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/../../urdf/icub25.urdf");
    Model::from_urdf_file(urdf, &LoadOptions::default()).expect("urdf/icub25.urdf loads")
}

/// Seeded random configurations, velocities and accelerations.
fn random_states(model: &Model) -> Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let mut rng = Lcg::new(42);
    (0..STATES)
        .map(|_| {
            let q = random_configuration(model, &mut rng);
            let nu = random_velocity(model, &mut rng);
            let nudot = random_velocity(model, &mut rng);
            (q, nu, nudot)
        })
        .collect()
}

/// `rnea`, `crba`, `centroidal_momentum_matrix`.
fn dynamics(c: &mut Criterion) {
    let model = icub();
    let states = random_states(&model);
    let mut data = Data::new(&model);
    let mut k = 0;
    let mut next = || {
        k = (k + 1) % STATES;
        k
    };
    c.bench_function("rnea", |b| {
        b.iter(|| {
            let (q, nu, nudot) = &states[next()];
            black_box(sea_dyn::rnea(&model, &mut data, q, nu, nudot));
        })
    });
    c.bench_function("crba", |b| {
        b.iter(|| {
            black_box(sea_dyn::crba(&model, &mut data, &states[next()].0));
        })
    });
    c.bench_function("centroidal_momentum_matrix", |b| {
        b.iter(|| {
            black_box(sea_dyn::centroidal_momentum_matrix(
                &model,
                &mut data,
                &states[next()].0,
            ));
        })
    });
}

/// `TreeFactor::factor` of `M` and `TreeFactor::schur_complement` of the stacked sole
/// Jacobians (k = 12), at one random configuration.
fn tree_factor(c: &mut Criterion) {
    let model = icub();
    let (q, _, _) = &random_states(&model)[0];
    let mut data = Data::new(&model);
    let mass_matrix = sea_dyn::crba(&model, &mut data, q).clone();
    let nv = model.nv();
    let mut jacobian = nalgebra::DMatrix::zeros(12, nv);
    for (c, sole) in ["l_sole", "r_sole"].into_iter().enumerate() {
        let frame = model.frame_id(sole).expect("the iCub has soles");
        let sole_jacobian = sea_dyn::jacobian::frame_jacobian(&model, &mut data, q, frame);
        jacobian.rows_mut(6 * c, 6).copy_from(sole_jacobian);
    }
    // Set up outside the timed closures, so that any filter of the benches runs on real data.
    let mut factor = sea_dyn::tree_factor::TreeFactor::new(&model);
    factor
        .factor(&mass_matrix, &[])
        .expect("M is positive definite");
    c.bench_function("tree_factor", |b| {
        b.iter(|| black_box(factor.factor(&mass_matrix, &[]).is_ok()))
    });
    let (mut y_t, mut schur) = (jacobian.clone(), nalgebra::DMatrix::zeros(12, 12));
    factor.schur_complement(&jacobian, &mut y_t, &mut schur);
    c.bench_function("schur_complement_two_feet", |b| {
        b.iter(|| {
            factor.schur_complement(&jacobian, &mut y_t, &mut schur);
            black_box(&schur);
        })
    });
    c.bench_function("solve_lt_multi_two_feet", |b| {
        b.iter(|| {
            sea_dyn::dense::copy_contiguous(&mut y_t, &jacobian);
            factor.solve_lt_multi(&mut y_t);
            black_box(&y_t);
        })
    });
    let mut gram = schur.clone();
    assert!(
        sea_dyn::dense::cholesky_in_place(&mut schur.clone()).is_ok(),
        "the two feet's Schur complement is positive definite"
    );
    c.bench_function("cholesky_12", |b| {
        b.iter(|| {
            sea_dyn::dense::copy_contiguous(&mut gram, &schur);
            black_box(sea_dyn::dense::cholesky_in_place(&mut gram).is_ok())
        })
    });
    sea_dyn::dense::copy_contiguous(&mut gram, &schur);
    sea_dyn::dense::cholesky_in_place(&mut gram).expect("positive definite");
    let small_rhs: Vec<f64> = (0..12).map(|i| (i as f64 * 0.61).cos()).collect();
    let mut small_solution = small_rhs.clone();
    c.bench_function("cholesky_solve_12", |b| {
        b.iter(|| {
            small_solution.copy_from_slice(&small_rhs);
            sea_dyn::dense::cholesky_solve_in_place(&gram, &mut small_solution);
            black_box(&small_solution);
        })
    });
    let rhs: Vec<f64> = (0..nv).map(|i| (i as f64 * 0.37).sin()).collect();
    let mut solution = rhs.clone();
    c.bench_function("tree_solve", |b| {
        b.iter(|| {
            solution.copy_from_slice(&rhs);
            factor.solve(&mut solution);
            black_box(&solution);
        })
    });
}

criterion_group!(benches, dynamics, tree_factor);
criterion_main!(benches);
