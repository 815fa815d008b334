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
}
