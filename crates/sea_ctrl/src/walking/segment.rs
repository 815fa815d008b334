//! One segment of the DCM plan in closed form (local time `tau` in `[0, T]`):
//!
//! - DCM `xi(tau) = P(tau) + c e^(omega (tau - T))`, `P` a cubic polynomial;
//! - VRP `p = xi - xidot / omega = P - P' / omega` (the exponential cancels);
//! - CoM, the solution of `xdot = -omega (x - xi)` from `x(0)`:
//!   `x(tau) = Q(tau) + (c / 2) e^(omega (tau - T)) + d e^(-omega tau)` with
//!   `Q = P - P'/omega + P''/omega^2 - P'''/omega^3` (so `Q + Q'/omega = P`) and `d` from
//!   `x(0)`; its velocity and acceleration are the derivatives of this expression.
//!
//! The growing term is anchored at the segment's end so that it never exceeds `|c|`; the
//! last segment (standing) has no growing term and lasts forever.

use nalgebra::Vector2;

/// A cubic polynomial in the plane, `a0 + a1 t + a2 t^2 + a3 t^3`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cubic(pub [Vector2<f64>; 4]);

impl Cubic {
    /// The constant `p`.
    pub fn constant(p: Vector2<f64>) -> Self {
        Self([p, Vector2::zeros(), Vector2::zeros(), Vector2::zeros()])
    }

    /// The `order`-th derivative at `t` (order 0..=3).
    pub fn derivative(&self, order: usize, t: f64) -> Vector2<f64> {
        let a = &self.0;
        match order {
            0 => a[0] + t * (a[1] + t * (a[2] + t * a[3])),
            1 => a[1] + t * (2.0 * a[2] + t * 3.0 * a[3]),
            2 => 2.0 * a[2] + 6.0 * t * a[3],
            3 => 6.0 * a[3],
            _ => Vector2::zeros(),
        }
    }

    /// The cubic with value `x0`, slope `v0` at 0 and `x1`, `v1` at `duration` (Hermite).
    pub fn hermite(
        (x0, v0): (Vector2<f64>, Vector2<f64>),
        (x1, v1): (Vector2<f64>, Vector2<f64>),
        duration: f64,
    ) -> Self {
        let t = duration;
        let a2 = (3.0 * (x1 - x0) - (2.0 * v0 + v1) * t) / (t * t);
        let a3 = (2.0 * (x0 - x1) + (v0 + v1) * t) / (t * t * t);
        Self([x0, v0, a2, a3])
    }
}

/// DCM, VRP and CoM (planar) of a segment at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlanarSample {
    pub dcm: Vector2<f64>,
    pub dcm_velocity: Vector2<f64>,
    pub vrp: Vector2<f64>,
    pub com: [Vector2<f64>; 3],
}

/// One segment (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DcmSegment {
    /// Start time in the plan [s].
    pub start: f64,
    /// Duration `T` [s] (infinite for the last).
    pub duration: f64,
    /// `P`.
    pub poly: Cubic,
    /// `c` (zero for the last).
    pub growth: Vector2<f64>,
    /// `d`, set by [`DcmSegment::set_com_start`].
    pub decay: Vector2<f64>,
}

impl DcmSegment {
    /// The segment whose VRP moves linearly from `p0` to `p1` over `duration` (constant when
    /// they are equal) and whose DCM ends at `xi_end`: `P = p0 + pdot / omega + pdot tau`,
    /// `c = xi_end - P(T)` (Englsberger et al. 2015's backward recursion, here with a linear
    /// VRP; the VRP check `P - P'/omega = p0 + pdot tau` holds by construction).
    pub fn linear_vrp(
        omega: f64,
        start: f64,
        duration: f64,
        (p0, p1): (Vector2<f64>, Vector2<f64>),
        xi_end: Vector2<f64>,
    ) -> Self {
        let pdot = (p1 - p0) / duration;
        let poly = Cubic([p0 + pdot / omega, pdot, Vector2::zeros(), Vector2::zeros()]);
        let growth = xi_end - poly.derivative(0, duration);
        Self {
            start,
            duration,
            poly,
            growth,
            decay: Vector2::zeros(),
        }
    }

    /// The last segment: DCM and VRP at rest at `p` from `start` on.
    pub fn at_rest(start: f64, p: Vector2<f64>) -> Self {
        Self {
            start,
            duration: f64::INFINITY,
            poly: Cubic::constant(p),
            growth: Vector2::zeros(),
            decay: Vector2::zeros(),
        }
    }

    /// A segment whose DCM is the polynomial `poly` alone.
    pub fn polynomial(start: f64, duration: f64, poly: Cubic) -> Self {
        Self {
            start,
            duration,
            poly,
            growth: Vector2::zeros(),
            decay: Vector2::zeros(),
        }
    }

    /// `e^(omega (tau - T))`, zero without a growing term.
    fn growth_factor(&self, omega: f64, tau: f64) -> f64 {
        if self.duration.is_finite() {
            (omega * (tau - self.duration)).exp()
        } else {
            0.0
        }
    }

    /// The `order`-th derivative of `Q` at `tau` (order 0..=2).
    fn q_derivative(&self, omega: f64, order: usize, tau: f64) -> Vector2<f64> {
        let p = |k: usize| self.poly.derivative(order + k, tau);
        p(0) - p(1) / omega + p(2) / omega.powi(2) - p(3) / omega.powi(3)
    }

    /// DCM and its velocity at `tau`.
    pub fn dcm(&self, omega: f64, tau: f64) -> (Vector2<f64>, Vector2<f64>) {
        let g = self.growth_factor(omega, tau);
        (
            self.poly.derivative(0, tau) + self.growth * g,
            self.poly.derivative(1, tau) + self.growth * (omega * g),
        )
    }

    /// Chooses `d` so that the CoM is at `x0` at `tau = 0`.
    pub fn set_com_start(&mut self, omega: f64, x0: Vector2<f64>) {
        let g = self.growth_factor(omega, 0.0);
        self.decay = x0 - self.q_derivative(omega, 0, 0.0) - self.growth * (0.5 * g);
    }

    /// CoM position, velocity and acceleration at `tau`.
    pub fn com(&self, omega: f64, tau: f64) -> [Vector2<f64>; 3] {
        let g = self.growth_factor(omega, tau);
        let h = (-omega * tau).exp();
        let half_c = self.growth * 0.5;
        [
            self.q_derivative(omega, 0, tau) + half_c * g + self.decay * h,
            self.q_derivative(omega, 1, tau) + half_c * (omega * g) - self.decay * (omega * h),
            self.q_derivative(omega, 2, tau)
                + half_c * (omega * omega * g)
                + self.decay * (omega * omega * h),
        ]
    }

    /// Everything at `tau`.
    pub fn sample(&self, omega: f64, tau: f64) -> PlanarSample {
        let (dcm, dcm_velocity) = self.dcm(omega, tau);
        PlanarSample {
            dcm,
            dcm_velocity,
            vrp: self.poly.derivative(0, tau) - self.poly.derivative(1, tau) / omega,
            com: self.com(omega, tau),
        }
    }
}
