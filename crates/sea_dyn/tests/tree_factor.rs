//! The tree-sparse factorisation `M + diag(d) = L^T L` (linalg/tree_factor.rs) against
//! nalgebra's dense Cholesky `M + diag(d) = C C^T`, on seeded random trees and on the iCub.
//!
//! The two factors differ (L is lower triangular in tree order and multiplies as `L^T L`), so
//! the comparisons use what they share: the solution `(M + D)^-1 b`, the quadratic form
//! `|L^-T b|^2 = b^T (M + D)^-1 b`, the Schur complement `J (M + D)^-1 J^T`, the reconstructed
//! product `L^T L`, and the determinant `prod L_ii^2 = prod C_ii^2`. The tree's sparsity is
//! checked exactly: `L^-T e_i` is zero outside the ancestors of DOF i, `L^-1 e_i` outside its
//! descendants.

use crate::common;

use common::*;
use nalgebra::{DMatrix, DVector};
use sea_dyn::sample::{random_configuration, Lcg as SampleLcg};
use sea_dyn::tree_factor::TreeFactor;
use sea_dyn::{Data, LoadOptions, Model};
use std::path::Path;

fn icub() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../urdf/icub25.urdf");
    Model::from_urdf_file(&path, &LoadOptions::default()).unwrap()
}

/// The models under test: the random trees of `common::seeds()` and the iCub.
fn models() -> Vec<(String, Model)> {
    let mut out: Vec<(String, Model)> = seeds()
        .map(|seed| (format!("random tree {seed}"), load(&random_robot(seed))))
        .collect();
    out.push(("icub".into(), icub()));
    out
}

/// `ancestors[v][w]`: DOF `w` is DOF `v` or one of its ancestors (velocity indices). The base
/// DOFs form a chain 0 - 1 - ... - 5, and a body hanging from the base hangs from DOF 5.
fn ancestor_table(model: &Model) -> Vec<Vec<bool>> {
    let nv = model.nv();
    let mut table = vec![vec![false; nv]; nv];
    for (d, row) in table.iter_mut().enumerate().take(6) {
        row[..=d].fill(true);
    }
    for body in 1..model.n_bodies() {
        let v = model.velocity_index(body);
        table[v][..6].fill(true);
        for b in model.support(body) {
            table[v][model.velocity_index(b)] = true;
        }
    }
    table
}

/// `M(q) + diag(d)` as a dense matrix.
fn with_diagonal(m: &DMatrix<f64>, d: &[f64]) -> DMatrix<f64> {
    let mut out = m.clone();
    for (i, v) in d.iter().enumerate() {
        out[(i, i)] += v;
    }
    out
}

/// Unit vector `e_i` of size n.
fn unit(n: usize, i: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[i] = 1.0;
    e
}

/// Checks one factorisation of `m + diag(d)` against nalgebra's Cholesky.
fn check_factor(name: &str, model: &Model, m: &DMatrix<f64>, d: &[f64], rng: &mut Lcg) {
    let nv = model.nv();
    let dense = with_diagonal(m, d);
    let scale = dense.amax();
    let cholesky = dense
        .clone()
        .cholesky()
        .expect("M + D is positive definite");
    let mut factor = TreeFactor::new(model);
    factor.factor(m, d).unwrap();

    // L^-1 column by column: lower triangular in tree order, so the support of L^-1 e_i is
    // i and its descendants; L^-T e_i lives on i and its ancestors.
    let ancestors = ancestor_table(model);
    let mut l_inv = DMatrix::zeros(nv, nv);
    for (i, ancestors_of_i) in ancestors.iter().enumerate() {
        let mut column = unit(nv, i);
        factor.solve_l(&mut column);
        let mut row = unit(nv, i);
        factor.solve_lt(&mut row);
        for (w, (c, r)) in column.iter().zip(&row).enumerate() {
            assert!(
                *c == 0.0 || ancestors[w][i],
                "{name}: L^-1 e_{i} is non-zero at {w}, not a descendant"
            );
            assert!(
                *r == 0.0 || ancestors_of_i[w],
                "{name}: L^-T e_{i} is non-zero at {w}, not an ancestor"
            );
        }
        l_inv.set_column(i, &DVector::from_vec(column));
    }
    // L^T L = M + D.
    let l = l_inv.clone().try_inverse().unwrap();
    assert_close_mat(
        &format!("{name}: L^T L"),
        &(l.transpose() * &l),
        &dense,
        1e-12,
        scale,
    );
    // det(M + D) = prod L_ii^2 = prod C_ii^2, compared as logarithms.
    let log_det_tree: f64 = (0..nv).map(|i| -2.0 * l_inv[(i, i)].abs().ln()).sum();
    let log_det_dense: f64 = (0..nv).map(|i| 2.0 * cholesky.l()[(i, i)].ln()).sum();
    assert!(
        (log_det_tree - log_det_dense).abs() < 1e-10 * (1.0 + log_det_dense.abs()),
        "{name}: log det {log_det_tree} vs {log_det_dense}"
    );

    // Solves and the quadratic form.
    let b = DVector::from_vec(rng.vector(nv, -1.0, 1.0));
    let exact = cholesky.solve(&b);
    let mut x = b.as_slice().to_vec();
    factor.solve(&mut x);
    let x = DVector::from_vec(x);
    assert_close_vec(&format!("{name}: solve"), &x, &exact, 1e-10, exact.amax());
    let mut y = b.as_slice().to_vec();
    factor.solve_lt(&mut y);
    let quadratic: f64 = y.iter().map(|v| v * v).sum();
    let expected = b.dot(&exact);
    assert!(
        (quadratic - expected).abs() < 1e-10 * expected.abs(),
        "{name}: |L^-T b|^2 = {quadratic}, b^T (M + D)^-1 b = {expected}"
    );
    check_schur(name, &factor, &cholesky, rng);
}

/// Schur complement `J (M + D)^-1 J^T` and `Y = L^-T J^T` for random `J` of 6, 12 and 18 rows.
fn check_schur(
    name: &str,
    factor: &TreeFactor,
    cholesky: &nalgebra::Cholesky<f64, nalgebra::Dyn>,
    rng: &mut Lcg,
) {
    let nv = cholesky.l().nrows();
    // 18 rows: wider than the stack copy of the multi solves (their general path).
    for k in [6, 12, 18] {
        let jacobian = DMatrix::from_fn(k, nv, |_, _| rng.range(-1.0, 1.0));
        let mut y_t = DMatrix::zeros(k, nv);
        let mut schur = DMatrix::zeros(k, k);
        factor.schur_complement(&jacobian, &mut y_t, &mut schur);
        let expected = &jacobian * cholesky.solve(&jacobian.transpose());
        let what = format!("{name}: Schur complement ({k} rows)");
        assert_close_mat(&what, &schur, &expected, 1e-10, expected.amax());
        for r in 0..k {
            let mut column: Vec<f64> = jacobian.row(r).iter().copied().collect();
            factor.solve_lt(&mut column);
            let column = DVector::from_vec(column);
            let what = format!("{name}: Y column {r}");
            // Same arithmetic up to the order of operations (a multiplication by 1 / L_ii).
            let scale = column.amax();
            assert_close_vec(&what, &y_t.row(r).transpose(), &column, 1e-14, scale);
        }
        // Both multi-right-hand-side solves on a Jacobian with zero columns, as a foot's
        // (other branches zero), which `solve_lt_multi` skips.
        let mut sparse = jacobian.clone();
        for i in (0..nv).step_by(3) {
            sparse.column_mut(i).fill(0.0);
        }
        let mut b_t = sparse.clone();
        factor.solve_lt_multi(&mut b_t);
        factor.solve_l_multi(&mut b_t);
        let expected = cholesky.solve(&sparse.transpose());
        let what = format!("{name}: (M + D)^-1 J^T by the multi solves ({k} rows)");
        assert_close_mat(&what, &b_t.transpose(), &expected, 1e-10, expected.amax());
    }
}

#[test]
fn tree_factor_agrees_with_dense_cholesky() {
    for (name, model) in models() {
        let mut rng = Lcg::new(name.len() as u64 * 31 + model.nv() as u64);
        let mut data = Data::new(&model);
        let q = random_q(&mut rng, model.nq());
        let m = sea_dyn::crba(&model, &mut data, &q).clone();
        let nv = model.nv();
        // No diagonal, the plant's joint regularisation (joints only), and a general one.
        let mut joints_only = vec![0.0; nv];
        joints_only[6..].fill(0.1);
        let general = rng.vector(nv, 0.0, 2.0);
        for (label, d) in [
            ("no diagonal", Vec::new()),
            ("joint diagonal", joints_only),
            ("general diagonal", general),
        ] {
            check_factor(&format!("{name}, {label}"), &model, &m, &d, &mut rng);
        }
    }
}

#[test]
fn the_diagonal_argument_equals_adding_it_to_the_matrix() {
    for (name, model) in models() {
        let mut rng = Lcg::new(7 + model.nv() as u64);
        let q = random_q(&mut rng, model.nq());
        let m = sea_dyn::crba(&model, &mut Data::new(&model), &q).clone();
        let d = rng.vector(model.nv(), 0.0, 1.0);
        let mut separate = TreeFactor::new(&model);
        separate.factor(&m, &d).unwrap();
        let mut added = TreeFactor::new(&model);
        added.factor(&with_diagonal(&m, &d), &[]).unwrap();
        let b = rng.vector(model.nv(), -1.0, 1.0);
        let (mut x1, mut x2) = (b.clone(), b);
        separate.solve(&mut x1);
        added.solve(&mut x2);
        assert_eq!(x1, x2, "{name}");
    }
}

#[test]
fn a_matrix_that_is_not_positive_definite_is_an_error() {
    let mut rng = SampleLcg::new(5);
    for (name, model) in models() {
        let q = random_configuration(&model, &mut rng);
        let m = sea_dyn::crba(&model, &mut Data::new(&model), &q).clone();
        let nv = model.nv();
        let lambda_min = m.clone().symmetric_eigenvalues().min();
        assert!(lambda_min > 0.0, "{name}: M is not positive definite");
        let mut factor = TreeFactor::new(&model);
        // Shifted just below and just above the smallest eigenvalue: a 2 % change of the shift
        // decides between positive definite and indefinite, usually with every diagonal entry
        // still positive (a check of the pivots' signs on the diagonal alone would not see it).
        let below = vec![-0.99 * lambda_min; nv];
        let above = vec![-1.01 * lambda_min; nv];
        assert!(
            factor.factor(&m, &below).is_ok(),
            "{name}: M - 0.99 lambda_min I"
        );
        let error = factor.factor(&m, &above);
        assert!(error.is_err(), "{name}: M - 1.01 lambda_min I was factored");
        println!("{name}: {}", error.unwrap_err());
        // Negative definite, and a NaN.
        assert!(
            factor.factor(&(-m.clone()), &[]).is_err(),
            "{name}: -M was factored"
        );
        let mut nan = m.clone();
        nan[(nv - 1, nv - 1)] = f64::NAN;
        assert!(
            factor.factor(&nan, &[]).is_err(),
            "{name}: NaN was factored"
        );
        // The factor is usable again after a failure.
        factor.factor(&m, &[]).unwrap();
        let mut x = unit(nv, 0);
        factor.solve(&mut x);
        let exact = m
            .clone()
            .cholesky()
            .unwrap()
            .solve(&DVector::from_vec(unit(nv, 0)));
        assert_close_vec(
            name.as_str(),
            &DVector::from_vec(x),
            &exact,
            1e-10,
            exact.amax(),
        );
    }
}
