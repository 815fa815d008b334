//! Property-based tests (issue 10, item 8): mutated URDF text (an element deleted or
//! duplicated, a number made NaN, infinite, negative, huge, tiny or not a number, the text cut
//! short) never makes `Model::from_urdf_str` panic; it either loads a model whose masses and
//! inertias are finite, or fails with an error that names the element (or, for text that is
//! not a URDF, says it cannot be parsed). Bounded for CI: 128 cases per robot.

use proptest::prelude::*;
use sea_dyn::{Error, LoadOptions, Model};

const PENDULUM: &str = include_str!("../../../urdf/pendulum2.urdf");
const BIPED: &str = include_str!("../../../urdf/mini_biped.urdf");

/// Elements a mutation deletes or duplicates.
const ELEMENTS: [&str; 10] = [
    "link", "joint", "inertial", "mass", "inertia", "origin", "axis", "parent", "child", "limit",
];

/// Replacements of one number.
const BAD_NUMBERS: [&str; 10] = [
    "NaN", "nan", "inf", "-inf", "-1", "0", "1e308", "-1e308", "1e-320", "abc",
];

/// One text mutation; indices are taken modulo the number of candidates.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the `index`-th number of an attribute value by `BAD_NUMBERS[bad]`.
    Number { index: usize, bad: usize },
    /// Delete the `index`-th occurrence of element `ELEMENTS[element]`.
    Delete { element: usize, index: usize },
    /// Duplicate the `index`-th occurrence of element `ELEMENTS[element]` in place.
    Duplicate { element: usize, index: usize },
    /// Cut the text at `fraction` of its length.
    Truncate { fraction: f64 },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), 0..BAD_NUMBERS.len())
            .prop_map(|(index, bad)| Mutation::Number { index, bad }),
        2 => (0..ELEMENTS.len(), any::<usize>())
            .prop_map(|(element, index)| Mutation::Delete { element, index }),
        2 => (0..ELEMENTS.len(), any::<usize>())
            .prop_map(|(element, index)| Mutation::Duplicate { element, index }),
        1 => (0.0..1.0f64).prop_map(|fraction| Mutation::Truncate { fraction }),
    ]
}

/// Byte ranges of the numbers inside attribute values (`="..."`, whitespace-separated).
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut rest = 0;
    while let Some(open) = text[rest..].find("=\"") {
        let start = rest + open + 2;
        let Some(len) = text[start..].find('"') else {
            break;
        };
        let value = &text[start..start + len];
        let mut offset = 0;
        for token in value.split(' ') {
            if !token.is_empty() && token.parse::<f64>().is_ok() {
                spans.push((start + offset, start + offset + token.len()));
            }
            offset += token.len() + 1;
        }
        rest = start + len + 1;
    }
    spans
}

/// Byte ranges of every `<name ...>` element: self-closing, or up to its first `</name>`.
fn element_spans(text: &str, name: &str) -> Vec<(usize, usize)> {
    let open = format!("<{name}");
    let close = format!("</{name}>");
    let mut spans = Vec::new();
    let mut rest = 0;
    while let Some(found) = text[rest..].find(&open) {
        let start = rest + found;
        rest = start + open.len();
        // `<link` must not match `<linkage`: the tag name ends at a space, `>` or `/`.
        if !matches!(text[rest..].chars().next(), Some(' ' | '>' | '/' | '\n')) {
            continue;
        }
        let Some(tag_end) = text[start..].find('>').map(|e| start + e + 1) else {
            break;
        };
        let end = if text[..tag_end].ends_with("/>") {
            tag_end
        } else {
            match text[tag_end..].find(&close) {
                Some(e) => tag_end + e + close.len(),
                None => continue,
            }
        };
        spans.push((start, end));
    }
    spans
}

/// The `index`-th (modulo) of `spans`, if any.
fn pick(spans: &[(usize, usize)], index: usize) -> Option<(usize, usize)> {
    (!spans.is_empty()).then(|| spans[index % spans.len()])
}

/// `text` with `mutation` applied (unchanged when it finds nothing to mutate).
fn apply(text: &str, mutation: &Mutation) -> String {
    let replace = |span: Option<(usize, usize)>, with: &dyn Fn(&str) -> String| match span {
        Some((a, b)) => format!("{}{}{}", &text[..a], with(&text[a..b]), &text[b..]),
        None => text.to_string(),
    };
    match *mutation {
        Mutation::Number { index, bad } => replace(pick(&number_spans(text), index), &|_| {
            BAD_NUMBERS[bad].to_string()
        }),
        Mutation::Delete { element, index } => replace(
            pick(&element_spans(text, ELEMENTS[element]), index),
            &|_| String::new(),
        ),
        Mutation::Duplicate { element, index } => replace(
            pick(&element_spans(text, ELEMENTS[element]), index),
            &|span| format!("{span}\n{span}"),
        ),
        Mutation::Truncate { fraction } => {
            let mut cut = (text.len() as f64 * fraction) as usize;
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text[..cut].to_string()
        }
    }
}

/// What is wrong with loading `text`, if anything: a loaded model must have finite, positive
/// masses and finite inertias; an error must name its element (or be a parse error).
fn load_problem(text: &str) -> Option<String> {
    match Model::from_urdf_str(text, &LoadOptions::default()) {
        Ok(model) => {
            let mass = model.total_mass();
            (!(mass.is_finite() && mass > 0.0)).then(|| format!("loaded with total mass {mass}"))
        }
        Err(Error::Model {
            element, message, ..
        }) => element
            .trim()
            .is_empty()
            .then(|| format!("no element named: {message}")),
        Err(error @ Error::Parse { .. }) => {
            let message = error.to_string();
            (!message.contains("URDF")).then(|| format!("unclear parse error: {message}"))
        }
        Err(Error::InvalidArgument { argument, .. }) if !argument.trim().is_empty() => None,
        Err(Error::UnknownFrame { name }) if !name.trim().is_empty() => None,
        Err(other) => Some(format!("unexpected error kind: {other:?}")),
    }
}

#[test]
fn mutations_find_their_targets() {
    // Guards the generators: without numbers or elements to mutate, the properties below
    // would test the unchanged files only.
    for text in [PENDULUM, BIPED] {
        assert!(number_spans(text).len() > 20);
        for name in ["link", "joint", "inertial", "mass", "origin"] {
            assert!(!element_spans(text, name).is_empty(), "{name}");
        }
        assert!(load_problem(text).is_none());
        // A NaN mass is refused naming its link (the property's error arm is reachable).
        let start = text.find("<mass value=\"").expect("a mass") + "<mass value=\"".len();
        let end = start + text[start..].find('"').expect("a closing quote");
        let nan_mass = format!("{}NaN{}", &text[..start], &text[end..]);
        let loaded = Model::from_urdf_str(&nan_mass, &LoadOptions::default());
        assert!(matches!(loaded, Err(Error::Model { .. })), "{loaded:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_pendulum_never_panics_and_errors_name_the_element(
        mutations in prop::collection::vec(mutation(), 1..4)
    ) {
        let text = mutations.iter().fold(PENDULUM.to_string(), |t, m| apply(&t, m));
        if let Some(problem) = load_problem(&text) {
            prop_assert!(false, "{mutations:?}: {problem}");
        }
    }

    #[test]
    fn mutated_biped_never_panics_and_errors_name_the_element(
        mutations in prop::collection::vec(mutation(), 1..4)
    ) {
        let text = mutations.iter().fold(BIPED.to_string(), |t, m| apply(&t, m));
        if let Some(problem) = load_problem(&text) {
            prop_assert!(false, "{mutations:?}: {problem}");
        }
    }
}
