//! Stability analysis of the closed loop: its equilibrium with the references frozen, the
//! linearisation on the state's tangent space in continuous time or over one control period
//! (zero-order hold), eigenvalues, growth rates and the least stable mode
//! ([`mod@linearize`]), and the parameter values where stability changes ([`margin`]); push
//! recovery ([`push`]) and the linear inverted pendulum's bounds on it, a walking gait's
//! sideways ([`gait_bound`]) and a standing robot's with steps ([`step_bound`]).

pub mod eigen;
pub mod gait_bound;
pub mod linearize;
pub mod margin;
pub mod push;
mod push_options;
pub mod step_bound;
pub mod system;
pub mod template_walk;

pub use linearize::{
    linearize, linearize_with, Equilibrium, Linearization, LinearizeOptions, StepCheck,
};
pub use margin::{
    scenario_value, stability_margin, stability_margin_report, IslandEnd, MarginConclusion,
    MarginMethod, MarginOptions, MarginReport, MarginSample, MarginWatch,
};
pub use system::{ClosedLoopSystem, ControlTiming};
