//! `sea_sim`: scenarios (TOML schema and robot presets), the closed loop of plant and
//! controller, recording and summary statistics, MCAP logging for Foxglove, benchmarks and the
//! `sea-sim` binary.

#![forbid(unsafe_code)]

pub mod analysis;
pub mod bench;
pub mod closed_loop;
/// The one error type, at its former path.
pub use sea_loop::error;
pub mod foxglove;
pub mod init;
pub mod mcap_log;
pub mod meshes;
pub mod output;
pub mod scenario;
pub mod sweep;

pub use error::{Error, Result};
