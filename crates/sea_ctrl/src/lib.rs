//! `sea_ctrl`: momentum-based balancing controllers for humanoid robots with rigid joints or
//! series elastic actuators (Nava, Pucci, Nori), control only (no file formats).
//!
//! - [`controller`]: the rigid, SEA and mixed controllers ([`MomentumController`]), one tick
//!   allocation-free ([`MomentumController::compute_into`]);
//! - [`momentum`]: the momentum task (hDot, eq:dotH_f, eq:IhTilde, eqn:jacobian);
//! - [`torque_map`]: joint torques affine in the contact wrenches (eq:torques, posturalNew);
//! - [`sea`]: the SEA terms (p, hjBar, inputDesMotVel) and the rigid motor torque (remark1);
//! - [`qp`]: the contact-wrench QP (inputTorquesSOT, inputTorquesSOTu, frictionCones), solved
//!   by the dense active-set method of [`active_set`] (Goldfarb-Idnani) with Clarabel as the
//!   reference and fallback;
//! - [`active_set`]: a dense, allocation-free Goldfarb-Idnani QP solver for small QPs;
//! - [`references`]: the CoM trajectory and the postural reference.
//!
//! docs/architecture.md maps every paper equation to its function.

#![forbid(unsafe_code)]

pub mod active_set;
pub mod controller;
pub mod error;
pub mod feedback;
pub mod momentum;
pub mod qp;
pub mod references;
pub mod sea;
pub mod torque_map;

pub use controller::{ControlOutput, ControllerKind, ControllerSettings, MomentumController};
pub use error::{Error, Result};
