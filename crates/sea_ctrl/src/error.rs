//! The one error type of `sea_ctrl`.
//!
//! A controller setting that is missing or out of range is [`Error::Setting`], naming the
//! setting by its dotted scenario key (e.g. `controller.momentum_proportional`), the rule it
//! breaks and, when there is one, the offending value. Numerical failures of the torque map
//! (a mass matrix or `Lambda Lambda^T + d^2 I` that is not positive definite) are
//! `Dynamics(sea_dyn::Error::Numerical { .. })`, never setting errors.

use thiserror::Error;

/// Errors of the controllers.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum Error {
    /// A controller setting is missing, unknown or out of range.
    #[error("{}", setting_message(key, rule, value.as_deref()))]
    Setting {
        /// Dotted key, e.g. `controller.postural_scale`.
        key: String,
        /// The rule it breaks, e.g. `must be finite and non-negative`.
        rule: String,
        /// The offending value, when there is one.
        value: Option<String>,
    },
    /// A model, argument or numerical problem from `sea_dyn`.
    #[error(transparent)]
    Dynamics(#[from] sea_dyn::Error),
}

impl Error {
    /// A setting error naming `key` and the `rule` it breaks, without a single offending value.
    pub fn config(key: impl Into<String>, rule: impl Into<String>) -> Self {
        Error::Setting {
            key: key.into(),
            rule: rule.into(),
            value: None,
        }
    }

    /// A setting error naming `key`, the `rule` it breaks and the offending `value`.
    pub fn invalid(key: impl Into<String>, rule: impl Into<String>, value: impl ToString) -> Self {
        Error::Setting {
            key: key.into(),
            rule: rule.into(),
            value: Some(value.to_string()),
        }
    }
}

/// Checks that the setting `key`'s `value` is finite and `> 0`; otherwise
/// [`Error::invalid`] naming the key, "must be positive and finite" and the value.
pub fn require_positive(key: impl Into<String>, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(key, "must be positive and finite", value))
    }
}

/// Checks that the setting `key`'s `value` is finite and `>= 0`; otherwise
/// [`Error::invalid`] naming the key, "must be finite and non-negative" and the value.
pub fn require_non_negative(key: impl Into<String>, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            key,
            "must be finite and non-negative",
            value,
        ))
    }
}

/// `setting 'key': rule, got value` (without the value part when there is none).
fn setting_message(key: &str, rule: &str, value: Option<&str>) -> String {
    match value {
        Some(value) => format!("setting '{key}': {rule}, got {value}"),
        None => format!("setting '{key}': {rule}"),
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setting_messages_name_key_rule_and_value() {
        let e = Error::invalid("controller.postural_scale", "must be non-negative", -1.0);
        assert_eq!(
            e.to_string(),
            "setting 'controller.postural_scale': must be non-negative, got -1"
        );
        let e = Error::config("controller.contacts", "needs one or two contact frames");
        assert_eq!(
            e.to_string(),
            "setting 'controller.contacts': needs one or two contact frames"
        );
    }

    #[test]
    fn sign_requirements_name_the_key_and_refuse_the_edges() {
        assert!(require_positive("walking.com_height", 1e-9).is_ok());
        assert!(require_non_negative("walking.swing_height", 0.0).is_ok());
        let e = require_positive("walking.com_height", 0.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "setting 'walking.com_height': must be positive and finite, got 0"
        );
        assert!(require_positive("gravity", f64::INFINITY).is_err());
        let e = require_non_negative("walking.swing_height", f64::NAN).unwrap_err();
        assert_eq!(
            e.to_string(),
            "setting 'walking.swing_height': must be finite and non-negative, got NaN"
        );
    }
}
