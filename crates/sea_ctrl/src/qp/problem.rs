//! The wrench QP's data: the contact constraints (paper frictionCones), the objectives
//! (inputTorquesSOTMinTau / inputTorquesMinVel with two feet, the momentum task in least
//! squares with one), and the problem in the sole-frame variables every solver works on.

use nalgebra::{DMatrix, DVector, Matrix3};
use sea_dyn::dense::{dot, gemm_small, gemm_tn};
use sea_dyn::ContactSurface;

/// Largest number of friction cone facets: the QP grows by one row per facet and contact, and
/// beyond a few dozen the linearised cone is already within 0.2 % of the true one (1e8 facets
/// allocated about 20 GB).
pub const MAX_FRICTION_FACETS: usize = 64;

/// Fewest friction cone facets: fewer than 3 half-planes do not bound the tangential force.
pub const MIN_FRICTION_FACETS: usize = 3;

#[cfg(feature = "serde")]
sea_dyn::number_bound!(
    /// [`ContactConstraints::cop_margin`]: a fraction of the sole's half-extents in `[0, 1)`.
    CopMargin,
    "must be in [0, 1) (a fraction of the sole's half-extents)",
    |v| (0.0..1.0).contains(&v),
    { "type": "number", "minimum": 0.0, "exclusiveMaximum": 1.0 }
);

/// Contact constraint parameters: the contact surface (friction, torsional friction, foot
/// rectangle; shared with the plant's wrench margins) and the QP's own choices.
// With the `serde` feature, one flat table (`[controller.contact]` of scenario files): the
// surface's keys with the QP's own. A reader splits the table by the two types' keys and
// reads each part by its type (serde reads `surface` only as the part's default: a reader
// gives no key of that name); the JSON Schema is the one table's.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct ContactConstraints {
    /// Number of friction cone facets (bounds: [`MIN_FRICTION_FACETS`], [`MAX_FRICTION_FACETS`]).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "read_facets"),
        schemars(range(min = MIN_FRICTION_FACETS, max = MAX_FRICTION_FACETS))
    )]
    pub facets: usize,
    /// Minimum normal force [N].
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub min_normal_force: f64,
    /// Fraction of the foot rectangle's half-extents the QP keeps free around its edges, in
    /// `[0, 1)`: the QP's centre of pressure stays in the rectangle shrunk about its centre by
    /// `1 - cop_margin`, so what the model does not know (a push, the sampling hold) has room
    /// before the plant's centre of pressure reaches the sole's edge. 0: the whole sole (the
    /// original study's QP).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "CopMargin::read"),
        schemars(with = "CopMargin")
    )]
    pub cop_margin: f64,
    /// Friction coefficients and foot rectangle of each sole (its keys listed after the QP's
    /// own in messages).
    #[cfg_attr(feature = "serde", schemars(flatten))]
    pub surface: ContactSurface,
}

/// Reads [`ContactConstraints::facets`]: [`MIN_FRICTION_FACETS`] to [`MAX_FRICTION_FACETS`].
#[cfg(feature = "serde")]
fn read_facets<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<usize, D::Error> {
    use serde::de::Error as _;
    let facets = <usize as serde::Deserialize>::deserialize(deserializer)?;
    if (MIN_FRICTION_FACETS..=MAX_FRICTION_FACETS).contains(&facets) {
        Ok(facets)
    } else {
        Err(D::Error::custom(format!(
            "must be between {MIN_FRICTION_FACETS} and {MAX_FRICTION_FACETS}, got {facets}"
        )))
    }
}

impl Default for ContactConstraints {
    /// [`ContactSurface::default`] with the original study's 12 facets and 10 N minimum normal
    /// force (docs/references.md#original-study-contact-wrench-qp), the whole sole for the
    /// centre of pressure.
    fn default() -> Self {
        Self {
            surface: ContactSurface::default(),
            facets: 12,
            min_normal_force: 10.0,
            cop_margin: 0.0,
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
        let ([x_min, x_max], [y_min, y_max]) = (
            self.cop_range(surface.foot_x),
            self.cop_range(surface.foot_y),
        );
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

impl ContactConstraints {
    /// The QP's centre-of-pressure interval on one sole axis: `[min, max]` shrunk about its
    /// centre by `1 - cop_margin` [m]
    /// (exactly `[min, max]` for a zero margin).
    pub fn cop_range(&self, [min, max]: [f64; 2]) -> [f64; 2] {
        let inset = 0.5 * (max - min) * self.cop_margin;
        [min + inset, max - inset]
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

/// Adds `weight |n_k|^2` over every contact's moment `n_k` (the last 3 of its 6 entries) to
/// an objective's Hessian `P` (k x k; `P += 2 weight` on those diagonal entries). The norm of a
/// moment is the same in world and sole axes, so the term is frame-free; with two feet it
/// makes the QP carry a moment by moving normal force between the feet before it moves a
/// sole's centre of pressure.
pub fn add_moment_regularization(hessian: &mut DMatrix<f64>, weight: f64) {
    for contact in 0..hessian.nrows() / 6 {
        for r in 3..6 {
            hessian[(6 * contact + r, 6 * contact + r)] += 2.0 * weight;
        }
    }
}

/// Weights of the relaxed momentum task ([`relaxed_momentum_objective`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxedMomentumWeights {
    /// Weight of the angular rows of `A f - b` against the linear rows' 1 [1/m^2]: below 1 the
    /// relaxed QP gives up angular momentum first and keeps the CoM's (a hip strategy).
    pub angular: f64,
    /// Weight of `|tau(f)|^2` [1/m^2]: small, it picks among the wrenches that realise the
    /// same momentum rate.
    pub torque: f64,
}

impl Default for RelaxedMomentumWeights {
    /// Angular 0.1, torque 1e-4.
    fn default() -> Self {
        Self {
            angular: 0.1,
            torque: 1e-4,
        }
    }
}

/// The relaxed momentum task of two feet, for a tick where the contact constraints admit no
/// `f` with `A f = b` (inputTorquesSOT is then infeasible): the closest momentum rate the
/// contacts can produce, `|W^(1/2) (A f - b)|^2 + w_tau |tau_bias + Sigma f|^2 + reg |f|^2`
/// with `W = diag(1, 1, 1, w_ang, w_ang, w_ang)`, as `0.5 f^T P f + c^T f`: `P = 2 (A^T W A +
/// w_tau Sigma^T Sigma + reg I)`, `c = 2 (w_tau Sigma^T tau_bias - A^T W b)` (k x k, k), from
/// the momentum map `A` (6 x k), `b = Hdot* - [m g; 0]` (6) and the torque map (`Sigma` n x k,
/// `tau_bias` n). Allocates nothing.
pub fn relaxed_momentum_objective(
    momentum: (&DMatrix<f64>, &DVector<f64>),
    torque: (&DMatrix<f64>, &DVector<f64>),
    weights: RelaxedMomentumWeights,
    regularization: f64,
    hessian: &mut DMatrix<f64>,
    gradient: &mut DVector<f64>,
) {
    let (sigma, tau_bias) = torque;
    torque_norm_objective(
        sigma,
        tau_bias,
        regularization / weights.torque,
        hessian,
        gradient,
    );
    *hessian *= weights.torque;
    *gradient *= weights.torque;
    let (a, b) = momentum;
    for r in 0..6 {
        let w = if r < 3 { 1.0 } else { weights.angular };
        for i in 0..a.ncols() {
            gradient[i] -= 2.0 * w * a[(r, i)] * b[r];
            for j in 0..a.ncols() {
                hessian[(i, j)] += 2.0 * w * a[(r, i)] * a[(r, j)];
            }
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn pseudo_random(rows: usize, cols: usize, seed: u64) -> DMatrix<f64> {
        let mut state = seed;
        DMatrix::from_fn(rows, cols, |_, _| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    #[test]
    fn the_cop_margin_shrinks_the_rectangle_about_its_centre() {
        let mut constraints = ContactConstraints::default();
        assert_eq!(constraints.cop_range([-0.05, 0.10]), [-0.05, 0.10]);
        constraints.cop_margin = 0.2;
        let [low, high] = constraints.cop_range([-0.05, 0.10]);
        assert!((low - (0.025 - 0.06)).abs() < 1e-15 && (high - (0.025 + 0.06)).abs() < 1e-15);
        // The sole rows bound the CoP by the shrunk rectangle: n_y = -x F_z at the new edge.
        let (c, b) = constraints.sole_rows();
        let r = constraints.facets;
        let at_toe = DVector::from_column_slice(&[0.0, 0.0, 100.0, 0.0, -high * 100.0, 0.0]);
        assert!(((&c * &at_toe)[r + 3] - b[r + 3]).abs() < 1e-12);
    }

    /// The relaxed objective's minimiser is the weighted least-squares solution written with
    /// whole matrices: `(A^T W A + w_tau S^T S + reg I) f = A^T W b - w_tau S^T tau_bias`.
    #[test]
    fn the_relaxed_objective_is_the_weighted_least_squares_of_the_momentum_task() {
        let (k, n) = (12, 9);
        let (a, sigma) = (pseudo_random(6, k, 1), pseudo_random(n, k, 2));
        let b = DVector::from_column_slice(pseudo_random(6, 1, 3).as_slice());
        let tau_bias = DVector::from_column_slice(pseudo_random(n, 1, 4).as_slice());
        let weights = RelaxedMomentumWeights::default();
        let reg = 1e-3;
        let (mut p, mut c) = (DMatrix::zeros(k, k), DVector::zeros(k));
        relaxed_momentum_objective((&a, &b), (&sigma, &tau_bias), weights, reg, &mut p, &mut c);
        let w = DMatrix::from_diagonal(&DVector::from_row_slice(&[
            1.0,
            1.0,
            1.0,
            weights.angular,
            weights.angular,
            weights.angular,
        ]));
        let normal = a.transpose() * &w * &a
            + sigma.transpose() * &sigma * weights.torque
            + DMatrix::identity(k, k) * reg;
        let rhs = a.transpose() * &w * &b - sigma.transpose() * &tau_bias * weights.torque;
        let expected = normal.lu().solve(&rhs).unwrap();
        let found = p.lu().solve(&(-c)).unwrap();
        assert!((found - &expected).norm() < 1e-10 * expected.norm());
    }

    #[test]
    fn the_moment_weight_lands_on_the_moments_of_every_contact() {
        let mut p = DMatrix::zeros(12, 12);
        add_moment_regularization(&mut p, 3.0);
        let diagonal: Vec<f64> = p.diagonal().iter().copied().collect();
        let one = [0.0, 0.0, 0.0, 6.0, 6.0, 6.0];
        assert_eq!(diagonal, [one, one].concat());
        assert_eq!(p.sum(), 6.0 * 6.0);
    }
}
