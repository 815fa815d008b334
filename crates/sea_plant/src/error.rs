//! Errors of the plant: `sea_dyn`'s error type, re-exported.
//!
//! The plant fails in the same ways as the dynamics library and needs no variant of its own:
//! a bad argument or setting is [`Error::InvalidArgument`] (naming it, with the expected and
//! the actual value); a mass matrix that is not positive definite, degenerate contact
//! constraints or a failed factorisation in the implicit step are [`Error::Numerical`]
//! (naming the operation), never input errors. One type keeps the Python mapping in one place.

pub use sea_dyn::error::{Error, Result};
