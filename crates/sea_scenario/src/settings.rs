//! The enum-like scenario settings, each typed once: its variants and their names.
//!
//! Scenario files name a setting by its serde name (`rename_all = "snake_case"`), so parsing a
//! scenario is serde's job; [`Setting`] gives the same names to the places that read a setting
//! outside a scenario file (the Python bindings' `method="rk4"`, `actuator="rigid"`,
//! `sampling="continuous"`) and to messages. A test checks that [`Setting::name`] and serde
//! agree on every variant.
//!
//! | key                    | type             | defined in |
//! |------------------------|------------------|------------|
//! | `actuators.kind`       | [`ActuatorKind`] | here       |
//! | `plant.method`         | [`Method`]       | `sea_plant` |
//! | `controller.kind`      | [`ControllerKind`] | `sea_ctrl` |
//! | `controller.sampling`  | [`Sampling`]     | here       |
//! | `controller.qp_solver` | [`QpSolver`]     | `sea_ctrl` |
//! | `controller.momentum_relaxation` | [`MomentumRelaxation`] | `sea_ctrl` |
//! | `controller.external_wrench` | [`ExternalWrench`] | `sea_ctrl` |
//! | `controller.identification_wrenches` | [`IdentificationWrenches`] | `sea_ctrl` |
//! | `controller.identification_acceleration` | [`IdentificationAcceleration`] | `sea_ctrl` |
//! | `reference.com_origin` | [`ComOrigin`]    | here       |

use crate::error::{Error, Result};
use schemars::JsonSchema;
pub use sea_ctrl::controller::{ControllerKind, MomentumRelaxation};
/// `controller.external_wrench`: what the controller knows of an unmodelled external wrench.
pub use sea_ctrl::external_wrench::ExternalWrench;
pub use sea_ctrl::qp::QpSolver;
/// `controller.identification_acceleration`: the finite difference that gives the stiffness
/// identification's model torques their acceleration.
pub use sea_ctrl::stiffness_id::IdentificationAcceleration;
/// `controller.identification_wrenches`: the contact wrenches the stiffness identification
/// takes.
pub use sea_ctrl::stiffness_id::IdentificationWrenches;
/// `controller.sampling`: how the controller is sampled (typed by the loop).
pub use sea_loop::Sampling;
pub use sea_plant::Method;
use serde::{Deserialize, Serialize};

/// An enum-like setting: every value and its name (the name serde reads and writes).
pub trait Setting: Copy + PartialEq + Sized + 'static {
    /// Every value, in the order messages list them.
    const ALL: &'static [Self];

    /// The value's name in scenario files.
    fn name(self) -> &'static str;

    /// The value called `name`, if any.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|value| value.name() == name)
    }

    /// The allowed names, quoted: `'continuous', 'zero_order_hold'`.
    fn allowed() -> String {
        quoted_list(Self::ALL.iter().map(|value| value.name()))
    }

    /// The value called `name`; otherwise a scenario error naming `key`, the value and the
    /// allowed names.
    fn parse(key: &str, name: &str) -> Result<Self> {
        Self::from_name(name).ok_or_else(|| not_one_of(key, name, &Self::allowed()))
    }
}

/// `'a', 'b', 'c'`.
pub(crate) fn quoted_list<'a>(names: impl Iterator<Item = &'a str>) -> String {
    names
        .map(|name| format!("'{name}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The error of a setting `key` given `value`, which is not one of `allowed` (quoted names).
pub(crate) fn not_one_of(key: &str, value: &str, allowed: &str) -> Error {
    Error::invalid(
        key,
        format!("must be one of {allowed}"),
        format!("'{value}'"),
    )
}

/// `actuators.kind`: the actuator of a joint.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ActuatorKind {
    /// A series elastic actuator with the table's parameters (the default).
    #[default]
    Elastic,
    /// A rigid joint (the table's elastic parameters are not used).
    Rigid,
}

impl Setting for ActuatorKind {
    const ALL: &'static [Self] = &[ActuatorKind::Elastic, ActuatorKind::Rigid];

    fn name(self) -> &'static str {
        match self {
            ActuatorKind::Elastic => "elastic",
            ActuatorKind::Rigid => "rigid",
        }
    }
}

impl Setting for Sampling {
    const ALL: &'static [Self] = &[
        Sampling::Continuous,
        Sampling::ZeroOrderHold,
        Sampling::MultiRate,
    ];

    fn name(self) -> &'static str {
        Sampling::name(self)
    }
}

impl Setting for IdentificationAcceleration {
    const ALL: &'static [Self] = &[
        IdentificationAcceleration::Backward,
        IdentificationAcceleration::Central,
    ];

    fn name(self) -> &'static str {
        match self {
            IdentificationAcceleration::Backward => "backward",
            IdentificationAcceleration::Central => "central",
        }
    }
}

impl Setting for IdentificationWrenches {
    const ALL: &'static [Self] = &[
        IdentificationWrenches::Measured,
        IdentificationWrenches::Commanded,
    ];

    fn name(self) -> &'static str {
        match self {
            IdentificationWrenches::Measured => "measured",
            IdentificationWrenches::Commanded => "commanded",
        }
    }
}

impl Setting for ExternalWrench {
    const ALL: &'static [Self] = &[
        ExternalWrench::None,
        ExternalWrench::Observed,
        ExternalWrench::Generalized,
    ];

    fn name(self) -> &'static str {
        match self {
            ExternalWrench::None => "none",
            ExternalWrench::Observed => "observed",
            ExternalWrench::Generalized => "generalized",
        }
    }
}

/// `reference.com_origin`: the origin of the CoM sinusoid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ComOrigin {
    /// CoM x, y above the stance sole origin, z the initial CoM's (the default).
    #[default]
    StanceSole,
    /// The initial CoM.
    Initial,
}

impl Setting for ComOrigin {
    const ALL: &'static [Self] = &[ComOrigin::StanceSole, ComOrigin::Initial];

    fn name(self) -> &'static str {
        match self {
            ComOrigin::StanceSole => "stance_sole",
            ComOrigin::Initial => "initial",
        }
    }
}

impl Setting for Method {
    const ALL: &'static [Self] = &[Method::Ros2, Method::LinearlyImplicitEuler, Method::Rk4];

    fn name(self) -> &'static str {
        match self {
            Method::Ros2 => "ros2",
            Method::LinearlyImplicitEuler => "implicit_euler",
            Method::Rk4 => "rk4",
        }
    }
}

impl Setting for ControllerKind {
    const ALL: &'static [Self] = &[ControllerKind::Sea, ControllerKind::Rigid];

    fn name(self) -> &'static str {
        match self {
            ControllerKind::Sea => "sea",
            ControllerKind::Rigid => "rigid",
        }
    }
}

impl Setting for MomentumRelaxation {
    const ALL: &'static [Self] = &[MomentumRelaxation::None, MomentumRelaxation::WhenInfeasible];

    fn name(self) -> &'static str {
        match self {
            MomentumRelaxation::None => "none",
            MomentumRelaxation::WhenInfeasible => "when_infeasible",
        }
    }
}

impl Setting for QpSolver {
    const ALL: &'static [Self] = &QpSolver::ALL;

    fn name(self) -> &'static str {
        QpSolver::name(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::de::DeserializeOwned;

    /// Every value's [`Setting::name`] is its serde name, both ways.
    fn names_agree_with_serde<S: Setting + Serialize + DeserializeOwned + std::fmt::Debug>() {
        for &value in S::ALL {
            let written = serde_json::to_value(value).unwrap();
            assert_eq!(written, serde_json::Value::from(value.name()), "{value:?}");
            let read: S = serde_json::from_value(written).unwrap();
            assert_eq!(read, value);
            assert_eq!(S::from_name(value.name()), Some(value));
        }
    }

    #[test]
    fn every_name_is_the_serde_name() {
        names_agree_with_serde::<ActuatorKind>();
        names_agree_with_serde::<Method>();
        names_agree_with_serde::<ControllerKind>();
        names_agree_with_serde::<Sampling>();
        names_agree_with_serde::<QpSolver>();
        names_agree_with_serde::<MomentumRelaxation>();
        names_agree_with_serde::<ExternalWrench>();
        names_agree_with_serde::<IdentificationWrenches>();
        names_agree_with_serde::<IdentificationAcceleration>();
        names_agree_with_serde::<ComOrigin>();
    }

    #[test]
    fn an_unknown_name_lists_the_allowed_ones() {
        let message = Sampling::parse("controller.sampling", "zoh")
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            "scenario key 'controller.sampling': must be one of 'continuous', \
             'zero_order_hold', 'multi_rate', got 'zoh'"
        );
    }
}
