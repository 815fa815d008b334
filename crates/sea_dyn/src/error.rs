//! The one error type of `sea_dyn`.
//!
//! Every variant carries fields, not only a message: the URDF element and its file
//! ([`Error::Model`]), the argument with the expected and the actual value ([`Error::InvalidArgument`]), the file and
//! line of a parse failure ([`Error::Parse`]), the path and cause of an I/O failure
//! ([`Error::Io`]). Numerical failures (a matrix that should be positive definite and is not)
//! are [`Error::Numerical`], distinct from input errors: the input was well formed, the state
//! it led to is not solvable. A description that loads but is physically doubtful (an inertia
//! violating the triangle inequality, a massless moving subtree) yields [`Warning`]s, kept in
//! the model, which strict loading turns into [`Error::Model`]. Bindings map each variant to one
//! Python class, in one place (`sea_py/src/errors.rs`).

use std::path::PathBuf;

use thiserror::Error;

/// Errors of `sea_dyn`.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum Error {
    /// The robot description is unusable.
    #[error("{}{element}: {message}", file_prefix(file.as_ref()))]
    Model {
        /// The element, e.g. `link 'l_foot'`, `joint 'r_knee'`, `robot`.
        element: String,
        /// The violated condition.
        message: String,
        /// The description's file, when the text came from one.
        file: Option<PathBuf>,
    },
    /// An argument has the wrong size or holds a non-finite or out-of-range value.
    #[error(
        "{}: expected {expected}, got {}",
        shortened(argument),
        shortened(actual)
    )]
    InvalidArgument {
        /// The argument, e.g. `q`, `q[3]`, `dt`.
        argument: String,
        /// What it must be, e.g. `shape (31,)`, `a finite number`.
        expected: String,
        /// What it was.
        actual: String,
    },
    /// A frame name that the model does not have.
    #[error("unknown frame '{}'", shortened(name))]
    UnknownFrame {
        /// The name asked for.
        name: String,
    },
    /// A file could not be parsed (the robot description's XML).
    #[error("{}", parse_message(file.as_ref(), *line, *column, message))]
    Parse {
        /// The file, when the text came from one.
        file: Option<PathBuf>,
        /// 1-based line, when the parser reports it.
        line: Option<usize>,
        /// 1-based column, when the parser reports it.
        column: Option<usize>,
        /// The parser's message.
        message: String,
    },
    /// Reading a file failed.
    #[error("{}: {}", path.display(), io_message(source))]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A numerical operation failed on well-formed input, e.g. a mass matrix that is not
    /// positive definite or degenerate contact constraints.
    #[error("{operation}: {detail}")]
    Numerical {
        /// What was computed, e.g. `factorising the mass matrix`.
        operation: String,
        /// Why it failed (pivot, index).
        detail: String,
    },
}

impl Error {
    /// A model error about `element` (e.g. `joint 'r_knee'`).
    pub fn model(element: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Model {
            element: element.into(),
            message: message.into(),
            file: None,
        }
    }

    /// An invalid argument: `argument` was `actual`, it must be `expected`.
    pub fn invalid(
        argument: impl Into<String>,
        expected: impl Into<String>,
        actual: impl ToString,
    ) -> Self {
        Error::InvalidArgument {
            argument: argument.into(),
            expected: expected.into(),
            actual: actual.to_string(),
        }
    }

    /// A numerical failure of `operation`.
    pub fn numerical(operation: impl Into<String>, detail: impl Into<String>) -> Self {
        Error::Numerical {
            operation: operation.into(),
            detail: detail.into(),
        }
    }

    /// An I/O failure on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }

    /// A parse failure of text not (yet) tied to a file or a line; see [`Error::in_file`].
    pub fn parse(message: impl Into<String>) -> Self {
        Error::Parse {
            file: None,
            line: None,
            column: None,
            message: message.into(),
        }
    }

    /// Names the file a parse failure or a model error came from. Other errors pass through
    /// unchanged.
    pub fn in_file(mut self, path: impl Into<PathBuf>) -> Self {
        if let Error::Parse { file, .. } | Error::Model { file, .. } = &mut self {
            file.get_or_insert_with(|| path.into());
        }
        self
    }

    /// Names the operation of a numerical failure (a factorisation reports only its pivot; the
    /// caller knows which matrix it was). Other errors pass through unchanged.
    pub fn during(self, operation: &str) -> Self {
        match self {
            Error::Numerical { detail, .. } => Error::numerical(operation, detail),
            other => other,
        }
    }
}

/// What is doubtful about a robot description that still loads; strict loading
/// ([`crate::LoadOptions::strict`]) refuses it as an [`Error::Model`] instead.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum WarningKind {
    /// A link with zero mass and a nonzero rotational inertia (the inertia is kept).
    ZeroMassWithInertia,
    /// A rotational inertia with a negative principal moment beyond rounding.
    InertiaNotPositiveSemidefinite,
    /// A positive mass with a zero principal moment (a point or rod mass): physically an
    /// idealisation, common for sensor and tool frames.
    SingularInertia,
    /// Principal moments that violate the triangle inequality `I1 + I2 >= I3`.
    TriangleInequality,
    /// A moving joint whose subtree carries neither mass nor inertia: `M(q)` is singular.
    MasslessSubtree,
    /// A revolute or prismatic joint's limit with `lower > upper` (the joint is taken as
    /// unlimited).
    InvertedLimits,
    /// A moving joint with a `mimic` element: the coupling to the joint it mimics is not
    /// modelled; the joint moves on its own (its own coordinate, as Pinocchio's default
    /// URDF parser makes it).
    MimicNotModelled,
}

/// A doubtful but usable part of a robot description, found while loading it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// What is doubtful.
    pub kind: WarningKind,
    /// The element, e.g. `link 'l_foot'`, `joint 'r_knee'`.
    pub element: String,
    /// What is wrong with it, with the numbers.
    pub message: String,
}

impl Warning {
    /// A warning of `kind` about `element`.
    pub fn new(kind: WarningKind, element: impl Into<String>, message: impl Into<String>) -> Self {
        Warning {
            kind,
            element: element.into(),
            message: message.into(),
        }
    }

    /// The same finding as a model error (strict loading).
    pub fn into_error(self) -> Error {
        Error::model(self.element, self.message)
    }
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.element, self.message)
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// `file:line:column: message`, leaving out the parts that are unknown.
pub fn parse_message(
    file: Option<&PathBuf>,
    line: Option<usize>,
    column: Option<usize>,
    message: &str,
) -> String {
    let mut place = match file {
        Some(file) => file.display().to_string(),
        None => "<text>".to_string(),
    };
    if let Some(line) = line {
        place.push_str(&format!(":{line}"));
        if let Some(column) = column {
            place.push_str(&format!(":{column}"));
        }
    }
    format!("{place}: {message}")
}

/// `value` as Rust writes it, or in exponent notation when it is so large or so small that
/// the plain form would spell out its zeros (|value| >= 1e16: `1e300` rather than 301 digits;
/// 0 < |value| < 1e-6: `1.5e-12`). Ordinary values (`0.46406250000000004`) stay plain.
pub fn readable_number(value: f64) -> String {
    let size = value.abs();
    if size >= 1e16 || (size > 0.0 && size < 1e-6) {
        format!("{value:e}")
    } else {
        format!("{value}")
    }
}

/// The longest text a message shows whole; longer text (a frame name of megabytes from a
/// hostile caller) shows its start and its length.
const SHOWN_CHARACTERS: usize = 200;

/// `text` as a message shows it: whole up to 200 characters, else its first characters and its
/// length, e.g. `xxxx... (10000000 characters)`.
pub fn shortened(text: &str) -> std::borrow::Cow<'_, str> {
    let count = text.chars().count();
    if count <= SHOWN_CHARACTERS {
        return text.into();
    }
    let start: String = text.chars().take(SHOWN_CHARACTERS - 40).collect();
    format!("{start}... ({count} characters)").into()
}

/// `text` with its control characters escaped as Rust writes them (`\u{1b}` for ESC, `\0`,
/// `\n`), so that a name from a file or a command line shown in a message or a comment cannot
/// drive a terminal or end a line; the characters of `kept` (e.g. `['\n', '\t']` for a
/// message's own line breaks) stay as they are.
pub fn escaped_controls<'a>(text: &'a str, kept: &[char]) -> std::borrow::Cow<'a, str> {
    let hidden = |c: char| c.is_control() && !kept.contains(&c);
    if !text.chars().any(hidden) {
        return text.into();
    }
    let mut shown = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if hidden(c) {
            shown.extend(c.escape_debug());
        } else {
            shown.push(c);
        }
    }
    shown.into()
}

/// `file: ` before a message about a file's content, or nothing when no file is known.
fn file_prefix(file: Option<&PathBuf>) -> String {
    file.map(|file| format!("{}: ", file.display()))
        .unwrap_or_default()
}

/// The operating system's description of an I/O error without the trailing `(os error N)`,
/// e.g. `No space left on device`; other errors as they display.
pub fn io_message(error: &std::io::Error) -> String {
    let text = error.to_string();
    match error.raw_os_error() {
        Some(code) => text
            .strip_suffix(&format!(" (os error {code})"))
            .unwrap_or(&text)
            .to_string(),
        None => text,
    }
}

/// 1-based `(line, column)` of byte `offset` in `text` (column counted in characters).
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    // The largest char boundary at or before `offset` (`str::floor_char_boundary` is unstable).
    let end = (0..=offset.min(text.len()))
        .rev()
        .find(|i| text.is_char_boundary(*i))
        .unwrap_or(0);
    let before = &text[..end];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Checks that `value` is finite and `> 0`; otherwise an [`Error::InvalidArgument`] naming
/// `argument`, "a positive finite number" and the value.
pub fn check_positive(argument: impl Into<String>, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(argument, "a positive finite number", value))
    }
}

/// Checks that `value` is finite and `>= 0`; otherwise an [`Error::InvalidArgument`] naming
/// `argument`, "a non-negative finite number" and the value.
pub fn check_non_negative(argument: impl Into<String>, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            "a non-negative finite number",
            value,
        ))
    }
}

/// Checks that `values` has `expected` entries, all finite; names `argument` otherwise.
pub fn check_vector(argument: &str, values: &[f64], expected: usize) -> Result<()> {
    if values.len() != expected {
        return Err(Error::invalid(
            argument,
            format!("shape ({expected},)"),
            format!("{} entries", values.len()),
        ));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(Error::invalid(
            format!("{argument}[{i}]"),
            "a finite number",
            values[i],
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn control_characters_are_escaped_except_the_kept_ones() {
        let kept = ['\n', '\t'];
        assert_eq!(
            escaped_controls("plain\tline\nnext", &kept),
            "plain\tline\nnext"
        );
        assert_eq!(
            escaped_controls("a\u{1b}[31mb\0c\rd", &kept),
            "a\\u{1b}[31mb\\0c\\rd"
        );
        assert_eq!(escaped_controls("a\nb", &[]), "a\\nb");
    }

    use super::*;

    #[test]
    fn messages_name_their_fields() {
        let e = Error::invalid("q", "shape (7,)", "3 entries");
        assert_eq!(e.to_string(), "q: expected shape (7,), got 3 entries");
        let e = Error::model("joint 'knee'", "has a zero axis");
        assert_eq!(e.to_string(), "joint 'knee': has a zero axis");
        let e = Error::numerical("pivot", "tree pivot 3").during("factorising the mass matrix");
        assert_eq!(e.to_string(), "factorising the mass matrix: tree pivot 3");
        assert!(matches!(e, Error::Numerical { .. }));
    }

    #[test]
    fn a_long_name_or_value_is_shown_by_its_start_and_length() {
        let name = "x".repeat(1_000_000);
        let text = Error::UnknownFrame { name: name.clone() }.to_string();
        assert!(text.len() < 250, "{} bytes", text.len());
        assert!(text.ends_with("x... (1000000 characters)'"), "{text}");
        let text = Error::invalid(format!("external['{name}']"), "a link", &name).to_string();
        assert!(text.len() < 500, "{} bytes", text.len());
        assert!(text.starts_with("external['xxx"), "{text}");
        // Up to the limit a text is shown whole, multi-byte characters counted as one.
        let whole = "é".repeat(SHOWN_CHARACTERS);
        assert_eq!(shortened(&whole), whole);
        assert!(shortened(&format!("{whole}é")).ends_with("(201 characters)"));
    }

    #[test]
    fn io_message_is_the_os_description_with_the_path() {
        let source = std::io::Error::from_raw_os_error(28); // ENOSPC on Linux
        let e = Error::io("/dev/full", source);
        let text = e.to_string();
        assert!(text.starts_with("/dev/full: "), "{text}");
        assert!(!text.contains("os error"), "{text}");
    }

    #[test]
    fn parse_message_and_line_column() {
        let text = "a\nbc\ndéf";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 3), (2, 2));
        assert_eq!(line_column(text, 8), (3, 3)); // after the two-byte 'é'
        let file = PathBuf::from("robot.urdf");
        assert_eq!(
            parse_message(Some(&file), Some(3), Some(2), "bad"),
            "robot.urdf:3:2: bad"
        );
        assert_eq!(parse_message(None, None, Some(2), "bad"), "<text>: bad");
    }

    #[test]
    fn check_vector_names_the_entry() {
        let e = check_vector("nu", &[0.0, f64::NAN], 2).unwrap_err();
        assert_eq!(e.to_string(), "nu[1]: expected a finite number, got NaN");
        let e = check_vector("nu", &[0.0], 2).unwrap_err();
        assert_eq!(e.to_string(), "nu: expected shape (2,), got 1 entries");
    }

    #[test]
    fn sign_checks_name_the_argument_and_refuse_the_edges() {
        assert!(check_positive("dt", 1e-300).is_ok());
        assert!(check_non_negative("friction", 0.0).is_ok());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = check_positive("dt", bad).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("dt: expected a positive finite number, got {bad}")
            );
        }
        for bad in [-1e-12, f64::NAN, f64::INFINITY] {
            let e = check_non_negative("friction", bad).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("friction: expected a non-negative finite number, got {bad}")
            );
        }
    }
}
