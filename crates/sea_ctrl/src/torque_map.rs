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
//! Why it is fast: `M^-1 J^T` uses the tree-sparse factorisation for all k rows at once (no
//! dense nv^3 Cholesky; `Y = L^-T J^T` only touches each foot's leg and the base, and
//! `J M^-1 J^T = Y^T Y` is summed over those rows only); `Lambda^+` is one right division by the
//! k x k Gram factor; `N` is applied to vectors as `v - Lambda^+ (Lambda v)`, O(n k) instead of
//! O(n^2 k) to form it; `Mbar` is applied to vectors, never formed; and every buffer is
//! allocated once, in [`TorqueMap::new`].

use crate::error::{Error, Result};
use nalgebra::{DMatrix, DVector};
use sea_dyn::dense::{
    cholesky_in_place, cholesky_solve_right_in_place, copy_contiguous, dot, gemm_small, gemm_tn,
};
use sea_dyn::model::FrameId;
use sea_dyn::tree_factor::{FactoredContacts, TreeFactor};
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
/// [`Self::tau_bias`] and `Self::sigma`.
pub struct TorqueMap {
    /// Input `h` (nv): bias forces of the controller's model, SEA terms included.
    pub bias: DVector<f64>,
    /// Input: added to the diagonal of `M` (nv) [kg m^2].
    pub diagonal: Vec<f64>,
    /// Input `J`: contact Jacobians, `[v_origin; omega]` world axes, stacked (k x nv).
    pub jacobian: DMatrix<f64>,
    /// Input `Jdot nu` of the contacts, stacked (k).
    pub jdot_nu: DVector<f64>,
    /// Input, optional: the contacts' desired accelerations `a*` (k; `J nudot + Jdot nu =
    /// a*` instead of 0, a swinging foot's task while walking); `None`: zero, the paper's
    /// eq:constraints_acc.
    pub desired_acceleration: Option<DVector<f64>>,
    /// Result `tau_bias` (n).
    pub tau_bias: DVector<f64>,
    /// Result `Sigma` (n x k).
    pub sigma: DMatrix<f64>,
    /// `Jbar^T`, `h_j_centroidal` of the last computation (`Mbar` is not formed: see
    /// [`CentroidalSplit::mbar_times`]).
    pub split: CentroidalSplit,
    /// `M + diag = L^T L` (tree-sparse).
    factor: TreeFactor,
    /// `(L^-T J^T)^T` (k x nv; zero outside the feet's legs and the base).
    linv_jt_t: DMatrix<f64>,
    /// `(M^-1 J^T)^T = J M^-1` (k x nv).
    minv_jt_t: DMatrix<f64>,
    /// `Lambda^T = B^T M^-1 J^T` (n x k).
    lambda_t: DMatrix<f64>,
    /// Cholesky factor of `Lambda Lambda^T + d^2 I` (k x k, lower triangle).
    gram: DMatrix<f64>,
    /// `Lambda^+ = Lambda^T (Lambda Lambda^T + d^2 I)^-1` (n x k).
    pinv: DMatrix<f64>,
    /// `J M^-1 J^T` after [`Self::lambda`], then `J M^-1 J^T - Lambda Jbar^T` (k x k).
    coupling: DMatrix<f64>,
    /// `J M^-1 J^T` (k x k), kept for [`Self::factored_contacts`].
    contact_schur: DMatrix<f64>,
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
            desired_acceleration: None,
            tau_bias: DVector::zeros(n),
            sigma: DMatrix::zeros(n, k),
            split: CentroidalSplit::new(n, k),
            factor: TreeFactor::new(model),
            linv_jt_t: DMatrix::zeros(k, nv),
            minv_jt_t: DMatrix::zeros(k, nv),
            lambda_t: DMatrix::zeros(n, k),
            gram: DMatrix::zeros(k, k),
            pinv: DMatrix::zeros(n, k),
            coupling: DMatrix::zeros(k, k),
            contact_schur: DMatrix::zeros(k, k),
            scratch_k: DVector::zeros(k),
            task_bias: DVector::zeros(k),
            stiffness_term: DVector::zeros(n),
            damping_term: DVector::zeros(n),
        }
    }

    /// The contact terms of the last [`Self::compute`] (factor of `M + diag`, `J`, `Jdot nu`,
    /// `(L^-T J^T)^T`, `J M^-1 J^T`) for the contact `frames` of its rows.
    pub fn factored_contacts<'a>(&'a self, frames: &'a [FrameId]) -> FactoredContacts<'a> {
        FactoredContacts {
            frames,
            diagonal: &self.diagonal,
            factor: &self.factor,
            jacobian: &self.jacobian,
            jdot_nu: &self.jdot_nu,
            linv_jt_t: &self.linv_jt_t,
            schur: &self.contact_schur,
        }
    }

    /// `Lambda^T = B^T M^-1 J^T` (n x k) of the last [`Self::compute`].
    pub fn lambda_t(&self) -> &DMatrix<f64> {
        &self.lambda_t
    }

    /// `J M^-1 J^T` (k x k) of the last [`Self::compute`].
    pub fn contact_schur(&self) -> &DMatrix<f64> {
        &self.contact_schur
    }

    /// `J M^-1 h - Jdot nu` (k) of the last [`Self::compute`]: eq:torques' right-hand side at
    /// `f = 0`.
    pub fn task_bias(&self) -> &DVector<f64> {
        &self.task_bias
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
        // Centroidal split (centrTrans), without forming Mbar.
        self.split
            .compute_without_mbar(mass_matrix, &self.bias, &self.jacobian)?;
        self.torque_bias(mass_matrix, posture);
        self.sigma();
        Ok(())
    }

    /// Paper eq:torques, `Lambda = J M^-1 B` (k x n; `J_j M_j^-1` in the coordinates of
    /// centrTrans): factors `M + diag` (tree-sparse) and stores `J M^-1` (k x nv), its joint
    /// columns transposed `Lambda^T = B^T M^-1 J^T` (n x k), and `J M^-1 J^T` (in `coupling`).
    fn lambda(&mut self, mass_matrix: &DMatrix<f64>) -> Result<()> {
        let n = self.tau_bias.len();
        self.factor
            .factor(mass_matrix, &self.diagonal)
            .map_err(|e| Error::Dynamics(e.during("factorising the controller's M + diag")))?;
        self.factor
            .schur_complement(&self.jacobian, &mut self.linv_jt_t, &mut self.coupling);
        copy_contiguous(&mut self.contact_schur, &self.coupling);
        copy_contiguous(&mut self.minv_jt_t, &self.linv_jt_t);
        self.factor.solve_l_multi(&mut self.minv_jt_t);
        self.lambda_t.tr_copy_from(&self.minv_jt_t.columns(6, n));
        Ok(())
    }

    /// Paper eq:torques, the damped pseudo-inverse `Lambda^+ = Lambda^T (Lambda Lambda^T + d^2
    /// I)^-1` (n x k), by a right division with the Cholesky factor of the k x k Gram matrix
    /// (never an n x n matrix).
    fn lambda_pseudo_inverse(&mut self, pinv_damping: f64) -> Result<()> {
        gemm_tn(
            &mut self.gram,
            1.0,
            &self.lambda_t,
            &self.lambda_t,
            0.0,
            true,
        );
        for r in 0..self.gram.nrows() {
            self.gram[(r, r)] += pinv_damping * pinv_damping;
        }
        cholesky_in_place(&mut self.gram).map_err(|pivot| {
            Error::Dynamics(sea_dyn::Error::numerical(
                "factorising Lambda Lambda^T + d^2 I",
                format!("not positive definite (pivot {pivot})"),
            ))
        })?;
        copy_contiguous(&mut self.pinv, &self.lambda_t);
        cholesky_solve_right_in_place(&self.gram, &mut self.pinv);
        Ok(())
    }

    /// Paper eq:torques with posturalNew at `f = 0`: `tau_bias = Lambda^+ (J M^-1 h - Jdot nu) +
    /// N_Lambda (h_j + u0)` (n), `h_j` being the joint bias of centrTrans
    /// ([`CentroidalSplit::h_j_centroidal`]; for the SEA controller `h` already holds hjBar).
    /// With desired contact accelerations `a*`, `J M^-1 h - Jdot nu + a*` in the first term.
    fn torque_bias(&mut self, mass_matrix: &DMatrix<f64>, posture: &PosturalTask) {
        // J M^-1 h - Jdot nu (+ a*) (k).
        copy_contiguous(&mut self.task_bias, &self.jdot_nu);
        if let Some(desired) = &self.desired_acceleration {
            self.task_bias -= desired;
        }
        self.task_bias.gemv(1.0, &self.minv_jt_t, &self.bias, -1.0);
        self.postural_torque(mass_matrix, posture);
        // u0 is in tau_bias.
        self.tau_bias += &self.split.h_j_centroidal;
        apply_null_space_projector(
            &self.lambda_t,
            &self.pinv,
            &mut self.tau_bias,
            &mut self.scratch_k,
        );
        self.tau_bias.gemv(1.0, &self.pinv, &self.task_bias, 1.0);
    }

    /// Paper eq:torques with posturalNew, the coefficient of `f` (n x k):
    /// `Sigma = -(Lambda^+ J M^-1 J^T + N_Lambda J_j^T) = -(J_j^T + Lambda^+ (J M^-1 J^T -
    /// Lambda J_j^T))`, `J_j^T` of centrTrans ([`CentroidalSplit::jbar_t`]); the second form
    /// applies `N_Lambda` without forming it.
    fn sigma(&mut self) {
        // coupling holds J M^-1 J^T (from `lambda`).
        let jbar_t = &self.split.jbar_t;
        gemm_tn(&mut self.coupling, -1.0, &self.lambda_t, jbar_t, 1.0, false);
        copy_contiguous(&mut self.sigma, &self.split.jbar_t);
        let (pinv, coupling) = (self.pinv.as_view(), self.coupling.as_view());
        gemm_small(&mut self.sigma, 1.0, pinv, coupling, 1.0);
        self.sigma.neg_mut();
    }

    /// Paper posturalNew, `u0 = -K_p^j N_Lambda M_j (s - s_d) - K_d^j N_Lambda M_j sdot` (n,
    /// `M_j` of centrTrans = `Mbar` of `M + diag`, gains diagonal) into `tau_bias`.
    fn postural_torque(&mut self, mass_matrix: &DMatrix<f64>, posture: &PosturalTask) {
        for (term, input) in [
            (&mut self.stiffness_term, posture.error),
            (&mut self.damping_term, posture.velocity),
        ] {
            self.split
                .mbar_times(mass_matrix, input, term.as_mut_slice());
            // The diagonal only touches the joint block of M, hence Mbar's diagonal.
            for (i, value) in term.iter_mut().enumerate() {
                *value += self.diagonal[6 + i] * input[i];
            }
            apply_null_space_projector(&self.lambda_t, &self.pinv, term, &mut self.scratch_k);
        }
        for i in 0..self.tau_bias.len() {
            self.tau_bias[i] = -posture.stiffness[i] * self.stiffness_term[i]
                - posture.damping[i] * self.damping_term[i];
        }
    }
}

/// Paper eq:torques, the null-space projector `N_Lambda = I - Lambda^+ Lambda` (n x n) applied
/// to a joint-space vector without forming it: `v <- v - Lambda^+ (Lambda v)` (O(n k) instead of
/// O(n^2 k)), with `Lambda^T` (n x k), `Lambda^+` (n x k) and a task-space scratch (k).
pub fn apply_null_space_projector(
    lambda_t: &DMatrix<f64>,
    pinv: &DMatrix<f64>,
    v: &mut DVector<f64>,
    scratch_k: &mut DVector<f64>,
) {
    for (entry, column) in scratch_k.iter_mut().zip(lambda_t.column_iter()) {
        *entry = dot(column.as_slice(), v.as_slice());
    }
    v.gemv(-1.0, pinv, scratch_k, 1.0);
}
