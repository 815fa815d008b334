//! The centroidal split of the joint dynamics used by the momentum controller: the joint rows
//! of eq:system in the coordinates of centrTrans, where the mass matrix is block diagonal, i.e.
//! eq:jointsCentroidal `M_j sddot = J_j^T f - h_j + tau` of eq:systemCentroidal.
//!
//! From `M` (nv x nv), `h` (nv) and the stacked contact Jacobian `J` (k x nv, k = 6 per
//! contact), all in this crate's mixed velocity `nu = [pdot_B; omega_B; sdot]` (world axes):
//!
//! - `Mbar = M_j - M_jb M_b^-1 M_bj` (n x n): the paper's `M_j` after centrTrans;
//! - `Jbar^T = J_j^T - M_jb M_b^-1 J_b^T` (n x k): the paper's `J_j^T` after centrTrans;
//! - `h_j_centroidal = h_j - M_jb M_b^-1 h_b` (n): the paper's `h_j` after centrTrans, i.e.
//!   the joint bias with the base acceleration eliminated. It is NOT the paper's `hbar_j`
//!   (label hjBar, `h_j - p`, the SEA substitution), which the SEA controller obtains by
//!   subtracting `p` from the joint rows of `h` before the split.
//!
//! These are the joint dynamics once the base acceleration is eliminated with the base rows:
//! `Mbar sddot = Jbar^T f - h_j_centroidal + tau`. They do not depend on the base velocity
//! representation (a Schur complement), which is why the split gives centrTrans's blocks
//! without forming the transformation.

use crate::error::{Error, Result};
use crate::linalg::dense::{dot, gemm_small};
use nalgebra::{DMatrix, DVector, Matrix6};

/// Buffers and results of the centroidal split for `n` joints and `k` constraint rows.
#[derive(Clone, Debug)]
pub struct CentroidalSplit {
    /// `Mbar` (n x n), symmetric positive definite.
    pub mbar: DMatrix<f64>,
    /// `Jbar^T` (n x k).
    pub jbar_t: DMatrix<f64>,
    /// `h_j_centroidal = h_j - M_jb M_b^-1 h_b` (n): the joint bias with the base eliminated
    /// (the paper's `h_j` after centrTrans; not the paper's hjBar).
    pub h_j_centroidal: DVector<f64>,
    /// `M_b^-1 M_bj` (6 x n).
    base_inv_coupling: DMatrix<f64>,
    /// `M_b^-1 J_b^T` (6 x k).
    base_inv_jacobian_t: DMatrix<f64>,
}

impl CentroidalSplit {
    /// Buffers for `n_joints` joints and `k` constraint rows.
    pub fn new(n_joints: usize, k: usize) -> Self {
        Self {
            mbar: DMatrix::zeros(n_joints, n_joints),
            jbar_t: DMatrix::zeros(n_joints, k),
            h_j_centroidal: DVector::zeros(n_joints),
            base_inv_coupling: DMatrix::zeros(6, n_joints),
            base_inv_jacobian_t: DMatrix::zeros(6, k),
        }
    }

    /// Computes the split from `mass_matrix` (nv x nv), `bias` (nv) and `jacobian` (k x nv):
    /// [`Self::compute_without_mbar`], then `Mbar` itself.
    pub fn compute(
        &mut self,
        mass_matrix: &DMatrix<f64>,
        bias: &DVector<f64>,
        jacobian: &DMatrix<f64>,
    ) -> Result<()> {
        self.compute_without_mbar(mass_matrix, bias, jacobian)?;
        let n = self.mbar.nrows();
        self.mbar.copy_from(&mass_matrix.view((6, 6), (n, n)));
        // Not nalgebra's gemm: it calls matrixmultiply, which allocates.
        let m_jb = mass_matrix.view((6, 0), (n, 6));
        let coupling = self.base_inv_coupling.as_view();
        gemm_small(&mut self.mbar, -1.0, m_jb, coupling, 1.0);
        Ok(())
    }

    /// `Jbar^T`, `h_j_centroidal` and `M_b^-1 M_bj`, leaving [`Self::mbar`] as it was: for a
    /// caller that only needs `Mbar` times a few vectors ([`Self::mbar_times`], O(n^2) each)
    /// rather than `Mbar` itself (O(6 n^2) to form).
    pub fn compute_without_mbar(
        &mut self,
        mass_matrix: &DMatrix<f64>,
        bias: &DVector<f64>,
        jacobian: &DMatrix<f64>,
    ) -> Result<()> {
        let n = self.mbar.nrows();
        let k = self.jbar_t.ncols();
        check_shapes(n, k, mass_matrix, bias, jacobian)?;
        let m_b: Matrix6<f64> = mass_matrix.fixed_view::<6, 6>(0, 0).into_owned();
        let chol = m_b.cholesky().ok_or_else(|| {
            Error::numerical(
                "centroidal split",
                "the base block of M is not positive definite",
            )
        })?;
        let m_jb = mass_matrix.view((6, 0), (n, 6));
        // M_b^-1 once (6 x 6), then fixed-size products: cheaper than 6-vector solves for the
        // n + k + 1 right-hand sides.
        let m_b_inv = chol.inverse();
        for (i, mut column) in self.base_inv_coupling.column_iter_mut().enumerate() {
            column.copy_from(&(m_b_inv * mass_matrix.fixed_view::<6, 1>(0, 6 + i)));
        }
        for (r, mut column) in self.base_inv_jacobian_t.column_iter_mut().enumerate() {
            let j_b = nalgebra::Vector6::from_fn(|b, _| jacobian[(r, b)]);
            column.copy_from(&(m_b_inv * j_b));
        }
        self.jbar_t.tr_copy_from(&jacobian.view((0, 6), (k, n)));
        let jacobian_t = self.base_inv_jacobian_t.as_view();
        gemm_small(&mut self.jbar_t, -1.0, m_jb, jacobian_t, 1.0);
        let h_b = m_b_inv * bias.fixed_rows::<6>(0);
        self.h_j_centroidal.copy_from(&bias.rows(6, n));
        self.h_j_centroidal.gemv(-1.0, &m_jb, &h_b, 1.0);
        Ok(())
    }

    /// `out = Mbar x = M_j x - M_jb (M_b^-1 M_bj x)` (n) for the `mass_matrix` of the last
    /// [`Self::compute_without_mbar`] (or [`Self::compute`]), without forming `Mbar`.
    pub fn mbar_times(&self, mass_matrix: &DMatrix<f64>, x: &[f64], out: &mut [f64]) {
        let nv = mass_matrix.nrows();
        let m = mass_matrix.as_slice();
        // M_j is symmetric: (M_j x)_i is column i of the joint block times x (contiguous).
        for (i, value) in out.iter_mut().enumerate() {
            let column = &m[(6 + i) * nv + 6..(6 + i) * nv + nv];
            *value = dot(column, x);
        }
        let mut base = nalgebra::Vector6::zeros();
        for (i, &xi) in x.iter().enumerate() {
            // Fixed-size view: a dynamic column times a scalar would allocate its result.
            base += self.base_inv_coupling.fixed_view::<6, 1>(0, i) * xi;
        }
        // M_jb = M_bj^T: row i of M_jb is the base part of column 6 + i.
        for (i, value) in out.iter_mut().enumerate() {
            let m_bj_column = mass_matrix.fixed_view::<6, 1>(0, 6 + i);
            *value -= m_bj_column.dot(&base);
        }
    }
}

/// Checks the shapes of the split's inputs for `n` joints and `k` constraint rows.
fn check_shapes(
    n: usize,
    k: usize,
    mass_matrix: &DMatrix<f64>,
    bias: &DVector<f64>,
    jacobian: &DMatrix<f64>,
) -> Result<()> {
    let nv = n + 6;
    if mass_matrix.shape() != (nv, nv) || bias.len() != nv || jacobian.shape() != (k, nv) {
        return Err(Error::invalid(
            "centroidal split (M, h, J)",
            format!("shapes ({nv}, {nv}), ({nv},), ({k}, {nv})"),
            format!(
                "{:?}, ({},), {:?}",
                mass_matrix.shape(),
                bias.len(),
                jacobian.shape()
            ),
        ));
    }
    Ok(())
}
