//! The one error type of `sea_sim`.

use thiserror::Error;

/// Errors of the controllers, scenarios and logging.
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
    /// A controller problem from `sea_ctrl`.
    #[error(transparent)]
    Control(#[from] sea_ctrl::Error),
    /// Reading or writing a file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Writing the MCAP log.
    #[error("MCAP log: {0}")]
    Log(String),
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
