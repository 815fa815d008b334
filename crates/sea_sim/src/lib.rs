//! `sea_sim`: the app. The `sea-sim` command (one file per command under `bin/`), `init` (a
//! scenario for a new humanoid from its URDF), the benchmarks, and a facade that keeps the
//! former public paths of the crates split out of it:
//!
//! - [`closed_loop`]: the closed loop (`sea_loop`) with the scenario's `run` conveniences;
//! - [`scenario`]: scenario files (`sea_scenario`);
//! - [`foxglove`], [`mcap_log`], [`meshes`], [`output`]: what a person sees (`sea_viz`);
//! - [`analysis`], [`sweep`]: studies of the closed loop (`sea_study`);
//! - [`error`]: the one error type (`sea_loop`'s).

#![forbid(unsafe_code)]

pub mod bench;
pub mod closed_loop;
pub mod init;

pub use sea_loop::error;
pub use sea_loop::{Error, Result};
pub use sea_scenario as scenario;
pub use sea_study::{analysis, sweep};
pub use sea_viz::{foxglove, mcap_log, meshes, output};
