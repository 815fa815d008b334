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
//! The Clarabel problem is built once with dense (all structural non-zero) matrices, so every
//! tick only updates values (`update_P`, `update_q`, `update_A`, `update_b`; presolve off). A
//! solve that does not end `Solved`/`AlmostSolved` is reported and replaced by the
//! unconstrained solution the caller gives.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector, Matrix3};

/// Contact constraint parameters (REFERENCE.md: 12 facets, mu = 1, torsional 2/150, minimum
/// normal force 10 N, foot x in [-0.05, 0.10] m, y in [-0.025, 0.025] m).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactConstraints {
    /// Friction coefficient `mu`.
    pub friction: f64,
    /// Number of friction cone facets.
    pub facets: usize,
    /// Torsional friction coefficient `mu_t` [m].
    pub torsional_friction: f64,
    /// Minimum normal force [N].
    pub min_normal_force: f64,
    /// Foot rectangle along the sole x axis [m].
    pub foot_x: [f64; 2],
    /// Foot rectangle along the sole y axis [m].
    pub foot_y: [f64; 2],
}

impl Default for ContactConstraints {
    fn default() -> Self {
        Self {
            friction: 1.0,
            facets: 12,
            torsional_friction: 2.0 / 150.0,
            min_normal_force: 10.0,
            foot_x: [-0.05, 0.10],
            foot_y: [-0.025, 0.025],
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
        let inscribed = self.friction * (std::f64::consts::PI / self.facets as f64).cos();
        for k in 0..self.facets {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / self.facets as f64;
            c[(k, 0)] = phi.cos();
            c[(k, 1)] = phi.sin();
            c[(k, 2)] = -inscribed;
        }
        let r = self.facets;
        c[(r, 2)] = -1.0;
        b[r] = -self.min_normal_force;
        c[(r + 1, 2)] = -self.torsional_friction;
        c[(r + 1, 5)] = 1.0;
        c[(r + 2, 2)] = -self.torsional_friction;
        c[(r + 2, 5)] = -1.0;
        let ([x_min, x_max], [y_min, y_max]) = (self.foot_x, self.foot_y);
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
    /// Dense constraint matrix `[A_eq; C]` and right side, refreshed each tick.
    constraint: DMatrix<f64>,
    rhs: DVector<f64>,
    solver: Option<DefaultSolver<f64>>,
    settings: DefaultSettings<f64>,
    /// Solves that fell back to the unconstrained solution.
    pub failures: usize,
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

/// Values of [`dense_csc`] in the same order.
fn dense_values(m: &DMatrix<f64>, upper: bool, out: &mut Vec<f64>) {
    out.clear();
    let (rows, cols) = m.shape();
    for j in 0..cols {
        let last = if upper { (j + 1).min(rows) } else { rows };
        out.extend((0..last).map(|i| m[(i, j)]));
    }
}

impl WrenchQp {
    /// A QP for `n_contacts` wrenches and `n_equalities` equality rows (0 or 6).
    pub fn new(n_contacts: usize, n_equalities: usize, constraints: &ContactConstraints) -> Self {
        let (sole_c, sole_b) = constraints.sole_rows();
        let rows = n_equalities + n_contacts * sole_c.nrows();
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .presolve_enable(false)
            .max_iter(100)
            .build()
            .expect("valid Clarabel settings");
        Self {
            n_contacts,
            n_equalities,
            sole_c,
            sole_b,
            constraint: DMatrix::zeros(rows, 6 * n_contacts),
            rhs: DVector::zeros(rows),
            solver: None,
            settings,
            failures: 0,
        }
    }

    /// Number of variables `6 n_contacts`.
    pub fn n_variables(&self) -> usize {
        6 * self.n_contacts
    }

    /// The inequality rows `C f <= b` in world axes for sole rotations `world_R_sole`.
    pub fn inequalities(&self, rotations: &[Matrix3<f64>]) -> (DMatrix<f64>, DVector<f64>) {
        let rows = self.sole_c.nrows();
        let mut c = DMatrix::zeros(rows * self.n_contacts, self.n_variables());
        let mut b = DVector::zeros(rows * self.n_contacts);
        for (k, rotation) in rotations.iter().enumerate() {
            let rt = rotation.transpose();
            for r in 0..rows {
                for part in 0..2 {
                    // Row r of C_s acting on R^T w_part: (C_s[r, part] R^T) w_part.
                    let sole = nalgebra::RowVector3::new(
                        self.sole_c[(r, 3 * part)],
                        self.sole_c[(r, 3 * part + 1)],
                        self.sole_c[(r, 3 * part + 2)],
                    );
                    let world = sole * rt;
                    for a in 0..3 {
                        c[(k * rows + r, 6 * k + 3 * part + a)] = world[a];
                    }
                }
                b[k * rows + r] = self.sole_b[r];
            }
        }
        (c, b)
    }

    /// Solves `min 0.5 f^T P f + c^T f` s.t. `A_eq f = b_eq`, `C f <= b`; on failure returns
    /// `fallback` with a `Fallback` status. `P` must be symmetric positive definite (n x n).
    pub fn solve(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
        equality: Option<(&DMatrix<f64>, &DVector<f64>)>,
        rotations: &[Matrix3<f64>],
        fallback: &DVector<f64>,
    ) -> (DVector<f64>, QpStatus) {
        let ne = self.n_equalities;
        if let Some((a_eq, b_eq)) = equality {
            self.constraint.rows_mut(0, ne).copy_from(a_eq);
            self.rhs.rows_mut(0, ne).copy_from(b_eq);
        }
        let (c, b) = self.inequalities(rotations);
        let ni = c.nrows();
        self.constraint.rows_mut(ne, ni).copy_from(&c);
        self.rhs.rows_mut(ne, ni).copy_from(&b);
        let outcome = self.solve_clarabel(hessian, gradient);
        match outcome {
            Ok(f) => (f, QpStatus::Solved),
            Err(reason) => {
                self.failures += 1;
                (fallback.clone(), QpStatus::Fallback(reason))
            }
        }
    }

    fn solve_clarabel(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
    ) -> Result<DVector<f64>, String> {
        let q = gradient.as_slice();
        let b = self.rhs.as_slice();
        let updated = match self.solver.as_mut() {
            Some(solver) => {
                let mut values = Vec::new();
                dense_values(hessian, true, &mut values);
                let mut ok = solver.update_P(&values).is_ok();
                dense_values(&self.constraint, false, &mut values);
                ok &= solver.update_A(&values).is_ok();
                ok &= solver.update_q(&q.to_vec()).is_ok() && solver.update_b(&b.to_vec()).is_ok();
                ok
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
            let a = dense_csc(&self.constraint, false);
            let solver = DefaultSolver::new(&p, q, &a, b, &cones, self.settings.clone())
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
