//! The joint torque map of the momentum controller (paper eq:torques with the postural task
//! posturalNew): joint torques affine in the contact wrenches, `tau(f) = tau_bias + Sigma f`,
//! with
//!
//! - `Lambda = J M^-1 B` (k x n), `Lambda^+ = Lambda^T (Lambda Lambda^T + d^2 I)^-1` (damped),
//!   `N = I - Lambda^+ Lambda` (n x n, never formed);
//! - `tau_bias = Lambda^+ (J M^-1 h - Jdot nu) + N (h_j + u0)`,
//! - `Sigma = -(Lambda^+ J M^-1 J^T + N Jbar^T) = -(Jbar^T + Lambda^+ (J M^-1 J^T - Lambda Jbar^T))`,
//! - `u0 = -K_p^j N Mbar (s - s_d) - K_d^j N Mbar sdot` (gains diagonal, applied after `N Mbar`).
//!
//! `M` is the controller's model inertia plus a diagonal (joint regularisation, motor reflected
//! inertia), `h` its bias forces (with the SEA spring terms), `J` the stacked contact Jacobian
//! (k = 6 per contact); `Mbar`, `Jbar^T`, `h_j` are the paper's `M_j`, `J_j^T`, `h_j` in the
//! coordinates of centrTrans and come from [`CentroidalSplit`]. The paper writes the map with
//! `tau_0 = h_j - J_j^T f + u0` (posturalNew) substituted into eq:torques; the SEA controller
//! passes `h` with hjBar in its joint rows and reads `beta` for `tau` (newJointDynamics).
//!
//! Why it is fast: `M^-1 J^T` uses the tree-sparse factorisation (no dense nv^3 Cholesky, and a
//! foot's rows only touch its leg and the base); `N` is applied to vectors as
//! `v - Lambda^+ (Lambda v)`, O(n k) instead of O(n^2 k) to form it; and every buffer is
//! allocated once, in [`TorqueMap::new`].

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};
use sea_dyn::dense::{cholesky_in_place, cholesky_solve_in_place, gemm_small};
use sea_dyn::tree_factor::TreeFactor;
use sea_dyn::{CentroidalSplit, Model};

/// The postural task's inputs (all of size n, joint order).
pub struct PosturalTask<'a> {
    /// `s - s_d` [rad].
    pub error: &'a [f64],
    /// `sdot` [rad/s].
    pub velocity: &'a [f64],
    /// `K_p^j` (diagonal).
    pub stiffness: &'a [f64],
    /// `K_d^j` (diagonal).
    pub damping: &'a [f64],
}

/// Inputs, buffers and results of the torque map for one model and contact count.
///
/// The caller fills the inputs [`Self::bias`], [`Self::diagonal`], [`Self::jacobian`] and
/// [`Self::jdot_nu`], then calls [`Self::compute`] with `M`; the results are
/// [`Self::tau_bias`] and [`Self::sigma`].
pub struct TorqueMap {
    /// Input `h` (nv): bias forces of the controller's model, SEA terms included.
    pub bias: DVector<f64>,
    /// Input: added to the diagonal of `M` (nv) [kg m^2].
    pub diagonal: Vec<f64>,
    /// Input `J`: contact Jacobians, `[v_origin; omega]` world axes, stacked (k x nv).
    pub jacobian: DMatrix<f64>,
    /// Input `Jdot nu` of the contacts, stacked (k).
    pub jdot_nu: DVector<f64>,
    /// Result `tau_bias` (n).
    pub tau_bias: DVector<f64>,
    /// Result `Sigma` (n x k).
    pub sigma: DMatrix<f64>,
    /// `Mbar`, `Jbar^T`, `h_j_centroidal` of the last computation.
    pub split: CentroidalSplit,
    /// `M + diag = L^T L` (tree-sparse).
    factor: TreeFactor,
    /// `M^-1 J^T` (nv x k).
    minv_jt: DMatrix<f64>,
    /// `Lambda^T = B^T M^-1 J^T` (n x k).
    lambda_t: DMatrix<f64>,
    /// Cholesky factor of `Lambda Lambda^T + d^2 I` (k x k, lower triangle).
    gram: DMatrix<f64>,
    /// `(Lambda^+)^T = (Lambda Lambda^T + d^2 I)^-1 Lambda` (k x n).
    pinv_t: DMatrix<f64>,
    /// `J M^-1 J^T - Lambda Jbar^T` (k x k).
    coupling: DMatrix<f64>,
    /// Task-space vector scratch (k).
    scratch_k: DVector<f64>,
    /// `J M^-1 h - Jdot nu` (k).
    task_bias: DVector<f64>,
    /// Joint-space scratch (n): `N Mbar (s - s_d)`.
    stiffness_term: DVector<f64>,
    /// Joint-space scratch (n): `N Mbar sdot`.
    damping_term: DVector<f64>,
}

impl TorqueMap {
    /// Buffers for `model` and `k` contact rows (6 per contact).
    pub fn new(model: &Model, k: usize) -> Self {
        let (nv, n) = (model.nv(), model.n_joints());
        Self {
            bias: DVector::zeros(nv),
            diagonal: vec![0.0; nv],
            jacobian: DMatrix::zeros(k, nv),
            jdot_nu: DVector::zeros(k),
            tau_bias: DVector::zeros(n),
            sigma: DMatrix::zeros(n, k),
            split: CentroidalSplit::new(n, k),
            factor: TreeFactor::new(model),
            minv_jt: DMatrix::zeros(nv, k),
            lambda_t: DMatrix::zeros(n, k),
            gram: DMatrix::zeros(k, k),
            pinv_t: DMatrix::zeros(k, n),
            coupling: DMatrix::zeros(k, k),
            scratch_k: DVector::zeros(k),
            task_bias: DVector::zeros(k),
            stiffness_term: DVector::zeros(n),
            damping_term: DVector::zeros(n),
        }
    }

    /// Computes `tau_bias` and `Sigma` for the model inertia `mass_matrix` (nv x nv, without
    /// [`Self::diagonal`]), the inputs in `self`, the postural task and the pseudo-inverse
    /// damping `d`.
    pub fn compute(
        &mut self,
        mass_matrix: &DMatrix<f64>,
        posture: &PosturalTask,
        pinv_damping: f64,
    ) -> Result<()> {
        self.lambda(mass_matrix)?;
        self.lambda_pseudo_inverse(pinv_damping)?;
        // Centroidal split (centrTrans); the diagonal only touches the joint block of M, hence
        // Mbar's diagonal.
        self.split
            .compute(mass_matrix, &self.bias, &self.jacobian)?;
        let n = self.tau_bias.len();
        for j in 0..n {
            self.split.mbar[(j, j)] += self.diagonal[6 + j];
        }
        self.torque_bias(posture);
        self.sigma();
        Ok(())
    }

    /// Paper eq:torques, `Lambda = J M^-1 B` (k x n; `J_j M_j^-1` in the coordinates of
    /// centrTrans): factors `M + diag` (tree-sparse) and stores `M^-1 J^T` (nv x k) and its
    /// joint rows `Lambda^T = B^T M^-1 J^T` (n x k).
    fn lambda(&mut self, mass_matrix: &DMatrix<f64>) -> Result<()> {
        let n = self.tau_bias.len();
        self.factor
            .factor(mass_matrix, &self.diagonal)
            .map_err(|e| Error::Dynamics(e.during("factorising the controller's M + diag")))?;
        for r in 0..self.jacobian.nrows() {
            let mut column = self.minv_jt.column_mut(r);
            column.tr_copy_from(&self.jacobian.row(r));
            self.factor.solve(column.as_mut_slice());
        }
        self.lambda_t.copy_from(&self.minv_jt.rows(6, n));
        Ok(())
    }

    /// Paper eq:torques, the damped pseudo-inverse `Lambda^+ = Lambda^T (Lambda Lambda^T + d^2
    /// I)^-1` (n x k), stored transposed as `(Lambda^+)^T` (k x n) through the Cholesky factor
    /// of the k x k Gram matrix (never an n x n matrix).
    fn lambda_pseudo_inverse(&mut self, pinv_damping: f64) -> Result<()> {
        self.gram.gemm_tr(1.0, &self.lambda_t, &self.lambda_t, 0.0);
        for r in 0..self.gram.nrows() {
            self.gram[(r, r)] += pinv_damping * pinv_damping;
        }
        cholesky_in_place(&mut self.gram).map_err(|pivot| {
            Error::Dynamics(sea_dyn::Error::numerical(
                "factorising Lambda Lambda^T + d^2 I",
                format!("not positive definite (pivot {pivot})"),
            ))
        })?;
        self.pinv_t.tr_copy_from(&self.lambda_t);
        for mut column in self.pinv_t.column_iter_mut() {
            cholesky_solve_in_place(&self.gram, column.as_mut_slice());
        }
        Ok(())
    }

    /// Paper eq:torques with posturalNew at `f = 0`: `tau_bias = Lambda^+ (J M^-1 h - Jdot nu) +
    /// N_Lambda (h_j + u0)` (n), `h_j` being the joint bias of centrTrans
    /// ([`CentroidalSplit::h_j_centroidal`]; for the SEA controller `h` already holds hjBar).
    fn torque_bias(&mut self, posture: &PosturalTask) {
        // J M^-1 h - Jdot nu (k).
        self.task_bias.copy_from(&self.jdot_nu);
        self.task_bias.gemv_tr(1.0, &self.minv_jt, &self.bias, -1.0);
        self.postural_torque(posture);
        // u0 is in tau_bias.
        self.tau_bias += &self.split.h_j_centroidal;
        apply_null_space_projector(
            &self.lambda_t,
            &self.pinv_t,
            &mut self.tau_bias,
            &mut self.scratch_k,
        );
        self.tau_bias
            .gemv_tr(1.0, &self.pinv_t, &self.task_bias, 1.0);
    }

    /// Paper eq:torques with posturalNew, the coefficient of `f` (n x k):
    /// `Sigma = -(Lambda^+ J M^-1 J^T + N_Lambda J_j^T) = -(J_j^T + Lambda^+ (J M^-1 J^T -
    /// Lambda J_j^T))`, `J_j^T` of centrTrans ([`CentroidalSplit::jbar_t`]); the second form
    /// applies `N_Lambda` without forming it.
    fn sigma(&mut self) {
        let (jacobian, minv_jt) = (self.jacobian.as_view(), self.minv_jt.as_view());
        gemm_small(&mut self.coupling, 1.0, jacobian, minv_jt, 0.0);
        self.coupling
            .gemm_tr(-1.0, &self.lambda_t, &self.split.jbar_t, 1.0);
        self.sigma.copy_from(&self.split.jbar_t);
        self.sigma.gemm_tr(1.0, &self.pinv_t, &self.coupling, 1.0);
        self.sigma.neg_mut();
    }

    /// Paper posturalNew, `u0 = -K_p^j N_Lambda M_j (s - s_d) - K_d^j N_Lambda M_j sdot` (n,
    /// `M_j` of centrTrans = `Mbar`, gains diagonal) into `tau_bias`.
    fn postural_torque(&mut self, posture: &PosturalTask) {
        let mbar = &self.split.mbar;
        for (term, input) in [
            (&mut self.stiffness_term, posture.error),
            (&mut self.damping_term, posture.velocity),
        ] {
            // Mbar is symmetric: (Mbar x)_i is column i times x (contiguous).
            for (i, value) in term.iter_mut().enumerate() {
                *value = mbar.column(i).iter().zip(input).map(|(m, x)| m * x).sum();
            }
            apply_null_space_projector(&self.lambda_t, &self.pinv_t, term, &mut self.scratch_k);
        }
        for i in 0..self.tau_bias.len() {
            self.tau_bias[i] = -posture.stiffness[i] * self.stiffness_term[i]
                - posture.damping[i] * self.damping_term[i];
        }
    }
}

/// Paper eq:torques, the null-space projector `N_Lambda = I - Lambda^+ Lambda` (n x n) applied
/// to a joint-space vector without forming it: `v <- v - Lambda^+ (Lambda v)` (O(n k) instead of
/// O(n^2 k)), with `Lambda^T` (n x k), `(Lambda^+)^T` (k x n) and a task-space scratch (k).
pub fn apply_null_space_projector(
    lambda_t: &DMatrix<f64>,
    pinv_t: &DMatrix<f64>,
    v: &mut DVector<f64>,
    scratch_k: &mut DVector<f64>,
) {
    scratch_k.gemv_tr(1.0, lambda_t, v, 0.0);
    v.gemv_tr(-1.0, pinv_t, scratch_k, 1.0);
}
