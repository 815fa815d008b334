//! `sea_ctrl`: momentum-based balancing controllers for humanoid robots with rigid joints or
//! series elastic actuators (Nava, Pucci, Nori), control only (no file formats).
//!
//! - [`controller`]: the rigid, SEA and mixed controllers ([`MomentumController`]), one tick
//!   allocation-free ([`MomentumController::compute_into`]);
//! - [`momentum`]: the momentum task (hDot, eq:dotH_f, eq:IhTilde, eqn:jacobian);
//! - [`torque_map`]: joint torques affine in the contact wrenches (eq:torques, posturalNew);
//! - [`sea`]: the SEA terms (p, hjBar, inputDesMotVel) and the rigid motor torque (remark1);
//! - [`qp`]: the contact-wrench QP (inputTorquesSOT, inputTorquesSOTu, frictionCones): the
//!   minimiser without inequalities first, then the dense active-set method of
//!   [`qp::active_set`] (Goldfarb-Idnani, allocation-free), Clarabel as the reference and
//!   fallback;
//! - [`references`]: the CoM trajectory and the postural reference;
//! - [`joint_loop`]: the joint torque loop of the multi-rate architecture (the paper's law is
//!   its special case);
//! - [`external_wrench`]: the unmodelled external wrench (a push) estimated from the
//!   centroidal momentum and the feet's force/torque sensors, taken into the dynamics;
//! - [`generalized_disturbance`]: the generalized force the model misses (link mass errors, a
//!   wrench on any link) estimated by inverse dynamics, taken into every row of the dynamics;
//! - [`stiffness_id`]: online identification of the spring stiffness from the encoders and the
//!   model;
//! - [`robot`]: the robot's controller as one stack ([`robot::RobotController`]): the
//!   whole-body law, the joint loops, the identification and the observers, with one per-tick
//!   contract (measured state in, motor commands out);
//! - [`excitation`]: a sinusoidal torque on chosen joints for a while, so that the
//!   identification sees joints the task leaves unloaded;
//! - [`walking`]: the walking planner: footsteps, the DCM and CoM reference, swing soles,
//!   contact phases, push-recovery steps (not yet used by the controller).
//!
//! docs/explanation/architecture.md maps every paper equation to its function.

#![forbid(unsafe_code)]

pub mod controller;
pub mod error;
pub mod excitation;
pub mod external_wrench;
pub mod feedback;
pub mod generalized_disturbance;
pub mod joint_loop;
pub mod momentum;
pub mod qp;
pub mod redundant_contacts;
pub mod references;
pub mod robot;
pub mod sea;
pub mod stiffness_id;
pub mod torque_map;
pub mod walking;

/// The active-set solver at its former path `sea_ctrl::active_set`.
pub use qp::active_set;

pub use controller::{ControlOutput, ControllerKind, ControllerSettings, MomentumController};
pub use error::{Error, Result};
pub use robot::RobotController;
pub use walking::WalkingSettings;
