//! `sea_ctrl`: momentum-based balancing controllers for humanoid robots with rigid joints or
//! series elastic actuators (Nava, Pucci, Nori), control only (no file formats).
//!
//! - [`controller`]: the rigid, SEA and mixed controllers ([`MomentumController`]);
//! - [`torque_map`]: joint torques affine in the contact wrenches (eq:torques, posturalNew);
//! - [`qp`]: the contact-wrench QP (inputTorquesSOT, inputTorquesSOTu), solved with Clarabel;
//! - [`references`]: the CoM trajectory and the postural reference.

#![forbid(unsafe_code)]

pub mod controller;
pub mod error;
pub mod qp;
pub mod references;
pub mod torque_map;

pub use controller::{ControlOutput, ControllerKind, ControllerSettings, MomentumController};
pub use error::{Error, Result};
