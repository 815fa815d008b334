//! The algorithms write into `Data` and allocate nothing
//! (docs/explanation/architecture.md#rules): a counting global allocator (per thread, so the
//! test harness's other threads do not interfere) checks the hot paths after a warm-up call.

mod common;
mod counting;

use common::*;
use counting::allocations;
use nalgebra::DMatrix;

/// Runs every algorithm once (warm-up), then counts the allocations of a second call at a
/// different state. Returns `(name, allocations)` per algorithm.
fn count_all(seed: u64) -> Vec<(&'static str, usize)> {
    use sea_dyn::*;
    let desc = random_robot(seed);
    let model = load(&desc);
    let mut data = Data::new(&model);
    let mut rng = Lcg::new(40_000 + seed);
    let (nq, nv, n) = (model.nq(), model.nv(), model.n_joints());
    let states: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..2)
        .map(|_| {
            (
                random_q(&mut rng, nq),
                random_v(&mut rng, nv, 1.0),
                random_v(&mut rng, nv, 1.0),
            )
        })
        .collect();
    let frame = model.frames.len() - 1;
    let mut q_out = vec![0.0; nq];
    let mut split = CentroidalSplit::new(n, 6);
    let jacobian = DMatrix::from_element(6, nv, 0.1);
    let mut out = Vec::new();
    for (pass, (q, nu, nudot)) in states.iter().enumerate() {
        let mut record = |name: &'static str, count: usize| {
            if pass == 1 {
                out.push((name, count));
            }
        };
        record(
            "rnea",
            allocations(|| rnea(&model, &mut data, q, nu, nudot)[0]),
        );
        record(
            "bias_forces",
            allocations(|| bias_forces(&model, &mut data, q, nu)[0]),
        );
        record(
            "gravity_forces",
            allocations(|| gravity_forces(&model, &mut data, q)[0]),
        );
        record("crba", allocations(|| crba(&model, &mut data, q)[(0, 0)]));
        record(
            "forward_kinematics",
            allocations(|| forward_kinematics(&model, &mut data, q)),
        );
        record(
            "forward_velocities",
            allocations(|| forward_velocities(&model, &mut data, q, nu)),
        );
        record(
            "frame_placement",
            allocations(|| frame_placement(&model, &data, frame)),
        );
        record(
            "frame_jacobian",
            allocations(|| frame_jacobian(&model, &mut data, q, frame)[(0, 0)]),
        );
        record(
            "frame_jacobian_dot_v",
            allocations(|| frame_jacobian_dot_v(&model, &mut data, q, nu, frame)),
        );
        record("com", allocations(|| com(&model, &mut data, q)));
        record(
            "centroidal_momentum_matrix",
            allocations(|| centroidal_momentum_matrix(&model, &mut data, q)[(0, 0)]),
        );
        record(
            "centroidal_momentum",
            allocations(|| centroidal_momentum(&model, &mut data, q, nu)),
        );
        record(
            "centroidal_momentum_bias",
            allocations(|| centroidal_momentum_bias(&model, &mut data, q, nu)),
        );
        record(
            "com_jacobian",
            allocations(|| com_jacobian(&model, &mut data, q)[(0, 0)]),
        );
        record(
            "integrate",
            allocations(|| integrate(&model, q, nu, 1e-3, &mut q_out)),
        );
        // Inputs of the split, computed outside the counted call.
        crba(&model, &mut data, q);
        let data_ref = &data;
        record(
            "CentroidalSplit::compute",
            allocations(|| {
                split
                    .compute(&data_ref.mass_matrix, &data_ref.tau, &jacobian)
                    .is_ok()
            }),
        );
    }
    out
}

#[test]
fn hot_paths_allocate_nothing_after_warm_up() {
    // Sanity check of the counter itself.
    assert!(
        allocations(|| vec![1u8; 16]) >= 1,
        "the counting allocator is not active"
    );
    for seed in [1, 7, 13] {
        let counts = count_all(seed);
        let hot = [
            "rnea",
            "bias_forces",
            "gravity_forces",
            "crba",
            "forward_kinematics",
            "forward_velocities",
            "frame_placement",
            "frame_jacobian",
            "frame_jacobian_dot_v",
            "com",
            "centroidal_momentum_matrix",
            "centroidal_momentum",
            "centroidal_momentum_bias",
            "integrate",
        ];
        let offenders: Vec<_> = counts
            .iter()
            .filter(|(name, c)| hot.contains(name) && *c > 0)
            .collect();
        assert!(
            offenders.is_empty(),
            "seed {seed}: allocations in {offenders:?} (all: {counts:?})"
        );
    }
}

#[test]
fn com_jacobian_and_centroidal_split_allocate_nothing_after_warm_up() {
    let counts = count_all(5);
    let offenders: Vec<_> = counts
        .iter()
        .filter(|(name, c)| ["com_jacobian", "CentroidalSplit::compute"].contains(name) && *c > 0)
        .collect();
    assert!(offenders.is_empty(), "allocations in {offenders:?}");
}
