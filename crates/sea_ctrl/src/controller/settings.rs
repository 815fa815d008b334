//! The controller's settings: which controller ([`ControllerKind`], rigid or SEA), what an
//! infeasible two-feet momentum equality does ([`MomentumRelaxation`]) and the
//! [`ControllerSettings`] with their check ([`ControllerSettings::validate`]): the momentum
//! task's gains `K_p`, `K_i` (eq:dotH_f, eq:IhTilde), the postural task's (posturalNew), the
//! QP's contact constraints (frictionCones) and regularisers (inputTorquesSOT), the
//! controller's estimates of `K_S`, `K_D` (hjBar, inputDesMotVel) and the reflected inertia of
//! the rigid controller (remark1).

use crate::error::{Error, Result};
use crate::qp::{ContactConstraints, QpSolver};
// Named by the doc comments only.
#[cfg(doc)]
use crate::qp::{add_moment_regularization, relaxed_momentum_objective, QpStatus};

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

/// Settings of the controller.
#[derive(Clone, Debug)]
pub struct ControllerSettings {
    /// Rigid or SEA.
    pub kind: ControllerKind,
    /// Contact frames (one or two feet).
    pub contacts: Vec<String>,
    /// Momentum proportional gains `K_p` (diagonal, linear then angular).
    pub momentum_proportional: [f64; 6],
    /// Momentum integral gains `K_i` (diagonal).
    pub momentum_integral: [f64; 6],
    /// Postural stiffness `K_p^j` (n, diagonal).
    pub postural_stiffness: Vec<f64>,
    /// Postural damping `K_d^j` (n, diagonal).
    pub postural_damping: Vec<f64>,
    /// Contact constraints of the QP.
    pub constraints: ContactConstraints,
    /// Controller's damping estimate = true damping x this scale.
    pub damping_estimate_scale: f64,
    /// Controller's stiffness estimate = true stiffness x this scale.
    pub stiffness_estimate_scale: f64,
    /// Per joint (n, coordinate order), a further factor on the stiffness estimate of each
    /// elastic joint; empty for none.
    pub stiffness_estimate_joint_scales: Vec<f64>,
    /// Damping of the pseudo-inverse of `Lambda` (original study: 5e-4,
    /// docs/references.md#original-study-contact-wrench-qp).
    pub pinv_damping: f64,
    /// QP Hessian regulariser (original study: 1e-3,
    /// docs/references.md#original-study-contact-wrench-qp).
    pub qp_regularization: f64,
    /// Two feet: weight of the contact moments `|n_k|^2` added to the torque-norm objective
    /// ([`add_moment_regularization`]; 0 in the original study).
    pub qp_moment_regularization: f64,
    /// Two feet: what an infeasible momentum equality does.
    pub momentum_relaxation: MomentumRelaxation,
    /// Rigid controller: add the motor reflected inertia of elastic joints to `M_j`.
    pub reflected_inertia: bool,
    /// Added to the joint diagonal of the controller's `M` [kg m^2].
    pub joint_inertia_regularization: f64,
    /// Try the QP's minimiser without inequalities first: when it satisfies them all it is the
    /// QP's optimum (the KKT conditions hold with zero multipliers) and no QP solver is called.
    pub qp_unconstrained_first: bool,
    /// The QP solver ([`QpSolver::default`]: the active set, Clarabel as fallback).
    pub qp_solver: QpSolver,
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
                self.damping_estimate_scale,
            ),
            (
                "controller.stiffness_estimate_scale",
                self.stiffness_estimate_scale,
            ),
        ]
        .into_iter()
        .chain(joint_scales)
        {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::config(key, format!("must be positive, got {v}")));
            }
        }
        Ok(())
    }

    /// The gains and the QP's contact-moment weight: finite and non-negative.
    fn validate_gains(&self) -> Result<()> {
        let gains: [(&str, &[f64]); 4] = [
            (
                "controller.momentum_proportional",
                &self.momentum_proportional,
            ),
            ("controller.momentum_integral", &self.momentum_integral),
            ("controller.postural_stiffness", &self.postural_stiffness),
            ("controller.postural_damping", &self.postural_damping),
        ];
        for (key, values) in gains {
            if let Some(g) = values.iter().find(|g| !(g.is_finite() && **g >= 0.0)) {
                let message = format!("must be finite and non-negative, got {g}");
                return Err(Error::config(key, message));
            }
        }
        let moment = self.qp_moment_regularization;
        if !(moment.is_finite() && moment >= 0.0) {
            let message = format!("must be finite and non-negative, got {moment}");
            return Err(Error::config(
                "controller.qp_moment_regularization",
                message,
            ));
        }
        Ok(())
    }
}
