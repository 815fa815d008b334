//! Robot descriptions: the robot-specific data a scenario's defaults come from (URDF, joints,
//! named postures, contacts, foot rectangle, actuators, joint groups, gains). Each is plain
//! data ([`RobotDescription`]) read from TOML: the paper's iCub (`robots/icub_paper.toml`,
//! built in, [`icub()`]), a file, or a table inline in the scenario ([`source`]); a scenario
//! takes its defaults from the one it names ([`defaults`]). Contacts are frame names or
//! `LINK:x,y,z` points of a link ([`contact`]).

pub mod contact;
pub mod defaults;
pub mod icub;
pub mod source;

pub use contact::{add_contact_frames, ContactSpec};
pub use icub::icub;
pub use source::{load_description, DescriptionSource};

use crate::error::{Error, Result};
use sea_dyn::ElasticParameters;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Everything a scenario takes from the robot when the file does not say otherwise.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotDescription {
    /// The URDF (the default of `robot.urdf`): a path, relative to the description's file (to
    /// the scenario's for a description inline in it), or a `package://` or `file://` URI.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<String>,
    /// The moving joints (the default of `robot.joints`), in the order of [`Self::postures`].
    pub joints: Vec<String>,
    /// Named initial postures (`robot.initial_posture = "NAME"`), one angle per joint of
    /// [`Self::joints`].
    pub postures: BTreeMap<String, Posture>,
    /// Contacts, stance foot first (the default of `robot.contacts`): frame names or
    /// `LINK:x,y,z` ([`ContactSpec`]).
    pub contacts: Vec<String>,
    /// The posture a scenario starts in (the default of `robot.initial_posture`): a name of
    /// [`Self::postures`] or "zero".
    pub initial_posture: String,
    /// The foot rectangle in the contact frame (the default of `controller.contact.foot_x`
    /// and `foot_y`; absent: [`sea_dyn::ContactSurface::default`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub foot: Option<FootRectangle>,
    /// Every joint's elastic actuator (the default of `[actuators]`' parameters; absent:
    /// [`ElasticParameters::default`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub actuator: Option<ElasticParameters>,
    /// Per-joint elastic actuators by joint name (the defaults of
    /// `[actuators.overrides.NAME]`; the scenario's `[actuators]` keys do not replace them,
    /// its overrides do).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub actuator_overrides: BTreeMap<String, ElasticParameters>,
    /// Joint groups by name (`reference.posture_step_joints`): each the joints its selectors
    /// pick, selector after selector, each in the model's joint order.
    #[serde(default)]
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

/// A foot's contact rectangle in the contact frame [m] (x forward, z the ground's normal).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FootRectangle {
    /// `[min, max]` along the contact frame's x axis.
    pub x: [f64; 2],
    /// `[min, max]` along the contact frame's y axis.
    pub y: [f64; 2],
}

impl std::fmt::Display for FootRectangle {
    /// `x [x0, x1] y [y0, y1] m`, each edge to 0.1 mm.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let edge = |value: f64| (value * 1e4).round() / 1e4 + 0.0;
        write!(
            f,
            "x [{}, {}] y [{}, {}] m",
            edge(self.x[0]),
            edge(self.x[1]),
            edge(self.y[0]),
            edge(self.y[1])
        )
    }
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
    #[serde(default)]
    pub sides: Vec<String>,
    /// The leg's joints after `SIDE_`, in the order of the two leg tables.
    #[serde(default)]
    pub leg_joints: Vec<String>,
    /// The stance leg's stiffness, order of [`Self::leg_joints`].
    #[serde(default)]
    pub stance_leg: Vec<f64>,
    /// A swing leg's stiffness, order of [`Self::leg_joints`].
    #[serde(default)]
    pub swing_leg: Vec<f64>,
    /// Other joints by exact name.
    #[serde(default)]
    pub by_name: BTreeMap<String, f64>,
    /// Other joints by the end of their name, first match.
    #[serde(default)]
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
    /// Reads a description from TOML text; `origin` names it in errors (a file, or the
    /// built-in name).
    pub fn from_toml(text: &str, origin: &str) -> Result<Self> {
        // toml's whole text: the line, the column and the rule (a description is a file of
        // its own, its lines are what its author sees).
        let description: Self = toml::from_str(text).map_err(|e| {
            Error::config(
                format!("robot description {origin}: "),
                e.to_string().trim(),
            )
        })?;
        description.check(origin)?;
        Ok(description)
    }

    /// Reads a description from the table inline in a scenario (`[robot.description]`);
    /// errors name the scenario's key, `robot.description.NAME`, whose line the scenario's
    /// errors then give.
    pub fn from_table(table: toml::Table) -> Result<Self> {
        let key = |name: &str| match name {
            "" => source::DESCRIPTION_KEY.to_string(),
            name => format!("{}.{name}", source::DESCRIPTION_KEY),
        };
        let description: Self = crate::parse::read_value(toml::Value::Table(table))
            .map_err(|e| Error::config(key(&e.key), e.rule))?;
        description.check_named(key)?;
        Ok(description)
    }

    /// Checks the lengths that tie its tables together: one angle per joint in every
    /// posture, one stiffness per leg joint, one or two contacts, a known initial posture.
    pub fn check(&self, origin: &str) -> Result<()> {
        self.check_named(|name: &str| format!("robot description {origin}: {name}"))
    }

    /// [`Self::check`], its errors naming the key `NAME` as `key(NAME)`.
    fn check_named(&self, key: impl Fn(&str) -> String) -> Result<()> {
        for (name, posture) in &self.postures {
            if posture.angles.len() != self.joints.len() {
                return Err(Error::invalid(
                    key(&format!("postures.{name}.angles")),
                    format!("needs one angle per joint ({})", self.joints.len()),
                    format!("{} angles", posture.angles.len()),
                ));
            }
        }
        let legs = &self.postural_stiffness;
        for (name, table) in [
            ("stance_leg", &legs.stance_leg),
            ("swing_leg", &legs.swing_leg),
        ] {
            if table.len() != legs.leg_joints.len() {
                return Err(Error::invalid(
                    key(&format!("postural_stiffness.{name}")),
                    format!("needs one entry per leg joint ({})", legs.leg_joints.len()),
                    format!("{} entries", table.len()),
                ));
            }
        }
        if self.contacts.is_empty() || self.contacts.len() > 2 {
            return Err(Error::invalid(
                key("contacts"),
                "one or two contacts",
                format!("{:?}", self.contacts),
            ));
        }
        let posture = &self.initial_posture;
        if posture != "zero" && !self.postures.contains_key(posture) {
            return Err(Error::invalid(
                key("initial_posture"),
                "must be \"zero\" or a name of `postures`",
                posture,
            ));
        }
        Ok(())
    }

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
