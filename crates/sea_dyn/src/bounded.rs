//! Bounded values (with the `serde` feature), checked while a settings table is read: a key
//! whose value is outside its type's range is refused by serde with a message naming what is
//! allowed and the value ("must be positive and finite, got 0"), which a reader reports under
//! the key; the JSON Schema shows the same bounds (`exclusiveMinimum`, ...). The bound is
//! declared once, on the field, by the type that owns the field (the actuator's parameters
//! here, the contact constraints in `sea_ctrl`, the scenario's own keys in `sea_scenario`).
//!
//! A field keeps its plain type (`f64`, `usize`, `[f64; N]`, `Vec<f64>`, a map of them) and is
//! read through its bound: `#[serde(deserialize_with = "Positive::read")]` with
//! `#[schemars(with = "Positive")]`; `read_option`, `read_entries`, `read_option_entries` and
//! `read_map` read an optional value, the entries of an array (the error names the entry:
//! "entry 2 must be ..."), and the values of a table (serde names the entry's key).
//! [`number_bound!`](crate::number_bound) declares a further bound.

use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};
use std::borrow::Cow;
use std::collections::BTreeMap;

/// `value` as written in a message: plain for ordinary magnitudes, in exponent notation for
/// tiny or huge ones (Rust's plain format prints 1e-300 with 300 digits).
pub fn shown(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || !value.is_finite() || (1e-4..1e15).contains(&magnitude) {
        value.to_string()
    } else {
        format!("{value:e}")
    }
}

/// A bound on a number: the rule its message states, the test, the schema's keywords.
pub trait NumberBound {
    /// What is allowed, as the message says it ("must be positive and finite").
    const RULE: &'static str;

    /// Whether `value` is allowed.
    fn holds(value: f64) -> bool;

    /// The JSON Schema of the allowed numbers.
    fn schema() -> Schema;
}

/// Reads a number and checks it against `B`; the error is "RULE, got VALUE".
pub fn read_number<'de, B: NumberBound, D: Deserializer<'de>>(
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

/// Checks every entry of an array against `B`; the error names the first failing entry:
/// "entry I RULE, got VALUE".
pub fn check_entries<B: NumberBound>(values: &[f64]) -> Result<(), String> {
    match values.iter().position(|&value| !B::holds(value)) {
        Some(i) => Err(format!("entry {i} {}, got {}", B::RULE, shown(values[i]))),
        None => Ok(()),
    }
}

/// Reads an array (or `Vec`) of numbers and checks every entry against `B`.
pub fn read_entries<'de, B, T, D>(deserializer: D) -> Result<T, D::Error>
where
    B: NumberBound,
    T: Deserialize<'de> + AsRef<[f64]>,
    D: Deserializer<'de>,
{
    let values = T::deserialize(deserializer)?;
    check_entries::<B>(values.as_ref()).map_err(D::Error::custom)?;
    Ok(values)
}

/// Declares a bounded number type: its doc, name, rule, test and schema, and the readers of
/// fields declared with it (`read`, `read_option`, `read_entries`, `read_option_entries`,
/// `read_map`).
#[macro_export]
macro_rules! number_bound {
    ($(#[$doc:meta])* $name:ident, $rule:expr, |$v:ident| $holds:expr, $schema:tt) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
        pub struct $name(pub f64);

        impl $crate::bounded::NumberBound for $name {
            const RULE: &'static str = $rule;

            fn holds($v: f64) -> bool {
                $holds
            }

            fn schema() -> ::schemars::Schema {
                ::schemars::json_schema!($schema)
            }
        }

        impl $name {
            /// Reads the number of a field declared with this bound.
            pub fn read<'de, D: ::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::std::result::Result<f64, D::Error> {
                $crate::bounded::read_number::<Self, D>(deserializer)
            }

            /// Reads the number of an optional field declared with this bound (`None` when
            /// the key is absent: with `#[serde(default)]`).
            pub fn read_option<'de, D: ::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::std::result::Result<Option<f64>, D::Error> {
                Self::read(deserializer).map(Some)
            }

            /// Reads an array (or `Vec`) field whose every entry has this bound.
            pub fn read_entries<'de, T, D>(deserializer: D) -> ::std::result::Result<T, D::Error>
            where
                T: ::serde::Deserialize<'de> + AsRef<[f64]>,
                D: ::serde::Deserializer<'de>,
            {
                $crate::bounded::read_entries::<Self, T, D>(deserializer)
            }

            /// Reads an optional array field whose every entry has this bound.
            pub fn read_option_entries<'de, T, D>(
                deserializer: D,
            ) -> ::std::result::Result<Option<T>, D::Error>
            where
                T: ::serde::Deserialize<'de> + AsRef<[f64]>,
                D: ::serde::Deserializer<'de>,
            {
                Self::read_entries(deserializer).map(Some)
            }

            /// Reads a table (name to number) whose every value has this bound; an error is
            /// the entry's (its path ends in the entry's name).
            pub fn read_map<'de, D: ::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::std::result::Result<::std::collections::BTreeMap<String, f64>, D::Error> {
                $crate::bounded::read_map::<Self, D>(deserializer)
            }
        }

        impl<'de> ::serde::Deserialize<'de> for $name {
            fn deserialize<D: ::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::std::result::Result<Self, D::Error> {
                Self::read(deserializer).map($name)
            }
        }

        impl From<$name> for f64 {
            fn from(value: $name) -> f64 {
                value.0
            }
        }

        impl ::schemars::JsonSchema for $name {
            fn inline_schema() -> bool {
                true
            }

            fn schema_name() -> ::std::borrow::Cow<'static, str> {
                stringify!($name).into()
            }

            fn json_schema(_: &mut ::schemars::SchemaGenerator) -> ::schemars::Schema {
                <Self as $crate::bounded::NumberBound>::schema()
            }
        }
    };
}

/// Reads a table of bounded numbers `B` by name.
pub fn read_map<'de, B, D>(deserializer: D) -> Result<BTreeMap<String, f64>, D::Error>
where
    B: Deserialize<'de> + Into<f64>,
    D: Deserializer<'de>,
{
    let map = BTreeMap::<String, B>::deserialize(deserializer)?;
    Ok(map.into_iter().map(|(k, v)| (k, v.into())).collect())
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

number_bound!(
    /// A finite number `> 1` (a factor that widens a range).
    MoreThanOne,
    "must be finite and more than 1",
    |v| v.is_finite() && v > 1.0,
    { "type": "number", "exclusiveMinimum": 1.0 }
);

number_bound!(
    /// A limit `> 0`, infinity allowed (a field of this type is optional: absent for no limit).
    PositiveLimit,
    "must be positive (or absent for no limit)",
    |v| v > 0.0,
    { "type": "number", "exclusiveMinimum": 0.0 }
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

    /// The value `text` (JSON) read as `T`, or serde's message.
    fn read<T: for<'de> Deserialize<'de>>(text: &str) -> Result<T, String> {
        serde_json::from_str(text).map_err(|e| {
            let message = e.to_string();
            match message.rsplit_once(" at line ") {
                Some((rule, _)) => rule.to_string(),
                None => message,
            }
        })
    }

    #[test]
    fn values_outside_the_bound_are_refused_with_the_rule_and_the_value() {
        assert_eq!(read::<Positive>("0.5"), Ok(Positive(0.5)));
        assert_eq!(read::<Positive>("2"), Ok(Positive(2.0)));
        let zero = read::<Positive>("0").unwrap_err();
        assert_eq!(zero, "must be positive and finite, got 0");
        let tiny = read::<NonNegative>("-1e-300").unwrap_err();
        assert_eq!(tiny, "must be finite and non-negative, got -1e-300");
        assert_eq!(read::<NonNegative>("0.0"), Ok(NonNegative(0.0)));
        let one = read::<MoreThanOne>("1").unwrap_err();
        assert_eq!(one, "must be finite and more than 1, got 1");
        assert!(PositiveLimit::holds(f64::INFINITY) && !PositiveLimit::holds(f64::NAN));
        assert_eq!(
            read::<AtLeastOne>("0").unwrap_err(),
            "must be at least 1, got 0"
        );
        assert_eq!(read::<AtLeastOne>("3"), Ok(AtLeastOne(3)));
    }

    #[test]
    fn entries_are_checked_one_by_one() {
        assert_eq!(check_entries::<NonNegative>(&[1.0, 0.0]), Ok(()));
        assert_eq!(
            check_entries::<NonNegative>(&[1.0, 2.0, -3.0]),
            Err("entry 2 must be finite and non-negative, got -3".into())
        );
        assert_eq!(
            check_entries::<Finite>(&[f64::NAN]),
            Err("entry 0 must be finite, got NaN".into())
        );
    }

    #[test]
    fn the_schema_shows_the_bounds() {
        let schema = serde_json::to_value(Positive::schema()).unwrap();
        assert_eq!(schema["exclusiveMinimum"], 0.0);
        let schema = serde_json::to_value(NonNegative::schema()).unwrap();
        assert_eq!(schema["minimum"], 0.0);
    }
}
