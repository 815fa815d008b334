//! Criterion benches of the dynamics algorithms on the iCub (`urdf/icub25.urdf`, nv = 31):
//! RNEA, CRBA and the centroidal momentum matrix, cycling through seeded random states (the
//! states of `sea-sim bench`). Run `cargo bench -p sea_dyn --bench dynamics`; criterion
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

criterion_group!(benches, dynamics);
criterion_main!(benches);
