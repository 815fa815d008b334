//! The ground the unilateral contacts touch: a plane, optionally inclined, with Coulomb
//! friction.

use crate::error::{Error, Result};
use nalgebra::Vector3;
use sea_dyn::error::check_non_negative;

/// A flat ground: the plane through `point` with upward unit `normal` (world axes), with the
/// Coulomb friction coefficient `friction` between it and the soles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Unit normal pointing out of the ground (world axes).
    pub normal: Vector3<f64>,
    /// A point of the plane (world) [m].
    pub point: Vector3<f64>,
    /// Coulomb friction coefficient `mu` (>= 0).
    pub friction: f64,
}

impl Ground {
    /// The horizontal plane `z = height` [m].
    pub fn flat(height: f64, friction: f64) -> Result<Self> {
        Self::inclined(height, 0.0, 0.0, friction)
    }

    /// The plane through `(0, 0, height)` tilted by `incline` [rad] (in `[0, pi/2)`) so that
    /// it rises along the horizontal direction of heading `heading` [rad] (0: along +x,
    /// pi/2: along +y). Errors name the bad argument.
    pub fn inclined(height: f64, incline: f64, heading: f64, friction: f64) -> Result<Self> {
        if !height.is_finite() {
            return Err(Error::invalid(
                "ground.height_m",
                "a finite number [m]",
                height,
            ));
        }
        if !(incline.is_finite() && (0.0..std::f64::consts::FRAC_PI_2).contains(&incline)) {
            return Err(Error::invalid(
                "ground.incline_rad",
                "an angle in [0, pi/2) [rad]",
                incline,
            ));
        }
        if !heading.is_finite() {
            return Err(Error::invalid(
                "ground.incline_heading_rad",
                "a finite angle [rad]",
                heading,
            ));
        }
        check_non_negative("ground.friction", friction)?;
        let (sin, cos) = incline.sin_cos();
        let normal = Vector3::new(-sin * heading.cos(), -sin * heading.sin(), cos);
        Ok(Self {
            normal,
            point: Vector3::new(0.0, 0.0, height),
            friction,
        })
    }

    /// Signed height of `position` above the plane along the normal [m] (negative: below).
    pub fn height_of(&self, position: &Vector3<f64>) -> f64 {
        self.normal.dot(&(position - self.point))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_inclined_plane_rises_along_its_heading() {
        let ground = Ground::inclined(0.1, 0.3, 0.0, 0.5).unwrap();
        let ahead = Vector3::new(1.0, 0.0, 0.1 + 0.3f64.tan());
        assert!(ground.height_of(&ahead).abs() < 1e-12);
        let sideways = Ground::inclined(0.0, 0.3, std::f64::consts::FRAC_PI_2, 0.5).unwrap();
        assert!(
            sideways
                .height_of(&Vector3::new(0.0, 1.0, 0.3f64.tan()))
                .abs()
                < 1e-12
        );
    }

    #[test]
    fn bad_grounds_name_the_key() {
        let cases = [
            (
                Ground::inclined(0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.5),
                "incline_rad",
            ),
            (Ground::inclined(0.0, -0.1, 0.0, 0.5), "incline_rad"),
            (Ground::flat(0.0, -1.0), "ground.friction"),
            (Ground::flat(0.0, f64::NAN), "ground.friction"),
            (Ground::flat(f64::INFINITY, 1.0), "ground.height"),
        ];
        for (result, key) in cases {
            let message = result.unwrap_err().to_string();
            assert!(message.contains(key), "{message}");
        }
    }
}
