//! Robot descriptions: the robot-specific data a scenario's defaults come from (joints,
//! named postures, contacts, joint groups, gains). Each is plain data
//! ([`RobotDescription`], deserialisable, so it can be read from a file); the one robot today
//! is the paper's iCub ([`icub`]).

pub mod icub;

pub use icub::icub;

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Everything a scenario takes from the robot when the file does not say otherwise.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotDescription {
    /// The moving joints (the default of `robot.joints`), in the order of [`Self::postures`].
    pub joints: Vec<String>,
    /// Named initial postures (`robot.initial_posture = "NAME"`), one angle per joint of
    /// [`Self::joints`].
    pub postures: BTreeMap<String, Posture>,
    /// Contact frames, stance foot first (the default of `robot.contacts`).
    pub contacts: Vec<String>,
    /// Joint groups by name (`reference.posture_step_joints`): each the joints its selectors
    /// pick, selector after selector, each in the model's joint order.
    pub joint_groups: BTreeMap<String, Vec<JointSelector>>,
    /// Postural stiffness by joint, before [`Self::postural_scale`].
    pub postural_stiffness: PosturalStiffness,
    /// Scale of the postural stiffness (the default of `controller.postural_scale`).
    pub postural_scale: f64,
    /// Momentum integral gains `K_i`, linear xyz then angular xyz (the default of
    /// `controller.momentum_integral`).
    pub momentum_integral: MomentumIntegral,
    /// Motor velocity loop gain `K_m` [1/s] (the default of `plant.motor_velocity_gain`).
    pub motor_velocity_gain: f64,
    /// Added to the joint block of `M` [kg m^2] in plant and controller (the default of
    /// `plant.joint_inertia_regularization` and `controller.joint_inertia_regularization`).
    pub joint_inertia_regularization: f64,
    /// Damping of the pseudo-inverse of `Lambda` (the default of `controller.pinv_damping`).
    pub pinv_damping: f64,
    /// QP Hessian regulariser (the default of `controller.qp_regularization`).
    pub qp_regularization: f64,
}

/// A named posture: joint angles in `unit`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Posture {
    /// Unit of [`Self::angles`].
    pub unit: AngleUnit,
    /// One angle per joint of [`RobotDescription::joints`].
    pub angles: Vec<f64>,
}

impl Posture {
    /// The angles in radians.
    pub fn radians(&self) -> Vec<f64> {
        match self.unit {
            AngleUnit::Rad => self.angles.clone(),
            AngleUnit::Deg => self.angles.iter().map(|a| a.to_radians()).collect(),
        }
    }
}

/// Unit of the angles of a [`Posture`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AngleUnit {
    /// Radians.
    Rad,
    /// Degrees.
    Deg,
}

/// The joints whose names start with `prefix` and contain one of `contains` (any, when it is
/// empty).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct JointSelector {
    /// Start of the name.
    pub prefix: String,
    /// Parts of the name, one of which must occur (none: every name with the prefix).
    #[serde(default)]
    pub contains: Vec<String>,
}

impl JointSelector {
    /// Whether joint `name` is selected.
    pub fn selects(&self, name: &str) -> bool {
        name.starts_with(&self.prefix)
            && (self.contains.is_empty() || self.contains.iter().any(|part| name.contains(part)))
    }
}

/// Postural stiffness by joint [Nm/rad]: a leg joint (`SIDE_JOINT`, SIDE one of
/// [`Self::sides`], JOINT one of [`Self::leg_joints`]) takes the stance or swing leg's entry
/// (stance when a contact frame starts with SIDE); any other joint its entry of
/// [`Self::by_name`], else of the first matching [`Self::by_suffix`], else [`Self::other`].
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PosturalStiffness {
    /// Leg prefixes ("l", "r"): a contact frame starting with one makes that leg the stance leg.
    pub sides: Vec<String>,
    /// The leg's joints after `SIDE_`, in the order of the two leg tables.
    pub leg_joints: Vec<String>,
    /// The stance leg's stiffness, order of [`Self::leg_joints`].
    pub stance_leg: Vec<f64>,
    /// A swing leg's stiffness, order of [`Self::leg_joints`].
    pub swing_leg: Vec<f64>,
    /// Other joints by exact name.
    pub by_name: BTreeMap<String, f64>,
    /// Other joints by the end of their name, first match.
    pub by_suffix: Vec<(String, f64)>,
    /// Any other joint.
    pub other: f64,
}

impl PosturalStiffness {
    /// The stiffness of joint `name` when `contacts` carry the robot.
    pub fn of(&self, name: &str, contacts: &[String]) -> f64 {
        for side in &self.sides {
            let leg_index = name
                .strip_prefix(side.as_str())
                .and_then(|rest| rest.strip_prefix('_'))
                .and_then(|joint| self.leg_joints.iter().position(|j| j == joint));
            if let Some(k) = leg_index {
                let stance = contacts.iter().any(|c| c.starts_with(side.as_str()));
                return if stance {
                    self.stance_leg[k]
                } else {
                    self.swing_leg[k]
                };
            }
        }
        if let Some(&stiffness) = self.by_name.get(name) {
            return stiffness;
        }
        self.by_suffix
            .iter()
            .find(|(suffix, _)| name.ends_with(suffix.as_str()))
            .map_or(self.other, |&(_, stiffness)| stiffness)
    }
}

/// Momentum integral gains, linear xyz then angular xyz, by the number of feet in contact.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MomentumIntegral {
    /// Balancing on one foot.
    pub one_foot: [f64; 6],
    /// Balancing on two feet.
    pub two_feet: [f64; 6],
}

impl MomentumIntegral {
    /// The gains for one foot (`one_foot`) or two.
    pub fn gains(&self, one_foot: bool) -> [f64; 6] {
        if one_foot {
            self.one_foot
        } else {
            self.two_feet
        }
    }
}

impl RobotDescription {
    /// The joints of `group` (a name of [`Self::joint_groups`]) among `joint_names`, `None`
    /// for an unknown group.
    pub fn group(&self, group: &str, joint_names: &[String]) -> Option<Vec<String>> {
        let selectors = self.joint_groups.get(group)?;
        Some(
            selectors
                .iter()
                .flat_map(|selector| joint_names.iter().filter(|n| selector.selects(n)))
                .cloned()
                .collect(),
        )
    }
}
