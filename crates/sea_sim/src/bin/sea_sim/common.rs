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

/// Exit status of a run that diverged (distinct from errors).
pub(crate) const EXIT_DIVERGED: u8 = 3;

/// Exit status of an error.
pub(crate) const EXIT_ERROR: u8 = 1;

/// Writes a line on stderr; a closed or full stderr loses the line, never the run.
pub(crate) fn say(message: impl Display) {
    let _ = writeln!(std::io::stderr().lock(), "{message}");
}

/// Writes `text` as it is on stdout (no newline added); a closed stdout loses the text, never
/// the run.
pub(crate) fn print_text(text: impl Display) {
    let mut out = std::io::stdout().lock();
    let _ = write!(out, "{text}").and_then(|()| out.flush());
}

/// Writes text on stdout; a closed stdout (`| head -c1`) loses the text, never the run.
pub(crate) fn print_out(text: impl Display) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{text}").and_then(|()| out.flush());
}

/// How a run ended.
pub(crate) enum Outcome {
    Completed,
    Diverged,
    Interrupted(i32),
}
