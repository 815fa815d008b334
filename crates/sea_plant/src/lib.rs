//! `sea_plant`: the robot with series elastic actuators (SEA) in contact (rigid bilateral or
//! unilateral with friction and impacts), as a dynamical system.
//!
//! Modules, each importing only those listed before it (no cycle):
//! - [`error`]: the error type (`sea_dyn`'s);
//! - [`actuation`]: the elastic coupling (paper eq:alpha), the motor dynamics (eq:motors) and
//!   the motor velocity loop (eq:tauMotors), per joint;
//! - [`contact`]: rigid contacts, their pose error, the Baumgarte-stabilised constraint
//!   (eq:constraints_acc) and the margins of a wrench;
//! - [`ground`]: the ground plane the unilateral contacts touch;
//! - [`unilateral`]: unilateral contacts at points of the soles (compliant Hunt-Crossley normal
//!   force, regularised Coulomb friction) and their stiffness for the implicit step;
//! - [`joint_stops`]: the URDF's position limits as stops, with the same law;
//! - [`plant`]: the plant's description ([`Plant`]: model, actuation, contacts, gains) and its
//!   state layout `x = [q; theta; nu; thetadot]`;
//! - [`workspace`]: the evaluation's buffers ([`Workspace`], grouped by the stage that computes
//!   them) and its outputs ([`PlantOutputs`]); declarations only;
//! - [`manifold`]: the retraction `x (+) dx` and the state-vector derivative;
//! - [`equilibrium`]: static torques and the spring preload holding a configuration at rest;
//! - `compliant_forces`: stage 3 of an evaluation under unilateral contacts and joint stops;
//! - [`evaluation`]: one evaluation of the forward dynamics ([`evaluate`]) into a workspace and
//!   the caller's outputs, and the hand-over of terms computed elsewhere;
//! - [`external`]: external wrenches on links (pushes) as generalised forces `J^T w`;
//! - [`integrator`]: fixed-step integrators on the state manifold (ROS2 Rosenbrock-W,
//!   linearly implicit Euler, RK4) with their own buffers ([`IntegratorCache`], the W-matrix
//!   in `integrator/w_matrix.rs`), and [`PlantData`], what stepping one plant needs;
//! - [`mod@simulate`]: the native loop with a held input.

#![forbid(unsafe_code)]

pub mod actuation;
mod compliant_forces;
pub mod contact;
pub mod equilibrium;
pub mod error;
pub mod evaluation;
pub mod external;
pub mod ground;
pub mod integrator;
pub mod joint_stops;
pub mod manifold;
pub mod plant;
pub mod simulate;
pub mod unilateral;
pub mod workspace;

pub use contact::{sole_margins, Contact, ContactLimits, WrenchMargins};
pub use error::{Error, Result};
pub use evaluation::evaluate;
pub use external::ExternalWrench;
pub use ground::Ground;
pub use integrator::{step, step_with_feedback, IntegratorCache, Method, PlantData};
pub use joint_stops::JointStops;
pub use manifold::{retract, state_derivative};
pub use plant::{ContactModel, MotorInput, Plant};
pub use sea_dyn::{StateLayout, TangentLayout};
pub use simulate::{simulate, SimulationLog, Status};
pub use unilateral::{CompliantContact, UnilateralContacts};
pub use workspace::{PlantOutputs, Workspace};
