//! The state of a robot with series elastic actuators, `x = [q (nq); theta (n_e); nu (nv);
//! thetadot (n_e)]` (nx = nq + nv + 2 n_e), and its tangent `dx = [dq (nv); dtheta (n_e);
//! dnu (nv); dthetadot (n_e)]` (nd = 2 nv + 2 n_e). `theta` are the motor angles of the
//! elastic joints (motor side), in the order of [`crate::Actuation::elastic_joints`].
//!
//! One place slices a state: the plant, the controller, the closed loop and the bindings all
//! use [`StateLayout`]'s accessors, and [`TangentLayout`]'s for a tangent vector (a
//! displacement `dx` or the derivative `xdot = [nu; thetadot; nudot; thetaddot]`).

use crate::actuator::Actuation;
use crate::model::Model;

/// Layout of the state vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StateLayout {
    /// Configuration size.
    pub nq: usize,
    /// Velocity size.
    pub nv: usize,
    /// Number of elastic joints.
    pub ne: usize,
}

impl StateLayout {
    /// State size `nq + nv + 2 n_e`.
    pub fn nx(&self) -> usize {
        self.nq + self.nv + 2 * self.ne
    }
    /// Tangent size `2 nv + 2 n_e`.
    pub fn nd(&self) -> usize {
        2 * self.nv + 2 * self.ne
    }
    /// Offset of `theta` in `x`.
    pub fn theta_offset(&self) -> usize {
        self.nq
    }
    /// Offset of `nu` in `x`.
    pub fn nu_offset(&self) -> usize {
        self.nq + self.ne
    }
    /// Offset of `thetadot` in `x`.
    pub fn thetadot_offset(&self) -> usize {
        self.nq + self.ne + self.nv
    }
    /// The layout of the tangent vectors of this state.
    pub fn tangent(&self) -> TangentLayout {
        TangentLayout {
            nv: self.nv,
            ne: self.ne,
        }
    }
}

impl StateLayout {
    /// The layout of `model` with `actuation`.
    pub fn new(model: &Model, actuation: &Actuation) -> Self {
        Self {
            nq: model.nq(),
            nv: model.nv(),
            ne: actuation.n_elastic(),
        }
    }

    /// `q` (nq) of a state.
    pub fn q<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[..self.nq]
    }

    /// Joint positions `s` (n) of a state.
    pub fn s<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[7..self.nq]
    }

    /// Motor angles `theta` (n_e) of a state [rad, motor side].
    pub fn theta<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[self.theta_offset()..self.theta_offset() + self.ne]
    }

    /// `nu` (nv) of a state.
    pub fn nu<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[self.nu_offset()..self.nu_offset() + self.nv]
    }

    /// Joint velocities `sdot` (n) of a state.
    pub fn sdot<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[self.nu_offset() + 6..self.nu_offset() + self.nv]
    }

    /// Motor velocities `thetadot` (n_e) of a state [rad/s, motor side].
    pub fn thetadot<'a>(&self, x: &'a [f64]) -> &'a [f64] {
        &x[self.thetadot_offset()..self.thetadot_offset() + self.ne]
    }

    /// `q` (nq) of a state, mutable.
    pub fn q_mut<'a>(&self, x: &'a mut [f64]) -> &'a mut [f64] {
        &mut x[..self.nq]
    }

    /// Motor angles `theta` (n_e) of a state, mutable.
    pub fn theta_mut<'a>(&self, x: &'a mut [f64]) -> &'a mut [f64] {
        let offset = self.theta_offset();
        &mut x[offset..offset + self.ne]
    }

    /// `nu` (nv) of a state, mutable.
    pub fn nu_mut<'a>(&self, x: &'a mut [f64]) -> &'a mut [f64] {
        let offset = self.nu_offset();
        &mut x[offset..offset + self.nv]
    }

    /// Motor velocities `thetadot` (n_e) of a state, mutable.
    pub fn thetadot_mut<'a>(&self, x: &'a mut [f64]) -> &'a mut [f64] {
        let offset = self.thetadot_offset();
        &mut x[offset..offset + self.ne]
    }
}

/// Layout of a tangent vector of the state, `dx = [dq (nv); dtheta (n_e); dnu (nv); dthetadot
/// (n_e)]` (nd = 2 nv + 2 n_e). In the derivative `xdot` the same four blocks hold
/// `[nu; thetadot; nudot; thetaddot]`. `dq` is the configuration's tangent: the base's
/// `[v; omega]` (6) then the joints (n), like `nu`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TangentLayout {
    /// Velocity size.
    pub nv: usize,
    /// Number of elastic joints.
    pub ne: usize,
}

/// The four blocks of a tangent vector (slices of it): in a displacement `dx` the names say
/// what they hold; in a derivative `xdot` they hold `nu`, `thetadot`, `nudot`, `thetaddot`.
#[derive(Debug)]
pub struct TangentBlocks<S> {
    /// `dq` (nv), or `nu` in `xdot`.
    pub dq: S,
    /// `dtheta` (n_e), or `thetadot` in `xdot`.
    pub dtheta: S,
    /// `dnu` (nv), or `nudot` in `xdot`.
    pub dnu: S,
    /// `dthetadot` (n_e), or `thetaddot` in `xdot`.
    pub dthetadot: S,
}

impl TangentLayout {
    /// Tangent size `2 nv + 2 n_e`.
    pub fn nd(&self) -> usize {
        2 * self.nv + 2 * self.ne
    }
    /// Offset of `dtheta` (`thetadot` in `xdot`).
    pub fn dtheta_offset(&self) -> usize {
        self.nv
    }
    /// Offset of `dnu` (`nudot` in `xdot`).
    pub fn dnu_offset(&self) -> usize {
        self.nv + self.ne
    }
    /// Offset of `dthetadot` (`thetaddot` in `xdot`).
    pub fn dthetadot_offset(&self) -> usize {
        2 * self.nv + self.ne
    }

    /// `dq` (nv) of a tangent vector (`nu` in `xdot`).
    pub fn dq<'a>(&self, dx: &'a [f64]) -> &'a [f64] {
        &dx[..self.nv]
    }

    /// `dtheta` (n_e) of a tangent vector (`thetadot` in `xdot`).
    pub fn dtheta<'a>(&self, dx: &'a [f64]) -> &'a [f64] {
        &dx[self.dtheta_offset()..self.dtheta_offset() + self.ne]
    }

    /// `dnu` (nv) of a tangent vector (`nudot` in `xdot`).
    pub fn dnu<'a>(&self, dx: &'a [f64]) -> &'a [f64] {
        &dx[self.dnu_offset()..self.dnu_offset() + self.nv]
    }

    /// `dthetadot` (n_e) of a tangent vector (`thetaddot` in `xdot`).
    pub fn dthetadot<'a>(&self, dx: &'a [f64]) -> &'a [f64] {
        &dx[self.dthetadot_offset()..self.dthetadot_offset() + self.ne]
    }

    /// The four blocks of `dx` (size nd).
    pub fn split<'a>(&self, dx: &'a [f64]) -> TangentBlocks<&'a [f64]> {
        let (dq, rest) = dx[..self.nd()].split_at(self.nv);
        let (dtheta, rest) = rest.split_at(self.ne);
        let (dnu, dthetadot) = rest.split_at(self.nv);
        TangentBlocks {
            dq,
            dtheta,
            dnu,
            dthetadot,
        }
    }

    /// The four blocks of `dx` (size nd), mutable.
    pub fn split_mut<'a>(&self, dx: &'a mut [f64]) -> TangentBlocks<&'a mut [f64]> {
        let nd = self.nd();
        let (dq, rest) = dx[..nd].split_at_mut(self.nv);
        let (dtheta, rest) = rest.split_at_mut(self.ne);
        let (dnu, dthetadot) = rest.split_at_mut(self.nv);
        TangentBlocks {
            dq,
            dtheta,
            dnu,
            dthetadot,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tangent_blocks_follow_the_documented_order() {
        let layout = StateLayout {
            nq: 10,
            nv: 9,
            ne: 2,
        };
        let tangent = layout.tangent();
        assert_eq!(tangent.nd(), layout.nd());
        let dx: Vec<f64> = (0..tangent.nd()).map(|i| i as f64).collect();
        let blocks = tangent.split(&dx);
        assert_eq!(blocks.dq, tangent.dq(&dx));
        assert_eq!(blocks.dtheta, tangent.dtheta(&dx));
        assert_eq!(blocks.dnu, tangent.dnu(&dx));
        assert_eq!(blocks.dthetadot, tangent.dthetadot(&dx));
        assert_eq!(blocks.dq, &dx[..9]);
        assert_eq!(blocks.dtheta, &dx[9..11]);
        assert_eq!(blocks.dnu, &dx[11..20]);
        assert_eq!(blocks.dthetadot, &dx[20..22]);
        let mut written = vec![0.0; tangent.nd()];
        let blocks = tangent.split_mut(&mut written);
        blocks.dq.fill(1.0);
        blocks.dtheta.fill(2.0);
        blocks.dnu.fill(3.0);
        blocks.dthetadot.fill(4.0);
        assert_eq!(written[tangent.dtheta_offset()], 2.0);
        assert_eq!(written[tangent.dnu_offset()], 3.0);
        assert_eq!(written[tangent.dthetadot_offset()], 4.0);
    }
}
