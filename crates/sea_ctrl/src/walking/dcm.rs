//! The DCM (capture point) trajectory over a footstep plan and the CoM reference it implies
//! ([`DcmPlan`]), for a LIP at constant height (docs/explanation/walking.md).
//!
//! The virtual repellent point (VRP) is held at the stance sole's origin through each single
//! support and moves linearly, at constant speed, from one stance sole to the next through
//! each double support; from standing it starts at the initial CoM, and after the last step
//! it moves to the final mid-feet point and stays there. The DCM is computed backwards from
//! its final value (at rest over the mid-feet point) by the exact solution of
//! `xidot = omega (xi - p)` over each segment (Englsberger et al. 2015's recursion
//! `xi_start = p + (xi_end - p) e^(-omega T)`, generalised to a linear VRP). The initial
//! transfer joins the CoM at rest to the DCM the recursion asks for at the first lift-off by
//! a cubic in the DCM (zero DCM velocity at the start), so the VRP starts at the CoM (no
//! jump of the CoM acceleration at the start) and meets the stance sole at the lift-off.
//!
//! Choice: a linear VRP in double support rather than Englsberger et al.'s polynomial blend
//! of the DCM around each switch. The recursion stays exact, the VRP stays on the segment
//! between the two soles (inside their convex hull) through double support, and the VRP is
//! continuous everywhere, so the DCM and the CoM velocity are continuous and the CoM
//! acceleration `omega^2 (x - p)` is too: no jump of the planned wrench at a switch.
//!
//! The CoM follows `xdot = -omega (x - xi)` from rest at the initial CoM, in closed form per
//! segment (`segment`), so position, velocity and acceleration are exact and satisfy
//! `xddot = omega^2 (x - p)`.

use super::footstep::FootstepPlan;
use super::lip::Lip;
use super::segment::{Cubic, DcmSegment, PlanarSample};
use crate::references::ComSample;
use nalgebra::{Vector2, Vector3};

/// The planned DCM, VRP and CoM at one instant (world; the z of each is the CoM's height).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcmSample {
    /// The DCM `xi` [m].
    pub world_xi: Vector3<f64>,
    /// Its velocity [m/s].
    pub world_xidot: Vector3<f64>,
    /// The VRP `p` (on flat ground at constant height, the centre of pressure raised to the
    /// CoM's height) [m].
    pub world_p_vrp: Vector3<f64>,
    /// The CoM reference: position [m], velocity [m/s], acceleration [m/s^2].
    pub com: ComSample,
}

/// Where a DCM plan starts (world x, y): the DCM [m], its velocity [m/s], the CoM [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DcmStart {
    /// The DCM `xi`.
    pub world_xi: Vector2<f64>,
    /// Its velocity `xidot`.
    pub world_xidot: Vector2<f64>,
    /// The CoM's ground projection.
    pub world_p_com: Vector2<f64>,
}

/// The DCM trajectory and CoM reference over a footstep plan (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct DcmPlan {
    lip: Lip,
    /// The CoM's height in world: ground plus `z0` [m].
    world_z_com: f64,
    segments: Vec<DcmSegment>,
}

impl DcmPlan {
    /// The plan over `footsteps` for the pendulum `lip`, starting at rest with the CoM over
    /// `world_p_com0` (x, y) on ground at height `world_z_ground` [m].
    pub fn new(
        footsteps: &FootstepPlan,
        lip: Lip,
        world_p_com0: Vector2<f64>,
        world_z_ground: f64,
    ) -> Self {
        let at_rest = DcmStart {
            world_xi: world_p_com0,
            world_xidot: Vector2::zeros(),
            world_p_com: world_p_com0,
        };
        Self::from_state(footsteps, lip, at_rest, world_z_ground)
    }

    /// The plan over `footsteps` (whose first double support starts at `footsteps.start_s`)
    /// from the DCM, DCM velocity and CoM of `start` (a measured state: a push-recovery plan,
    /// `walking::recovery`): the first double support's cubic joins `start`'s DCM and DCM
    /// velocity to the DCM the recursion asks for at the first lift-off; the CoM starts at
    /// `start`'s.
    pub fn from_state(
        footsteps: &FootstepPlan,
        lip: Lip,
        start: DcmStart,
        world_z_ground: f64,
    ) -> Self {
        let omega = lip.omega;
        let mut segments = backward_recursion(footsteps, omega);
        let first = &segments[0];
        let target = first.dcm(omega, 0.0);
        let transfer = first.start - footsteps.start_s;
        let initial = DcmSegment::polynomial(
            footsteps.start_s,
            transfer,
            Cubic::hermite((start.world_xi, start.world_xidot), target, transfer),
        );
        segments.insert(0, initial);
        Self::from_segments(lip, segments, start.world_p_com, world_z_ground)
    }

    /// The plan of the DCM `segments` (in time order, the last at rest), the CoM starting at
    /// `world_p_com0` (x, y) on ground at height `world_z_ground` [m].
    pub(crate) fn from_segments(
        lip: Lip,
        mut segments: Vec<DcmSegment>,
        world_p_com0: Vector2<f64>,
        world_z_ground: f64,
    ) -> Self {
        let omega = lip.omega;
        let mut x0 = world_p_com0;
        for segment in &mut segments {
            segment.set_com_start(omega, x0);
            if segment.duration.is_finite() {
                x0 = segment.com(omega, segment.duration)[0];
            }
        }
        Self {
            lip,
            world_z_com: world_z_ground + lip.com_height,
            segments,
        }
    }

    /// The CoM's height in world: the ground's plus `z0` [m].
    pub fn world_z_com(&self) -> f64 {
        self.world_z_com
    }

    /// The pendulum.
    pub fn lip(&self) -> Lip {
        self.lip
    }

    /// The times at which the VRP's motion changes (the start of each segment, the plan's
    /// start first: 0, or a re-plan's time) [s]: lift-offs, touchdowns, the end of the initial
    /// transfer, the start of standing.
    pub fn switch_times(&self) -> Vec<f64> {
        self.segments.iter().map(|segment| segment.start).collect()
    }

    /// The time the plan starts [s]: the walk's start, or the time of the measured state a
    /// re-plan started from (a step adjusted, a recovery planned, the settling after a
    /// recovery step's touchdown).
    pub fn start_time(&self) -> f64 {
        self.segments[0].start
    }

    /// The time from which the DCM is at rest over the final mid-feet point [s].
    pub fn end_time(&self) -> f64 {
        self.segments.last().map_or(0.0, |segment| segment.start)
    }

    /// The plan at time `t` [s] (before its start: the start; after the end: at rest, the
    /// CoM converging to the DCM).
    pub fn sample(&self, t: f64) -> DcmSample {
        let t = t.max(self.segments[0].start);
        let index = self.segments.partition_point(|segment| segment.start <= t) - 1;
        self.sample_segment(index, t - self.segments[index].start)
    }

    /// Segment `index` at its local time `tau` (also at its end, to compare with the next
    /// segment's start).
    pub(crate) fn sample_segment(&self, index: usize, tau: f64) -> DcmSample {
        let planar = self.segments[index].sample(self.lip.omega, tau);
        self.lift(planar)
    }

    /// Durations of the segments (the last infinite).
    #[cfg(test)]
    pub(crate) fn segment_durations(&self) -> Vec<f64> {
        self.segments
            .iter()
            .map(|segment| segment.duration)
            .collect()
    }

    /// The planar sample at the CoM's height.
    fn lift(&self, planar: PlanarSample) -> DcmSample {
        let z = self.world_z_com;
        let at_height = |v: Vector2<f64>| Vector3::new(v.x, v.y, z);
        let flat = |v: Vector2<f64>| Vector3::new(v.x, v.y, 0.0);
        DcmSample {
            world_xi: at_height(planar.dcm),
            world_xidot: flat(planar.dcm_velocity),
            world_p_vrp: at_height(planar.vrp),
            com: ComSample {
                position: at_height(planar.com[0]),
                velocity: flat(planar.com[1]),
                acceleration: flat(planar.com[2]),
            },
        }
    }
}

/// The segments after the initial transfer, computed backwards from the DCM at rest over the
/// final mid-feet point: per step a single support (VRP at the stance sole) and a double
/// support (VRP from this stance sole to the next, or to the final mid-feet point over the
/// transfer), then standing.
pub(crate) fn backward_recursion(footsteps: &FootstepPlan, omega: f64) -> Vec<DcmSegment> {
    let rest_point = footsteps.final_stance().mid_frame().world_p_sole;
    let mut vrp_moves = Vec::with_capacity(2 * footsteps.steps.len());
    for (index, step) in footsteps.steps.iter().enumerate() {
        let stance = footsteps.stance_sole(index).world_p_sole;
        let single_support = step.touchdown - step.lift_off;
        vrp_moves.push((step.lift_off, single_support, stance, stance));
        let (duration, next) = match footsteps.steps.get(index + 1) {
            Some(next) => (
                next.lift_off - step.touchdown,
                footsteps.stance_sole(index + 1).world_p_sole,
            ),
            None => (footsteps.transfer_duration, rest_point),
        };
        vrp_moves.push((step.touchdown, duration, stance, next));
    }
    let mut segments = vec![DcmSegment::at_rest(footsteps.end_time(), rest_point)];
    let mut xi_end = rest_point;
    for &(start, duration, p0, p1) in vrp_moves.iter().rev() {
        let segment = DcmSegment::linear_vrp(omega, start, duration, (p0, p1), xi_end);
        xi_end = segment.dcm(omega, 0.0).0;
        segments.push(segment);
    }
    segments.reverse();
    segments
}
