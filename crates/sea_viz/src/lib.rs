//! `sea_viz`: what a person sees of a run. Foxglove channels and the robot's scene
//! ([`foxglove`]), MCAP logs ([`mcap_log`]), the live view ([`foxglove::live`]), the robot's
//! meshes ([`meshes`]: STL, OBJ, COLLADA, bounded and decimated) and output files written whole
//! or not at all ([`output`]). The logs and the live view are `sea_loop` sinks; warnings are
//! returned to the caller, never printed.

#![forbid(unsafe_code)]

pub mod foxglove;
pub mod mcap_log;
pub mod meshes;
pub mod output;

pub use sea_loop::{error, Error, Result};
