//! What observers tell the controller about the dynamics its model misses, and how it enters
//! them: the external wrench on the base ([`crate::external_wrench`]; its generalized force
//! less in the base rows of `h`, hDot with an external wrench), the generalized disturbance
//! `d^` ([`crate::generalized_disturbance`]; `h - d^` in every row, its base rows' wrench `w_d`
//! about the CoM carried by the contacts: inputTorquesSOT's momentum equality `A f = b - w_d`)
//! and the CoM offset (the CoM position error of eq:IhTilde taken at the robot's CoM). All
//! zero or empty: the paper's controller.

use super::MomentumController;
use crate::error::Result;
use crate::external_wrench::base_generalized_force;
use nalgebra::{DVector, Vector3, Vector6};
use sea_dyn::spatial::Force;

/// The observers' corrections the controller's dynamics take (zero or empty: none).
#[derive(Clone, Debug)]
pub(super) struct Disturbances {
    /// The external wrench the dynamics take as acting on the base, about the CoM, world axes
    /// [N, Nm] ([`crate::external_wrench`]; zero unless set).
    pub(super) external_wrench: Vector6<f64>,
    /// The generalized disturbance `d^` the dynamics take in every row (nv; empty: none,
    /// [`crate::generalized_disturbance`]).
    pub(super) generalized_disturbance: DVector<f64>,
    /// The wrench about the CoM (world axes) of the generalized disturbance's base rows at the
    /// last tick, which the momentum task's contact wrenches carry (zero: none).
    pub(super) disturbance_wrench: Vector6<f64>,
    /// The robot's CoM less the model's (world) [m] that the CoM position error takes
    /// ([`MomentumController::set_com_offset`]; zero: none).
    pub(super) com_offset: Vector3<f64>,
}

impl Disturbances {
    /// None: zero wrenches, no generalized disturbance, zero CoM offset.
    pub(super) fn new() -> Self {
        Self {
            external_wrench: Vector6::zeros(),
            generalized_disturbance: DVector::zeros(0),
            disturbance_wrench: Vector6::zeros(),
            com_offset: Vector3::zeros(),
        }
    }

    /// `h` (`bias`, nv) less the external wrench's generalized force in the base rows when one
    /// is set, less the generalized disturbance in every row when one is set, whose base rows'
    /// wrench about the CoM (`p_com_rel`, the CoM less the base, world) it keeps for the
    /// momentum target.
    pub(super) fn correct_bias(&mut self, bias: &mut DVector<f64>, p_com_rel: &Vector3<f64>) {
        if self.external_wrench != Vector6::zeros() {
            let force = base_generalized_force(&self.external_wrench, p_com_rel);
            bias.rows_mut(0, 6).axpy(-1.0, &force, 1.0);
        }
        if !self.generalized_disturbance.is_empty() {
            *bias -= &self.generalized_disturbance;
            let d = &self.generalized_disturbance;
            let at_base = Force::new(d.fixed_rows::<3>(0).into(), d.fixed_rows::<3>(3).into());
            self.disturbance_wrench = at_base.moment_about(p_com_rel).to_vector();
        }
    }

    /// The robot's CoM [m, world] from the model's `com`: the position the CoM position error
    /// takes (eq:IhTilde; `set_com_offset`).
    pub(super) fn robot_com(&self, com: Vector3<f64>) -> Vector3<f64> {
        com + self.com_offset
    }

    /// `b - w_d` into `target`: the feet carry what the model misses
    /// (`crate::generalized_disturbance`).
    pub(super) fn carry(&self, target: &mut Vector6<f64>) {
        *target -= self.disturbance_wrench;
    }

    /// The external wrench the tick's dynamics took, about the CoM (world axes): the one set
    /// plus the generalized disturbance's base rows' wrench ([`super::ControlOutput`]).
    pub(super) fn total_wrench(&self) -> Vector6<f64> {
        self.external_wrench + self.disturbance_wrench
    }
}

impl MomentumController {
    /// The external wrench (about the CoM, world axes) [N, Nm] that the dynamics of the next
    /// ticks take as acting on the floating base, e.g. an observer's estimate
    /// ([`crate::external_wrench`]); zero: none (the paper's controller).
    pub fn set_external_wrench(&mut self, wrench: &Vector6<f64>) {
        self.disturbances.external_wrench = *wrench;
    }

    /// The generalized disturbance `d^` (nv) [N, Nm] that the dynamics of the next ticks take
    /// (bias forces `h - d^`), e.g. an observer's estimate
    /// ([`crate::generalized_disturbance`]); empty or zero: none (the paper's controller).
    ///
    /// # Errors
    /// `InvalidArgument` when `disturbance` is neither empty nor of size nv.
    pub fn set_generalized_disturbance(&mut self, disturbance: &DVector<f64>) -> Result<()> {
        let nv = self.model.nv();
        if !disturbance.is_empty() && disturbance.len() != nv {
            return Err(sea_dyn::Error::InvalidArgument {
                argument: "generalized disturbance".into(),
                expected: format!("shape ({nv},)"),
                actual: format!("({},)", disturbance.len()),
            }
            .into());
        }
        self.disturbances
            .generalized_disturbance
            .clone_from(disturbance);
        if disturbance.is_empty() {
            self.disturbances.disturbance_wrench = Vector6::zeros();
        }
        Ok(())
    }

    /// The robot's CoM less the model's, `offset` (world) [m], that the CoM position error of
    /// the next ticks takes (the momentum task's integral term: the robot's CoM is brought to
    /// the reference, while the momentum and its map stay the model's, about its CoM), e.g. an
    /// observer's estimate ([`crate::generalized_disturbance`]); zero: none.
    pub fn set_com_offset(&mut self, offset: &Vector3<f64>) {
        self.disturbances.com_offset = *offset;
    }

    /// The generalized disturbance the dynamics take (nv; empty: none).
    pub fn generalized_disturbance(&self) -> &DVector<f64> {
        &self.disturbances.generalized_disturbance
    }
}
