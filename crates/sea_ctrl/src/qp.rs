//! The contact-wrench QP (paper eq:inputTorquesSOT), solved with Clarabel.
//!
//! Variables: the stacked contact wrenches `f` (6 per contact, `[force; moment about the sole
//! origin]`, world axes). Objective `0.5 f^T P f + c^T f` given by the controller (one foot:
//! momentum tracking `|A f - b|^2`; two feet: `|tau(f)|^2`), plus a regulariser. Constraints:
//! optional equalities `A f = b` (two feet: the momentum task) and, per contact, in its sole
//! frame (`w_s = blockdiag(R^T, R^T) w`): a linearised friction cone with `facets` faces
//! inscribed in the cone of coefficient `mu` (`cos(phi_k) F_x + sin(phi_k) F_y <= mu cos(pi /
//! facets) F_z`), a minimum normal force, torsional friction `|n_z| <= mu_t F_z`, and the centre
//! of pressure `(-n_y / F_z, n_x / F_z)` inside the foot rectangle.
//!
//! Clarabel works on the wrenches in their sole frames, `w = T^T f` with
//! `T = blockdiag(R_k, R_k)`: the contact constraints are then constant and sparse (at most three
//! non-zeros a row), and the rotations move into `P' = T^T P T`, `c' = T^T c` and
//! `A_eq' = A_eq T`. The problem is built once; every tick only updates values (`update_P`,
//! `update_q`, `update_A`, `update_b`; presolve off). A solve that does not end
//! `Solved`/`AlmostSolved` is reported and replaced by the unconstrained solution the caller
//! gives.
//!
//! Before Clarabel (when [`WrenchQp::unconstrained_first`] is set) the caller's minimiser
//! without the inequalities is checked against them: if it satisfies every one, it is the QP's
//! optimum (a convex problem whose KKT conditions hold with zero inequality multipliers), so
//! the interior-point solve is skipped. While balancing, the contacts are mostly far from
//! their friction, CoP and normal-force limits, and this check costs a few hundred flops
//! against Clarabel's tens of microseconds; when a constraint binds, Clarabel solves.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector, Matrix3};
use sea_dyn::ContactSurface;

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

    /// Sole-frame constraint rows `C_s w_s <= b_s` for one contact (rows x 6, rows).
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
    solver: Option<DefaultSolver<f64>>,
    settings: DefaultSettings<f64>,
    /// Solves that fell back to the unconstrained solution.
    pub failures: usize,
    /// Accept the minimiser without inequalities when it satisfies them (see the module doc).
    pub unconstrained_first: bool,
    /// Solves done by Clarabel.
    pub clarabel_solves: usize,
    /// Solves where the minimiser without inequalities was feasible, hence optimal.
    pub unconstrained_solves: usize,
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

impl WrenchQp {
    /// A QP for `n_contacts` wrenches and `n_equalities` equality rows (0 or 6).
    pub fn new(n_contacts: usize, n_equalities: usize, constraints: &ContactConstraints) -> Self {
        let (sole_c, sole_b) = constraints.sole_rows();
        let per_contact = sole_c.nrows();
        let rows = n_equalities + n_contacts * per_contact;
        let n = 6 * n_contacts;
        // Pattern: equality rows dense; contact k's rows only on its own six variables, where
        // the sole constraint is non-zero.
        let mut colptr = vec![0];
        let mut rowval = Vec::new();
        let mut nzval = Vec::new();
        let mut rhs = DVector::zeros(rows);
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
        for contact in 0..n_contacts {
            rhs.rows_mut(n_equalities + contact * per_contact, per_contact)
                .copy_from(&sole_b);
        }
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .presolve_enable(false)
            .max_iter(100)
            // Wrenches to 1e-7 relative are far below the model's accuracy; the looser gap and
            // feasibility tolerances save iterations on every tick.
            .tol_gap_abs(1e-7)
            .tol_gap_rel(1e-7)
            .tol_feas(1e-7)
            // Measured on the two-feet iCub QP (`controller_tick_clarabel_us`): iterative
            // refinement and equilibration cost about 35 us a solve and save no iterations
            // (5 to 7 either way); termination still checks the unscaled residuals.
            .iterative_refinement_enable(false)
            .equilibrate_enable(false)
            .build()
            .expect("valid Clarabel settings");
        Self {
            n_contacts,
            n_equalities,
            sole_c,
            sole_b,
            constraint_values: nzval.clone(),
            constraint_pattern: CscMatrix::new(rows, n, colptr, rowval, nzval),
            rhs,
            rotation: DMatrix::zeros(n, n),
            solver: None,
            settings,
            failures: 0,
            unconstrained_first: true,
            clarabel_solves: 0,
            unconstrained_solves: 0,
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
            self.sole_c
                .row_iter()
                .zip(self.sole_b.iter())
                .all(|(row, &bound)| {
                    row.iter().zip(&sole).map(|(c, w)| c * w).sum::<f64>() <= bound
                })
        })
    }

    /// Solves `min 0.5 f^T P f + c^T f` s.t. `A_eq f = b_eq`, `C f <= b` (world wrenches).
    /// `unconstrained` is the minimiser without `C f <= b` (None if it could not be
    /// computed): returned directly when feasible (see the module doc), and on Clarabel's
    /// failure returned with a `Fallback` status (zeros if None). `P` must be symmetric
    /// positive definite (n x n).
    pub fn solve(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
        equality: Option<(&DMatrix<f64>, &DVector<f64>)>,
        rotations: &[Matrix3<f64>],
        unconstrained: Option<&DVector<f64>>,
    ) -> (DVector<f64>, QpStatus) {
        if let Some(f) = unconstrained {
            if self.unconstrained_first && self.satisfies_inequalities(f, rotations) {
                self.unconstrained_solves += 1;
                return (f.clone(), QpStatus::Solved);
            }
        }
        self.clarabel_solves += 1;
        self.rotation.fill(0.0);
        for (k, r) in rotations.iter().enumerate() {
            self.rotation.view_mut((6 * k, 6 * k), (3, 3)).copy_from(r);
            self.rotation
                .view_mut((6 * k + 3, 6 * k + 3), (3, 3))
                .copy_from(r);
        }
        let t = &self.rotation;
        let hessian_sole = t.transpose() * hessian * t;
        let gradient_sole = t.transpose() * gradient;
        if let Some((a_eq, b_eq)) = equality {
            let a_sole = a_eq * t;
            self.rhs.rows_mut(0, self.n_equalities).copy_from(b_eq);
            // Equality rows are the first n_equalities entries of every column.
            let mut index = 0;
            for j in 0..self.n_variables() {
                let count =
                    self.constraint_pattern.colptr[j + 1] - self.constraint_pattern.colptr[j];
                for i in 0..self.n_equalities {
                    self.constraint_values[index + i] = a_sole[(i, j)];
                }
                index += count;
            }
        }
        match self.solve_clarabel(&hessian_sole, &gradient_sole) {
            Ok(w) => (&self.rotation * w, QpStatus::Solved),
            Err(reason) => {
                self.failures += 1;
                let fallback = unconstrained
                    .cloned()
                    .unwrap_or_else(|| DVector::zeros(self.n_variables()));
                (fallback, QpStatus::Fallback(reason))
            }
        }
    }

    fn solve_clarabel(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
    ) -> Result<DVector<f64>, String> {
        let q = gradient.as_slice().to_vec();
        let b = self.rhs.as_slice().to_vec();
        let updated = match self.solver.as_mut() {
            Some(solver) => {
                let mut values = Vec::new();
                upper_values(hessian, &mut values);
                solver.update_P(&values).is_ok()
                    && solver.update_A(&self.constraint_values).is_ok()
                    && solver.update_q(&q).is_ok()
                    && solver.update_b(&b).is_ok()
            }
            None => false,
        };
        if !updated {
            let cones = if self.n_equalities > 0 {
                vec![
                    SupportedConeT::ZeroConeT(self.n_equalities),
                    SupportedConeT::NonnegativeConeT(self.rhs.len() - self.n_equalities),
                ]
            } else {
                vec![SupportedConeT::NonnegativeConeT(self.rhs.len())]
            };
            let p = dense_csc(hessian, true);
            let mut a = self.constraint_pattern.clone();
            a.nzval.copy_from_slice(&self.constraint_values);
            let solver = DefaultSolver::new(&p, &q, &a, &b, &cones, self.settings.clone())
                .map_err(|e| format!("setup failed: {e}"))?;
            self.solver = Some(solver);
        }
        let solver = self.solver.as_mut().expect("solver was just built");
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                let x = DVector::from_column_slice(&solver.solution.x);
                if x.iter().all(|v| v.is_finite()) {
                    Ok(x)
                } else {
                    Err("non-finite solution".into())
                }
            }
            other => Err(format!("{other:?}")),
        }
    }
}
