//! `sea_study`: studies of the closed loop built from scenarios. Linearisation, eigenvalues
//! and stability margins, push bisection ([`analysis`]), parameter sweeps on threads
//! ([`sweep`], rayon; the Python package adds Ray).

#![forbid(unsafe_code)]

pub mod analysis;
pub mod sweep;

pub use sea_loop::{error, Error, Result};
