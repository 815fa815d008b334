//! Physical checks of URDF link inertias and of the mass a moving joint carries.
//!
//! Tolerant as Pinocchio, careful as MuJoCo: only what makes the numbers meaningless is an
//! error (a non-finite value, a negative mass). What is physically doubtful but computable
//! loads with a [`Warning`] naming the link and the principal moments (strict loading refuses
//! it): zero mass with a nonzero inertia, a negative principal moment, a singular inertia with
//! a positive mass (point or rod mass, e.g. sensor frames), the triangle inequality violated.
//! A link with zero mass and zero inertia is massless: a frame of its body, silently. The
//! dynamics need `M(q)` positive definite, not every body inertia: a massless body on a moving
//! joint is fine while something below it carries mass; a moving joint with an entirely
//! massless subtree makes `M(q)` singular and is reported ([`massless_subtree_warnings`]).

use crate::error::{Error, Result, Warning, WarningKind};
use crate::model::Joint;
use crate::spatial::BodyInertia;
use nalgebra::{Matrix3, SymmetricEigen};

/// Relative tolerance of the inertia triangle inequality (URDF values are printed rounded).
const TRIANGLE_TOLERANCE: f64 = 1e-6;

/// Principal moments within this fraction of the largest one count as zero (rounding of the
/// printed values and of the eigen decomposition, e.g. `-2e-22` next to `3e-6`).
const ROUNDING_TOLERANCE: f64 = 1e-9;

/// Principal moments below this [kg m^2] count as zero whatever the largest one (printed
/// noise such as `2.4e-35` or `5e-20`; a milligram at a micrometre is `1e-18`).
const ZERO_MOMENT: f64 = 1e-18;

/// Checks a link's mass and rotational inertia (about the CoM, link axes). `Ok(false)` for a
/// massless link (zero mass, zero inertia); `Ok(true)` if it has an inertia to keep, with any
/// doubt pushed to `warnings`; `Err` for a negative mass (non-finite values are checked
/// before).
pub(crate) fn check_link_inertia(
    what: &str,
    mass: f64,
    inertia: &Matrix3<f64>,
    warnings: &mut Vec<Warning>,
) -> Result<bool> {
    if mass < 0.0 {
        return Err(Error::model(what, format!("has negative mass {mass}")));
    }
    if mass == 0.0 && inertia.iter().all(|v| *v == 0.0) {
        return Ok(false);
    }
    let moments = SymmetricEigen::new(*inertia).eigenvalues;
    let largest = moments.iter().fold(0.0_f64, |a, m| a.max(m.abs()));
    let zero = (ROUNDING_TOLERANCE * largest).max(ZERO_MOMENT);
    // Moments within rounding of zero are zero: they neither make the inertia indefinite nor
    // break the triangle inequality.
    let moments = moments.map(|m| if m.abs() <= zero { 0.0 } else { m });
    if mass == 0.0 && moments.iter().all(|m| *m == 0.0) {
        return Ok(false); // massless up to printed noise
    }
    let text = format!("{:?}", moments.as_slice());
    let warn = |kind, message: String| Warning::new(kind, what, message);
    if mass == 0.0 {
        warnings.push(warn(
            WarningKind::ZeroMassWithInertia,
            format!("has zero mass but a nonzero rotational inertia (principal moments {text}): kept as a pure rotational inertia"),
        ));
    }
    if moments.iter().any(|m| *m < 0.0) {
        warnings.push(warn(
            WarningKind::InertiaNotPositiveSemidefinite,
            format!("inertia is not positive semidefinite (principal moments {text})"),
        ));
        return Ok(true);
    }
    if mass > 0.0 && moments.iter().any(|m| *m == 0.0) {
        let message = if moments.iter().all(|m| *m == 0.0) {
            format!("has mass {mass} but zero rotational inertia (a point mass)")
        } else {
            format!("inertia is singular (principal moments {text}; a rod or point mass)")
        };
        warnings.push(warn(WarningKind::SingularInertia, message));
    }
    let trace = moments.sum();
    if (0..3).any(|k| trace - moments[k] < moments[k] - TRIANGLE_TOLERANCE * trace) {
        warnings.push(warn(
            WarningKind::TriangleInequality,
            format!("inertia violates the triangle inequality (principal moments {text})"),
        ));
    }
    Ok(true)
}

/// Whether a body carries neither mass nor rotational inertia.
fn is_empty(inertia: &BodyInertia) -> bool {
    inertia.mass == 0.0 && inertia.inertia_com.iter().all(|v| *v == 0.0)
}

/// One warning per topmost moving joint whose whole subtree is massless (`M(q)` then has a
/// zero row and column), and one for a robot without any mass. Bodies are in depth-first
/// order (`parent < child`), `joints[i - 1]` moving body `i`.
pub(crate) fn massless_subtree_warnings(
    joints: &[Joint],
    body_inertias: &[BodyInertia],
) -> Vec<Warning> {
    let n_bodies = body_inertias.len();
    let mut subtree_empty: Vec<bool> = body_inertias.iter().map(is_empty).collect();
    let mut joints_below = vec![0usize; n_bodies];
    for body in (1..n_bodies).rev() {
        let parent = joints[body - 1].parent;
        subtree_empty[parent] &= subtree_empty[body];
        joints_below[parent] += joints_below[body] + 1;
    }
    if subtree_empty[0] {
        return vec![Warning::new(
            WarningKind::MasslessSubtree,
            "robot",
            "carries neither mass nor inertia: M(q) is singular",
        )];
    }
    (1..n_bodies)
        .filter(|&body| subtree_empty[body] && !subtree_empty[joints[body - 1].parent])
        .map(|body| {
            Warning::new(
                WarningKind::MasslessSubtree,
                format!("joint '{}'", joints[body - 1].name),
                format!(
                    "moves no mass (its links, and the {} moving joints below it, carry neither mass nor inertia): M(q) is singular",
                    joints_below[body]
                ),
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(mass: f64, diagonal: [f64; 3]) -> (Result<bool>, Vec<WarningKind>) {
        let mut warnings = Vec::new();
        let inertia = Matrix3::from_diagonal(&diagonal.into());
        let result = check_link_inertia("link 'l'", mass, &inertia, &mut warnings);
        (result, warnings.iter().map(|w| w.kind).collect())
    }

    #[test]
    fn verdicts_of_the_inertia_checks() {
        use WarningKind::*;
        assert!(matches!(check(1.0, [0.1, 0.1, 0.1]), (Ok(true), w) if w.is_empty()));
        assert!(matches!(check(0.0, [0.0; 3]), (Ok(false), w) if w.is_empty()));
        assert!(check(-1.0, [0.1; 3]).0.is_err());
        assert_eq!(check(0.0, [0.1; 3]).1, vec![ZeroMassWithInertia]);
        assert_eq!(check(1.0, [0.0; 3]).1, vec![SingularInertia]);
        assert_eq!(check(1.0, [0.1, 0.1, 0.0]).1, vec![SingularInertia]);
        // Rounding: a moment of -1e-22 next to 3e-6 is zero, not negative.
        assert_eq!(check(1.0, [3e-6, 3e-6, -1e-22]).1, vec![SingularInertia]);
        // Printed noise is zero: a point mass (iCub's `r_hip_2`, `r_ankle_1`).
        assert_eq!(check(1.0, [-5e-20, 5e-20, 4e-21]).1, vec![SingularInertia]);
        // One nonzero moment (ANYmal's base placeholder): singular and not a rigid body.
        assert_eq!(
            check(1e-6, [3e-6, -1e-22, 0.0]).1,
            vec![SingularInertia, TriangleInequality]
        );
        assert_eq!(
            check(1.0, [0.1, -0.01, 0.1]).1,
            vec![InertiaNotPositiveSemidefinite]
        );
        assert_eq!(check(1.0, [0.1, 0.1, 0.5]).1, vec![TriangleInequality]);
    }
}
