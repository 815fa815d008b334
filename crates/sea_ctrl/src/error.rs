//! The one error type of `sea_ctrl`.

use thiserror::Error;

/// Errors of the controllers.
#[derive(Debug, Error)]
pub enum Error {
    /// A scenario setting is missing, unknown or out of range; names the key.
    #[error("scenario key '{key}': {message}")]
    Config {
        /// Dotted key, e.g. `controller.kind`.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A model or plant problem from `sea_dyn`.
    #[error(transparent)]
    Dynamics(#[from] sea_dyn::Error),
}

impl Error {
    /// A configuration error naming `key`.
    pub fn config(key: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Config {
            key: key.into(),
            message: message.into(),
        }
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;
