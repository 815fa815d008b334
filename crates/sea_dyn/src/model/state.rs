//! The state of a robot with series elastic actuators, `x = [q (nq); theta (n_e); nu (nv);
//! thetadot (n_e)]` (nx = nq + nv + 2 n_e), and its tangent `dx = [dq (nv); dtheta (n_e);
//! dnu (nv); dthetadot (n_e)]` (nd = 2 nv + 2 n_e). `theta` are the motor angles of the
//! elastic joints (motor side), in the order of [`crate::Actuation::elastic_joints`].
//!
//! One place slices a state: the plant, the controller, the closed loop and the bindings all
//! use [`StateLayout`]'s accessors.

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
