//! Two feet whose constraints are redundant: the two-feet momentum task restricted to the
//! wrenches the joints can produce (paper eq:torques, eq:dotH_f and inputTorquesSOT when the
//! Lemma's premise, `Lambda` of full row rank, fails).
//!
//! The torque map solves `Lambda tau = J M^-1 (h - J^T f) - Jdot nu` (eq:torques; `Lambda = J
//! M^-1 B`, k x n) by a damped pseudo-inverse. With legs of 6 joints `Lambda` has full row rank
//! k = 12 and every `f` is produced exactly by some `tau`. With legs of 5 joints (no hip yaw, as
//! `urdf/mini_biped.urdf`) the stacked contact Jacobian `J` has rank 11 and `Lambda` rank 10:
//! its left null space has two directions,
//!
//! - one in the left null space of `J` (`J^T y = 0`): an internal wrench of the two feet that
//!   no joint feels and no momentum sees (`Sigma y = 0`, `A y = 0`); harmless, the QP's
//!   regulariser picks it;
//! - one that is not (`y^T J M^-1 J^T != 0`): the equation holds only for wrenches with
//!   `y^T (J M^-1 J^T f - (J M^-1 h - Jdot nu)) = 0`. Another `f` is a wrench no torque
//!   produces: the pseudo-inverse returns the least-squares torque, the plant delivers another
//!   wrench, and the momentum rate and the joints' accelerations are not the controller's.
//!
//! Under that consistency row the momentum map `A` loses one direction: one component of the
//! momentum rate (mostly the yaw moment about the CoM on the mini biped) is what the dynamics
//! make it, whatever the torques, yet the paper's equality `A f = b` demands it. The QP's
//! solution then breaks the consistency row every tick; the run diverged at 0.17 s
//! (docs/findings/robots.md; with these equalities it completes, given a pseudo-inverse damping
//! that holds the one zero-momentum mode, the null space of `Lambda`). [`RedundantContacts`] replaces `A f = b` by the equalities
//!
//! ```text
//! U_c^T A f = U_c^T b     (the momentum task in the directions the contacts can move)
//! C f = d                 (the wrenches the joints can produce)
//! ```
//!
//! with `C = W^T G / sigma` (rows of unit norm), `d = W^T (J M^-1 h - Jdot nu) / sigma`, `G = J
//! M^-1 J^T`, `W` the directions of `Lambda`'s left null space that `G` sees, and `U_c` the
//! range of `A` on the null space of `C`. The count of each is fixed when the controller is
//! built (from the ranks at its initial posture); with full-rank `Lambda` there are none and the
//! paper's `A f = b` is used unchanged.

use crate::momentum::{momentum_map_identity_blocks, set_momentum_map_contact};
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use sea_dyn::{Data, FrameId, Model};

/// Relative singular value below which a direction counts as lost (also `sea-sim init`'s, for
/// the rank of the two feet's constraints).
pub const RANK_TOLERANCE: f64 = 1e-8;

/// The equalities of a redundant two-feet contact set (see the module doc), rebuilt every tick
/// by [`Self::update`]. The decompositions allocate (the full-rank path, without this, does
/// not).
#[derive(Clone, Debug)]
pub struct RedundantContacts {
    /// `k - rank(Lambda)`: the dimension of `Lambda`'s left null space.
    lambda_left_null: usize,
    /// `rank(J) - rank(Lambda)`: consistency rows `C f = d`.
    consistency_rows: usize,
    /// `6 -` the momentum directions lost under `C f = d`: rows `U_c^T A f = U_c^T b`.
    controlled_momentum: usize,
    /// `[U_c^T A; C]` (rows x k).
    pub equality: DMatrix<f64>,
    /// `[U_c^T b; d]` (rows).
    pub target: DVector<f64>,
}

/// The rank of `matrix`: its singular values above [`RANK_TOLERANCE`] times the largest.
fn rank(matrix: &DMatrix<f64>) -> usize {
    let singular = matrix.singular_values();
    let largest = singular.max();
    singular
        .iter()
        .filter(|&&s| s > RANK_TOLERANCE * largest)
        .count()
}

/// The eigenvectors of the symmetric `gram` (columns) and its eigenvalues, both in the order
/// of the eigenvalues, ascending.
fn sorted_eigen(gram: DMatrix<f64>) -> (DMatrix<f64>, Vec<f64>) {
    let eigen = SymmetricEigen::new(gram);
    let mut order: Vec<usize> = (0..eigen.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let vectors = DMatrix::from_fn(eigen.eigenvectors.nrows(), order.len(), |r, c| {
        eigen.eigenvectors[(r, order[c])]
    });
    (
        vectors,
        order.iter().map(|&i| eigen.eigenvalues[i]).collect(),
    )
}

/// Orthonormal eigenvectors of the symmetric `gram` for its `count` smallest eigenvalues
/// (k x count).
fn smallest_eigenvectors(gram: &DMatrix<f64>, count: usize) -> DMatrix<f64> {
    sorted_eigen(gram.clone()).0.columns(0, count).into_owned()
}

/// The `count` leading left singular vectors of `matrix` (rows x count) and their singular
/// values (descending), from the eigenvectors of `matrix matrix^T` (rows x rows, small here:
/// 2 x 2 and 6 x 6). The leading singular values are far apart from the rest (a lost
/// direction's is round-off), so the squared ones keep them apart.
///
/// Not nalgebra 0.33's `svd(true, true)`: on the wide, nearly rank-one matrix of
/// [`RedundantContacts::consistency`] its factors are wrong for some round-off of the entries
/// (mini_biped standing: `U S V^T` off the matrix by 0.42 of its norm 8.75, the leading
/// singular value 8.762 for 8.752), and the consistency row built from them asks the QP for
/// wrenches no torque produces (infeasible from the first tick).
fn leading_left_singular(matrix: &DMatrix<f64>, count: usize) -> (DMatrix<f64>, Vec<f64>) {
    let (vectors, values) = sorted_eigen(matrix * matrix.transpose());
    let n = values.len();
    let leading = DMatrix::from_fn(n, count, |r, c| vectors[(r, n - 1 - c)]);
    let singular = (0..count)
        .map(|c| values[n - 1 - c].max(0.0).sqrt())
        .collect();
    (leading, singular)
}

impl RedundantContacts {
    /// The redundancy of a two-feet contact set from `Lambda^T` (n x k), `G = J M^-1 J^T` (k x
    /// k) and the momentum map `A` (6 x k) at one posture; `None` when `Lambda` has the rank of
    /// `J` (every wrench the contacts see is produced by some torque: the paper's case).
    pub fn detect(
        lambda_t: &DMatrix<f64>,
        schur: &DMatrix<f64>,
        momentum_map: &DMatrix<f64>,
    ) -> Option<Self> {
        let k = schur.nrows();
        let rank_lambda = rank(lambda_t);
        let rank_jacobian = rank(schur);
        if rank_lambda >= rank_jacobian {
            return None;
        }
        let mut found = Self {
            lambda_left_null: k - rank_lambda,
            consistency_rows: rank_jacobian - rank_lambda,
            controlled_momentum: 6,
            equality: DMatrix::zeros(6 + rank_jacobian - rank_lambda, k),
            target: DVector::zeros(6 + rank_jacobian - rank_lambda),
        };
        let zeros = DVector::zeros(k);
        let consistency = found.consistency(lambda_t, schur, &zeros).0;
        let projected = momentum_map - momentum_map * consistency.transpose() * &consistency;
        found.controlled_momentum = rank(&projected);
        let rows = found.controlled_momentum + found.consistency_rows;
        found.equality = DMatrix::zeros(rows, k);
        found.target = DVector::zeros(rows);
        Some(found)
    }

    /// [`Self::detect`] for the contact `frames` of `model` at the configuration `q` (nq), the
    /// controller's `M + diag` (`diagonal`, nv); `data` is scratch. Dense and allocating: for
    /// the controller's construction.
    pub fn at_posture(
        model: &Model,
        data: &mut Data,
        frames: &[FrameId],
        q: &[f64],
        diagonal: &[f64],
    ) -> Option<Self> {
        let (nv, k) = (model.nv(), 6 * frames.len());
        let mut inertia = sea_dyn::crba(model, data, q).clone();
        for (i, value) in diagonal.iter().enumerate() {
            inertia[(i, i)] += value;
        }
        let mut jacobian = DMatrix::zeros(k, nv);
        let mut momentum_map = momentum_map_identity_blocks(frames.len());
        let com = sea_dyn::com(model, data, q);
        for (c, &frame) in frames.iter().enumerate() {
            let rows = sea_dyn::frame_jacobian(model, data, q, frame);
            jacobian.rows_mut(6 * c, 6).copy_from(rows);
            let pose = sea_dyn::frame_placement(model, data, frame);
            set_momentum_map_contact(&mut momentum_map, c, &pose.translation, &com);
        }
        let minv_jt = inertia.cholesky()?.solve(&jacobian.transpose());
        let lambda_t = minv_jt.rows(6, nv - 6).into_owned();
        let schur = &jacobian * minv_jt;
        Self::detect(&lambda_t, &schur, &momentum_map)
    }

    /// Equality rows of the QP: `6 -` lost momentum directions `+` consistency rows (6 on the
    /// mini biped: 5 + 1).
    pub fn n_rows(&self) -> usize {
        self.controlled_momentum + self.consistency_rows
    }

    /// Consistency rows `C f = d` ([`Self::n_rows`] of them come from here and from `A`): `C`
    /// (r x k, orthonormal rows), `d` (r) from `Lambda^T` (n x k), `G` (k x k) and `J M^-1 h -
    /// Jdot nu` (k).
    fn consistency(
        &self,
        lambda_t: &DMatrix<f64>,
        schur: &DMatrix<f64>,
        task_bias: &DVector<f64>,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let left_null = smallest_eigenvectors(&lambda_t.tr_mul(lambda_t), self.lambda_left_null);
        // The rows of G seen from Lambda's left null space; the directions G sees are the
        // leading singular vectors (the others are J's own left null space).
        let seen = left_null.tr_mul(schur);
        let r = self.consistency_rows;
        let (u, singular) = leading_left_singular(&seen, r);
        // Row i: u_i^T seen / sigma_i = v_i^T (unit norm); its target likewise scaled.
        let mut rows = u.tr_mul(&seen);
        let mut target = (left_null * &u).tr_mul(task_bias);
        for (i, sigma) in singular.iter().enumerate() {
            rows.row_mut(i).unscale_mut(*sigma);
            target[i] /= sigma;
        }
        (rows, target)
    }

    /// This tick's equalities `[U_c^T A; C] f = [U_c^T b; d]` into [`Self::equality`] and
    /// [`Self::target`], from `Lambda^T` (n x k), `G = J M^-1 J^T` (k x k), `J M^-1 h - Jdot
    /// nu` (k), the momentum map `A` (6 x k) and `b = Hdot* - [m g; 0]` (6).
    pub fn update(
        &mut self,
        lambda_t: &DMatrix<f64>,
        schur: &DMatrix<f64>,
        task_bias: &DVector<f64>,
        momentum_map: &DMatrix<f64>,
        momentum_target: &DVector<f64>,
    ) {
        let (c, d) = self.consistency(lambda_t, schur, task_bias);
        // A on the null space of C: its range is what the momentum rate can follow.
        let projected = momentum_map - momentum_map * c.transpose() * &c;
        let (controlled, _) = leading_left_singular(&projected, self.controlled_momentum);
        let m = self.controlled_momentum;
        self.equality
            .rows_mut(0, m)
            .copy_from(&controlled.tr_mul(momentum_map));
        self.target
            .rows_mut(0, m)
            .copy_from(&controlled.tr_mul(momentum_target));
        self.equality
            .rows_mut(m, self.consistency_rows)
            .copy_from(&c);
        self.target.rows_mut(m, self.consistency_rows).copy_from(&d);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_leading_singular_direction_rebuilds_a_nearly_rank_one_wide_matrix() {
        let v = DVector::from_fn(12, |i, _| (0.7 * i as f64).sin());
        let u = DVector::from_vec(vec![0.6, -0.8]);
        let mut matrix = &u * v.transpose() * 8.75;
        matrix[(1, 3)] += 1e-14;
        let (leading, singular) = leading_left_singular(&matrix, 1);
        let largest = matrix.singular_values().max();
        assert!(
            (singular[0] - largest).abs() < 1e-12 * largest,
            "{singular:?}"
        );
        let direction = leading.column(0);
        let rebuilt = direction * (direction.transpose() * &matrix);
        assert!((rebuilt - &matrix).norm() < 1e-12 * matrix.norm());
        assert!((direction.dot(&u).abs() - 1.0).abs() < 1e-12);
    }
}
