//! Bounded values, checked while a scenario file is read: a key whose value is outside its
//! type's range is refused by serde with a message naming what is allowed and the value
//! ("must be positive and finite, got 0"), which the reader reports under the key
//! ([`super::parse`]); the JSON Schema shows the same bounds (`exclusiveMinimum`, ...).
//!
//! A field of the schema keeps its plain type (`f64`, `usize`) and is read through its bound:
//! `#[serde(deserialize_with = "Positive::read")]` with `#[schemars(with = "Positive")]`.

use super::validate::shown;
use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};
use std::borrow::Cow;

/// A bound on a number: the rule its message states, the test, the schema's keywords.
trait NumberBound {
    /// What is allowed, as the message says it ("must be positive and finite").
    const RULE: &'static str;

    /// Whether `value` is allowed.
    fn holds(value: f64) -> bool;

    /// The JSON Schema of the allowed numbers.
    fn schema() -> Schema;
}

/// Reads a number and checks it against `B`; the error is "RULE, got VALUE".
fn read_number<'de, B: NumberBound, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<f64, D::Error> {
    let value = f64::deserialize(deserializer)?;
    if B::holds(value) {
        Ok(value)
    } else {
        Err(D::Error::custom(format!(
            "{}, got {}",
            B::RULE,
            shown(value)
        )))
    }
}

/// Declares a bounded number type: its doc, name, rule, test and schema.
macro_rules! number_bound {
    ($(#[$doc:meta])* $name:ident, $rule:literal, |$v:ident| $holds:expr, $schema:tt) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
        pub struct $name(pub f64);

        impl NumberBound for $name {
            const RULE: &'static str = $rule;

            fn holds($v: f64) -> bool {
                $holds
            }

            fn schema() -> Schema {
                json_schema!($schema)
            }
        }

        impl $name {
            /// Reads the number of a field declared with this bound.
            pub fn read<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
                read_number::<Self, D>(deserializer)
            }

            /// Reads the number of an optional field declared with this bound (`None` when
            /// the key is absent: with `#[serde(default)]`).
            pub fn read_option<'de, D: Deserializer<'de>>(
                deserializer: D,
            ) -> Result<Option<f64>, D::Error> {
                Self::read(deserializer).map(Some)
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                Self::read(deserializer).map($name)
            }
        }

        impl JsonSchema for $name {
            fn inline_schema() -> bool {
                true
            }

            fn schema_name() -> Cow<'static, str> {
                stringify!($name).into()
            }

            fn json_schema(_: &mut SchemaGenerator) -> Schema {
                <Self as NumberBound>::schema()
            }
        }
    };
}

number_bound!(
    /// A finite number `> 0`.
    Positive,
    "must be positive and finite",
    |v| v.is_finite() && v > 0.0,
    { "type": "number", "exclusiveMinimum": 0.0 }
);

number_bound!(
    /// A finite number `>= 0`.
    NonNegative,
    "must be finite and non-negative",
    |v| v.is_finite() && v >= 0.0,
    { "type": "number", "minimum": 0.0 }
);

number_bound!(
    /// A finite number.
    Finite,
    "must be finite",
    |v| v.is_finite(),
    { "type": "number" }
);

/// A whole number `>= 1` (a count of steps or samples).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct AtLeastOne(pub usize);

impl AtLeastOne {
    /// Reads the count of a field declared with this bound.
    pub fn read<'de, D: Deserializer<'de>>(deserializer: D) -> Result<usize, D::Error> {
        let value = usize::deserialize(deserializer)?;
        if value >= 1 {
            Ok(value)
        } else {
            Err(D::Error::custom(format!("must be at least 1, got {value}")))
        }
    }
}

impl<'de> Deserialize<'de> for AtLeastOne {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Self::read(deserializer).map(AtLeastOne)
    }
}

impl JsonSchema for AtLeastOne {
    fn inline_schema() -> bool {
        true
    }

    fn schema_name() -> Cow<'static, str> {
        "AtLeastOne".into()
    }

    fn json_schema(_: &mut SchemaGenerator) -> Schema {
        json_schema!({ "type": "integer", "minimum": 1 })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The value `text` (TOML) read as `T`, or serde's message.
    fn read<T: for<'de> Deserialize<'de>>(text: &str) -> Result<T, String> {
        let table: toml::Table = toml::from_str(&format!("v = {text}")).unwrap();
        table["v"]
            .clone()
            .try_into()
            .map_err(|e: toml::de::Error| e.message().to_string())
    }

    #[test]
    fn values_outside_the_bound_are_refused_with_the_rule_and_the_value() {
        assert_eq!(read::<Positive>("0.5"), Ok(Positive(0.5)));
        assert_eq!(read::<Positive>("2"), Ok(Positive(2.0)));
        let zero = read::<Positive>("0").unwrap_err();
        assert_eq!(zero, "must be positive and finite, got 0");
        let nan = read::<NonNegative>("nan").unwrap_err();
        assert_eq!(nan, "must be finite and non-negative, got NaN");
        assert_eq!(read::<NonNegative>("0.0"), Ok(NonNegative(0.0)));
        assert!(read::<Finite>("inf")
            .unwrap_err()
            .contains("must be finite, got inf"));
        assert_eq!(
            read::<AtLeastOne>("0").unwrap_err(),
            "must be at least 1, got 0"
        );
        assert_eq!(read::<AtLeastOne>("3"), Ok(AtLeastOne(3)));
    }

    #[test]
    fn the_schema_shows_the_bounds() {
        let schema = serde_json::to_value(Positive::schema()).unwrap();
        assert_eq!(schema["exclusiveMinimum"], 0.0);
        let schema = serde_json::to_value(NonNegative::schema()).unwrap();
        assert_eq!(schema["minimum"], 0.0);
    }
}
