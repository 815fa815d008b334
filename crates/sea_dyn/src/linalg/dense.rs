//! Small dense linear algebra without allocation: in-place Cholesky `A = L L^T` and triangular
//! solves (the k x k contact Schur complements; joint-space matrices use `tree_factor`).
//!
//! nalgebra's decompositions take ownership of (or copy) their matrix; the simulator factors
//! matrices every step, so these work in preallocated buffers instead. They run on the
//! column-major storage directly so the inner loops are contiguous (vectorisable) and free of
//! bounds checks. Only the lower triangle of the input is read; the factor overwrites it.

use nalgebra::{DMatrix, DMatrixView};

/// Factors the symmetric positive definite `a` in place (lower triangle becomes `L`,
/// left-looking, column by column). Returns the index of the first non-positive pivot.
pub fn cholesky_in_place(a: &mut DMatrix<f64>) -> Result<(), usize> {
    let n = a.nrows();
    let s = a.as_mut_slice();
    for j in 0..n {
        // Column j from row j down: a[j.., j] -= sum_k a[j.., k] a[j, k].
        for k in 0..j {
            let ajk = s[k * n + j];
            if ajk != 0.0 {
                let (left, right) = s.split_at_mut(j * n);
                let source = &left[k * n + j..k * n + n];
                let target = &mut right[j..n];
                for (t, v) in target.iter_mut().zip(source) {
                    *t -= v * ajk;
                }
            }
        }
        let diagonal = s[j * n + j];
        if diagonal <= 0.0 || !diagonal.is_finite() {
            return Err(j);
        }
        let pivot = diagonal.sqrt();
        let inverse = 1.0 / pivot;
        s[j * n + j] = pivot;
        for v in &mut s[j * n + j + 1..j * n + n] {
            *v *= inverse;
        }
    }
    Ok(())
}

/// Solves `L y = b` in place (forward substitution, column-oriented).
pub fn forward_substitute(l: &DMatrix<f64>, b: &mut [f64]) {
    let n = l.nrows();
    let s = l.as_slice();
    for j in 0..n {
        let column = &s[j * n..j * n + n];
        let yj = b[j] / column[j];
        b[j] = yj;
        if yj != 0.0 {
            for (bi, lij) in b[j + 1..].iter_mut().zip(&column[j + 1..]) {
                *bi -= lij * yj;
            }
        }
    }
}

/// Solves `L^T x = y` in place (backward substitution, dot products on columns).
pub fn backward_substitute(l: &DMatrix<f64>, b: &mut [f64]) {
    let n = l.nrows();
    let s = l.as_slice();
    for j in (0..n).rev() {
        let column = &s[j * n..j * n + n];
        let dot: f64 = column[j + 1..]
            .iter()
            .zip(&b[j + 1..])
            .map(|(a, x)| a * x)
            .sum();
        b[j] = (b[j] - dot) / column[j];
    }
}

/// Solves `L L^T x = b` in place (`b` becomes `x`), with `l` from [`cholesky_in_place`].
pub fn cholesky_solve_in_place(l: &DMatrix<f64>, b: &mut [f64]) {
    forward_substitute(l, b);
    backward_substitute(l, b);
}

/// `c <- alpha a b + beta c` (`a` r x m, `b` m x k, `c` r x k) without allocation: nalgebra's
/// `gemm` hands every product whose sizes all exceed 5 to `matrixmultiply`, which allocates
/// its packing buffers on each call. Column by column with `gemv`; for the controller's sizes
/// (up to 31 x 12) about as fast as `matrixmultiply`.
pub fn gemm_small(
    c: &mut DMatrix<f64>,
    alpha: f64,
    a: DMatrixView<'_, f64>,
    b: DMatrixView<'_, f64>,
    beta: f64,
) {
    assert!(
        a.ncols() == b.nrows() && c.shape() == (a.nrows(), b.ncols()),
        "gemm_small: shapes {:?} x {:?} into {:?}",
        a.shape(),
        b.shape(),
        c.shape()
    );
    for (mut c_column, b_column) in c.column_iter_mut().zip(b.column_iter()) {
        c_column.gemv(alpha, &a, &b_column, beta);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd(n: usize) -> DMatrix<f64> {
        let r = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3) % 5) as f64 - 2.0);
        &r * r.transpose() + DMatrix::identity(n, n)
    }

    #[test]
    fn solves_spd_system() {
        let n = 7;
        let a = spd(n);
        let x_true: Vec<f64> = (0..n).map(|i| i as f64 - 3.0).collect();
        let b = &a * nalgebra::DVector::from_vec(x_true.clone());
        let mut l = a.clone();
        cholesky_in_place(&mut l).unwrap();
        let mut x = b.as_slice().to_vec();
        cholesky_solve_in_place(&l, &mut x);
        for (xi, ti) in x.iter().zip(&x_true) {
            assert!((xi - ti).abs() < 1e-10);
        }
    }

    #[test]
    fn rejects_indefinite() {
        let mut a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert_eq!(cholesky_in_place(&mut a), Err(1));
    }
}
