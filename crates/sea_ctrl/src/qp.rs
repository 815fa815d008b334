//! The contact-wrench QP, paper inputTorquesSOT (rigid joints: `min |tau*(f)|^2`, label
//! inputTorquesSOTMinTau) and inputTorquesSOTu (SEA: `min |beta*(f)|^2`, label
//! inputTorquesMinVel; the same problem after the substitutions of newJointDynamics), solved
//! with Clarabel.
//!
//! Variables: the stacked contact wrenches `f` (6 per contact, `[force; moment about the sole
//! origin]`, world axes). Objective `0.5 f^T P f + c^T f`: two feet, [`torque_norm_objective`]
//! `|tau(f)|^2` with `tau(f) = tau_bias + Sigma f` from the torque map; one foot (where `A f =
//! b` fixes `f`), [`momentum_tracking_objective`] `|A f - b|^2`; both plus a regulariser.
//! Constraints: the momentum task `Hdot(f) = Hdot*` as the equalities `A f = b` (two feet;
//! see [`crate::momentum`]) and, per contact, the contact constraints `C f <= b` (label
//! frictionCones, [`ContactConstraints::sole_rows`]) in its sole frame (`w_s =
//! blockdiag(R^T, R^T) w`): a linearised friction cone with `facets` faces inscribed in the
//! cone of coefficient `mu` (`cos(phi_k) F_x + sin(phi_k) F_y <= mu cos(pi / facets) F_z`), a
//! minimum normal force, torsional friction `|n_z| <= mu_t F_z`, and the centre of pressure
//! `(-n_y / F_z, n_x / F_z)` inside the foot rectangle.
//!
//! Clarabel works on the wrenches in their sole frames, `w = T^T f` with
//! `T = blockdiag(R_k, R_k)`: the contact constraints are then constant and sparse (at most three
//! non-zeros a row), and the rotations move into `P' = T^T P T`, `c' = T^T c` and
//! `A_eq' = A_eq T`. The problem is built once; every tick only updates values (`update_P`,
//! `update_q`, `update_A`, `update_b`; presolve off), in buffers allocated in
//! [`WrenchQp::new`]. A solve that does not end `Solved`/`AlmostSolved` is reported and
//! replaced by the unconstrained solution the caller gives.
//!
//! Order of a solve ([`WrenchQp::solve`]):
//!
//! 1. (when [`WrenchQp::unconstrained_first`] is set) the caller's minimiser without the
//!    inequalities ([`Minimizer`]) is checked against them: if it satisfies every one, it is
//!    the QP's optimum (a convex problem whose KKT conditions hold with zero inequality
//!    multipliers). While balancing, the contacts are mostly far from their friction, CoP and
//!    normal-force limits, and this check costs a few hundred flops;
//! 2. (when [`WrenchQp::solver`] is [`QpSolver::ActiveSet`], the default) the dense
//!    Goldfarb-Idnani dual active-set method of [`crate::active_set`] on the sole-frame
//!    problem: exact up to rounding, allocation-free, a few microseconds for 12 variables;
//! 3. Clarabel (interior point), the reference: when selected, or when the active set fails
//!    (iteration limit, infeasible, numerically singular);
//! 4. the unconstrained solution with a `Fallback` status when Clarabel fails too.
//!
//! With [`WrenchQp::cross_check`] on, every tick the active set solves is also solved by
//! Clarabel and the differences and constraint violations are kept in [`WrenchQp::agreement`]
//! (for tests; off by default and then not on the per-tick path).

use crate::active_set::{ActiveSetError, ActiveSetQp};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector, Matrix3};
use sea_dyn::dense::{
    backward_substitute, cholesky_in_place, cholesky_solve_in_place, copy_contiguous, dot,
    forward_substitute, gemm_small, gemm_tn,
};
use sea_dyn::ContactSurface;

/// Which solver solves the wrench QP when the minimiser without inequalities is not taken;
/// with the `serde` feature, named as [`QpSolver::name`] says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize),
    serde(rename_all = "snake_case")
)]
pub enum QpSolver {
    /// The dense Goldfarb-Idnani active-set method ([`crate::active_set`]), Clarabel as
    /// fallback.
    #[default]
    ActiveSet,
    /// Clarabel (interior point) on every solve.
    Clarabel,
}

impl QpSolver {
    /// Every solver, in the order of [`Self::name`]'s documentation.
    pub const ALL: [QpSolver; 2] = [QpSolver::ActiveSet, QpSolver::Clarabel];

    /// The setting's name: "active_set" or "clarabel".
    pub fn name(self) -> &'static str {
        match self {
            QpSolver::ActiveSet => "active_set",
            QpSolver::Clarabel => "clarabel",
        }
    }
}

/// How many solves took each path of [`WrenchQp::solve`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QpSolveCounts {
    /// The minimiser without inequalities was feasible, hence optimal.
    pub unconstrained: usize,
    /// Solved by the active-set method.
    pub active_set: usize,
    /// Solved (or attempted) by Clarabel, including the active set's fallbacks.
    pub clarabel: usize,
}

/// The agreement of the active set with Clarabel over the ticks of a cross-check
/// ([`WrenchQp::cross_check`]). Differences are Euclidean norms of force or moment 3-vectors
/// (frame independent); violations are in the constraint rows' units (N for the rows of
/// [`ContactConstraints::sole_rows`], whose normal-force coefficient is 1 or a length).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QpAgreement {
    /// Ticks compared.
    pub ticks: usize,
    /// Ticks where Clarabel failed (not compared).
    pub reference_failures: usize,
    /// Largest difference between the active set's and Clarabel's force or moment [N, Nm].
    pub max_wrench_difference: f64,
    /// Largest force or moment norm of Clarabel's solutions (the scale of the differences).
    pub max_wrench: f64,
    /// Largest `|f_active - f_clarabel|_2 / sqrt(1 + |J_clarabel|)` (whole vectors, `J` the
    /// objective `0.5 f^T P f + c^T f`): Clarabel stops at a duality gap of about
    /// `eps (1 + |J|)`, and in a QP whose Hessian is at least `lambda_min I` a feasible point
    /// that much above the optimum is within `sqrt(2 eps (1 + |J|) / lambda_min)` of it, so
    /// this ratio is bounded by `sqrt(2 eps / lambda_min)`.
    pub max_scaled_difference: f64,
    /// Largest `(J_active - J_clarabel) / (1 + |J_clarabel|)`: about rounding when both are
    /// optimal; Clarabel's point, feasible only to its tolerance, may lie below.
    pub max_objective_excess: f64,
    /// Largest KKT stationarity residual of the active set's solution with its multipliers
    /// ([`ActiveSetQp::stationarity_residual`], relative): its own optimality certificate.
    pub max_stationarity_residual: f64,
    /// Largest violation `max(C w - b, 0)` of the active set's wrenches.
    pub max_inequality_violation: f64,
    /// The same for Clarabel's wrenches (its feasibility tolerance at work).
    pub reference_max_inequality_violation: f64,
    /// Largest `|A f - b|_inf` of the active set's wrenches.
    pub max_equality_residual: f64,
    /// Largest `|b|_inf` (the scale of the residuals).
    pub max_equality_target: f64,
    /// Ticks whose active-set optimum has at least one active inequality.
    pub ticks_with_active_inequalities: usize,
    /// Most inequalities active at one optimum.
    pub max_active_inequalities: usize,
}

/// Contact constraint parameters: the contact surface (friction, torsional friction, foot
/// rectangle; shared with the plant's wrench margins) and the QP's own choices.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactConstraints {
    /// Friction coefficients and foot rectangle of each sole.
    pub surface: ContactSurface,
    /// Number of friction cone facets.
    pub facets: usize,
    /// Minimum normal force [N].
    pub min_normal_force: f64,
}

impl Default for ContactConstraints {
    /// [`ContactSurface::default`] with the original study's 12 facets and 10 N minimum normal
    /// force (REFERENCE.md, QP bullet).
    fn default() -> Self {
        Self {
            surface: ContactSurface::default(),
            facets: 12,
            min_normal_force: 10.0,
        }
    }
}

impl ContactConstraints {
    /// Inequality rows per contact.
    pub fn rows_per_contact(&self) -> usize {
        self.facets + 7
    }

    /// Paper frictionCones, `C f < b` of inputTorquesSOT for one contact in its sole frame:
    /// the rows `C_s w_s <= b_s` (rows x 6, rows; [`Self::rows_per_contact`] rows) on the sole
    /// wrench `w_s = [F; n]` (moment about the sole origin): friction facets, minimum normal
    /// force, torsional friction, centre of pressure in the foot rectangle.
    pub fn sole_rows(&self) -> (DMatrix<f64>, DVector<f64>) {
        let rows = self.rows_per_contact();
        let mut c = DMatrix::zeros(rows, 6);
        let mut b = DVector::zeros(rows);
        let surface = &self.surface;
        let inscribed = surface.friction * (std::f64::consts::PI / self.facets as f64).cos();
        for k in 0..self.facets {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / self.facets as f64;
            c[(k, 0)] = phi.cos();
            c[(k, 1)] = phi.sin();
            c[(k, 2)] = -inscribed;
        }
        let r = self.facets;
        c[(r, 2)] = -1.0;
        b[r] = -self.min_normal_force;
        c[(r + 1, 2)] = -surface.torsional_friction;
        c[(r + 1, 5)] = 1.0;
        c[(r + 2, 2)] = -surface.torsional_friction;
        c[(r + 2, 5)] = -1.0;
        let ([x_min, x_max], [y_min, y_max]) = (surface.foot_x, surface.foot_y);
        c[(r + 3, 2)] = -x_max;
        c[(r + 3, 4)] = -1.0;
        c[(r + 4, 2)] = x_min;
        c[(r + 4, 4)] = 1.0;
        c[(r + 5, 2)] = -y_max;
        c[(r + 5, 3)] = 1.0;
        c[(r + 6, 2)] = y_min;
        c[(r + 6, 3)] = -1.0;
        (c, b)
    }
}

/// How a tick's QP ended.
#[derive(Clone, Debug, PartialEq)]
pub enum QpStatus {
    /// Solved (or almost solved) by Clarabel.
    Solved,
    /// Clarabel failed; the unconstrained solution was used.
    Fallback(String),
}

/// Paper inputTorquesSOTMinTau (rigid joints) / inputTorquesMinVel (SEA, `beta` for `tau`):
/// the objective `|tau_bias + Sigma f|^2 + reg |f|^2` as `0.5 f^T P f + c^T f` (constant
/// dropped): `P = 2 (Sigma^T Sigma + reg I)` (k x k), `c = 2 Sigma^T tau_bias` (k), from
/// `Sigma` (n x k) and `tau_bias` (n) of the torque map.
pub fn torque_norm_objective(
    sigma: &DMatrix<f64>,
    tau_bias: &DVector<f64>,
    regularization: f64,
    hessian: &mut DMatrix<f64>,
    gradient: &mut DVector<f64>,
) {
    gemm_tn(hessian, 2.0, sigma, sigma, 0.0, true);
    for (entry, column) in gradient.iter_mut().zip(sigma.column_iter()) {
        *entry = 2.0 * dot(column.as_slice(), tau_bias.as_slice());
    }
    add_to_diagonal(hessian, 2.0 * regularization);
}

/// The one-contact objective: the momentum task hDot / eq:dotH_f in least squares,
/// `|A f - b|^2 + reg |f|^2` as `0.5 f^T P f + c^T f`: `P = 2 (A^T A + reg I)` (k x k),
/// `c = -2 A^T b` (k), from the momentum map `A` (6 x k) and `b = Hdot* - [m g; 0]` (6). With
/// one contact `A` is invertible, so this is `A f = b` wherever the contact constraints allow.
pub fn momentum_tracking_objective(
    momentum_map: &DMatrix<f64>,
    momentum_target: &DVector<f64>,
    regularization: f64,
    hessian: &mut DMatrix<f64>,
    gradient: &mut DVector<f64>,
) {
    hessian.gemm_tr(2.0, momentum_map, momentum_map, 0.0);
    gradient.gemv_tr(-2.0, momentum_map, momentum_target, 0.0);
    add_to_diagonal(hessian, 2.0 * regularization);
}

fn add_to_diagonal(matrix: &mut DMatrix<f64>, value: f64) {
    for i in 0..matrix.nrows() {
        matrix[(i, i)] += value;
    }
}

/// Minimisers of `0.5 f^T P f + c^T f` without the inequalities (k variables, m equality
/// rows), in buffers allocated once: the candidate the QP accepts when it is feasible, and
/// the fallback when Clarabel fails.
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

/// The contact-wrench QP for a fixed number of contacts and equality rows.
pub struct WrenchQp {
    n_contacts: usize,
    n_equalities: usize,
    sole_c: DMatrix<f64>,
    sole_b: DVector<f64>,
    /// Constraint matrix in CSC form: equality rows dense, inequality rows with the sparsity of
    /// the sole constraints; `constraint_values` follows its storage order.
    constraint_pattern: CscMatrix<f64>,
    constraint_values: Vec<f64>,
    rhs: DVector<f64>,
    /// `T = blockdiag(R_k, R_k)` of the current tick (k x k).
    rotation: DMatrix<f64>,
    /// Sole-frame problem of the current tick: `T^T P` (scratch), `P' = T^T P T` (k x k),
    /// `c' = T^T c` (k), `A_eq' = A_eq T` (n_equalities x k), the solution `w` (k).
    product: DMatrix<f64>,
    hessian_sole: DMatrix<f64>,
    gradient_sole: DVector<f64>,
    equality_sole: DMatrix<f64>,
    solution_sole: DVector<f64>,
    /// Clarabel's inputs as slices: upper triangle of `P'`, `c'`, the right-hand side.
    hessian_values: Vec<f64>,
    gradient_values: Vec<f64>,
    rhs_values: Vec<f64>,
    /// Clarabel, built on the first solve.
    clarabel: Option<DefaultSolver<f64>>,
    settings: DefaultSettings<f64>,
    /// Solves that fell back to the unconstrained solution.
    pub failures: usize,
    /// Accept the minimiser without inequalities when it satisfies them (see the module doc).
    pub unconstrained_first: bool,
    /// Solves done by Clarabel.
    pub clarabel_solves: usize,
    /// Solves where the minimiser without inequalities was feasible, hence optimal.
    pub unconstrained_solves: usize,
    /// Which solver solves when the minimiser without inequalities is not taken.
    pub solver: QpSolver,
    /// The active-set solver, its inequalities the sole rows of every contact.
    active_set: ActiveSetQp,
    /// Solves done by the active set.
    pub active_set_solves: usize,
    /// Active-set solves that failed and went to Clarabel.
    pub active_set_failures: usize,
    /// Why the last failed active-set solve failed.
    pub last_active_set_failure: Option<ActiveSetError>,
    /// Also solve every active-set tick with Clarabel and record the agreement (for tests).
    pub cross_check: bool,
    /// The cross-check's figures so far.
    pub agreement: QpAgreement,
    /// The active set's sole-frame solution during a cross-check (k), and scratch (k).
    checked_sole: DVector<f64>,
    scratch: DVector<f64>,
}

/// Column-major dense CSC matrix (all entries structural); `upper` keeps only `i <= j`.
fn dense_csc(m: &DMatrix<f64>, upper: bool) -> CscMatrix<f64> {
    let (rows, cols) = m.shape();
    let mut colptr = vec![0];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for j in 0..cols {
        let last = if upper { (j + 1).min(rows) } else { rows };
        for i in 0..last {
            rowval.push(i);
            nzval.push(m[(i, j)]);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows, cols, colptr, rowval, nzval)
}

/// Values of the upper triangle of `m` in [`dense_csc`] order.
fn upper_values(m: &DMatrix<f64>, out: &mut Vec<f64>) {
    out.clear();
    for j in 0..m.ncols() {
        out.extend((0..=j.min(m.nrows() - 1)).map(|i| m[(i, j)]));
    }
}

/// Clarabel's stopping tolerance (absolute and relative duality gap, feasibility): wrenches to
/// about 1e-7 relative are far below the model's accuracy; looser than Clarabel's defaults
/// (1e-8), which saves iterations on every tick. The bound of the cross-check's agreement
/// ([`QpAgreement::max_scaled_difference`]) follows from it.
pub const CLARABEL_TOLERANCE: f64 = 1e-7;

/// Clarabel's settings for the wrench QP.
fn clarabel_settings() -> DefaultSettings<f64> {
    DefaultSettingsBuilder::default()
        .verbose(false)
        .presolve_enable(false)
        .max_iter(100)
        .tol_gap_abs(CLARABEL_TOLERANCE)
        .tol_gap_rel(CLARABEL_TOLERANCE)
        .tol_feas(CLARABEL_TOLERANCE)
        // Measured on the two-feet iCub QP (`controller_tick_clarabel_us`): iterative
        // refinement and equilibration cost about 35 us a solve and save no iterations
        // (5 to 7 either way); termination still checks the unscaled residuals.
        .iterative_refinement_enable(false)
        .equilibrate_enable(false)
        .build()
        .expect("valid Clarabel settings")
}

/// The constraint matrix pattern (rows x 6 n_contacts, CSC) of `n_equalities` dense rows over
/// the contacts' sole rows `sole_c` (per_contact x 6): contact k's rows only on its own six
/// variables, where the sole constraint is non-zero. Equality values start at zero.
fn constraint_pattern(
    sole_c: &DMatrix<f64>,
    n_contacts: usize,
    n_equalities: usize,
) -> CscMatrix<f64> {
    let per_contact = sole_c.nrows();
    let rows = n_equalities + n_contacts * per_contact;
    let n = 6 * n_contacts;
    let mut colptr = vec![0];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for j in 0..n {
        let (contact, component) = (j / 6, j % 6);
        rowval.extend(0..n_equalities);
        nzval.extend(std::iter::repeat_n(0.0, n_equalities));
        for r in 0..per_contact {
            let value = sole_c[(r, component)];
            if value != 0.0 {
                rowval.push(n_equalities + contact * per_contact + r);
                nzval.push(value);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows, n, colptr, rowval, nzval)
}

/// One tick's figures of the cross-check (see [`QpAgreement`]).
struct TickComparison {
    difference: f64,
    scale: f64,
    scaled_difference: f64,
    objective_excess: f64,
    stationarity: f64,
    violation: f64,
    reference_violation: f64,
    residual: f64,
    target: f64,
    active: usize,
}

impl QpAgreement {
    /// Adds one compared tick.
    fn add(&mut self, tick: &TickComparison) {
        self.ticks += 1;
        self.max_wrench_difference = self.max_wrench_difference.max(tick.difference);
        self.max_wrench = self.max_wrench.max(tick.scale);
        self.max_scaled_difference = self.max_scaled_difference.max(tick.scaled_difference);
        self.max_objective_excess = if self.ticks == 1 {
            tick.objective_excess
        } else {
            self.max_objective_excess.max(tick.objective_excess)
        };
        self.max_stationarity_residual = self.max_stationarity_residual.max(tick.stationarity);
        self.max_inequality_violation = self.max_inequality_violation.max(tick.violation);
        self.reference_max_inequality_violation = self
            .reference_max_inequality_violation
            .max(tick.reference_violation);
        self.max_equality_residual = self.max_equality_residual.max(tick.residual);
        self.max_equality_target = self.max_equality_target.max(tick.target);
        self.ticks_with_active_inequalities += usize::from(tick.active > 0);
        self.max_active_inequalities = self.max_active_inequalities.max(tick.active);
    }
}

/// The inequality rows of `n_contacts` contacts in their sole frames: `sole_c` (rows x 6) on
/// each contact's six variables (block diagonal, rows n_contacts x 6 n_contacts) and
/// `sole_b` repeated.
fn block_diagonal_rows(
    sole_c: &DMatrix<f64>,
    sole_b: &DVector<f64>,
    n_contacts: usize,
) -> (DMatrix<f64>, DVector<f64>) {
    let rows = sole_c.nrows();
    let mut c = DMatrix::zeros(rows * n_contacts, 6 * n_contacts);
    let mut b = DVector::zeros(rows * n_contacts);
    for k in 0..n_contacts {
        c.view_mut((k * rows, 6 * k), (rows, 6)).copy_from(sole_c);
        b.rows_mut(k * rows, rows).copy_from(sole_b);
    }
    (c, b)
}

/// `|a - b|_2`.
fn distance(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

/// The largest Euclidean norm of the difference of two stacked wrenches' force or moment
/// 3-vectors, and the largest such norm of `reference`.
fn wrench_difference(solution: &DVector<f64>, reference: &DVector<f64>) -> (f64, f64) {
    let (mut difference, mut scale): (f64, f64) = (0.0, 0.0);
    for start in (0..solution.len()).step_by(3) {
        let a = solution.fixed_rows::<3>(start);
        let b = reference.fixed_rows::<3>(start);
        difference = difference.max((a - b).norm());
        scale = scale.max(b.norm());
    }
    (difference, scale)
}

impl WrenchQp {
    /// A QP for `n_contacts` wrenches and `n_equalities` equality rows (0 or 6).
    pub fn new(n_contacts: usize, n_equalities: usize, constraints: &ContactConstraints) -> Self {
        let (sole_c, sole_b) = constraints.sole_rows();
        let per_contact = sole_c.nrows();
        let rows = n_equalities + n_contacts * per_contact;
        let n = 6 * n_contacts;
        let mut rhs = DVector::zeros(rows);
        for contact in 0..n_contacts {
            rhs.rows_mut(n_equalities + contact * per_contact, per_contact)
                .copy_from(&sole_b);
        }
        let constraint_pattern = constraint_pattern(&sole_c, n_contacts, n_equalities);
        let mut active_set = ActiveSetQp::new(n, n_equalities, n_contacts * per_contact);
        let (block_c, block_b) = block_diagonal_rows(&sole_c, &sole_b, n_contacts);
        active_set.set_inequalities(&block_c, &block_b);
        Self {
            n_contacts,
            n_equalities,
            sole_c,
            sole_b,
            constraint_values: constraint_pattern.nzval.clone(),
            constraint_pattern,
            rhs,
            rotation: DMatrix::zeros(n, n),
            product: DMatrix::zeros(n, n),
            hessian_sole: DMatrix::zeros(n, n),
            gradient_sole: DVector::zeros(n),
            equality_sole: DMatrix::zeros(n_equalities, n),
            solution_sole: DVector::zeros(n),
            hessian_values: Vec::with_capacity(n * (n + 1) / 2),
            gradient_values: vec![0.0; n],
            rhs_values: vec![0.0; rows],
            clarabel: None,
            settings: clarabel_settings(),
            failures: 0,
            unconstrained_first: true,
            clarabel_solves: 0,
            unconstrained_solves: 0,
            solver: QpSolver::default(),
            active_set,
            active_set_solves: 0,
            active_set_failures: 0,
            last_active_set_failure: None,
            cross_check: false,
            agreement: QpAgreement::default(),
            checked_sole: DVector::zeros(n),
            scratch: DVector::zeros(n),
        }
    }

    /// How many solves took each path.
    pub fn solve_counts(&self) -> QpSolveCounts {
        QpSolveCounts {
            unconstrained: self.unconstrained_solves,
            active_set: self.active_set_solves,
            clarabel: self.clarabel_solves,
        }
    }

    /// Number of variables `6 n_contacts`.
    pub fn n_variables(&self) -> usize {
        6 * self.n_contacts
    }

    /// The inequality rows `C f <= b` in world axes for sole rotations `world_R_sole`
    /// (for checks: the solver itself works in the sole frames).
    pub fn inequalities(&self, rotations: &[Matrix3<f64>]) -> (DMatrix<f64>, DVector<f64>) {
        let rows = self.sole_c.nrows();
        let mut c = DMatrix::zeros(rows * self.n_contacts, self.n_variables());
        let mut b = DVector::zeros(rows * self.n_contacts);
        for (k, rotation) in rotations.iter().enumerate() {
            let mut t = DMatrix::zeros(6, 6);
            t.view_mut((0, 0), (3, 3)).copy_from(&rotation.transpose());
            t.view_mut((3, 3), (3, 3)).copy_from(&rotation.transpose());
            c.view_mut((k * rows, 6 * k), (rows, 6))
                .copy_from(&(&self.sole_c * t));
            b.rows_mut(k * rows, rows).copy_from(&self.sole_b);
        }
        (c, b)
    }

    /// Whether the world wrenches `f` satisfy every contact inequality (`C f <= b`, exactly) for
    /// sole rotations `world_R_sole`.
    pub fn satisfies_inequalities(&self, f: &DVector<f64>, rotations: &[Matrix3<f64>]) -> bool {
        rotations.iter().enumerate().all(|(k, rotation)| {
            let force = rotation.tr_mul(&f.fixed_rows::<3>(6 * k));
            let moment = rotation.tr_mul(&f.fixed_rows::<3>(6 * k + 3));
            let sole = [force.x, force.y, force.z, moment.x, moment.y, moment.z];
            self.sole_rows(sole).all(|(value, bound)| value <= bound)
        })
    }

    /// `(C_s w_s, b_s)` row by row for one contact's sole-frame wrench `w_s`.
    fn sole_rows(&self, w_s: [f64; 6]) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.sole_c
            .row_iter()
            .zip(self.sole_b.iter())
            .map(move |(row, &bound)| {
                let value = row.iter().zip(&w_s).map(|(c, w)| c * w).sum::<f64>();
                (value, bound)
            })
    }

    /// Solves `min 0.5 f^T P f + c^T f` s.t. `A_eq f = b_eq`, `C f <= b` (world wrenches) into
    /// `wrenches` (k). `unconstrained` is the minimiser without `C f <= b` (None if it could
    /// not be computed): returned directly when feasible (see the module doc), and on
    /// Clarabel's failure returned with a `Fallback` status (zeros if None); otherwise the
    /// active set or Clarabel solves (the order of the module doc). `P` must be symmetric
    /// positive definite (k x k). The active-set path allocates nothing; Clarabel allocates
    /// when it builds its solver (first solve), its own work, and a failure's message.
    pub fn solve(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
        equality: Option<(&DMatrix<f64>, &DVector<f64>)>,
        rotations: &[Matrix3<f64>],
        unconstrained: Option<&DVector<f64>>,
        wrenches: &mut DVector<f64>,
    ) -> QpStatus {
        if let Some(f) = unconstrained {
            if self.unconstrained_first && self.satisfies_inequalities(f, rotations) {
                self.unconstrained_solves += 1;
                wrenches.copy_from(f);
                return QpStatus::Solved;
            }
        }
        self.rotate_into_sole_frames(hessian, gradient, equality, rotations);
        if self.solver == QpSolver::ActiveSet {
            let b_eq = equality.map(|(_, b)| b);
            if let Some(active) = self.solve_active_set(b_eq) {
                if self.cross_check {
                    self.compare_with_clarabel(b_eq, active);
                }
                wrenches.gemv(1.0, &self.rotation, &self.solution_sole, 0.0);
                return QpStatus::Solved;
            }
        }
        self.clarabel_solves += 1;
        match self.solve_clarabel() {
            Ok(()) => {
                wrenches.gemv(1.0, &self.rotation, &self.solution_sole, 0.0);
                QpStatus::Solved
            }
            Err(reason) => {
                self.failures += 1;
                match unconstrained {
                    Some(f) => wrenches.copy_from(f),
                    None => wrenches.as_mut_slice().fill(0.0),
                }
                QpStatus::Fallback(reason)
            }
        }
    }

    /// The active set on the sole-frame problem of [`Self::rotate_into_sole_frames`] (`b_eq`
    /// the equality targets), the solution into `solution_sole`; the number of active
    /// inequalities, or `None` (counted) when it fails.
    fn solve_active_set(&mut self, b_eq: Option<&DVector<f64>>) -> Option<usize> {
        let equality = b_eq.map(|b| (&self.equality_sole, b));
        let result = self.active_set.solve(
            &self.hessian_sole,
            &self.gradient_sole,
            equality,
            &mut self.solution_sole,
        );
        match result {
            Ok(report) => {
                self.active_set_solves += 1;
                Some(report.active_inequalities)
            }
            Err(error) => {
                self.active_set_failures += 1;
                self.last_active_set_failure = Some(error);
                None
            }
        }
    }

    /// The cross-check: Clarabel on the same sole-frame problem, its differences from the
    /// active set's solution (in `solution_sole`, restored afterwards) and both solutions'
    /// constraint violations into [`Self::agreement`]; `active` inequalities were active.
    fn compare_with_clarabel(&mut self, b_eq: Option<&DVector<f64>>, active: usize) {
        copy_contiguous(&mut self.checked_sole, &self.solution_sole);
        if self.solve_clarabel().is_err() {
            self.agreement.reference_failures += 1;
            copy_contiguous(&mut self.solution_sole, &self.checked_sole);
            return;
        }
        let (reference, checked) = (&self.solution_sole, &self.checked_sole);
        let (difference, scale) = wrench_difference(checked, reference);
        let objective_reference = self.sole_objective(reference);
        let objective = self.sole_objective(checked);
        let (residual, target) = match b_eq {
            Some(b) => {
                self.scratch.rows_mut(0, b.len()).copy_from(b);
                let mut residual = self.scratch.rows_mut(0, b.len());
                residual.gemv(1.0, &self.equality_sole, checked, -1.0);
                (residual.amax(), b.amax())
            }
            None => (0.0, 0.0),
        };
        let equality = b_eq.map(|_| &self.equality_sole);
        let stationarity = self.active_set.stationarity_residual(
            &self.hessian_sole,
            &self.gradient_sole,
            equality,
            checked,
            &mut self.scratch,
        );
        let root = (1.0 + objective_reference.abs()).sqrt();
        let tick = TickComparison {
            difference,
            scale,
            scaled_difference: distance(checked, reference) / root,
            objective_excess: (objective - objective_reference) / (root * root),
            stationarity,
            violation: self.inequality_violation(checked),
            reference_violation: self.inequality_violation(reference),
            residual,
            target,
            active,
        };
        self.agreement.add(&tick);
        copy_contiguous(&mut self.solution_sole, &self.checked_sole);
    }

    /// `0.5 w^T P' w + c'^T w` of the sole-frame problem.
    fn sole_objective(&self, w: &DVector<f64>) -> f64 {
        let quadratic: f64 = self
            .hessian_sole
            .column_iter()
            .zip(w.iter())
            .map(|(column, w_j)| column.dot(w) * w_j)
            .sum();
        0.5 * quadratic + self.gradient_sole.dot(w)
    }

    /// `max(C_s w_s - b_s, 0)` over every contact's sole rows for sole-frame wrenches `w`.
    fn inequality_violation(&self, w: &DVector<f64>) -> f64 {
        let mut worst: f64 = 0.0;
        for k in 0..self.n_contacts {
            let w_k = w.fixed_rows::<6>(6 * k);
            let sole = [w_k[0], w_k[1], w_k[2], w_k[3], w_k[4], w_k[5]];
            for (value, bound) in self.sole_rows(sole) {
                worst = worst.max(value - bound);
            }
        }
        worst
    }

    /// The problem in the sole-frame variables `w = T^T f`: `T`, `P' = T^T P T`, `c' = T^T c`,
    /// and the equality values `A_eq' = A_eq T`, `b_eq` into the constraint data.
    fn rotate_into_sole_frames(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
        equality: Option<(&DMatrix<f64>, &DVector<f64>)>,
        rotations: &[Matrix3<f64>],
    ) {
        self.rotation.as_mut_slice().fill(0.0);
        for (k, r) in rotations.iter().enumerate() {
            self.rotation.view_mut((6 * k, 6 * k), (3, 3)).copy_from(r);
            self.rotation
                .view_mut((6 * k + 3, 6 * k + 3), (3, 3))
                .copy_from(r);
        }
        self.product.gemm_tr(1.0, &self.rotation, hessian, 0.0);
        let (product, rotation) = (self.product.as_view(), self.rotation.as_view());
        gemm_small(&mut self.hessian_sole, 1.0, product, rotation, 0.0);
        self.gradient_sole
            .gemv_tr(1.0, &self.rotation, gradient, 0.0);
        if let Some((a_eq, b_eq)) = equality {
            gemm_small(
                &mut self.equality_sole,
                1.0,
                a_eq.as_view(),
                self.rotation.as_view(),
                0.0,
            );
            self.rhs.rows_mut(0, self.n_equalities).copy_from(b_eq);
            // Equality rows are the first n_equalities entries of every column.
            let mut index = 0;
            for j in 0..self.n_variables() {
                let count =
                    self.constraint_pattern.colptr[j + 1] - self.constraint_pattern.colptr[j];
                for i in 0..self.n_equalities {
                    self.constraint_values[index + i] = self.equality_sole[(i, j)];
                }
                index += count;
            }
        }
    }

    /// Clarabel on the sole-frame problem of [`Self::rotate_into_sole_frames`], the solution into
    /// `solution_sole`; builds the solver on the first call (or after an update fails).
    fn solve_clarabel(&mut self) -> Result<(), String> {
        self.gradient_values
            .copy_from_slice(self.gradient_sole.as_slice());
        self.rhs_values.copy_from_slice(self.rhs.as_slice());
        upper_values(&self.hessian_sole, &mut self.hessian_values);
        let updated = match self.clarabel.as_mut() {
            Some(solver) => {
                solver.update_P(&self.hessian_values).is_ok()
                    && solver.update_A(&self.constraint_values).is_ok()
                    && solver.update_q(&self.gradient_values).is_ok()
                    && solver.update_b(&self.rhs_values).is_ok()
            }
            None => false,
        };
        if !updated {
            self.build_solver()?;
        }
        let solver = self.clarabel.as_mut().expect("solver was just built");
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                let x = &solver.solution.x;
                if x.iter().all(|v| v.is_finite()) {
                    self.solution_sole.copy_from_slice(x);
                    Ok(())
                } else {
                    Err("non-finite solution".into())
                }
            }
            other => Err(format!("{other:?}")),
        }
    }

    /// A new Clarabel solver for the current problem data (allocates: once per controller).
    fn build_solver(&mut self) -> Result<(), String> {
        let cones = if self.n_equalities > 0 {
            vec![
                SupportedConeT::ZeroConeT(self.n_equalities),
                SupportedConeT::NonnegativeConeT(self.rhs.len() - self.n_equalities),
            ]
        } else {
            vec![SupportedConeT::NonnegativeConeT(self.rhs.len())]
        };
        let p = dense_csc(&self.hessian_sole, true);
        let mut a = self.constraint_pattern.clone();
        a.nzval.copy_from_slice(&self.constraint_values);
        let solver = DefaultSolver::new(
            &p,
            &self.gradient_values,
            &a,
            &self.rhs_values,
            &cones,
            self.settings.clone(),
        )
        .map_err(|e| format!("setup failed: {e}"))?;
        self.clarabel = Some(solver);
        Ok(())
    }
}
