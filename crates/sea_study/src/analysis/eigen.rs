//! Eigenvalues and eigenvectors of a real square matrix: balancing (Parlett and Reinsch), the
//! real Schur form of nalgebra, and inverse iteration for one eigenvector.

use crate::error::{Error, Result};
use nalgebra::{Complex, DMatrix, DVector, Schur};

/// Sweeps of the real Schur iteration allowed per row of the matrix before it is called
/// unconverged (LAPACK's `dhseqr` allows 30 per eigenvalue; the iteration is unbounded in
/// nalgebra's `complex_eigenvalues`).
pub const SCHUR_SWEEPS_PER_ROW: usize = 60;

/// Passes of the balancing over every row at most: it converges in a few (Parlett and
/// Reinsch), the bound only keeps a pathological matrix from cycling.
const MAX_BALANCE_PASSES: usize = 100;

/// Balances `a` in place by a diagonal similarity of powers of two (Parlett and Reinsch,
/// Numer. Math. 13, 1969): row and column norms are made comparable, so the Schur iteration
/// sees entries of one scale although the state mixes positions, motor angles and accelerations.
/// Returns the diagonal `d` with `balanced = D^-1 a D`.
pub fn balance(a: &mut DMatrix<f64>) -> Vec<f64> {
    let n = a.nrows();
    let mut d = vec![1.0; n];
    let mut changed = true;
    let mut passes = 0;
    while changed && passes < MAX_BALANCE_PASSES {
        changed = false;
        passes += 1;
        for i in 0..n {
            let column: f64 = (0..n).filter(|&k| k != i).map(|k| a[(k, i)].abs()).sum();
            let row: f64 = (0..n).filter(|&k| k != i).map(|k| a[(i, k)].abs()).sum();
            // A sum that overflows (finite entries near the float range) has no balance: the
            // halvings below would never end on an infinite norm.
            if column == 0.0 || row == 0.0 || !(column + row).is_finite() {
                continue;
            }
            let mut f = 1.0;
            let (mut c, mut r) = (column, row);
            while c < r / 2.0 {
                c *= 2.0;
                r /= 2.0;
                f *= 2.0;
            }
            while c >= r * 2.0 {
                c /= 2.0;
                r *= 2.0;
                f /= 2.0;
            }
            if (c + r) < 0.95 * (column + row) {
                changed = true;
                d[i] *= f;
                // D^-1 A D: row i divided by f, column i multiplied by f.
                a.row_mut(i).scale_mut(1.0 / f);
                a.column_mut(i).scale_mut(f);
            }
        }
    }
    d
}

/// The eigenvalues of `a` (real Schur form of the balanced matrix).
///
/// A matrix with an infinite or NaN entry (a linearisation whose differences overflowed), and
/// one whose Schur iteration does not converge within [`SCHUR_SWEEPS_PER_ROW`] sweeps per row,
/// is a numerical error: neither has a spectrum to report, and both would otherwise keep the
/// balancing or the iteration running forever.
pub fn eigenvalues(a: &DMatrix<f64>) -> Result<Vec<Complex<f64>>> {
    const OPERATION: &str = "the eigenvalues of the linearisation";
    if let Some(bad) = a.iter().find(|entry| !entry.is_finite()) {
        let detail = format!(
            "its {}x{} matrix has a non-finite entry ({bad}): the closed loop's differences \
             overflowed at this value",
            a.nrows(),
            a.ncols()
        );
        return Err(Error::Dynamics(sea_dyn::Error::numerical(
            OPERATION, detail,
        )));
    }
    let mut balanced = a.clone();
    balance(&mut balanced);
    if balanced.iter().any(|entry| !entry.is_finite()) {
        let detail = "its entries overflow once balanced: the closed loop's differences are \
                      near the float range at this value";
        return Err(Error::Dynamics(sea_dyn::Error::numerical(
            OPERATION, detail,
        )));
    }
    let sweeps = SCHUR_SWEEPS_PER_ROW * a.nrows().max(1);
    match Schur::try_new(balanced, f64::EPSILON, sweeps) {
        Some(schur) => Ok(schur.complex_eigenvalues().iter().copied().collect()),
        None => {
            let detail = format!("the real Schur iteration did not converge in {sweeps} sweeps");
            Err(Error::Dynamics(sea_dyn::Error::numerical(
                OPERATION, detail,
            )))
        }
    }
}

/// A unit eigenvector of `a` for the eigenvalue `lambda` by inverse iteration with a slightly
/// shifted `lambda` (so the shifted matrix stays invertible), normalised so that its largest
/// entry is real and positive.
pub fn eigenvector(a: &DMatrix<f64>, lambda: Complex<f64>) -> DVector<Complex<f64>> {
    let n = a.nrows();
    let scale = a.amax().max(1.0);
    let shift = lambda + Complex::new(1e-10 * scale, 1e-10 * scale);
    let shifted = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(a[(i, j)], 0.0)
            - if i == j {
                shift
            } else {
                Complex::new(0.0, 0.0)
            }
    });
    let lu = shifted.lu();
    // A start vector with every mode in it (deterministic).
    let mut v = DVector::from_fn(n, |i, _| {
        Complex::new(1.0 + 0.37 * i as f64, 0.11 * i as f64)
    });
    for _ in 0..4 {
        if let Some(next) = lu.solve(&v) {
            let norm = next.norm();
            if !(norm.is_finite() && norm > 0.0) {
                break;
            }
            v = next.map(|c| c / norm);
        }
    }
    let largest = v
        .iter()
        .copied()
        .max_by(|p, q| p.norm().total_cmp(&q.norm()));
    if let Some(p) = largest.filter(|p| p.norm() > 0.0) {
        let phase = p.conj() / p.norm();
        v.iter_mut().for_each(|c| *c *= phase);
    }
    v
}

/// The largest distance from an eigenvalue of `first` to the nearest eigenvalue of `second`,
/// relative to `max(|lambda|, 1)` (the change between two computations of one spectrum).
pub fn spectrum_distance(first: &[Complex<f64>], second: &[Complex<f64>]) -> f64 {
    first
        .iter()
        .map(|a| {
            second
                .iter()
                .map(|b| (a - b).norm() / a.norm().max(1.0))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenpairs_of_a_badly_scaled_matrix() {
        // Block diagonal: a rotation-like pair at -1 +- 2i and a fast real pole at -1e4, with a
        // coupling of very different scale.
        let a = DMatrix::from_row_slice(
            3,
            3,
            &[-1.0, 2.0e-3, 0.0, -2.0e3, -1.0, 5.0e2, 0.0, 0.0, -1.0e4],
        );
        let mut values = eigenvalues(&a).unwrap();
        values.sort_by(|p, q| q.re.total_cmp(&p.re).then(q.im.total_cmp(&p.im)));
        assert!(
            (values[0] - Complex::new(-1.0, 2.0)).norm() < 1e-9,
            "{values:?}"
        );
        assert!(
            (values[2] - Complex::new(-1.0e4, 0.0)).norm() < 1e-6,
            "{values:?}"
        );
        for lambda in values {
            let v = eigenvector(&a, lambda);
            let ac = a.map(|e| Complex::new(e, 0.0));
            let residual = (&ac * &v - v.map(|c| c * lambda)).norm();
            assert!(residual < 1e-8 * lambda.norm(), "{lambda}: {residual}");
        }
    }

    #[test]
    fn a_matrix_whose_row_sums_overflow_is_an_error_or_a_spectrum_not_a_hang() {
        // Finite entries whose row and column sums overflow: the balancing used to halve an
        // infinite norm forever.
        let big = 0.9 * f64::MAX;
        let a = DMatrix::from_row_slice(3, 3, &[-1.0, big, big, 1.0, -2.0, 0.0, 1.0, 0.0, -3.0]);
        if let Err(e) = eigenvalues(&a) {
            assert!(e.to_string().contains("the eigenvalues"), "{e}");
        }
    }

    #[test]
    fn a_matrix_with_an_infinite_or_nan_entry_is_a_numerical_error_not_a_hang() {
        for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            let a = DMatrix::from_row_slice(2, 2, &[-1.0, bad, 1.0, -2.0]);
            let message = eigenvalues(&a).unwrap_err().to_string();
            assert!(message.contains("non-finite entry"), "{message}");
        }
    }
}
