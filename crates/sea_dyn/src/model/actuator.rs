//! Series elastic actuators (paper, eq:elasticSystem and eq:alpha) and mixed actuation.
//!
//! Each joint is rigid (driven by a joint torque) or elastic: a motor of inertia `I_m` (motor
//! side) drives the joint through a transmission of ratio `Gamma` and a spring-damper,
//! `tau = K_S (Gamma theta - s) + K_D (Gamma thetadot - sdot)` and
//! `I_m thetaddot = tau_m - Gamma tau` (the paper's notation, one joint's diagonal entry of each
//! matrix; docs/reference/conventions.md#sea-parameters). `theta` is the motor angle (motor side),
//! so `Gamma theta` is on the joint side; the reflected motor inertia is `I_m / Gamma^2`. Motor
//! torques may be limited to `|tau_m| <= torque_limit`.

use crate::error::{check_non_negative, check_positive, Error, Result};
use crate::model::Model;
use std::collections::HashMap;

/// Parameters of one elastic actuator. With the `serde` feature, a table of these keys (any
/// subset: a missing key takes [`ElasticParameters::default`]'s value, an unknown key is an
/// error, a value outside its bound is refused as it is read: `crate::bounded`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct ElasticParameters {
    /// Transmission ratio `Gamma` (joint angle per motor angle), e.g. 0.01 for 1/100.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::Positive::read"),
        schemars(with = "crate::bounded::Positive")
    )]
    pub ratio: f64,
    /// Motor rotor inertia `I_m` [kg m^2], motor side.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::Positive::read"),
        schemars(with = "crate::bounded::Positive")
    )]
    pub motor_inertia: f64,
    /// Spring stiffness `K_S` [Nm/rad], joint side.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::Positive::read"),
        schemars(with = "crate::bounded::Positive")
    )]
    pub stiffness: f64,
    /// Spring damping `K_D` [Nms/rad], joint side.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::NonNegative::read"),
        schemars(with = "crate::bounded::NonNegative")
    )]
    pub damping: f64,
    /// Motor torque limit [Nm], motor side; `None` for no limit.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::PositiveLimit::read_option"),
        schemars(with = "Option<crate::bounded::PositiveLimit>")
    )]
    pub torque_limit: Option<f64>,
}

impl Default for ElasticParameters {
    /// The paper's iCub SEA, [`ElasticParameters::paper_icub`].
    fn default() -> Self {
        Self::paper_icub()
    }
}

impl ElasticParameters {
    /// The iCub SEA of the paper (docs/references.md#paper-simulation-results): `Gamma`
    /// 1/100, `I_m` 1e-5 kg m^2, `K_S` 350 Nm/rad, `K_D` 0.25 Nms/rad (the original code used
    /// 1), no torque limit. The one definition of these figures: the scenario schema and the
    /// Python bindings take their defaults from here.
    pub fn paper_icub() -> Self {
        Self {
            ratio: 0.01,
            motor_inertia: 1e-5,
            stiffness: 350.0,
            damping: 0.25,
            torque_limit: None,
        }
    }

    /// The motor angle `theta` [rad, motor side] at which the spring holds the joint torque
    /// `tau` [Nm] at rest at joint angle `s` [rad]: from paper eq:alpha with zero velocities,
    /// `tau = K_S (Gamma theta - s)`, so `theta = (s + tau / K_S) / Gamma`. With `tau = 0` the
    /// spring is at rest, `theta = s / Gamma`.
    pub fn preloaded_motor_angle(&self, s: f64, tau: f64) -> f64 {
        (s + tau / self.stiffness) / self.ratio
    }

    /// Motor reflected inertia, paper remark1 (eq:equivJoints): the joint-side diagonal entry
    /// of `Gamma^-1 I_m Gamma^-1`, `I_m / Gamma^2` [kg m^2], which a rigid model of this joint adds
    /// to `M_j`.
    pub fn reflected_inertia(&self) -> f64 {
        self.motor_inertia / (self.ratio * self.ratio)
    }

    /// Checks every parameter; `joint` names the actuator in the message.
    pub fn validate(&self, joint: &str) -> Result<()> {
        let positive = [
            ("ratio", self.ratio),
            ("motor_inertia", self.motor_inertia),
            ("stiffness", self.stiffness),
        ];
        for (name, value) in positive {
            check_positive(format!("actuator of joint '{joint}': {name}"), value)?;
        }
        check_non_negative(
            format!("actuator of joint '{joint}': damping"),
            self.damping,
        )?;
        if let Some(limit) = self.torque_limit {
            if limit.is_nan() || limit <= 0.0 {
                return Err(Error::invalid(
                    format!("actuator of joint '{joint}': torque_limit"),
                    "a positive number",
                    limit,
                ));
            }
        }
        Ok(())
    }
}

/// How one joint is actuated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Actuator {
    /// Joint torque applied directly.
    Rigid,
    /// Series elastic actuator.
    Elastic(ElasticParameters),
}

/// Actuation of every joint of a model: per-joint actuators in coordinate order, and the
/// elastic ones gathered (their order is the order of `theta`).
#[derive(Clone, Debug)]
pub struct Actuation {
    /// Actuator of each joint, coordinate order (n).
    pub actuators: Vec<Actuator>,
    /// Coordinate index of each elastic joint, increasing (n_e).
    pub elastic_joints: Vec<usize>,
    /// Parameters of each elastic joint, same order (n_e).
    pub elastic: Vec<ElasticParameters>,
}

impl Actuation {
    /// Every joint rigid.
    pub fn rigid(model: &Model) -> Self {
        Self::from_actuators(vec![Actuator::Rigid; model.n_joints()])
    }

    /// `default` for every joint, then `overrides` by joint name.
    pub fn new(
        model: &Model,
        default: Actuator,
        overrides: &HashMap<String, Actuator>,
    ) -> Result<Self> {
        let mut actuators = vec![default; model.n_joints()];
        for (name, actuator) in overrides {
            let index = model.joint_index(name).ok_or_else(|| {
                Error::invalid(
                    "actuator override",
                    "a moving joint of the model",
                    format!("unknown joint '{name}'"),
                )
            })?;
            actuators[index] = *actuator;
        }
        for (index, actuator) in actuators.iter().enumerate() {
            if let Actuator::Elastic(p) = actuator {
                p.validate(&model.joint_names[index])?;
            }
        }
        Ok(Self::from_actuators(actuators))
    }

    fn from_actuators(actuators: Vec<Actuator>) -> Self {
        let mut elastic_joints = Vec::new();
        let mut elastic = Vec::new();
        for (index, actuator) in actuators.iter().enumerate() {
            if let Actuator::Elastic(p) = actuator {
                elastic_joints.push(index);
                elastic.push(*p);
            }
        }
        Self {
            actuators,
            elastic_joints,
            elastic,
        }
    }

    /// Number of elastic joints `n_e`.
    pub fn n_elastic(&self) -> usize {
        self.elastic_joints.len()
    }
}
