//! The linear inverted pendulum (LIP) at constant height and its divergent component of
//! motion (DCM, the capture point in the plane), docs/references.md#walking:
//!
//! - `omega = sqrt(g / z0)` ([`Lip::new`]);
//! - CoM dynamics `xddot = omega^2 (x - p)` with `p` the virtual repellent point (VRP; the
//!   centre of pressure on flat ground at constant height);
//! - DCM `xi = x + xdot / omega` ([`Lip::dcm`]; Pratt et al. 2006's capture point), whose
//!   dynamics `xidot = omega (xi - p)` diverge while the CoM follows it stably,
//!   `xdot = -omega (x - xi)` (Englsberger et al. 2015, eqs. of the DCM);
//! - with `p` constant over `t`: `xi(t) = p + (xi(0) - p) e^(omega t)` ([`Lip::dcm_after`]).

use crate::error::{require_positive, Result};
use nalgebra::Vector2;

/// A linear inverted pendulum: its natural frequency `omega` and height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lip {
    /// `omega = sqrt(g / z0)` [1/s].
    pub omega: f64,
    /// The CoM height above the ground `z0` [m].
    pub com_height: f64,
}

impl Lip {
    /// The pendulum of height `com_height` (`walking.com_height`, > 0) under gravity of
    /// magnitude `gravity` [m/s^2] (> 0).
    pub fn new(gravity: f64, com_height: f64) -> Result<Self> {
        require_positive("walking.com_height", com_height)?;
        require_positive("gravity", gravity)?;
        Ok(Self {
            omega: (gravity / com_height).sqrt(),
            com_height,
        })
    }

    /// The DCM (capture point) of a CoM at `x` moving at `xdot`: `xi = x + xdot / omega`.
    pub fn dcm(&self, x: Vector2<f64>, xdot: Vector2<f64>) -> Vector2<f64> {
        x + xdot / self.omega
    }

    /// The DCM after `t` [s] from `xi0` with the VRP held at `p`:
    /// `xi(t) = p + (xi0 - p) e^(omega t)`.
    pub fn dcm_after(&self, p: Vector2<f64>, xi0: Vector2<f64>, t: f64) -> Vector2<f64> {
        p + (xi0 - p) * (self.omega * t).exp()
    }
}
