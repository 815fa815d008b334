//! The wrench QP's data: the contact constraints (paper frictionCones), the objectives
//! (inputTorquesSOTMinTau / inputTorquesMinVel with two feet, the momentum task in least
//! squares with one), and the problem in the sole-frame variables every solver works on.

use nalgebra::{DMatrix, DVector, Matrix3};
use sea_dyn::dense::{dot, gemm_small, gemm_tn};
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
    /// force (docs/references.md#original-study-contact-wrench-qp).
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

/// The QP of one tick in the sole-frame variables `w = T^T f`, `T = blockdiag(R_k, R_k)` over
/// the contacts (`R_k` = `world_R_sole` of contact k): `P' = T^T P T`, `c' = T^T c`,
/// `A_eq' = A_eq T`, and the constant contact rows `C_s w_s <= b_s` of every contact. Buffers
/// allocated once in [`SoleFrameProblem::new`].
pub(super) struct SoleFrameProblem {
    pub(super) n_contacts: usize,
    pub(super) n_equalities: usize,
    /// One contact's rows `C_s` (per_contact x 6) and bounds `b_s` (per_contact).
    pub(super) sole_c: DMatrix<f64>,
    pub(super) sole_b: DVector<f64>,
    /// `T` of the current tick (k x k).
    rotation: DMatrix<f64>,
    /// `T^T P` (scratch, k x k).
    product: DMatrix<f64>,
    /// `P'` (k x k), `c'` (k), `A_eq'` (n_equalities x k).
    pub(super) hessian: DMatrix<f64>,
    pub(super) gradient: DVector<f64>,
    pub(super) equality: DMatrix<f64>,
}

impl SoleFrameProblem {
    /// Buffers for `n_contacts` contacts and `n_equalities` equality rows.
    pub(super) fn new(
        n_contacts: usize,
        n_equalities: usize,
        constraints: &ContactConstraints,
    ) -> Self {
        let (sole_c, sole_b) = constraints.sole_rows();
        let n = 6 * n_contacts;
        Self {
            n_contacts,
            n_equalities,
            sole_c,
            sole_b,
            rotation: DMatrix::zeros(n, n),
            product: DMatrix::zeros(n, n),
            hessian: DMatrix::zeros(n, n),
            gradient: DVector::zeros(n),
            equality: DMatrix::zeros(n_equalities, n),
        }
    }

    /// Number of variables `6 n_contacts`.
    pub(super) fn n_variables(&self) -> usize {
        6 * self.n_contacts
    }

    /// Sets `T` from the sole rotations `world_R_sole`, then `P' = T^T P T`, `c' = T^T c` and
    /// (when given) `A_eq' = A_eq T`.
    pub(super) fn set(
        &mut self,
        hessian: &DMatrix<f64>,
        gradient: &DVector<f64>,
        equality: Option<&DMatrix<f64>>,
        sole_rotations: &[Matrix3<f64>],
    ) {
        self.rotation.as_mut_slice().fill(0.0);
        for (k, r) in sole_rotations.iter().enumerate() {
            self.rotation.view_mut((6 * k, 6 * k), (3, 3)).copy_from(r);
            self.rotation
                .view_mut((6 * k + 3, 6 * k + 3), (3, 3))
                .copy_from(r);
        }
        self.product.gemm_tr(1.0, &self.rotation, hessian, 0.0);
        let (product, rotation) = (self.product.as_view(), self.rotation.as_view());
        gemm_small(&mut self.hessian, 1.0, product, rotation, 0.0);
        self.gradient.gemv_tr(1.0, &self.rotation, gradient, 0.0);
        if let Some(a_eq) = equality {
            gemm_small(
                &mut self.equality,
                1.0,
                a_eq.as_view(),
                self.rotation.as_view(),
                0.0,
            );
        }
    }

    /// The world wrenches `f = T w` of sole-frame wrenches `w`, into `wrenches`.
    pub(super) fn to_world(&self, w: &DVector<f64>, wrenches: &mut DVector<f64>) {
        wrenches.gemv(1.0, &self.rotation, w, 0.0);
    }

    /// Every contact's rows: `sole_c` block diagonal (rows n_contacts x 6 n_contacts) and
    /// `sole_b` repeated.
    pub(super) fn block_diagonal_rows(&self) -> (DMatrix<f64>, DVector<f64>) {
        let rows = self.sole_c.nrows();
        let mut c = DMatrix::zeros(rows * self.n_contacts, self.n_variables());
        let mut b = DVector::zeros(rows * self.n_contacts);
        for k in 0..self.n_contacts {
            c.view_mut((k * rows, 6 * k), (rows, 6))
                .copy_from(&self.sole_c);
            b.rows_mut(k * rows, rows).copy_from(&self.sole_b);
        }
        (c, b)
    }

    /// The inequality rows `C f <= b` in world axes for sole rotations `world_R_sole`.
    pub(super) fn world_inequalities(
        &self,
        sole_rotations: &[Matrix3<f64>],
    ) -> (DMatrix<f64>, DVector<f64>) {
        let rows = self.sole_c.nrows();
        let mut c = DMatrix::zeros(rows * self.n_contacts, self.n_variables());
        let mut b = DVector::zeros(rows * self.n_contacts);
        for (k, rotation) in sole_rotations.iter().enumerate() {
            let mut t = DMatrix::zeros(6, 6);
            t.view_mut((0, 0), (3, 3)).copy_from(&rotation.transpose());
            t.view_mut((3, 3), (3, 3)).copy_from(&rotation.transpose());
            c.view_mut((k * rows, 6 * k), (rows, 6))
                .copy_from(&(&self.sole_c * t));
            b.rows_mut(k * rows, rows).copy_from(&self.sole_b);
        }
        (c, b)
    }

    /// Whether the world wrenches `f` satisfy every contact inequality (`C f <= b`, exactly)
    /// for sole rotations `world_R_sole`.
    pub(super) fn satisfies_inequalities(
        &self,
        f: &DVector<f64>,
        sole_rotations: &[Matrix3<f64>],
    ) -> bool {
        sole_rotations.iter().enumerate().all(|(k, rotation)| {
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

    /// `max(C_s w_s - b_s, 0)` over every contact's sole rows for sole-frame wrenches `w`.
    pub(super) fn inequality_violation(&self, w: &DVector<f64>) -> f64 {
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

    /// `0.5 w^T P' w + c'^T w` for sole-frame wrenches `w`.
    pub(super) fn objective(&self, w: &DVector<f64>) -> f64 {
        let quadratic: f64 = self
            .hessian
            .column_iter()
            .zip(w.iter())
            .map(|(column, w_j)| column.dot(w) * w_j)
            .sum();
        0.5 * quadratic + self.gradient.dot(w)
    }
}
