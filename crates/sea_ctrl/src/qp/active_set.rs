//! A dense active-set solver for small strictly convex QPs,
//!
//! ```text
//! min 0.5 x^T P x + c^T x   s.t.   A x = b,   G x <= h,
//! ```
//!
//! `P` symmetric positive definite: the dual method of Goldfarb and Idnani (D. Goldfarb,
//! A. Idnani, "A numerically stable dual method for solving strictly convex quadratic
//! programs", Mathematical Programming 27, 1983, pp. 1-33; the algorithm of quadprog and of
//! eiquadprog, the solver TSID uses). It starts from the unconstrained minimiser `-P^-1 c`
//! (dual feasible), adds the equalities, then repeatedly adds the most violated inequality,
//! stepping in primal and dual space and dropping an active inequality whose multiplier would
//! turn negative (a partial step), until no inequality is violated. Every iterate is the
//! optimum of the QP restricted to its active set, so the multipliers stay non-negative and
//! the objective grows monotonically; the method ends after finitely many steps.
//!
//! Numerically it keeps `J = L^-T Q` and the upper triangular `R` of `L^-1 N = Q [R; 0]`
//! (`P = L L^T` Cholesky, `N` the active constraint normals), updated by Givens rotations
//! when a constraint enters or leaves (Goldfarb-Idnani, section 4): no factorisation is
//! repeated inside the loop. The step direction in primal space is `z = J_2 J_2^T n` and in
//! dual space `-r = -R^-1 J_1^T n`.
//!
//! Every buffer is sized in [`ActiveSetQp::new`]; a solve allocates nothing. A solve that
//! cannot finish (not positive definite, dependent equalities, infeasible, degenerate, the
//! iteration limit) returns an [`ActiveSetError`], so the caller can fall back to another
//! solver.

use nalgebra::{DMatrix, DVector};
use sea_dyn::dense::copy_contiguous;

/// Largest number of active-set changes (additions and drops) in one solve. The method is
/// finite, and the wrench QP needs a handful (at most 12 constraints can be active); the
/// limit only guards against cycling caused by rounding at degenerate vertices, where the
/// caller's fallback solver takes over.
pub const MAX_ITERATIONS: usize = 200;

/// Relative feasibility tolerance: an inequality `g^T x <= h` counts as violated when its
/// distance to the half-space, `(g^T x - h) / |g|`, exceeds this times `1 + |x|_inf`. Far
/// above the rounding of a 12-variable solve (about 1e-14 relative) and far below Clarabel's
/// feasibility tolerance (1e-7), so the answer is as feasible as the reference's.
pub const FEASIBILITY_TOLERANCE: f64 = 1e-10;

/// Relative linear-dependence tolerance: a constraint normal `n` whose part outside the
/// span of the active normals (in the `P^-1` metric, `|J_2^T n|`) is below this times
/// `|J^T n|` is treated as dependent on them (no primal step exists along it). Rounding
/// leaves dependent normals about 1e-15 relative away from the span.
pub const DEPENDENCE_TOLERANCE: f64 = 1e-12;

/// Why a solve did not finish; the caller falls back to another solver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActiveSetError {
    /// `P` is not (numerically) positive definite.
    NotPositiveDefinite,
    /// The equality rows are linearly dependent.
    DependentEqualities,
    /// No point satisfies the constraints (no primal or dual step exists).
    Infeasible,
    /// A constraint to add is numerically dependent on the active set.
    Degenerate,
    /// [`MAX_ITERATIONS`] active-set changes without an optimum.
    IterationLimit,
    /// A non-finite value appeared (non-finite problem data).
    NotFinite,
}

impl std::fmt::Display for ActiveSetError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let text = match self {
            Self::NotPositiveDefinite => "Hessian not positive definite",
            Self::DependentEqualities => "equality rows linearly dependent",
            Self::Infeasible => "infeasible constraints",
            Self::Degenerate => "degenerate active set",
            Self::IterationLimit => "iteration limit reached",
            Self::NotFinite => "non-finite value",
        };
        f.write_str(text)
    }
}

impl std::error::Error for ActiveSetError {}

/// What a successful solve did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActiveSetReport {
    /// Active-set changes (inequalities added or dropped).
    pub iterations: usize,
    /// Inequalities dropped on the way (partial steps).
    pub drops: usize,
    /// Inequalities active at the optimum.
    pub active_inequalities: usize,
}

/// A constraint of the active set: equality row or inequality row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Constraint {
    Equality(usize),
    Inequality(usize),
}

/// The Goldfarb-Idnani solver for `n` variables, `m_eq` equality rows and the inequality rows
/// `G x <= h` set by [`Self::set_inequalities`], with all buffers (see the module doc).
pub struct ActiveSetQp {
    n: usize,
    m_eq: usize,
    /// Inequality normals `G^T` (n x m_in), one constraint per column (contiguous), and
    /// bounds `h` (m_in), and the column norms `|g_i|`.
    normals: DMatrix<f64>,
    bounds: DVector<f64>,
    normal_norms: DVector<f64>,
    /// Cholesky factor `L` of `P` (lower triangle used).
    factor: DMatrix<f64>,
    /// `J = L^-T Q` (n x n).
    j: DMatrix<f64>,
    /// `R` (upper triangular, first `active.len()` columns used).
    r: DMatrix<f64>,
    /// `J^T n` of the constraint being added.
    d: DVector<f64>,
    /// Primal step direction.
    z: DVector<f64>,
    /// Dual step direction `R^-1 d_1` (first `active.len()` entries).
    dual_step: DVector<f64>,
    /// Multipliers of the active constraints in eiquadprog's convention (`P x + c = N u`),
    /// plus one slot for the constraint being added.
    u: DVector<f64>,
    /// The normal of the constraint being added, as `n^T x + n_0 >= 0` (`n = -g` for
    /// inequalities, `a` for equalities).
    normal: DVector<f64>,
    /// Active constraints in order (equalities first); capacity n + 1.
    active: Vec<Constraint>,
    /// Whether inequality i is active.
    is_active: Vec<bool>,
}

impl ActiveSetQp {
    /// Buffers for `n` variables, `m_eq` equality rows and `m_in` inequality rows (all
    /// inequalities `0 x <= 0` until [`Self::set_inequalities`]).
    pub fn new(n: usize, m_eq: usize, m_in: usize) -> Self {
        Self {
            n,
            m_eq,
            normals: DMatrix::zeros(n, m_in),
            bounds: DVector::zeros(m_in),
            normal_norms: DVector::zeros(m_in),
            factor: DMatrix::zeros(n, n),
            j: DMatrix::zeros(n, n),
            r: DMatrix::zeros(n, n),
            d: DVector::zeros(n),
            z: DVector::zeros(n),
            dual_step: DVector::zeros(n + 1),
            u: DVector::zeros(n + 1),
            normal: DVector::zeros(n),
            active: Vec::with_capacity(n + 1),
            is_active: vec![false; m_in],
        }
    }

    /// Sets the inequalities `G x <= h` (`G` m_in x n, `h` m_in), kept for later solves.
    pub fn set_inequalities(&mut self, g: &DMatrix<f64>, h: &DVector<f64>) {
        self.normals.tr_copy_from(g);
        copy_contiguous(&mut self.bounds, h);
        for (i, norm) in self.normal_norms.iter_mut().enumerate() {
            *norm = self.normals.column(i).norm();
        }
    }

    /// Solves `min 0.5 x^T P x + c^T x` s.t. `A x = b` (`equality`, `A` m_eq x n; `None` when
    /// m_eq = 0) and the inequalities of [`Self::set_inequalities`], into `x` (n). `P` must be
    /// symmetric positive definite (its lower triangle is read).
    pub fn solve(
        &mut self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        equality: Option<(&DMatrix<f64>, &DVector<f64>)>,
        x: &mut DVector<f64>,
    ) -> Result<ActiveSetReport, ActiveSetError> {
        self.factorize(p)?;
        self.unconstrained_minimizer(c, x);
        self.active.clear();
        self.is_active.fill(false);
        self.r.as_mut_slice().fill(0.0);
        let mut r_norm = 1.0;
        if let Some((a, b)) = equality {
            self.add_equalities(a, b, x, &mut r_norm)?;
        }
        let (mut iterations, mut drops) = (0, 0);
        while let Some(candidate) = self.most_violated(x) {
            drops += self.add_inequality(candidate, x, &mut r_norm, &mut iterations)?;
        }
        if !x.iter().all(|v| v.is_finite()) {
            return Err(ActiveSetError::NotFinite);
        }
        Ok(ActiveSetReport {
            iterations,
            drops,
            active_inequalities: self.active.len() - self.m_eq_active(),
        })
    }

    /// Active equality rows (all of them after a successful solve).
    fn m_eq_active(&self) -> usize {
        self.active
            .iter()
            .filter(|c| matches!(c, Constraint::Equality(_)))
            .count()
    }

    /// The multipliers of the last successful solve, with `P x + c + A^T lambda + G^T mu = 0`:
    /// `lambda` (m_eq) of the equalities and `mu >= 0` (m_in, zero for inactive rows).
    pub fn multipliers(&self, lambda: &mut DVector<f64>, mu: &mut DVector<f64>) {
        lambda.as_mut_slice().fill(0.0);
        mu.as_mut_slice().fill(0.0);
        for (slot, constraint) in self.active.iter().enumerate() {
            match *constraint {
                Constraint::Equality(i) => lambda[i] = -self.u[slot],
                Constraint::Inequality(i) => mu[i] = self.u[slot],
            }
        }
    }

    /// The KKT stationarity residual of the last successful solve's `x`,
    /// `|P x + c + A^T lambda + G^T mu|_inf / (1 + max(|P x|_inf, |c|_inf))` with its
    /// multipliers (`mu >= 0` by construction, zero on inactive rows): with feasibility and
    /// complementarity (active rows hold with equality) the certificate that `x` is the
    /// optimum. `scratch` (n) is overwritten.
    pub fn stationarity_residual(
        &self,
        p: &DMatrix<f64>,
        c: &DVector<f64>,
        a: Option<&DMatrix<f64>>,
        x: &DVector<f64>,
        scratch: &mut DVector<f64>,
    ) -> f64 {
        scratch.gemv(1.0, p, x, 0.0);
        let scale = 1.0 + scratch.amax().max(c.amax());
        *scratch += c;
        for (slot, constraint) in self.active.iter().enumerate() {
            match (*constraint, a) {
                (Constraint::Equality(i), Some(a)) => {
                    for (k, value) in scratch.iter_mut().enumerate() {
                        *value -= self.u[slot] * a[(i, k)];
                    }
                }
                (Constraint::Inequality(i), _) => {
                    scratch.axpy(self.u[slot], &self.normals.column(i), 1.0);
                }
                (Constraint::Equality(_), None) => {}
            }
        }
        scratch.amax() / scale
    }

    /// `L` of `P = L L^T` into `factor` (in place, lower triangle) and `J = L^-T` (upper).
    fn factorize(&mut self, p: &DMatrix<f64>) -> Result<(), ActiveSetError> {
        let n = self.n;
        let l = &mut self.factor;
        copy_contiguous(l, p);
        for k in 0..n {
            let mut pivot = l[(k, k)];
            for i in 0..k {
                pivot -= l[(k, i)] * l[(k, i)];
            }
            // Also rejects NaN.
            if !(pivot > 0.0 && pivot.is_finite()) {
                return Err(ActiveSetError::NotPositiveDefinite);
            }
            let diagonal = pivot.sqrt();
            l[(k, k)] = diagonal;
            for row in k + 1..n {
                let mut value = l[(row, k)];
                for i in 0..k {
                    value -= l[(row, i)] * l[(k, i)];
                }
                l[(row, k)] = value / diagonal;
            }
        }
        // J = L^-T: column j solves L^T J_j = e_j (upper triangular, back substitution).
        self.j.as_mut_slice().fill(0.0);
        for col in 0..n {
            self.j[(col, col)] = 1.0 / l[(col, col)];
            for row in (0..col).rev() {
                let mut sum = 0.0;
                for k in row + 1..=col {
                    sum += l[(k, row)] * self.j[(k, col)];
                }
                self.j[(row, col)] = -sum / l[(row, row)];
            }
        }
        Ok(())
    }

    /// `x = -P^-1 c = -J J^T c`.
    fn unconstrained_minimizer(&mut self, c: &DVector<f64>, x: &mut DVector<f64>) {
        self.d.gemv_tr(1.0, &self.j, c, 0.0);
        x.gemv(-1.0, &self.j, &self.d, 0.0);
    }

    /// Adds the equality rows one by one, each with its full step (Goldfarb-Idnani with
    /// equalities: they are never dropped).
    fn add_equalities(
        &mut self,
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        x: &mut DVector<f64>,
        r_norm: &mut f64,
    ) -> Result<(), ActiveSetError> {
        for i in 0..self.m_eq {
            self.normal.tr_copy_from(&a.row(i));
            self.step_directions();
            let q = self.active.len();
            let denominator = self.z.dot(&self.normal);
            if !self.has_primal_step() {
                return Err(ActiveSetError::DependentEqualities);
            }
            let t = (b[i] - self.normal.dot(x)) / denominator;
            x.axpy(t, &self.z, 1.0);
            self.u[q] = t;
            for k in 0..q {
                self.u[k] -= t * self.dual_step[k];
            }
            self.active.push(Constraint::Equality(i));
            if !self.add_to_factors(r_norm) {
                return Err(ActiveSetError::DependentEqualities);
            }
        }
        Ok(())
    }

    /// The inactive inequality with the largest normalised violation beyond the tolerance
    /// (see [`FEASIBILITY_TOLERANCE`]), or `None` when `x` is feasible.
    fn most_violated(&self, x: &DVector<f64>) -> Option<usize> {
        let tolerance = FEASIBILITY_TOLERANCE * (1.0 + x.amax());
        let mut worst = None;
        let mut worst_distance = tolerance;
        for i in 0..self.bounds.len() {
            if self.is_active[i] || self.normal_norms[i] == 0.0 {
                continue;
            }
            let excess = self.normals.column(i).dot(x) - self.bounds[i];
            let distance = excess / self.normal_norms[i];
            // NaN is taken too, and then fails the solve (a non-finite step).
            if distance > worst_distance || distance.is_nan() {
                worst_distance = distance;
                worst = Some(i);
            }
        }
        worst
    }

    /// Step 2 of Goldfarb-Idnani for the violated inequality `candidate`: steps until it is
    /// satisfied with equality (added to the active set), dropping active inequalities whose
    /// multiplier reaches zero on the way; returns how many it dropped.
    fn add_inequality(
        &mut self,
        candidate: usize,
        x: &mut DVector<f64>,
        r_norm: &mut f64,
        iterations: &mut usize,
    ) -> Result<usize, ActiveSetError> {
        // As `n^T x + h >= 0` with `n = -g`.
        self.normal.copy_from(&self.normals.column(candidate));
        self.normal.neg_mut();
        let q0 = self.active.len();
        self.u[q0] = 0.0;
        let mut drops = 0;
        loop {
            *iterations += 1;
            if *iterations > MAX_ITERATIONS {
                return Err(ActiveSetError::IterationLimit);
            }
            self.step_directions();
            let q = self.active.len();
            let (partial, drop) = self.partial_step(q);
            let slack = self.normal.dot(x) + self.bounds[candidate];
            let full = if self.has_primal_step() {
                -slack / self.z.dot(&self.normal)
            } else {
                f64::INFINITY
            };
            let step = partial.min(full);
            if !step.is_finite() {
                return Err(if step.is_nan() {
                    ActiveSetError::NotFinite
                } else {
                    ActiveSetError::Infeasible
                });
            }
            if full.is_finite() {
                x.axpy(step, &self.z, 1.0);
            }
            for k in 0..q {
                self.u[k] -= step * self.dual_step[k];
            }
            self.u[q] += step;
            if step == full {
                self.active.push(Constraint::Inequality(candidate));
                self.is_active[candidate] = true;
                if !self.add_to_factors(r_norm) {
                    return Err(ActiveSetError::Degenerate);
                }
                return Ok(drops);
            }
            self.drop_constraint(drop.expect("a finite partial step has a constraint"));
            drops += 1;
        }
    }

    /// `d = J^T n`, the primal direction `z = J_2 d_2` and the dual direction `R^-1 d_1` for
    /// the current active set (`q` constraints; `J_1`, `d_1` the first q columns/entries).
    fn step_directions(&mut self) {
        let q = self.active.len();
        self.d.gemv_tr(1.0, &self.j, &self.normal, 0.0);
        self.z.as_mut_slice().fill(0.0);
        for col in q..self.n {
            self.z.axpy(self.d[col], &self.j.column(col), 1.0);
        }
        for row in (0..q).rev() {
            let mut value = self.d[row];
            for k in row + 1..q {
                value -= self.r[(row, k)] * self.dual_step[k];
            }
            self.dual_step[row] = value / self.r[(row, row)];
        }
    }

    /// Whether the constraint being added has a primal step: its normal is not (numerically)
    /// in the span of the active normals, `|d_2| > DEPENDENCE_TOLERANCE |d|`.
    fn has_primal_step(&self) -> bool {
        let q = self.active.len();
        let outside = self.d.rows_range(q..).norm_squared();
        outside > (DEPENDENCE_TOLERANCE * DEPENDENCE_TOLERANCE) * self.d.norm_squared()
    }

    /// The partial step length: the largest dual step keeping the active inequalities'
    /// multipliers non-negative, `min u_k / r_k` over `r_k > 0`, and the slot that reaches
    /// zero there (`INFINITY, None` when no multiplier decreases).
    fn partial_step(&self, q: usize) -> (f64, Option<usize>) {
        let mut step = f64::INFINITY;
        let mut slot = None;
        for k in 0..q {
            if matches!(self.active[k], Constraint::Inequality(_)) && self.dual_step[k] > 0.0 {
                let ratio = self.u[k] / self.dual_step[k];
                if ratio < step {
                    step = ratio;
                    slot = Some(k);
                }
            }
        }
        (step, slot)
    }

    /// Updates `J` and `R` for the constraint just pushed onto `active` (its `d = J^T n` in
    /// `self.d`): Givens rotations of `J`'s trailing columns zero `d` below the new
    /// diagonal, which becomes `R`'s new column. `false` when the new diagonal is negligible
    /// (the normal depends on the active ones).
    fn add_to_factors(&mut self, r_norm: &mut f64) -> bool {
        let q = self.active.len() - 1;
        for col in (q + 1..self.n).rev() {
            let (a, b) = (self.d[col - 1], self.d[col]);
            let Some((cos, sin, h)) = givens(a, b) else {
                continue;
            };
            self.d[col - 1] = h;
            self.d[col] = 0.0;
            rotate_columns(&mut self.j, col - 1, col, cos, sin);
        }
        for row in 0..=q {
            self.r[(row, q)] = self.d[row];
        }
        let diagonal = self.d[q].abs();
        if diagonal <= f64::EPSILON * *r_norm {
            return false;
        }
        *r_norm = r_norm.max(diagonal);
        true
    }

    /// Removes the active constraint in `slot` (an inequality): shifts the later constraints,
    /// their multipliers (including the one being added, in the slot after the last) and
    /// `R`'s columns down, then restores `R`'s triangular form by Givens rotations of its rows,
    /// applied to `J`'s columns.
    fn drop_constraint(&mut self, slot: usize) {
        let q = self.active.len();
        if let Constraint::Inequality(i) = self.active[slot] {
            self.is_active[i] = false;
        }
        self.active.remove(slot);
        for k in slot..q {
            self.u[k] = self.u[k + 1];
        }
        self.u[q] = 0.0;
        for col in slot..q - 1 {
            for row in 0..self.n {
                self.r[(row, col)] = self.r[(row, col + 1)];
            }
        }
        for row in 0..self.n {
            self.r[(row, q - 1)] = 0.0;
        }
        for col in slot..q - 1 {
            let (a, b) = (self.r[(col, col)], self.r[(col + 1, col)]);
            let Some((cos, sin, h)) = givens(a, b) else {
                continue;
            };
            self.r[(col, col)] = h;
            self.r[(col + 1, col)] = 0.0;
            for k in col + 1..q - 1 {
                let (top, bottom) = (self.r[(col, k)], self.r[(col + 1, k)]);
                self.r[(col, k)] = cos * top + sin * bottom;
                self.r[(col + 1, k)] = sin * top - cos * bottom;
            }
            rotate_columns(&mut self.j, col, col + 1, cos, sin);
        }
    }
}

/// The reflection `[[cos, sin], [sin, -cos]]` mapping `(a, b)` to `(h, 0)` with `h >= 0`
/// (as Goldfarb-Idnani's updates use it); `None` when `b` is already zero relative to `a`
/// or both are zero.
fn givens(a: f64, b: f64) -> Option<(f64, f64, f64)> {
    let h = a.hypot(b);
    if h == 0.0 || b == 0.0 && a >= 0.0 {
        return None;
    }
    Some((a / h, b / h, h))
}

/// Applies the reflection of [`givens`] to columns `left`, `right` of `m`.
fn rotate_columns(m: &mut DMatrix<f64>, left: usize, right: usize, cos: f64, sin: f64) {
    for row in 0..m.nrows() {
        let (a, b) = (m[(row, left)], m[(row, right)]);
        m[(row, left)] = cos * a + sin * b;
        m[(row, right)] = sin * a - cos * b;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::dmatrix;
    use nalgebra::dvector;

    /// Solves with identity-free data; panics on error.
    fn solve(
        p: DMatrix<f64>,
        c: DVector<f64>,
        equality: Option<(DMatrix<f64>, DVector<f64>)>,
        g: DMatrix<f64>,
        h: DVector<f64>,
    ) -> Result<(DVector<f64>, ActiveSetReport, ActiveSetQp), ActiveSetError> {
        let n = c.len();
        let m_eq = equality.as_ref().map_or(0, |(a, _)| a.nrows());
        let mut qp = ActiveSetQp::new(n, m_eq, g.nrows());
        qp.set_inequalities(&g, &h);
        let mut x = DVector::zeros(n);
        let report = qp.solve(&p, &c, equality.as_ref().map(|(a, b)| (a, b)), &mut x)?;
        Ok((x, report, qp))
    }

    fn assert_close(x: &DVector<f64>, expected: &DVector<f64>) {
        assert!((x - expected).amax() < 1e-12, "{x} != {expected}");
    }

    #[test]
    fn without_binding_constraints_the_unconstrained_minimiser() {
        let (x, report, _) = solve(
            DMatrix::identity(2, 2),
            dvector![-1.0, -1.0],
            None,
            dmatrix![1.0, 0.0],
            dvector![2.0],
        )
        .unwrap();
        assert_close(&x, &dvector![1.0, 1.0]);
        assert_eq!(report.active_inequalities, 0);
    }

    #[test]
    fn a_box_projects_the_minimiser() {
        // min 0.5 |x - (1, 1)|^2 s.t. x <= 0.5: (0.5, 0.5), multipliers 0.5.
        let (x, report, qp) = solve(
            DMatrix::identity(2, 2),
            dvector![-1.0, -1.0],
            None,
            DMatrix::identity(2, 2),
            dvector![0.5, 0.5],
        )
        .unwrap();
        assert_close(&x, &dvector![0.5, 0.5]);
        assert_eq!(report.active_inequalities, 2);
        let (mut lambda, mut mu) = (DVector::zeros(0), DVector::zeros(2));
        qp.multipliers(&mut lambda, &mut mu);
        assert_close(&mu, &dvector![0.5, 0.5]);
    }

    #[test]
    fn equality_and_inequality_together() {
        // min 0.5 |x|^2 s.t. x1 + x2 + x3 = 3, x1 <= 0.5: x = (0.5, 1.25, 1.25), lambda =
        // -1.25, mu = 0.75 (x + lambda (1,1,1) + mu e1 = 0).
        let (x, report, qp) = solve(
            DMatrix::identity(3, 3),
            DVector::zeros(3),
            Some((dmatrix![1.0, 1.0, 1.0], dvector![3.0])),
            dmatrix![1.0, 0.0, 0.0],
            dvector![0.5],
        )
        .unwrap();
        assert_close(&x, &dvector![0.5, 1.25, 1.25]);
        assert_eq!(report.active_inequalities, 1);
        let (mut lambda, mut mu) = (DVector::zeros(1), DVector::zeros(1));
        qp.multipliers(&mut lambda, &mut mu);
        assert_close(&lambda, &dvector![-1.25]);
        assert_close(&mu, &dvector![0.75]);
    }

    /// Checks the KKT conditions of `x` with the solver's multipliers: stationarity,
    /// primal feasibility, dual feasibility, complementarity (to `tolerance`).
    fn assert_kkt(
        qp: &ActiveSetQp,
        (p, c): (&DMatrix<f64>, &DVector<f64>),
        (a, b): (&DMatrix<f64>, &DVector<f64>),
        (g, h): (&DMatrix<f64>, &DVector<f64>),
        x: &DVector<f64>,
        tolerance: f64,
    ) {
        let (mut lambda, mut mu) = (DVector::zeros(a.nrows()), DVector::zeros(g.nrows()));
        qp.multipliers(&mut lambda, &mut mu);
        let stationarity = p * x + c + a.transpose() * &lambda + g.transpose() * &mu;
        assert!((a * x - b).amax() < tolerance, "equalities {}", a * x - b);
        assert!(
            stationarity.amax() < tolerance,
            "stationarity {stationarity}"
        );
        let slack = h - g * x;
        for i in 0..g.nrows() {
            assert!(mu[i] >= 0.0 && slack[i] >= -tolerance, "{mu} {slack}");
            assert!(
                (mu[i] * slack[i]).abs() < tolerance,
                "complementarity {mu} {slack}"
            );
        }
    }

    #[test]
    fn random_qps_meet_the_kkt_conditions_including_ones_that_drop_constraints() {
        // Random strictly convex QPs in 4 variables with 10 inequalities and, in every other
        // one, 2 equalities, around a feasible point (x = 0 satisfies them all); some solves
        // drop a constraint they added (partial steps), the path the other tests do not take.
        let mut rng = sea_dyn::sample::Lcg::new(5);
        let (n, m) = (4, 10);
        let mut total_drops = 0;
        for case in 0..400 {
            let m_eq = if case % 2 == 0 { 0 } else { 2 };
            let a = DMatrix::from_fn(m_eq, n, |_, _| rng.next_signed());
            let b = DVector::zeros(m_eq);
            let root = DMatrix::from_fn(n, n, |_, _| rng.next_signed());
            let p = root.transpose() * &root + DMatrix::identity(n, n) * 0.1;
            let c = DVector::from_fn(n, |_, _| 5.0 * rng.next_signed());
            let g = DMatrix::from_fn(m, n, |_, _| rng.next_signed());
            let h = DVector::from_fn(m, |_, _| 0.5 * (rng.next_signed() + 1.0));
            let equality = (m_eq > 0).then(|| (a.clone(), b.clone()));
            let (x, report, qp) =
                solve(p.clone(), c.clone(), equality, g.clone(), h.clone()).unwrap();
            assert_kkt(&qp, (&p, &c), (&a, &b), (&g, &h), &x, 1e-9);
            total_drops += report.drops;
        }
        println!("constraints dropped: {total_drops}");
        assert!(total_drops > 0, "no solve dropped a constraint");
    }

    #[test]
    fn a_degenerate_vertex_is_solved() {
        // Three constraints through the origin, all active at the optimum (0, 0).
        let (x, _, _) = solve(
            DMatrix::identity(2, 2),
            dvector![-1.0, -1.0],
            None,
            dmatrix![1.0, 0.0; 0.0, 1.0; 1.0, 1.0],
            dvector![0.0, 0.0, 0.0],
        )
        .unwrap();
        assert_close(&x, &dvector![0.0, 0.0]);
    }

    #[test]
    fn infeasible_constraints_are_reported() {
        let result = solve(
            DMatrix::identity(1, 1),
            dvector![0.0],
            None,
            dmatrix![1.0; -1.0],
            dvector![-1.0, -1.0],
        );
        assert_eq!(result.err(), Some(ActiveSetError::Infeasible));
    }

    #[test]
    fn dependent_equalities_and_indefinite_hessians_are_reported() {
        let result = solve(
            DMatrix::identity(2, 2),
            DVector::zeros(2),
            Some((dmatrix![1.0, 1.0; 2.0, 2.0], dvector![1.0, 2.0])),
            DMatrix::zeros(0, 2),
            DVector::zeros(0),
        );
        assert_eq!(result.err(), Some(ActiveSetError::DependentEqualities));
        let result = solve(
            dmatrix![1.0, 0.0; 0.0, -1.0],
            DVector::zeros(2),
            None,
            DMatrix::zeros(0, 2),
            DVector::zeros(0),
        );
        assert_eq!(result.err(), Some(ActiveSetError::NotPositiveDefinite));
    }
}
