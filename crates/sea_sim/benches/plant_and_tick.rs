//! Criterion benches of the SEA plant and the controller on the iCub standing on two feet
//! (`urdf/icub25.urdf`): one evaluation of the plant's right-hand side, one ROS2 step of 1 ms,
//! and one controller tick (with the shortcut through the QP's minimiser without inequalities,
//! with Clarabel on every tick, and with the active set on every tick). The setups are `sea-sim bench`'s (`sea_sim::bench`), so
//! the figures are comparable. Run `cargo bench -p sea_sim --bench plant_and_tick`.
#![allow(
    missing_docs,
    reason = "criterion_group! defines an undocumented function"
)]

use criterion::{criterion_group, criterion_main, Criterion};
use sea_ctrl::qp::QpSolver;
use sea_dyn::{LoadOptions, Model};
use sea_plant::{Method, PlantData};
use sea_sim::bench::{standing_motor_input, standing_sea_plant, TickBench, TickQp};
use std::hint::black_box;

/// The iCub URDF shipped with the repository.
const URDF: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../urdf/icub25.urdf");

/// `plant_dynamics` and `plant_step_ros2`.
fn plant(c: &mut Criterion) {
    let model = Model::from_urdf_file(URDF, &LoadOptions::default()).expect("URDF loads");
    let (plant, x) = standing_sea_plant(&model).expect("the iCub has both soles");
    let u = standing_motor_input(&model, &x);
    let mut pd = PlantData::new(&plant);
    let mut x_next = x.clone();
    c.bench_function("plant_dynamics", |b| {
        b.iter(|| {
            black_box(
                sea_plant::evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).is_ok(),
            )
        })
    });
    c.bench_function("plant_step_ros2", |b| {
        b.iter(|| {
            black_box(
                sea_plant::step(&plant, &mut pd, &x, &u, 1e-3, Method::Ros2, &mut x_next).is_ok(),
            )
        })
    });
}

/// `controller_tick`, `controller_tick_clarabel` and `controller_tick_active_set`.
fn tick(c: &mut Criterion) {
    for (name, qp) in [
        ("controller_tick", TickQp::Default),
        (
            "controller_tick_clarabel",
            TickQp::Every(QpSolver::Clarabel),
        ),
        (
            "controller_tick_active_set",
            TickQp::Every(QpSolver::ActiveSet),
        ),
    ] {
        let mut ticks = TickBench::two_feet(URDF, qp).expect("scenario builds");
        let mut k = 0;
        c.bench_function(name, |b| {
            b.iter(|| {
                k += 1;
                assert!(ticks.tick(k), "the controller fails");
            })
        });
    }
}

criterion_group!(benches, plant, tick);
criterion_main!(benches);
