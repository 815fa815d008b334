//! The controller's settings: which controller ([`ControllerKind`], rigid or SEA), what an
//! infeasible two-feet momentum equality does ([`MomentumRelaxation`]) and the
//! [`ControllerSettings`] with their check ([`ControllerSettings::validate`]): the momentum
//! task's gains `K_p`, `K_i` (eq:dotH_f, eq:IhTilde), the postural task's (posturalNew), the
//! QP's contact constraints (frictionCones) and regularisers (inputTorquesSOT), the
//! controller's estimates of `K_S`, `K_D` (hjBar, inputDesMotVel) and the reflected inertia of
//! the rigid controller (remark1).

use super::tuning::ControllerTuning;
use crate::error::{require_non_negative, require_positive, Error, Result};
use crate::qp::ContactConstraints;
// Named by the doc comments only.
#[cfg(doc)]
use crate::qp::{relaxed_momentum_objective, QpStatus};

/// Which controller; with the `serde` feature, named "sea" or "rigid".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum ControllerKind {
    /// The SEA controller (desired motor velocities).
    Sea,
    /// The rigid-joint controller (joint torques, `tau_m = Gamma tau` on elastic joints).
    Rigid,
}

/// What the two-feet QP does when its momentum equality `A f = b` is infeasible under the
/// contact constraints; with the `serde` feature, named "none" or "when_infeasible".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum MomentumRelaxation {
    /// The paper's QP only: an infeasible tick falls back to the minimiser without the contact
    /// constraints ([`QpStatus::Fallback`]), whose wrenches the contacts cannot carry.
    #[default]
    None,
    /// An infeasible tick solves the relaxed momentum task instead: the closest momentum rate
    /// the contacts can produce, the CoM's before the angular momentum
    /// ([`relaxed_momentum_objective`], [`QpStatus::MomentumRelaxed`]). The centre of pressure
    /// then sits on the edge of the QP's sole (keep `cop_margin` above 0).
    WhenInfeasible,
}

/// Settings of the controller: its kind, contacts and contact constraints, the task gains
/// resolved for the robot, and the user's [`ControllerTuning`] (read as is).
#[derive(Clone, Debug)]
pub struct ControllerSettings {
    /// Rigid or SEA.
    pub kind: ControllerKind,
    /// Contact frames (one or two feet).
    pub contacts: Vec<String>,
    /// Momentum proportional gains `K_p` (diagonal, linear then angular): the tuning's
    /// `momentum_proportional` or the robot's default.
    pub momentum_proportional: [f64; 6],
    /// Momentum integral gains `K_i` (diagonal): the tuning's `momentum_integral` or the
    /// robot's default.
    pub momentum_integral: [f64; 6],
    /// Postural stiffness `K_p^j` (n, diagonal): the tuning's `postural_stiffness` (or the
    /// robot's default) times its `postural_scale`.
    pub postural_stiffness: Vec<f64>,
    /// Postural damping `K_d^j` (n, diagonal).
    pub postural_damping: Vec<f64>,
    /// Contact constraints of the QP.
    pub constraints: ContactConstraints,
    /// Per joint (n, coordinate order), the tuning's `stiffness_estimate_joint_scales` by
    /// name, 1 for a joint it leaves out; empty for none.
    pub stiffness_estimate_joint_scales: Vec<f64>,
    /// Everything else as the user sets it: the estimate scales, the regularisers, the QP's
    /// solver and the reflected inertia.
    pub tuning: ControllerTuning,
}

impl ControllerSettings {
    /// Checks the settings for a model with `n` joints; names the offending key.
    pub fn validate(&self, n: usize) -> Result<()> {
        if self.contacts.is_empty() || self.contacts.len() > 2 {
            return Err(Error::config(
                "controller.contacts",
                "needs one or two contact frames",
            ));
        }
        self.validate_estimate_scales(n)?;
        self.validate_gains()?;
        let margin = self.constraints.cop_margin;
        if !(0.0..1.0).contains(&margin) {
            let message = format!("must be in [0, 1), got {margin}");
            return Err(Error::config("controller.contact.cop_margin", message));
        }
        if self.postural_stiffness.len() != n || self.postural_damping.len() != n {
            return Err(Error::config(
                "controller.postural_stiffness",
                format!("needs {n} entries (one per joint)"),
            ));
        }
        Ok(())
    }

    /// The estimate scales: `stiffness_estimate_joint_scales` empty or of `n` entries, every
    /// scale finite and positive.
    fn validate_estimate_scales(&self, n: usize) -> Result<()> {
        let joint_scales = &self.stiffness_estimate_joint_scales;
        if !joint_scales.is_empty() && joint_scales.len() != n {
            return Err(Error::config(
                "controller.stiffness_estimate_joint_scales",
                format!("needs {n} entries, got {}", joint_scales.len()),
            ));
        }
        let joint_scales = joint_scales
            .iter()
            .map(|&v| ("controller.stiffness_estimate_joint_scales", v));
        for (key, v) in [
            (
                "controller.damping_estimate_scale",
                self.tuning.damping_estimate_scale,
            ),
            (
                "controller.stiffness_estimate_scale",
                self.tuning.stiffness_estimate_scale,
            ),
        ]
        .into_iter()
        .chain(joint_scales)
        {
            require_positive(key, v)?;
        }
        Ok(())
    }

    /// The gains and the QP's weights (contact moments, the relaxed task's angular rows):
    /// finite and non-negative.
    fn validate_gains(&self) -> Result<()> {
        let gains: [(&str, &[f64]); 6] = [
            (
                "controller.momentum_proportional",
                &self.momentum_proportional,
            ),
            ("controller.momentum_integral", &self.momentum_integral),
            ("controller.postural_stiffness", &self.postural_stiffness),
            ("controller.postural_damping", &self.postural_damping),
            (
                "controller.qp_moment_regularization",
                std::slice::from_ref(&self.tuning.qp_moment_regularization),
            ),
            (
                "controller.relaxed_angular_weight",
                std::slice::from_ref(&self.tuning.relaxed_angular_weight),
            ),
        ];
        for (key, values) in gains {
            for &g in values {
                require_non_negative(key, g)?;
            }
        }
        Ok(())
    }
}
