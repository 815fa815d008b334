//! The one error type of `sea_sim`.
//!
//! A scenario value that breaks a rule is [`Error::Scenario`], naming the dotted key, the rule
//! and the value; malformed TOML is [`Error::Parse`] with the file, line and column; reading or
//! writing a file is [`Error::Io`] with the path and the operating system's cause. Model,
//! argument and numerical failures come from `sea_dyn` ([`Error::Dynamics`]) and controller
//! settings from `sea_ctrl` ([`Error::Control`]), unchanged (a scenario's read and build turn
//! a controller setting's error into [`Error::Scenario`] with the file and line of its key).

use std::path::PathBuf;

use thiserror::Error;

/// Errors of the scenarios, the closed loop and logging.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum Error {
    /// A scenario value is missing, unknown, of the wrong type or out of range.
    #[error("{}", located_message(file.as_ref(), *line, &scenario_message(key, rule, value.as_deref())))]
    Scenario {
        /// Dotted key, e.g. `controller.postural_scale`.
        key: String,
        /// The rule it breaks, e.g. `must be finite and non-negative`.
        rule: String,
        /// The offending value, when there is one.
        value: Option<String>,
        /// The scenario file, when the text came from one.
        file: Option<PathBuf>,
        /// 1-based line of the key in the scenario's text (of its table when the text does
        /// not give the key); `None` when the text does not have it or an override set it.
        line: Option<usize>,
    },
    /// A scenario file is not valid TOML.
    #[error("{}", sea_dyn::error::parse_message(file.as_ref(), *line, *column, message))]
    Parse {
        /// The file, when the text came from one.
        file: Option<PathBuf>,
        /// 1-based line, when known.
        line: Option<usize>,
        /// 1-based column, when known.
        column: Option<usize>,
        /// The parser's message.
        message: String,
    },
    /// A model, argument or numerical problem from `sea_dyn`.
    #[error(transparent)]
    Dynamics(#[from] sea_dyn::Error),
    /// A controller problem from `sea_ctrl`.
    #[error(transparent)]
    Control(#[from] sea_ctrl::Error),
    /// Reading or writing a file.
    #[error("{path}: {}", sea_dyn::error::io_message(source))]
    Io {
        /// The file.
        path: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Writing the MCAP log failed for a reason other than I/O (a sample of the wrong size, a
    /// finished log, a stopped writer).
    #[error("MCAP log: {0}")]
    Log(String),
    /// Writing an output other than the MCAP log failed for a reason other than I/O (the
    /// Foxglove live view's server, a JSON summary); the message names the output.
    #[error("{0}")]
    Output(String),
}

impl Error {
    /// A scenario error naming `key` and the `rule` it breaks, without a single offending value.
    pub fn config(key: impl Into<String>, rule: impl Into<String>) -> Self {
        Error::Scenario {
            key: key.into(),
            rule: rule.into(),
            value: None,
            file: None,
            line: None,
        }
    }

    /// A scenario error naming `key`, the `rule` it breaks and the offending `value`.
    pub fn invalid(key: impl Into<String>, rule: impl Into<String>, value: impl ToString) -> Self {
        Error::Scenario {
            key: key.into(),
            rule: rule.into(),
            value: Some(value.to_string()),
            file: None,
            line: None,
        }
    }

    /// A bad argument of a function, not a scenario key (a margin's range, `init`'s foot):
    /// `sea_dyn`'s `InvalidArgument` naming the `argument`, what it must be and what it was,
    /// a `ValueError` with `argument` in Python.
    pub fn argument(
        argument: impl Into<String>,
        expected: impl Into<String>,
        actual: impl ToString,
    ) -> Self {
        Error::Dynamics(sea_dyn::Error::invalid(argument, expected, actual))
    }

    /// The same error with the argument of a bad argument ([`Error::argument`]) renamed by
    /// `names`, pairs `(library name, caller's name)`: how the caller spelt it (a command
    /// line's flag, a Python argument). Other errors, and arguments not listed, pass through
    /// unchanged.
    pub fn argument_named(self, names: &[(&str, &str)]) -> Self {
        match self {
            Error::Dynamics(sea_dyn::Error::InvalidArgument {
                argument,
                expected,
                actual,
            }) => {
                let named = names.iter().find(|(name, _)| *name == argument);
                Error::Dynamics(sea_dyn::Error::InvalidArgument {
                    argument: named.map_or(argument, |(_, caller)| caller.to_string()),
                    expected,
                    actual,
                })
            }
            other => other,
        }
    }

    /// An I/O failure on `path`.
    pub fn io(path: impl AsRef<std::path::Path>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.as_ref().display().to_string(),
            source,
        }
    }

    /// Names the file a parse failure or a scenario key's error came from. Other errors pass
    /// through unchanged.
    pub fn in_file(mut self, path: impl Into<PathBuf>) -> Self {
        if let Error::Parse { file, .. } | Error::Scenario { file, .. } = &mut self {
            file.get_or_insert_with(|| path.into());
        }
        self
    }

    /// The same error with a scenario key's `line` in its text set by `line_of` (given the
    /// key), unless it is set already. Other errors pass through unchanged.
    pub fn at_line(mut self, line_of: impl FnOnce(&str) -> Option<usize>) -> Self {
        if let Error::Scenario { key, line, .. } = &mut self {
            if line.is_none() {
                *line = line_of(key);
            }
        }
        self
    }
}

/// `scenario key 'key': rule, got value` (without the value part when there is none).
fn scenario_message(key: &str, rule: &str, value: Option<&str>) -> String {
    match value {
        Some(value) => format!("scenario key '{key}': {rule}, got {value}"),
        None => format!("scenario key '{key}': {rule}"),
    }
}

/// `message` after the file and line it is about (`file:line: message`, `<text>:line:` without
/// a file, `file:` without a line), or alone when neither is known.
fn located_message(file: Option<&PathBuf>, line: Option<usize>, message: &str) -> String {
    if file.is_none() && line.is_none() {
        return message.to_string();
    }
    sea_dyn::error::parse_message(file, line, None, message)
}

/// The text of a panic's payload (a `&str` or a `String`; "unknown panic" otherwise), for an
/// error that reports a panic caught on another thread.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;
