//! What the loop takes: the built objects of a run ([`Setup`]) and its plain settings
//! ([`LoopSettings`]): the time grid, the plant's integrator, the stopping rules, the
//! measurement model, the disturbances and what the sinks draw. No file format: a scenario
//! file is read and built above the loop (`sea_scenario`), or these are made by hand.

use crate::disturbance_schedule::DisturbanceConfig;
use crate::sampling::Schedule;
use crate::sensing::SensingConfig;
use sea_ctrl::controller::MomentumController;
use sea_ctrl::references::{ComTrajectory, PostureReference};
use sea_dyn::Model;
use sea_plant::{Method, Plant};
use std::path::PathBuf;

/// The built objects of one run: model, plant, controller, initial state and references (a
/// scenario file built, or objects made by hand).
pub struct Setup {
    /// Robot model.
    pub model: Model,
    /// Plant.
    pub plant: Plant,
    /// Controller.
    pub controller: MomentumController,
    /// Initial plant state.
    pub x0: Vec<f64>,
    /// CoM reference.
    pub com_reference: ComTrajectory,
    /// Postural reference.
    pub posture: PostureReference,
    /// Elastic joint names (order of theta).
    pub elastic_names: Vec<String>,
    /// What the build let pass but the user should hear of (a doubtful URDF element, a
    /// walking command the step limits clip), one message each naming its element or key;
    /// the run is unaffected.
    pub warnings: Vec<String>,
}

/// The bounds that end a run as diverged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DivergenceBounds {
    /// The CoM error bound [m].
    pub com_error_m: f64,
    /// The joint error norm bound [rad].
    pub joint_error_rad: f64,
    /// A joint of the true state outside its URDF position limits ends the run.
    pub stop_at_joint_limits: bool,
}

/// What the sinks draw besides the samples: the robot's URDF and contact surfaces, the
/// disturbances' links.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunScene {
    /// The URDF file, resolved (its meshes are drawn).
    pub urdf: PathBuf,
    /// The contacts as given (frame names or `LINK:x,y,z`), in the order of the wrenches.
    pub contacts: Vec<String>,
    /// The foot rectangle of every contact, `x` and `y` bounds in the sole frame [m].
    pub foot: Option<([f64; 2], [f64; 2])>,
}

/// The plain settings of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopSettings {
    /// The time grid.
    pub schedule: Schedule,
    /// The plant's integrator.
    pub method: Method,
    /// Plant steps between two refreshes of the integrator's `W` matrix.
    pub w_refresh_steps: usize,
    /// The simulated duration asked for [s] (the progress' denominator).
    pub duration_s: f64,
    /// Record every this many samples (at least 1).
    pub record_every: usize,
    /// The divergence bounds.
    pub bounds: DivergenceBounds,
    /// A foot's wrench that a unilateral contact with friction cannot transmit ends the run
    /// as "fell".
    pub stop_on_fall: bool,
    /// When a run under unilateral contacts has fallen ([`crate::fall_check`]).
    pub fall_bounds: crate::fall_check::FallBounds,
    /// What the controller measures.
    pub sensing: SensingConfig,
    /// External wrenches on links over time windows.
    pub disturbances: Vec<DisturbanceConfig>,
    /// What the sinks draw.
    pub scene: RunScene,
}

impl LoopSettings {
    /// Buffers to step `plant` with these settings (`w_refresh_steps`).
    pub fn plant_data(&self, plant: &Plant) -> sea_plant::PlantData {
        let mut data = sea_plant::PlantData::new(plant);
        data.integrator.set_w_refresh_steps(self.w_refresh_steps);
        data
    }

    /// The link of each disturbance, in order.
    pub fn disturbance_links(&self) -> Vec<String> {
        self.disturbances.iter().map(|d| d.link.clone()).collect()
    }
}
