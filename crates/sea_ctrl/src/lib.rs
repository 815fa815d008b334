//! `sea_ctrl`: momentum-based balancing controllers (rigid and SEA), the contact-wrench QP,
//! references, the closed-loop scenario runner, MCAP logging and the `sea-sim` binary.

#![forbid(unsafe_code)]

pub mod bench;
pub mod closed_loop;
pub mod controller;
pub mod error;
pub mod mcap_log;
pub mod qp;
pub mod references;
pub mod scenario;
pub mod torque_map;

pub use error::{Error, Result};
