//! The minimiser of the QP's objective without its inequalities (with or without the
//! equality rows): the first candidate of a solve, optimal when feasible, and the fallback
//! when every solver fails.

use nalgebra::{DMatrix, DVector};
use sea_dyn::dense::{
    backward_substitute, cholesky_in_place, cholesky_solve_in_place, copy_contiguous,
    forward_substitute, gemm_tn,
};

/// Minimisers of `0.5 f^T P f + c^T f` without the inequalities (k variables, m equality
/// rows), in buffers allocated once: the candidate [`super::WrenchQp::solve`] accepts when it is
/// feasible, and the fallback when the solvers fail.
pub struct Minimizer {
    /// Cholesky factor of `P` (k x k, lower triangle).
    factor: DMatrix<f64>,
    /// `V = L^-1 A^T` (k x m).
    range: DMatrix<f64>,
    /// `A P^-1 A^T = V^T V`, then its Cholesky factor (m x m).
    schur: DMatrix<f64>,
    /// `L^-1 c` (k), then `w + V lambda`.
    scaled_gradient: DVector<f64>,
    /// The multipliers `lambda` (m).
    multipliers: DVector<f64>,
}

impl Minimizer {
    /// Buffers for `k` variables and `m` equality rows.
    pub fn new(k: usize, m: usize) -> Self {
        Self {
            factor: DMatrix::zeros(k, k),
            range: DMatrix::zeros(k, m),
            schur: DMatrix::zeros(m, m),
            scaled_gradient: DVector::zeros(k),
            multipliers: DVector::zeros(m),
        }
    }

    /// Factors `P = L L^T` into `self.factor` and sets `w = L^-1 c`; `false` if `P` is not
    /// positive definite.
    fn factor_objective(&mut self, p: &DMatrix<f64>, c: &DVector<f64>) -> bool {
        copy_contiguous(&mut self.factor, p);
        if cholesky_in_place(&mut self.factor).is_err() {
            return false;
        }
        copy_contiguous(&mut self.scaled_gradient, c);
        forward_substitute(&self.factor, self.scaled_gradient.as_mut_slice());
        true
    }

    /// `argmin 0.5 f^T P f + c^T f = -P^-1 c` into `out` (k) for `P` positive definite (k x
    /// k, Cholesky); `false` if it is not.
    pub fn unconstrained(
        &mut self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> bool {
        if !self.factor_objective(p, c) {
            return false;
        }
        copy_contiguous(out, &self.scaled_gradient);
        backward_substitute(&self.factor, out.as_mut_slice());
        out.neg_mut();
        true
    }

    /// `argmin 0.5 f^T P f + c^T f` s.t. `A f = b` into `out` (k) by the range-space method:
    /// with `P = L L^T`, `V = L^-1 A^T`, `w = L^-1 c`, the multipliers solve
    /// `V^T V lambda = -(V^T w + b)` and `f = -L^-T (w + V lambda)` (the KKT system
    /// `[[P, A^T], [A, 0]] [f; lambda] = [-c; b]` with two small Cholesky factors instead of an
    /// LU of the (k + m)-square KKT matrix). `A` m x k, `b` m; `false` if `P` is not positive
    /// definite, `A` not of full row rank, or the solution not finite.
    pub fn equality_constrained(
        &mut self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> bool {
        if !self.factor_objective(p, c) {
            return false;
        }
        self.range.tr_copy_from(a);
        for mut column in self.range.column_iter_mut() {
            forward_substitute(&self.factor, column.as_mut_slice());
        }
        gemm_tn(&mut self.schur, 1.0, &self.range, &self.range, 0.0, true);
        if cholesky_in_place(&mut self.schur).is_err() {
            return false;
        }
        copy_contiguous(&mut self.multipliers, b);
        self.multipliers
            .gemv_tr(1.0, &self.range, &self.scaled_gradient, 1.0);
        self.multipliers.neg_mut();
        cholesky_solve_in_place(&self.schur, self.multipliers.as_mut_slice());
        self.scaled_gradient
            .gemv(1.0, &self.range, &self.multipliers, 1.0);
        copy_contiguous(out, &self.scaled_gradient);
        backward_substitute(&self.factor, out.as_mut_slice());
        out.neg_mut();
        out.iter().all(|v| v.is_finite())
    }
}
