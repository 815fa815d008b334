//! The Clarabel adapter: the sole-frame problem of [`SoleFrameProblem`] as a Clarabel
//! problem (interior point), the reference and fallback of the active set.
//!
//! In the sole-frame variables the contact constraints are constant and sparse (at most
//! three non-zeros a row); only `P'`, `c'`, `A_eq'` and `b_eq` change. The solver is built
//! once (first solve); every later solve only updates values (`update_P`, `update_q`,
//! `update_A`, `update_b`; presolve off), in buffers allocated in [`ClarabelQp::new`].

use super::problem::SoleFrameProblem;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector};

/// Clarabel's stopping tolerance (absolute and relative duality gap, feasibility): wrenches to
/// about 1e-7 relative are far below the model's accuracy; looser than Clarabel's defaults
/// (1e-8), which saves iterations on every tick. The bound of the cross-check's agreement
/// ([`super::QpAgreement::max_scaled_difference`]) follows from it.
pub const CLARABEL_TOLERANCE: f64 = 1e-7;

/// Clarabel on the wrench QP's sole-frame problem, with its value buffers.
pub(super) struct ClarabelQp {
    n_equalities: usize,
    /// Constraint matrix in CSC form: equality rows dense, inequality rows with the sparsity of
    /// the sole constraints; `constraint_values` follows its storage order.
    constraint_pattern: CscMatrix<f64>,
    constraint_values: Vec<f64>,
    /// Clarabel's inputs as slices: upper triangle of `P'`, `c'`, the right-hand side (`b_eq`
    /// then every contact's `b_s`).
    hessian_values: Vec<f64>,
    gradient_values: Vec<f64>,
    rhs_values: Vec<f64>,
    /// Clarabel, built on the first solve.
    solver: Option<DefaultSolver<f64>>,
    settings: DefaultSettings<f64>,
}

impl ClarabelQp {
    /// Buffers for `problem`'s size and constraint rows.
    pub(super) fn new(problem: &SoleFrameProblem) -> Self {
        let (sole_b, n_equalities) = (&problem.sole_b, problem.n_equalities);
        let per_contact = sole_b.len();
        let rows = n_equalities + problem.n_contacts * per_contact;
        let n = problem.n_variables();
        let mut rhs_values = vec![0.0; rows];
        for contact in 0..problem.n_contacts {
            let start = n_equalities + contact * per_contact;
            rhs_values[start..start + per_contact].copy_from_slice(sole_b.as_slice());
        }
        let constraint_pattern =
            constraint_pattern(&problem.sole_c, problem.n_contacts, n_equalities);
        Self {
            n_equalities,
            constraint_values: constraint_pattern.nzval.clone(),
            constraint_pattern,
            hessian_values: Vec::with_capacity(n * (n + 1) / 2),
            gradient_values: vec![0.0; n],
            rhs_values,
            solver: None,
            settings: clarabel_settings(),
        }
    }

    /// Solves `problem` (with the equality targets `b_eq` when it has equality rows) into
    /// `solution` (sole-frame wrenches); builds the solver on the first call (or after an
    /// update fails). The error says why Clarabel did not solve.
    pub(super) fn solve(
        &mut self,
        problem: &SoleFrameProblem,
        b_eq: Option<&DVector<f64>>,
        solution: &mut DVector<f64>,
    ) -> Result<(), String> {
        if let Some(b_eq) = b_eq {
            self.set_equalities(&problem.equality, b_eq);
        }
        self.gradient_values
            .copy_from_slice(problem.gradient.as_slice());
        upper_values(&problem.hessian, &mut self.hessian_values);
        let updated = match self.solver.as_mut() {
            Some(solver) => {
                solver.update_P(&self.hessian_values).is_ok()
                    && solver.update_A(&self.constraint_values).is_ok()
                    && solver.update_q(&self.gradient_values).is_ok()
                    && solver.update_b(&self.rhs_values).is_ok()
            }
            None => false,
        };
        if !updated {
            self.solver = Some(self.new_solver(&problem.hessian, self.settings.clone())?);
        }
        let solver = self.solver.as_mut().expect("solver was just built");
        match solved(solver, solution) {
            Err(SolverStatus::MaxIterations) => {
                // Equilibration off (the per-tick settings) stalls on some badly scaled
                // problems; one solve with it on, in a solver of its own, keeps the fast one.
                let mut settings = self.settings.clone();
                settings.equilibrate_enable = true;
                let mut equilibrated = self.new_solver(&problem.hessian, settings)?;
                solved(&mut equilibrated, solution).map_err(|status| format!("{status:?}"))
            }
            result => result.map_err(|status| format!("{status:?}")),
        }
    }

    /// `A_eq'` into the equality rows of the constraint values (the first `n_equalities`
    /// entries of every column) and `b_eq` into the right-hand side.
    fn set_equalities(&mut self, equality: &DMatrix<f64>, b_eq: &DVector<f64>) {
        self.rhs_values[..self.n_equalities].copy_from_slice(b_eq.as_slice());
        let mut index = 0;
        for j in 0..equality.ncols() {
            let count = self.constraint_pattern.colptr[j + 1] - self.constraint_pattern.colptr[j];
            for i in 0..self.n_equalities {
                self.constraint_values[index + i] = equality[(i, j)];
            }
            index += count;
        }
    }

    /// A new Clarabel solver for the current values with `settings`, `hessian` = `P'`
    /// (allocates: once per controller, and for the equilibrated retry of [`Self::solve`]).
    fn new_solver(
        &self,
        hessian: &DMatrix<f64>,
        settings: DefaultSettings<f64>,
    ) -> Result<DefaultSolver<f64>, String> {
        let rows = self.rhs_values.len();
        let cones = if self.n_equalities > 0 {
            vec![
                SupportedConeT::ZeroConeT(self.n_equalities),
                SupportedConeT::NonnegativeConeT(rows - self.n_equalities),
            ]
        } else {
            vec![SupportedConeT::NonnegativeConeT(rows)]
        };
        let p = dense_csc(hessian, true);
        let mut a = self.constraint_pattern.clone();
        a.nzval.copy_from_slice(&self.constraint_values);
        DefaultSolver::new(
            &p,
            &self.gradient_values,
            &a,
            &self.rhs_values,
            &cones,
            settings,
        )
        .map_err(|e| format!("setup failed: {e}"))
    }
}

/// Solves with `solver` into `solution`; the status when it did not solve (or `Unsolved` for a
/// non-finite solution).
fn solved(
    solver: &mut DefaultSolver<f64>,
    solution: &mut DVector<f64>,
) -> Result<(), SolverStatus> {
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            let x = &solver.solution.x;
            if x.iter().all(|v| v.is_finite()) {
                solution.copy_from_slice(x);
                Ok(())
            } else {
                Err(SolverStatus::Unsolved)
            }
        }
        other => Err(other),
    }
}

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
