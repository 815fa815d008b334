//! The contact surface of a foot: the sole rectangle and the friction between sole and ground.
//!
//! One definition shared by the plant (margins of the simulated wrenches), the controller
//! (the QP's contact constraints, paper frictionCones) and the scenario schema; its defaults are
//! the original study's (docs/references.md#original-study-contact-wrench-qp).

/// Friction coefficients and foot rectangle of one sole, sole frame (x forward, z normal).
/// With the `serde` feature, a table of these keys (missing keys take the default's values,
/// unknown keys are errors, values outside their bounds are refused as they are read).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(default, deny_unknown_fields)
)]
pub struct ContactSurface {
    /// Coulomb friction coefficient `mu`.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::Positive::read"),
        schemars(with = "crate::bounded::Positive")
    )]
    pub friction: f64,
    /// Torsional friction coefficient `mu_t` [m]: `|n_z| <= mu_t F_z`.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::bounded::NonNegative::read"),
        schemars(with = "crate::bounded::NonNegative")
    )]
    pub torsional_friction: f64,
    /// Foot rectangle along the sole x axis `[min, max]` [m].
    #[cfg_attr(feature = "serde", serde(deserialize_with = "read_foot_interval"))]
    pub foot_x: [f64; 2],
    /// Foot rectangle along the sole y axis `[min, max]` [m].
    #[cfg_attr(feature = "serde", serde(deserialize_with = "read_foot_interval"))]
    pub foot_y: [f64; 2],
}

/// Reads a foot rectangle's side `[min, max]`: finite entries, `min < max`.
#[cfg(feature = "serde")]
fn read_foot_interval<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<[f64; 2], D::Error> {
    use serde::de::Error as _;
    let [min, max]: [f64; 2] = crate::bounded::Finite::read_entries(deserializer)?;
    if min < max {
        Ok([min, max])
    } else {
        Err(D::Error::custom(format!(
            "must be [min, max] with min < max (sole frame) [m], got [{min}, {max}]"
        )))
    }
}

impl Default for ContactSurface {
    /// The original study's iCub sole (docs/references.md#original-study-contact-wrench-qp):
    /// mu = 1, mu_t = 2/150 m, x in [-0.05, 0.10] m, y in [-0.025, 0.025] m.
    fn default() -> Self {
        Self {
            friction: 1.0,
            torsional_friction: 2.0 / 150.0,
            foot_x: [-0.05, 0.10],
            foot_y: [-0.025, 0.025],
        }
    }
}
