//! The one error type of `sea_dyn`.
//!
//! Model problems (`Error::Model`) name the URDF element and the violated condition; input
//! problems (`Error::Input`) name the argument and the expected shape. Bindings map the first to
//! `sea_momentum.ModelError` and the second to `ValueError`, in one place.

use thiserror::Error;

/// Errors of `sea_dyn`.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum Error {
    /// The robot description is unusable; the message names the element and the condition.
    #[error("{0}")]
    Model(String),
    /// An argument has the wrong size or holds a non-finite or out-of-range value.
    #[error("{0}")]
    Input(String),
    /// A frame name that the model does not have.
    #[error("unknown frame '{0}'")]
    UnknownFrame(String),
}

impl Error {
    /// A model error with the given message.
    pub fn model(message: impl Into<String>) -> Self {
        Error::Model(message.into())
    }

    /// An input error with the given message.
    pub fn input(message: impl Into<String>) -> Self {
        Error::Input(message.into())
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Checks that `values` has `expected` entries, all finite; names `argument` otherwise.
pub fn check_vector(argument: &str, values: &[f64], expected: usize) -> Result<()> {
    if values.len() != expected {
        return Err(Error::input(format!(
            "{argument} must have shape ({expected},), got {} entries",
            values.len()
        )));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(format!(
            "{argument}[{i}] is not finite ({})",
            values[i]
        )));
    }
    Ok(())
}
