//! Actuators from Python: `Plant(actuator=..., actuators={...})`'s kinds and dicts, read by the
//! scenario schema as an `[actuators]` table is.

use crate::errors::argument_error;
use crate::numbers::Real;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sea_dyn::Actuator;
use sea_sim::scenario::{ActuatorConfig, ActuatorKind, Setting};

/// A Python value of an actuator dict as TOML: a number (NaN and infinities included) or a
/// string (`kind`); `None` is `None` (the key is left out: no torque limit).
fn actuator_value(
    value: &Bound<'_, PyAny>,
    key: &str,
    where_: &str,
) -> PyResult<Option<toml::Value>> {
    if value.is_none() {
        return Ok(None);
    }
    if let Ok(text) = value.extract::<String>() {
        return Ok(Some(toml::Value::String(text)));
    }
    match value.extract::<Real>() {
        Ok(Real(number)) => Ok(Some(toml::Value::Float(number))),
        Err(_) => Err(argument_error(
            &format!("{where_}['{key}']"),
            "a number",
            value,
        )),
    }
}

/// An actuator from a dict of the keys of a scenario's actuator table (`kind`, ratio,
/// motor_inertia, stiffness, damping, torque_limit; defaults: the paper's iCub SEA), read by
/// the scenario schema ([`ActuatorConfig::from_table`]); `where_` names the dict in errors.
fn actuator_from_dict(dict: &Bound<'_, PyDict>, where_: &str) -> PyResult<Actuator> {
    let mut table = toml::Table::new();
    for (key, value) in dict.iter() {
        let key: String = key
            .extract()
            .map_err(|_| argument_error(where_, "a dict with str keys", &key))?;
        if let Some(value) = actuator_value(&value, &key, where_)? {
            table.insert(key, value);
        }
    }
    let keys: Vec<String> = table.keys().cloned().collect();
    match ActuatorConfig::from_table(table) {
        Ok(config) => match config.ignored_key(&keys) {
            Some(key) => Err(argument_error(
                &format!("{where_}['{key}']"),
                "no such key with kind 'rigid': a rigid joint has no spring, damper or motor",
                match dict.get_item(key)? {
                    Some(value) => value.repr()?.to_string(),
                    None => "?".to_string(),
                },
            )),
            None => Ok(config.actuator()),
        },
        Err(error) if error.rule.starts_with("unknown field") => Err(argument_error(
            where_,
            "keys among kind, ratio, motor_inertia, stiffness, damping, torque_limit",
            format!("unknown actuator key '{}'", error.key),
        )),
        Err(error) => {
            // A bound's rule ("must be positive and finite, got -100") says what is allowed;
            // a type error's (serde's "invalid type: ...") does not.
            let bound = error.rule.strip_prefix("must be ");
            let expected = match (error.key.as_str(), bound) {
                ("kind", _) => format!("one of {}", ActuatorKind::allowed()),
                (_, Some(rule)) => {
                    format!("a number, {}", rule.split(", got ").next().unwrap_or(rule))
                }
                (_, None) => "a number".to_string(),
            };
            let shown = match dict.get_item(&error.key)? {
                Some(value) => value.repr()?.to_string(),
                None => "?".to_string(),
            };
            Err(argument_error(
                &format!("{where_}['{}']", error.key),
                &expected,
                shown,
            ))
        }
    }
}

/// An actuator from a kind ("rigid", "elastic": the paper's iCub SEA) or a dict of parameters.
pub(crate) fn actuator_from_py(value: &Bound<'_, PyAny>, where_: &str) -> PyResult<Actuator> {
    if let Ok(text) = value.extract::<String>() {
        let kind = ActuatorKind::from_name(&text).ok_or_else(|| {
            argument_error(
                where_,
                &format!("one of {} or a dict of parameters", ActuatorKind::allowed()),
                format!("'{text}'"),
            )
        })?;
        let config = ActuatorConfig {
            kind,
            ..ActuatorConfig::default()
        };
        return Ok(config.actuator());
    }
    let dict = value
        .cast::<PyDict>()
        .map_err(|_| argument_error(where_, "'rigid', 'elastic' or a dict", value))?;
    actuator_from_dict(dict, where_)
}
