//! From TOML text to the TOML tree the schema reads: `--set key=value` overrides, and the
//! errors of both steps naming what is wrong (the line of malformed TOML; the dotted key,
//! the rule and the value of a schema error). The key of a schema error is the path serde
//! walked to the value (`serde_path_to_error`); a table read on its own by a deserializer of
//! the schema (an actuator override, the contact table) gives the rest of the path in its
//! message ("in `overrides.l_knee.stifness`: rule", [`TableError::within`]).

use super::settings::{not_one_of, quoted_list};
use crate::error::{Error, Result};
use serde::de::DeserializeOwned;

/// The result of reading a table on its own.
pub type TableResult<T> = std::result::Result<T, TableError>;

/// Parses `value` of an override of `key` as TOML (number, bool, array, quoted string), else as
/// a bare string. An integer beyond TOML's (a 64-bit signed integer) is an error naming the
/// key, not a string that the key's reader would call a wrong type.
fn override_value(key: &str, value: &str) -> Result<toml::Value> {
    let wrapped = format!("v = {value}");
    match toml::from_str::<toml::Table>(&wrapped) {
        Ok(mut table) => Ok(table
            .remove("v")
            .unwrap_or(toml::Value::String(value.into()))),
        Err(_) if is_integer_literal(value) => Err(Error::invalid(
            key,
            format!(
                "must be an integer TOML can hold, from {} to {}",
                i64::MIN,
                i64::MAX
            ),
            value,
        )),
        Err(_) => Ok(toml::Value::String(value.into())),
    }
}

/// Whether `text` is a TOML decimal integer by its syntax (a sign, then digits without a
/// leading zero, a single `_` only between digits): TOML refuses such text only when its value
/// is beyond the range. Other text (`007`, `1_`) stays a bare string.
fn is_integer_literal(text: &str) -> bool {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    digits.starts_with(|c: char| ('1'..='9').contains(&c))
        && digits
            .split('_')
            .all(|group| !group.is_empty() && group.bytes().all(|b| b.is_ascii_digit()))
}

/// Applies `key.path=value` to a TOML tree, creating tables as needed.
pub fn apply_override(root: &mut toml::Table, key: &str, value: &str) -> Result<()> {
    let parts: Vec<&str> = key.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(Error::config(key, "malformed override key"));
    }
    let mut table = root;
    for part in &parts[..parts.len() - 1] {
        let entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry
            .as_table_mut()
            .ok_or_else(|| Error::config(key, format!("'{part}' is not a table")))?;
    }
    table.insert(
        parts[parts.len() - 1].to_string(),
        override_value(key, value)?,
    );
    Ok(())
}

/// A TOML syntax error with the line and column of its span in `text`.
pub(crate) fn syntax_error(error: &toml::de::Error, text: &str) -> Error {
    let (line, column) = match error.span() {
        Some(span) => {
            let (line, column) = sea_dyn::error::line_column(text, span.start);
            (Some(line), Some(column))
        }
        None => (None, None),
    };
    Error::Parse {
        file: None,
        line,
        column,
        message: format!("malformed TOML: {}", error.message().trim()),
    }
}

/// A schema (serde) error of the whole scenario `root`, naming the dotted key it is about.
/// serde says only "invalid type: unit variant" of a setting given a number or a list: the
/// value is then looked up in `root` and shown.
pub(crate) fn schema_error(error: TableError, root: &toml::Table) -> Error {
    if error.rule.starts_with("invalid type: unit variant") {
        if let Some(value) = lookup(root, &error.key) {
            let rule = format!(
                "invalid type: {} `{value}`, expected a string",
                value.type_str()
            );
            return Error::config(error.key, rule);
        }
    }
    error.into_error()
}

/// Reads `T` from a TOML value; an error names the key path serde walked to the bad value.
pub fn read_value<T: DeserializeOwned>(value: toml::Value) -> TableResult<T> {
    serde_path_to_error::deserialize(value).map_err(|e| TableError::at(&e))
}

/// The value at the dotted `key` of `root`.
pub(crate) fn lookup<'a>(root: &'a toml::Table, key: &str) -> Option<&'a toml::Value> {
    let (tables, last) = match key.rsplit_once('.') {
        Some((tables, last)) => (Some(tables), last),
        None => (None, key),
    };
    let mut table = root;
    for part in tables.into_iter().flat_map(|t| t.split('.')) {
        table = table.get(part)?.as_table()?;
    }
    table.get(last)
}

/// A schema error of a table read on its own: the dotted key relative to the table ("" for
/// the table itself) and the rule it breaks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TableError {
    /// The key, relative to the table read.
    pub key: String,
    /// serde's message, e.g. "unknown field `stifness`, expected one of ...".
    pub rule: String,
}

impl TableError {
    /// The key and rule of a serde error at the path serde walked (`serde_path_to_error`;
    /// entries of arrays name their array: the rule says which entry). For a missing field
    /// the path is its table and the field is named in the message, so the key is
    /// `table.field`; a table read on its own names the rest of its path in the message
    /// ("in `overrides.l_knee.stiffness`: rule", [`Self::within`]).
    pub fn at(error: &serde_path_to_error::Error<toml::de::Error>) -> Self {
        let path = key_of(error.path());
        let rule = error.inner().message().trim();
        let nested = rule
            .strip_prefix("in `")
            .and_then(|rest| rest.split_once("`: "));
        if let Some((inner, rule)) = nested {
            return Self::new(dotted(&path, inner), rule);
        }
        let missing = rule
            .strip_prefix("missing field `")
            .and_then(|rest| rest.split('`').next());
        Self::new(dotted(&path, missing.unwrap_or("")), rule)
    }

    fn new(key: String, rule: &str) -> Self {
        Self {
            key,
            rule: rule.to_string(),
        }
    }

    /// The same error of a table read without the keys `taken` (read on their own): an
    /// unknown field's message lists them among the expected fields.
    pub fn besides(self, taken: &[&str]) -> Self {
        let Some((unknown, expected)) = self.rule.split_once(", expected ") else {
            return self;
        };
        if !unknown.starts_with("unknown field `") {
            return self;
        }
        let names = taken
            .iter()
            .copied()
            .chain(expected.split('`').skip(1).step_by(2));
        let listed: Vec<String> = names.map(|name| format!("`{name}`")).collect();
        let rule = format!("{unknown}, expected one of {}", listed.join(", "));
        Self { rule, ..self }
    }

    /// The error of the key `key` in a table whose keys are `expected` (serde's wording).
    pub fn unknown_field(key: &str, expected: &[&str]) -> Self {
        let listed: Vec<String> = expected.iter().map(|name| format!("`{name}`")).collect();
        let rule = format!(
            "unknown field `{key}`, expected one of {}",
            listed.join(", ")
        );
        Self::new(key.to_string(), &rule)
    }

    /// The same error with its key under `table`.
    pub fn under(self, table: &str) -> Self {
        Self {
            key: dotted(table, &self.key),
            ..self
        }
    }

    /// The message of this error for the enclosing table, `prefix` naming this table in it
    /// ("" for the enclosing table itself, "overrides.NAME." for a sub-table): read back by
    /// [`Self::at`] as the key `prefix + key`.
    pub fn within(&self, prefix: &str) -> String {
        let key = dotted(prefix.trim_end_matches('.'), &self.key);
        if key.is_empty() {
            self.rule.clone()
        } else {
            format!("in `{key}`: {}", self.rule)
        }
    }

    /// The scenario error: serde's unknown variant becomes "must be one of 'a', 'b', got 'x'";
    /// a rule ending in ", got VALUE" keeps the value apart.
    pub fn into_error(self) -> Error {
        let key = if self.key.is_empty() {
            "scenario".to_string()
        } else {
            self.key
        };
        if let Some((value, allowed)) = unknown_variant(&self.rule) {
            return not_one_of(&key, value, &allowed);
        }
        match self.rule.rsplit_once(", got ") {
            // A bounded value's "RULE, got VALUE" (super::bounded): the value as its own field.
            Some((rule, value)) => Error::invalid(key, rule, value),
            None => Error::config(key, self.rule),
        }
    }
}

/// The dotted key of a path serde walked: its table keys and struct fields (array indices
/// left out; "" for the root).
fn key_of(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let names: Vec<String> = path
        .iter()
        .filter_map(|segment| match segment {
            Segment::Map { key } => Some(key.clone()),
            Segment::Enum { variant } => Some(variant.clone()),
            Segment::Seq { .. } | Segment::Unknown => None,
        })
        .collect();
    names.join(".")
}

/// `a.b` of `a` and `b`, either possibly empty.
fn dotted(a: &str, b: &str) -> String {
    match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_string(),
        (false, true) => a.to_string(),
        (false, false) => format!("{a}.{b}"),
    }
}

/// The value and the allowed names (quoted list) of serde's "unknown variant `x`, expected
/// `a` or `b`" (or "expected one of `a`, `b`, `c`").
fn unknown_variant(rule: &str) -> Option<(&str, String)> {
    let (value, expected) = rule
        .strip_prefix("unknown variant `")?
        .split_once("`, expected ")?;
    let names = expected.split('`').skip(1).step_by(2);
    Some((value, quoted_list(names)))
}

/// The keys of a struct `T` that serde reads (its fields' names, skipped fields left out), as
/// its derived `Deserialize` declares them: asked of a deserializer that only records them.
pub(crate) fn field_names<'de, T: serde::Deserialize<'de>>() -> &'static [&'static str] {
    let mut names: &'static [&'static str] = &[];
    let _ = T::deserialize(FieldNames(&mut names));
    names
}

/// A deserializer that records the fields a struct asks for, and refuses everything.
struct FieldNames<'a>(&'a mut &'static [&'static str]);

/// [`FieldNames`]' refusal.
#[derive(Debug)]
struct NotAStruct;

impl std::fmt::Display for NotAStruct {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("not a struct")
    }
}

impl std::error::Error for NotAStruct {}

impl serde::de::Error for NotAStruct {
    fn custom<M: std::fmt::Display>(_: M) -> Self {
        NotAStruct
    }
}

impl<'de> serde::Deserializer<'de> for FieldNames<'_> {
    type Error = NotAStruct;

    fn deserialize_any<V: serde::de::Visitor<'de>>(
        self,
        _: V,
    ) -> std::result::Result<V::Value, NotAStruct> {
        Err(NotAStruct)
    }

    fn deserialize_struct<V: serde::de::Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> std::result::Result<V::Value, NotAStruct> {
        *self.0 = fields;
        Err(NotAStruct)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

/// `table` split in two: the keys in `names`, and the others.
pub(crate) fn split(table: toml::Table, names: &[&str]) -> (toml::Table, toml::Table) {
    table
        .into_iter()
        .partition(|(key, _)| names.contains(&key.as_str()))
}

/// Reads `T` from a table on its own, whose keys `taken` were removed (and read) before.
pub(crate) fn table_as<T: DeserializeOwned>(table: toml::Table, taken: &[&str]) -> TableResult<T> {
    read_value(toml::Value::Table(table)).map_err(|e| e.besides(taken))
}

/// Removes `key` from `table` and reads its value (`None` when absent).
pub(crate) fn take<T: DeserializeOwned>(
    table: &mut toml::Table,
    key: &str,
) -> TableResult<Option<T>> {
    table
        .remove(key)
        .map(|value| read_value(value).map_err(|e| e.under(key)))
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serde_variant_lists_become_the_allowed_names() {
        assert_eq!(
            unknown_variant("unknown variant `zoh`, expected `continuous` or `zero_order_hold`"),
            Some(("zoh", "'continuous', 'zero_order_hold'".to_string()))
        );
        assert_eq!(
            unknown_variant("unknown variant `x`, expected one of `ros2`, `implicit_euler`, `rk4`"),
            Some(("x", "'ros2', 'implicit_euler', 'rk4'".to_string()))
        );
        assert_eq!(unknown_variant("invalid type: integer `3`"), None);
    }

    #[test]
    fn sub_table_messages_read_back_as_their_key() {
        let error = TableError {
            key: "stifness".into(),
            rule: "unknown field `stifness`, expected `ratio`".into(),
        };
        assert_eq!(
            error.within("overrides.l_knee."),
            "in `overrides.l_knee.stifness`: unknown field `stifness`, expected `ratio`"
        );
        let top = TableError {
            key: String::new(),
            rule: "invalid type".into(),
        };
        assert_eq!(top.within(""), "invalid type");
        assert_eq!(top.within("overrides.x."), "in `overrides.x`: invalid type");
    }

    #[test]
    fn an_override_integer_beyond_tomls_range_is_an_error_naming_the_key() {
        let mut root = toml::Table::new();
        let message = apply_override(&mut root, "sensing.seed", "18446744073709551615")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("sensing.seed") && message.contains("9223372036854775807"),
            "{message}"
        );
        apply_override(&mut root, "sensing.seed", "9223372036854775807").unwrap();
        assert_eq!(
            root["sensing"]["seed"],
            toml::Value::Integer(i64::MAX),
            "the largest integer TOML holds"
        );
        apply_override(&mut root, "sensing.seed", "-9_223_372_036_854_775_809").unwrap_err();
        // Text that is not a TOML integer stays a bare string for the key's reader to judge.
        for text in ["12ab", "007", "1_", "1__2", "+", "-_1"] {
            apply_override(&mut root, "robot.name", text).unwrap();
            assert_eq!(root["robot"]["name"], toml::Value::String(text.into()));
        }
    }
}
