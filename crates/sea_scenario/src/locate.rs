//! Where a scenario error's dotted key is in the scenario's TOML text, so that the error can
//! give `file:line`: the line of the key itself, else of the nearest table above it that the
//! text gives (a missing key is shown at its table's header). Keys are the paths of the
//! schema's errors, `controller.rate_hz` or `disturbances[0].duration_s`.

use crate::error::Error;
use std::ops::Range;
use std::path::PathBuf;
use toml_edit::{ImDocument, Item, Table, Value};

/// Where a scenario was read from: its file (when it came from one), its text and the
/// overrides applied to it, kept with the scenario so that an error found after the read (at
/// build, e.g. `robot.initial_posture[0]`) gives the key's file and line too.
#[derive(Clone, Default)]
pub struct Origin {
    /// The scenario file; `None` for text given directly.
    pub file: Option<PathBuf>,
    /// The scenario's TOML text, as read.
    text: String,
    /// The `key=value` overrides applied over `text`.
    overrides: Vec<(String, String)>,
}

impl std::fmt::Debug for Origin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Origin")
            .field("file", &self.file)
            .field("text_bytes", &self.text.len())
            .field("overrides", &self.overrides)
            .finish()
    }
}

impl Origin {
    /// The origin of `text` read with `overrides` (no file yet).
    pub(crate) fn of_text(text: &str, overrides: &[(String, String)]) -> Self {
        Origin {
            file: None,
            text: text.to_string(),
            overrides: overrides.to_vec(),
        }
    }

    /// The value the text with the overrides gives the dotted table key `key` (e.g.
    /// `actuators.damping`), as written; `None` when neither sets it (a default) or the text
    /// does not parse.
    pub fn given_value(&self, key: &str) -> Option<toml::Value> {
        let mut root: toml::Table = self.text.parse().ok()?;
        for (k, v) in &self.overrides {
            crate::parse::apply_override(&mut root, k, v).ok()?;
        }
        crate::parse::lookup(&root, key).cloned()
    }

    /// A scenario key's `error` with the line of its key in the text (unless an override set
    /// it) and the file; a controller setting's error (`sea_ctrl`'s, keyed by the same dotted
    /// keys) becomes a scenario key's. Every other error passes through unchanged.
    pub fn locate(&self, error: Error) -> Error {
        let error = match error {
            Error::Control(sea_ctrl::Error::Setting { key, rule, value }) => Error::Scenario {
                key,
                rule,
                value,
                file: None,
                line: None,
            },
            Error::Scenario { .. } => error,
            other => return other,
        };
        let located = error.at_line(|key| {
            let set = overridden(key, &self.overrides);
            (!set).then(|| line_of_key(&self.text, key)).flatten()
        });
        match &self.file {
            Some(file) => located.in_file(file),
            None => located,
        }
    }
}

/// One step of a dotted key.
#[derive(Debug, PartialEq)]
enum Step<'a> {
    /// A table's key.
    Key(&'a str),
    /// An array's entry.
    Index(usize),
}

/// The steps of `key` (`a.b[0].c`); `None` when it is not such a path.
fn steps(key: &str) -> Option<Vec<Step<'_>>> {
    let mut steps = Vec::new();
    for part in key.split('.') {
        let (name, mut indices) = part
            .split_once('[')
            .map_or((part, ""), |(n, rest)| (n, rest));
        if name.is_empty() {
            return None;
        }
        steps.push(Step::Key(name));
        while !indices.is_empty() {
            let (index, rest) = indices.split_once(']')?;
            steps.push(Step::Index(index.parse().ok()?));
            indices = rest.strip_prefix('[').unwrap_or(rest);
        }
    }
    Some(steps)
}

/// A place in the parsed document.
#[derive(Clone, Copy)]
enum Node<'a> {
    Item(&'a Item),
    Table(&'a Table),
    Value(&'a Value),
}

impl<'a> Node<'a> {
    /// The node at `step` below this one and the span of its key (or entry).
    fn child(self, step: &Step<'_>) -> Option<(Node<'a>, Option<Range<usize>>)> {
        match (self, step) {
            (Node::Table(table), Step::Key(name)) => {
                let (key, item) = table.get_key_value(name)?;
                Some((Node::Item(item), key.span()))
            }
            (Node::Item(item), Step::Key(name)) => {
                let (key, item) = item.as_table_like()?.get_key_value(name)?;
                Some((Node::Item(item), key.span()))
            }
            (Node::Value(Value::InlineTable(table)), Step::Key(name)) => {
                let (key, item) = table.get_key_value(name)?;
                Some((Node::Item(item), key.span()))
            }
            (Node::Item(Item::ArrayOfTables(array)), Step::Index(i)) => {
                let table = array.get(*i)?;
                Some((Node::Table(table), table.span()))
            }
            (Node::Item(Item::Value(Value::Array(array))), Step::Index(i))
            | (Node::Value(Value::Array(array)), Step::Index(i)) => {
                let value = array.get(*i)?;
                Some((Node::Value(value), value.span()))
            }
            _ => None,
        }
    }
}

/// The 1-based line in `text` of the dotted `key`, else of the deepest table or entry above it
/// that `text` gives; `None` when `text` gives none of its path or is not TOML.
pub(crate) fn line_of_key(text: &str, key: &str) -> Option<usize> {
    let document = ImDocument::parse(text).ok()?;
    let mut node = Node::Table(document.as_table());
    let mut found = None;
    for step in steps(key)? {
        let Some((child, span)) = node.child(&step) else {
            break;
        };
        found = span.or(found);
        node = child;
    }
    found.map(|span| sea_dyn::error::line_column(text, span.start).0)
}

/// Whether an override (`key=value` pairs) sets `key`, a table above it or a key below it:
/// the text's line would then not be where the value came from.
pub(crate) fn overridden(key: &str, overrides: &[(String, String)]) -> bool {
    let within = |inner: &str, outer: &str| {
        inner == outer
            || inner
                .strip_prefix(outer)
                .is_some_and(|rest| rest.starts_with('.') || rest.starts_with('['))
    };
    overrides
        .iter()
        .any(|(set, _)| within(key, set) || within(set, key))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "\
[simulation]
duration_s = 1.0

[controller]
rate_hz = 100
contact = { friction = 0.5 }

[[disturbances]]
start_s = 0.1

[[disturbances]]
start_s = 0.2
force_n = [0.0, 1.0, 2.0]
";

    #[test]
    fn keys_are_found_on_their_lines_and_missing_keys_at_their_table() {
        assert_eq!(line_of_key(TEXT, "simulation.duration_s"), Some(2));
        assert_eq!(line_of_key(TEXT, "controller.rate_hz"), Some(5));
        assert_eq!(line_of_key(TEXT, "controller.contact.friction"), Some(6));
        assert_eq!(line_of_key(TEXT, "disturbances[1].start_s"), Some(12));
        assert_eq!(line_of_key(TEXT, "disturbances[1].force_n[2]"), Some(13));
        // Not in the text: the nearest table above it that is.
        assert_eq!(line_of_key(TEXT, "controller.kind"), Some(4));
        assert_eq!(line_of_key(TEXT, "disturbances[1].link"), Some(11));
        assert_eq!(line_of_key(TEXT, "robot.urdf"), None);
        assert_eq!(line_of_key("not = [toml", "not"), None);
    }

    #[test]
    fn paths_with_indices_are_split_and_malformed_ones_refused() {
        assert_eq!(
            steps("a.b[0][3].c"),
            Some(vec![
                Step::Key("a"),
                Step::Key("b"),
                Step::Index(0),
                Step::Index(3),
                Step::Key("c")
            ])
        );
        assert_eq!(steps("a..b"), None);
        assert_eq!(steps("a[x]"), None);
    }

    #[test]
    fn an_override_of_the_key_a_table_above_or_a_key_below_counts() {
        let set = |key: &str| vec![(key.to_string(), "1".to_string())];
        assert!(overridden("controller.rate_hz", &set("controller.rate_hz")));
        assert!(overridden("controller.rate_hz", &set("controller")));
        assert!(overridden("controller", &set("controller.rate_hz")));
        assert!(overridden("disturbances[0].start_s", &set("disturbances")));
        assert!(!overridden(
            "controller.rate_hz_x",
            &set("controller.rate_hz")
        ));
        assert!(!overridden(
            "simulation.duration_s",
            &set("controller.rate_hz")
        ));
    }
}
