//! `sea_plant`: the robot with series elastic actuators (SEA) in rigid contact, as a
//! dynamical system.
//!
//! - [`plant`]: the plant's description ([`Plant`]: model, actuation, contacts, gains) and its
//!   state layout `x = [q; theta; nu; thetadot]`;
//! - [`actuation`]: the elastic coupling (paper eq:alpha), the motor dynamics (eq:motors) and
//!   the motor velocity loop (eq:tauMotors);
//! - [`contact`]: rigid contacts with Baumgarte stabilisation (eq:constraints_acc) and the
//!   margins of the simulated wrenches;
//! - [`dynamics`]: one evaluation of the forward dynamics ([`evaluate`]) into [`PlantData`];
//! - [`integrator`]: fixed-step integrators on the state manifold (ROS2 Rosenbrock-W,
//!   linearly implicit Euler, RK4), with the W-matrix solve in `integrator/w_matrix.rs`;
//! - [`manifold`]: the retraction `x (+) dx` and the state-vector derivative;
//! - [`simulate`]: the native loop with a held input.

#![forbid(unsafe_code)]

pub mod actuation;
pub mod contact;
pub mod dynamics;
pub mod error;
pub mod integrator;
pub mod manifold;
pub mod plant;
pub mod simulate;

pub use contact::{sole_margins, Contact, ContactLimits, WrenchMargins};
pub use dynamics::{evaluate, PlantData};
pub use error::{Error, Result};
pub use integrator::{step, Method};
pub use manifold::{retract, state_derivative};
pub use plant::{MotorInput, Plant};
pub use sea_dyn::StateLayout;
pub use simulate::{simulate, SimulationLog, Status};
