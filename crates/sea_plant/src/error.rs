//! Errors of the plant (the dynamics library's error type).

pub use sea_dyn::error::{Error, Result};
