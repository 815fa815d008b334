//! Small dense linear algebra without allocation: in-place Cholesky `A = L L^T` and triangular
//! solves (the k x k contact Schur complements; joint-space matrices use `tree_factor`).
//!
//! nalgebra's decompositions take ownership of (or copy) their matrix; the simulator factors
//! matrices every step, so these work in preallocated buffers instead. They run on the
//! column-major storage directly so the inner loops are contiguous (vectorisable) and free of
//! bounds checks. Only the lower triangle of the input is read; the factor overwrites it, and
//! the solves read only the lower triangle of a factor.

use super::mul_add;
use nalgebra::storage::{IsContiguous, RawStorage, RawStorageMut};
use nalgebra::{DMatrix, DMatrixView, Dim, Matrix};

/// Factors the symmetric positive definite `a` in place (lower triangle becomes `L`,
/// right-looking, column by column; the strict upper triangle is overwritten with values of no
/// meaning). Returns the index of the first non-positive pivot.
pub fn cholesky_in_place(a: &mut DMatrix<f64>) -> Result<(), usize> {
    let n = a.nrows();
    with_fixed_width!(n, |order| cholesky_kernel(a.as_mut_slice(), order))
}

/// Right-looking: once column `j` is known, every later column is updated from it, and those
/// updates are independent of each other (a left-looking column would instead gather `j`
/// dependent updates into one target). The trailing update uses the unscaled column and
/// `1 / d_j` (`L_ij L_cj = a_ij a_cj / d_j`), so the square root of the pivot is off the chain
/// from one pivot to the next.
#[inline(always)]
fn cholesky_kernel(s: &mut [f64], n: usize) -> Result<(), usize> {
    for j in 0..n {
        let diagonal = s[j * n + j];
        if diagonal <= 0.0 || !diagonal.is_finite() {
            return Err(j);
        }
        let reciprocal = 1.0 / diagonal;
        let (done, trailing) = s.split_at_mut((j + 1) * n);
        let column = &done[j * n..];
        for c in j + 1..n {
            let factor = column[c] * reciprocal;
            // Whole columns (fixed length, no remainder loops): rows above `c` are the strict
            // upper triangle, which the factor leaves unspecified.
            let target = &mut trailing[(c - j - 1) * n..(c - j) * n];
            for (t, v) in target.iter_mut().zip(column) {
                *t = mul_add(-v, factor, *t);
            }
        }
        let pivot = diagonal.sqrt();
        // 1 / sqrt(d) = sqrt(d) / d: a multiply instead of a second division.
        let inverse = pivot * reciprocal;
        let column = &mut s[j * n + j..j * n + n];
        column[0] = pivot;
        column[1..].iter_mut().for_each(|v| *v *= inverse);
    }
    Ok(())
}

/// Solves `L y = b` in place (forward substitution, column-oriented).
pub fn forward_substitute(l: &DMatrix<f64>, b: &mut [f64]) {
    let n = l.nrows();
    with_fixed_width!(n, |order| forward_kernel(l.as_slice(), b, order));
}

/// Up to this order the substitutions keep the reciprocals of the diagonal on the stack.
const LOCAL_ORDER: usize = 12;

/// `1 / L_jj` for `j < n <= LOCAL_ORDER`: independent divisions, computed before a
/// substitution so that its chain from one unknown to the next has none.
#[inline(always)]
fn reciprocal_diagonal(s: &[f64], n: usize) -> [f64; LOCAL_ORDER] {
    let mut reciprocal = [0.0; LOCAL_ORDER];
    for (j, r) in reciprocal.iter_mut().enumerate().take(n) {
        *r = 1.0 / s[j * n + j];
    }
    reciprocal
}

#[inline(always)]
fn forward_kernel(s: &[f64], b: &mut [f64], n: usize) {
    let reciprocal = (n <= LOCAL_ORDER).then(|| reciprocal_diagonal(s, n));
    for j in 0..n {
        let column = &s[j * n..j * n + n];
        let yj = match &reciprocal {
            Some(r) => b[j] * r[j],
            None => b[j] / column[j],
        };
        b[j] = yj;
        if yj != 0.0 {
            for (bi, lij) in b[j + 1..].iter_mut().zip(&column[j + 1..]) {
                *bi = mul_add(-lij, yj, *bi);
            }
        }
    }
}

/// Solves `L^T x = b` in place (backward substitution).
pub fn backward_substitute(l: &DMatrix<f64>, b: &mut [f64]) {
    let n = l.nrows();
    with_fixed_width!(n, |order| backward_kernel(l.as_slice(), b, order));
}

/// Row-oriented on `L^T` (row `j` of `L`, strided in the column-major storage): once `x_j` is
/// known, every earlier unknown is updated from it, so the chain from one unknown to the next
/// is one multiply-add (a dot product per unknown would be a chain of sums).
#[inline(always)]
fn backward_kernel(s: &[f64], b: &mut [f64], n: usize) {
    let reciprocal = (n <= LOCAL_ORDER).then(|| reciprocal_diagonal(s, n));
    for j in (0..n).rev() {
        let xj = match &reciprocal {
            Some(r) => b[j] * r[j],
            None => b[j] / s[j * n + j],
        };
        b[j] = xj;
        if xj != 0.0 {
            for (i, bi) in b[..j].iter_mut().enumerate() {
                *bi = mul_add(-s[i * n + j], xj, *bi);
            }
        }
    }
}

/// Solves `L L^T x = b` in place (`b` becomes `x`), with `l` from [`cholesky_in_place`].
pub fn cholesky_solve_in_place(l: &DMatrix<f64>, b: &mut [f64]) {
    forward_substitute(l, b);
    backward_substitute(l, b);
}

/// Solves `X (L L^T) = B` in place for `X` (`b` r x k becomes `X = B (L L^T)^-1`), with `l` (k x
/// k) from [`cholesky_in_place`]: the right division by a symmetric matrix, column by column,
/// so every operation is an axpy over a contiguous column of `b` (r entries) instead of r
/// separate k x k solves with strided rows.
pub fn cholesky_solve_right_in_place(l: &DMatrix<f64>, b: &mut DMatrix<f64>) {
    let (r, k) = b.shape();
    let l = l.as_slice();
    let x = b.as_mut_slice();
    // Z L^T = B: Z_j = (B_j - sum_{i<j} L[j, i] Z_i) / L[j, j].
    for j in 0..k {
        let (done, rest) = x.split_at_mut(j * r);
        let target = &mut rest[..r];
        for i in 0..j {
            let lji = l[i * k + j];
            for (t, z) in target.iter_mut().zip(&done[i * r..i * r + r]) {
                *t = mul_add(-lji, *z, *t);
            }
        }
        let inverse = 1.0 / l[j * k + j];
        target.iter_mut().for_each(|t| *t *= inverse);
    }
    // X L = Z: X_j = (Z_j - sum_{i>j} L[i, j] X_i) / L[j, j], from the last column.
    for j in (0..k).rev() {
        let (head, done) = x.split_at_mut((j + 1) * r);
        let target = &mut head[j * r..];
        for i in j + 1..k {
            let lij = l[j * k + i];
            let source = &done[(i - j - 1) * r..(i - j) * r];
            for (t, v) in target.iter_mut().zip(source) {
                *t = mul_add(-lij, *v, *t);
            }
        }
        let inverse = 1.0 / l[j * k + j];
        target.iter_mut().for_each(|t| *t *= inverse);
    }
}

/// `dst <- src` for matrices or vectors of the same shape with contiguous storage, as one
/// slice copy (a `memcpy`). nalgebra's `copy_from` goes entry by entry through its strides:
/// 0.12 us for a 12 x 31 Jacobian here, several per step. Panics if the shapes differ.
#[inline]
pub fn copy_contiguous<R1, C1, S1, R2, C2, S2>(
    dst: &mut Matrix<f64, R1, C1, S1>,
    src: &Matrix<f64, R2, C2, S2>,
) where
    R1: Dim,
    C1: Dim,
    R2: Dim,
    C2: Dim,
    S1: RawStorageMut<f64, R1, C1> + IsContiguous,
    S2: RawStorage<f64, R2, C2> + IsContiguous,
{
    assert_eq!(dst.shape(), src.shape(), "copy_contiguous: shapes differ");
    dst.as_mut_slice().copy_from_slice(src.as_slice());
}

/// `sum_i a_i b_i` with four independent partial sums, so that the compiler can vectorise it
/// (a single running sum is a dependency chain it must keep in order).
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    let mut lanes = [0.0; 4];
    let (a_chunks, b_chunks) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a_chunks
        .remainder()
        .iter()
        .zip(b_chunks.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a_chunks.zip(b_chunks) {
        for lane in 0..4 {
            lanes[lane] = mul_add(x[lane], y[lane], lanes[lane]);
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + tail
}

/// `[a . b0, a . b1, a . b2, a . b3]`: four dot products in one pass over `a` (each with four
/// partial sums, as [`dot`]), so `a` is loaded once for four columns.
#[inline]
fn dot4(a: &[f64], b: [&[f64]; 4]) -> [f64; 4] {
    let m = a.len();
    let whole = m - m % 4;
    let mut lanes = [[0.0; 4]; 4];
    for start in (0..whole).step_by(4) {
        let x = &a[start..start + 4];
        for (column, sums) in b.iter().zip(lanes.iter_mut()) {
            let y = &column[start..start + 4];
            for lane in 0..4 {
                sums[lane] = mul_add(x[lane], y[lane], sums[lane]);
            }
        }
    }
    let mut out = [0.0; 4];
    for ((value, sums), column) in out.iter_mut().zip(&lanes).zip(&b) {
        let tail: f64 = (whole..m).map(|i| a[i] * column[i]).sum();
        *value = (sums[0] + sums[1]) + (sums[2] + sums[3]) + tail;
    }
    out
}

/// `c <- alpha a^T b + beta c` (`a` m x r, `b` m x k, `c` r x k, all column-major and
/// contiguous) as dot products of columns, four columns of `b` per pass (`dot4`);
/// `symmetric` (for `a == b`) computes the lower triangle's blocks only and mirrors them.
/// nalgebra's `gemm_tr` sums each entry in one dependency chain.
pub fn gemm_tn(
    c: &mut DMatrix<f64>,
    alpha: f64,
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    beta: f64,
    symmetric: bool,
) {
    let (m, r) = a.shape();
    let k = b.ncols();
    assert!(
        b.nrows() == m && c.shape() == (r, k) && (!symmetric || r == k),
        "gemm_tn: shapes {:?}^T x {:?} into {:?}",
        a.shape(),
        b.shape(),
        c.shape()
    );
    let (a, b) = (a.as_slice(), b.as_slice());
    let c = c.as_mut_slice();
    let column = |j: usize| &b[j * m..j * m + m];
    let store = |c: &mut [f64], i: usize, j: usize, value: f64| {
        let entry = &mut c[j * r + i];
        *entry = if beta == 0.0 {
            alpha * value
        } else {
            beta * *entry + alpha * value
        };
    };
    let blocked = k - k % 4;
    for j in (0..blocked).step_by(4) {
        let columns = [column(j), column(j + 1), column(j + 2), column(j + 3)];
        let first = if symmetric { j } else { 0 };
        for i in first..r {
            let values = dot4(&a[i * m..i * m + m], columns);
            for (offset, value) in values.into_iter().enumerate() {
                store(c, i, j + offset, value);
            }
        }
    }
    for j in blocked..k {
        let first = if symmetric { j } else { 0 };
        for i in first..r {
            store(c, i, j, dot(&a[i * m..i * m + m], column(j)));
        }
    }
    if symmetric {
        // The blocks computed rows i >= j (block start); mirror the strict lower triangle.
        for j in 0..k {
            for i in j + 1..r {
                c[i * r + j] = c[j * r + i];
            }
        }
    }
}

/// `y <- alpha a x + beta y` for `a` k x n with few rows (the contact rows, k = 6 or 12): the
/// k sums stay in registers over the n columns. nalgebra's `gemv` adds column after column
/// into `y` in memory, a chain of read-modify-writes of the same k entries.
pub fn gemv_few_rows(y: &mut [f64], alpha: f64, a: &DMatrix<f64>, x: &[f64], beta: f64) {
    let (k, n) = a.shape();
    assert!(y.len() == k && x.len() == n, "gemv_few_rows: sizes");
    if k > LOCAL_ORDER {
        let mut y_vector = nalgebra::DVectorViewMut::from_slice(y, k);
        y_vector.gemv(alpha, a, &nalgebra::DVectorView::from_slice(x, n), beta);
        return;
    }
    with_fixed_width!(k, |rows| gemv_few_rows_kernel(
        y,
        alpha,
        a.as_slice(),
        x,
        beta,
        rows
    ));
}

#[inline(always)]
fn gemv_few_rows_kernel(y: &mut [f64], alpha: f64, a: &[f64], x: &[f64], beta: f64, k: usize) {
    let mut sum = [0.0; LOCAL_ORDER];
    let sum = &mut sum[..k];
    for (column, &xi) in a.chunks_exact(k).zip(x) {
        for (s, v) in sum.iter_mut().zip(column) {
            *s = mul_add(*v, xi, *s);
        }
    }
    for (yi, s) in y.iter_mut().zip(sum.iter()) {
        *yi = if beta == 0.0 {
            alpha * s
        } else {
            alpha * s + beta * *yi
        };
    }
}

/// `y <- alpha a^T x + beta y` for `a` k x n with few rows (k = 6 or 12): `x` stays in
/// registers and each entry of `y` is one fixed-length dot product with a column of `a`.
pub fn gemv_tr_few_rows(y: &mut [f64], alpha: f64, a: &DMatrix<f64>, x: &[f64], beta: f64) {
    let (k, n) = a.shape();
    assert!(y.len() == n && x.len() == k, "gemv_tr_few_rows: sizes");
    with_fixed_width!(k, |rows| {
        for (yi, column) in y.iter_mut().zip(a.as_slice().chunks_exact(rows)) {
            let product = column
                .iter()
                .zip(x)
                .fold(0.0, |sum, (v, xr)| mul_add(*v, *xr, sum));
            *yi = if beta == 0.0 {
                alpha * product
            } else {
                alpha * product + beta * *yi
            };
        }
    });
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
    fn right_division_matches_the_transposed_solve() {
        let (k, r) = (6, 9);
        let a = spd(k);
        let b = DMatrix::from_fn(r, k, |i, j| ((i * 5 + j * 11) % 7) as f64 - 3.0);
        let mut l = a.clone();
        cholesky_in_place(&mut l).unwrap();
        let mut x = b.clone();
        cholesky_solve_right_in_place(&l, &mut x);
        let residual = &x * &a - &b;
        assert!(residual.amax() < 1e-10, "X A - B = {residual}");
    }

    #[test]
    fn gemm_tn_matches_the_product() {
        let a = DMatrix::from_fn(9, 4, |i, j| ((i * 3 + j * 7) % 11) as f64 - 5.0);
        let b = DMatrix::from_fn(9, 3, |i, j| ((i * 5 + j) % 7) as f64 - 3.0);
        let mut c = DMatrix::from_element(4, 3, 1.0);
        gemm_tn(&mut c, 2.0, &a, &b, 0.5, false);
        let expected = a.transpose() * &b * 2.0 + DMatrix::from_element(4, 3, 0.5);
        assert!((&c - &expected).amax() < 1e-12, "{c} vs {expected}");
        // Symmetric, with a block of four columns and a remainder of two.
        let wide = DMatrix::from_fn(9, 6, |i, j| ((i * 3 + j * 7) % 11) as f64 - 5.0);
        let mut gram = DMatrix::zeros(6, 6);
        gemm_tn(&mut gram, 1.0, &wide, &wide, 0.0, true);
        assert!((&gram - wide.transpose() * &wide).amax() < 1e-12);
    }

    #[test]
    fn rejects_indefinite() {
        let mut a = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert_eq!(cholesky_in_place(&mut a), Err(1));
    }
}
