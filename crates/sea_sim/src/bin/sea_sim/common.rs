//! What every command shares: value parsers of the flags, exit statuses, how runs end, and
//! the lines written on stdout and stderr (never an abort on a closed pipe).

use std::fmt::Display;
use std::io::Write;

/// `LOWER:UPPER` of `--range`.
pub(crate) fn parse_range(text: &str) -> Result<(f64, f64), String> {
    let (lower, upper) = text
        .split_once(':')
        .ok_or_else(|| format!("expected LOWER:UPPER, got '{text}'"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .map_err(|e| format!("'{s}' in '{text}': {e}"))
    };
    Ok((number(lower)?, number(upper)?))
}

/// A finite, positive number (clap names the flag in its error).
pub(crate) fn parse_positive(text: &str) -> Result<f64, String> {
    parse_finite(text, "finite, positive", |value| value > 0.0)
}

/// A finite, non-negative number (clap names the flag in its error).
pub(crate) fn parse_non_negative(text: &str) -> Result<f64, String> {
    parse_finite(text, "finite, non-negative", |value| value >= 0.0)
}

/// A finite number that `accepts`; `what` names the kind in the error ("finite, positive").
fn parse_finite(text: &str, what: &str, accepts: impl Fn(f64) -> bool) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(value) if value.is_finite() && accepts(value) => Ok(value),
        Ok(value) => Err(format!("must be a {what} number, got {value}")),
        Err(e) => Err(format!("expected a {what} number: {e}")),
    }
}

/// An existing folder (`--package-dir`; clap names the flag in its error): a missing one, or a
/// file, would be searched in vain.
pub(crate) fn parse_folder(text: &str) -> Result<std::path::PathBuf, String> {
    let path = std::path::PathBuf::from(text);
    match sea_dyn::files::not_a_folder(&path) {
        None => Ok(path),
        Some(problem) => Err(format!("'{text}': not a folder ({problem})")),
    }
}

/// `KEY=VALUE` of `--set`.
pub(crate) fn parse_key_value(text: &str) -> Result<(String, String), String> {
    let (key, value) = text
        .split_once('=')
        .ok_or_else(|| format!("expected KEY=VALUE, got '{text}'"))?;
    if key.trim().is_empty() {
        return Err(format!("empty key in '{text}'"));
    }
    Ok((key.trim().to_string(), value.trim().to_string()))
}

pub(crate) use sea_dyn::error::readable_number;

/// `value` with `decimals` decimals, or in exponent notation with as many when its size would
/// make the fixed form longer than `width` characters.
pub(crate) fn fixed_number(value: f64, width: usize, decimals: usize) -> String {
    let fixed = format!("{value:width$.decimals$}");
    if fixed.len() > width {
        format!("{value:width$.decimals$e}")
    } else {
        fixed
    }
}

/// Exit status of a run that diverged (distinct from errors).
pub(crate) const EXIT_DIVERGED: u8 = 3;

/// Exit status of an error.
pub(crate) const EXIT_ERROR: u8 = 1;

/// Writes a line on stderr; a closed or full stderr loses the line, never the run.
pub(crate) fn say(message: impl Display) {
    // Control characters escaped (a hostile name cannot drive the terminal); the message's
    // own line breaks and tabs kept.
    let text = message.to_string();
    let shown = sea_dyn::error::escaped_controls(&text, &['\n', '\t']);
    let _ = writeln!(std::io::stderr().lock(), "{shown}");
}

/// Writes `text` on stdout as it is (no newline added): stdout carries machine-readable JSON
/// and CSV, which escape their own strings.
///
/// Errors: [`sea_sim::Error::Io`] on `stdout` when the text cannot be written (a full disk
/// behind a redirection): the text is the command's product, so the exit status says so. A
/// closed pipe (`| head -c1`) is no error: the reader chose to stop, and only the text is lost.
pub(crate) fn print_text(text: impl Display) -> sea_sim::Result<()> {
    let mut out = std::io::stdout().lock();
    let written = write!(out, "{text}").and_then(|()| out.flush());
    stdout_result(written)
}

/// Writes text and a newline on stdout, as [`print_text`].
pub(crate) fn print_out(text: impl Display) -> sea_sim::Result<()> {
    print_text(format_args!("{text}\n"))
}

/// A write on stdout as a result: a closed pipe is no error, anything else names stdout.
fn stdout_result(written: std::io::Result<()>) -> sea_sim::Result<()> {
    match written {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(sea_sim::Error::Io {
            path: "stdout".to_string(),
            source: e,
        }),
        _ => Ok(()),
    }
}

/// How a run ended.
pub(crate) enum Outcome {
    Completed,
    Diverged,
    Interrupted(i32),
}
