//! Walking, the planning part (docs/explanation/walking.md): footsteps from a walking command
//! or a list, the divergent component of motion (DCM) over them with the CoM reference the
//! momentum task tracks, the swing soles' trajectories, the contact schedule with the load
//! hand-over between the feet, and the step that recovers a push from the capture point.
//! Pure planning on flat ground: nothing here reads the robot or the controller (the
//! controller reads [`Gait`]).
//!
//! - [`settings`]: [`WalkingSettings`] (the future `[walking]` table), its check;
//! - [`footstep`]: feet, sole poses (`world_p_sole`, `world_yaw_sole`), timed footsteps, the
//!   reach / no-crossing / turn rule;
//! - [`command`]: footsteps from a command (forward, sideways, turning velocity) or a list,
//!   stopping on command;
//! - [`lip`]: the linear inverted pendulum, `omega = sqrt(g / z0)`, the DCM;
//! - [`dcm`]: the DCM trajectory (backward recursion, linear VRP in double support) and the
//!   CoM position, velocity and acceleration in closed form ([`DcmPlan`]);
//! - [`swing`]: the swing sole's pose, velocity, acceleration ([`SwingTrajectory`]);
//! - [`phase`]: which feet are in contact at `t`, the phase's fraction, the next touchdown,
//!   the left foot's load share;
//! - [`polygon`]: the support polygon of one sole or both;
//! - [`capture`]: whether a step is needed, and where and when ([`recovery_step`]);
//! - [`adjust`]: step adjustment while walking, the landing moved by the DCM error
//!   ([`adjust_step`]);
//! - [`recovery`]: the walk of one push-recovery step from a measured state
//!   ([`recovery_gait`]);
//! - [`gait`]: a planned walk sampled at a tick into the CoM reference and each foot's task
//!   ([`Gait`]), what the controller follows (`controller::contact_phase`).
//!
//! Sources: docs/references.md#walking.

pub mod adjust;
pub mod capture;
pub mod command;
pub mod dcm;
pub mod footstep;
pub mod gait;
pub mod lip;
pub mod phase;
pub mod polygon;
pub mod recovery;
mod segment;
pub mod settings;
pub mod step_timing;
pub mod swing;
mod validation;

#[cfg(test)]
mod tests;

pub use adjust::{adjust_step, StepAdjustment};
pub use capture::{
    needs_step, recovery_step, recovery_step_beyond, stance_margin, swing_foot_for, RecoveryStep,
    StepRequest,
};
pub use command::{
    command_clips, command_increments, footsteps_from_command, footsteps_from_list,
    footsteps_from_settings, stop_after, CommandClip,
};
pub use dcm::{DcmPlan, DcmSample, DcmStart};
pub use footstep::{check_step, Foot, Footstep, FootstepPlan, SolePose, Stance};
pub use gait::{FootTask, Gait};
pub use lip::Lip;
pub use phase::{GaitPhase, Support};
pub use polygon::SupportPolygon;
pub use recovery::{recovery_gait, settle_from, MeasuredCom, RecoveryFrame};
pub use settings::{
    CaptureMargin, FootstepSpec, RobotWalkingFigures, WalkCommand, WalkingSettings,
    ICUB_LEG_LENGTH, MAX_COMMAND_STEPS, STEP_LENGTH_PER_REACH,
};
pub use step_timing::StepTiming;
pub use swing::{PlanarQuintic, Quintic, SwingSample, SwingTrajectory, ToeOff};
