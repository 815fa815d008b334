//! The controller's tuning as a user sets it ([`ControllerTuning`]): the controller's estimates
//! of the robot (stiffness, damping, masses), the task gains, the pseudo-inverse and QP
//! regularisers, the QP's solver and the rigid controller's reflected inertia. With the
//! `serde` feature these are keys of a scenario's flat `[controller]` table, each bounded as it
//! is read (`sea_dyn::bounded`); what needs the robot (a joint's or link's name, the number of
//! joints, the robot description's gains) is resolved when the controller is built.

use super::settings::MomentumRelaxation;
use crate::qp::{QpSolver, RelaxedMomentumWeights};
use std::collections::BTreeMap;

/// The controller's tuning (module doc). With the `serde` feature, the keys of the same names
/// of a scenario's `[controller]` (its own defaults: [`ControllerTuning::default`]; a robot
/// description sets `postural_scale`, `pinv_damping`, `qp_regularization` and
/// `joint_inertia_regularization` for its robot).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct ControllerTuning {
    /// Controller damping estimate `K_D^` = true damping x scale (inputDesMotVel; default 1:
    /// the plant's damping).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::Positive::read"),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub damping_estimate_scale: f64,
    /// Controller stiffness estimate `K_S^` = true stiffness x scale (hjBar; default 1: the
    /// plant's stiffness).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::Positive::read"),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub stiffness_estimate_scale: f64,
    /// Per joint name, a further factor on that joint's stiffness estimate (e.g.
    /// `{ l_knee = 1.3 }`; default none; a name that is not a joint of the model is refused
    /// when the controller is built).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::Positive::read_map"),
        schemars(with = "BTreeMap<String, sea_dyn::bounded::Positive>")
    )]
    pub stiffness_estimate_joint_scales: BTreeMap<String, f64>,
    /// The controller's model: every link's mass and rotational inertia times this scale
    /// (centres of mass unchanged; default 1: the plant's model).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::Positive::read"),
        schemars(with = "sea_dyn::bounded::Positive")
    )]
    pub mass_estimate_scale: f64,
    /// Per link name, a further factor on that link's mass and rotational inertia in the
    /// controller's model (a massless link fused into its parent scales that body; default
    /// none; a name that is not a link of the model is refused when the controller is built).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::Positive::read_map"),
        schemars(with = "BTreeMap<String, sea_dyn::bounded::Positive>")
    )]
    pub link_mass_estimate_scales: BTreeMap<String, f64>,
    /// Momentum integral gains `K_i` (eq:IhTilde; linear xyz, angular xyz; default: the robot
    /// description's for one or two feet).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read_option_entries"),
        schemars(with = "Option<[sea_dyn::bounded::NonNegative; 6]>")
    )]
    pub momentum_integral: Option<[f64; 6]>,
    /// Momentum proportional gains `K_p` (eq:dotH_f; default: the critical damping of the
    /// integral gains).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read_option_entries"),
        schemars(with = "Option<[sea_dyn::bounded::NonNegative; 6]>")
    )]
    pub momentum_proportional: Option<[f64; 6]>,
    /// Postural stiffness `K_p^j` per joint [Nm/rad] before `postural_scale` (posturalNew;
    /// default: the robot description's by joint group; one entry per joint of the model).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read_option_entries"),
        schemars(with = "Option<Vec<sea_dyn::bounded::NonNegative>>")
    )]
    pub postural_stiffness: Option<Vec<f64>>,
    /// Scale of the postural stiffness (default: the robot description's; the original
    /// study's 0.2).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub postural_scale: f64,
    /// Damping of the pseudo-inverse of `Lambda` (eq:torques; default: the robot
    /// description's; the original study's 5e-4,
    /// docs/references.md#original-study-contact-wrench-qp).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub pinv_damping: f64,
    /// QP Hessian regulariser (inputTorquesSOT; default: the robot description's; the
    /// original study's 1e-3, docs/references.md#original-study-contact-wrench-qp).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub qp_regularization: f64,
    /// Two feet: weight of the contact moments `|n|^2` in the QP's objective (0, the original
    /// study's objective; the push scenarios' 30 moves normal force between the feet before
    /// they move a sole's centre of pressure).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub qp_moment_regularization: f64,
    /// Two feet, when the momentum equality is infeasible under the contact constraints:
    /// "none" (the paper's QP; the minimiser without the contact constraints is used) or
    /// "when_infeasible" (the closest momentum rate the contacts can produce).
    pub momentum_relaxation: MomentumRelaxation,
    /// With `momentum_relaxation = "when_infeasible"`: the weight of the relaxed task's
    /// angular rows against its linear rows' 1 [1/m^2] (default 0.1: the CoM's rate kept
    /// before the angular momentum's, a hip strategy). While walking the moments about the
    /// CoM must not give way first: walk_fast.toml with the relaxation completes its 51 steps
    /// at 1 or more and diverges after 36 at 0.1 (docs/findings/stepping.md).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub relaxed_angular_weight: f64,
    /// Skip the QP solver when the QP's minimiser without inequalities satisfies them (it is
    /// then the optimum: the KKT conditions hold with zero multipliers); `false` runs the
    /// solver every tick.
    pub qp_unconstrained_first: bool,
    /// The QP solver: "active_set" (Goldfarb-Idnani, Clarabel as fallback; the default) or
    /// "clarabel".
    pub qp_solver: QpSolver,
    /// Rigid controller: include the motor reflected inertia of elastic joints in `M_j`
    /// (remark1).
    pub reflected_inertia: bool,
    /// Added to the controller model's joint inertia diagonal [kg m^2] (default: the robot
    /// description's; the original study's 0.1).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "sea_dyn::bounded::NonNegative::read"),
        schemars(with = "sea_dyn::bounded::NonNegative")
    )]
    pub joint_inertia_regularization: f64,
}

impl Default for ControllerTuning {
    /// The plant's own estimates (every scale 1), the robot description's gains (`None`), the
    /// original study's regularisers and postural scale (the paper's iCub,
    /// `robots/icub_paper.toml`), the paper's QP (no moment weight, no relaxation) with the
    /// minimiser without inequalities first and the active-set solver, and the reflected
    /// inertia.
    fn default() -> Self {
        Self {
            damping_estimate_scale: 1.0,
            stiffness_estimate_scale: 1.0,
            stiffness_estimate_joint_scales: BTreeMap::new(),
            mass_estimate_scale: 1.0,
            link_mass_estimate_scales: BTreeMap::new(),
            momentum_integral: None,
            momentum_proportional: None,
            postural_stiffness: None,
            postural_scale: 0.2,
            pinv_damping: 5e-4,
            qp_regularization: 1e-3,
            qp_moment_regularization: 0.0,
            momentum_relaxation: MomentumRelaxation::default(),
            relaxed_angular_weight: RelaxedMomentumWeights::default().angular,
            qp_unconstrained_first: true,
            qp_solver: QpSolver::default(),
            reflected_inertia: true,
            joint_inertia_regularization: 0.1,
        }
    }
}

#[cfg(all(test, feature = "serde"))]
mod tests {
    use super::*;

    /// The tuning of a TOML table, or serde's message.
    fn read(text: &str) -> Result<ControllerTuning, String> {
        toml::from_str(text).map_err(|e| e.message().to_string())
    }

    #[test]
    fn keys_are_read_by_name_and_bounded_as_read() {
        let tuning =
            read("pinv_damping = 1e-3\nlink_mass_estimate_scales = { l_knee = 1.2 }").unwrap();
        assert_eq!(tuning.pinv_damping, 1e-3);
        assert_eq!(tuning.link_mass_estimate_scales["l_knee"], 1.2);
        assert_eq!(tuning.qp_regularization, 1e-3, "the default");
        let zero = read("link_mass_estimate_scales = { l_knee = 0 }").unwrap_err();
        assert!(
            zero.contains("must be positive and finite, got 0"),
            "{zero}"
        );
        let negative = read("momentum_integral = [1, 2, 3, 4, 5, -1]").unwrap_err();
        assert!(
            negative.contains("entry 5 must be finite and non-negative"),
            "{negative}"
        );
        let unknown = read("pinv_dampin = 1").unwrap_err();
        assert!(unknown.contains("unknown field `pinv_dampin`"), "{unknown}");
    }
}
