//! Small dense linear algebra without allocation: in-place Cholesky `A = L L^T` and solves.
//!
//! nalgebra's decompositions take ownership of (or copy) their matrix; the simulator factors
//! matrices every step, so these work in preallocated buffers instead. Only the lower triangle
//! of the input is read; the factor overwrites it.

use nalgebra::DMatrix;

/// Factors the symmetric positive definite `a` in place (lower triangle becomes `L`).
/// Returns the index of the first non-positive pivot on failure.
pub fn cholesky_in_place(a: &mut DMatrix<f64>) -> Result<(), usize> {
    let n = a.nrows();
    for j in 0..n {
        let mut diagonal = a[(j, j)];
        for k in 0..j {
            diagonal -= a[(j, k)] * a[(j, k)];
        }
        if diagonal <= 0.0 || !diagonal.is_finite() {
            return Err(j);
        }
        let pivot = diagonal.sqrt();
        a[(j, j)] = pivot;
        for i in (j + 1)..n {
            let mut value = a[(i, j)];
            for k in 0..j {
                value -= a[(i, k)] * a[(j, k)];
            }
            a[(i, j)] = value / pivot;
        }
    }
    Ok(())
}

/// Solves `L L^T x = b` in place (`b` becomes `x`), with `l` from [`cholesky_in_place`].
pub fn cholesky_solve_in_place(l: &DMatrix<f64>, b: &mut [f64]) {
    let n = l.nrows();
    for i in 0..n {
        let mut value = b[i];
        for k in 0..i {
            value -= l[(i, k)] * b[k];
        }
        b[i] = value / l[(i, i)];
    }
    for i in (0..n).rev() {
        let mut value = b[i];
        for k in (i + 1)..n {
            value -= l[(k, i)] * b[k];
        }
        b[i] = value / l[(i, i)];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_spd_system() {
        let n = 7;
        let r = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3) % 5) as f64 - 2.0);
        let a = &r * r.transpose() + DMatrix::identity(n, n);
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
