//! Step timing adaptation while walking (`walking.step_timing`, with the step adjustment): the
//! swing in flight may land earlier than planned when its adjusted landing lies beyond the
//! step limits (Khadiv, Herzog, Moosavian and Righetti 2016, step location and timing
//! adaptation; docs/references.md#walking).
//!
//! With the stance's centre of pressure `p` held until the touchdown, the DCM `xi` now is at
//! `p + (xi - p) e^(omega tau)` a time `tau` later. Keeping the plan's DCM offset from the
//! landing at touchdown, `b = xi_plan(T) - landing_plan`, the landing that takes the walk on
//! from the measured DCM is
//!
//! ```text
//! wished(tau) = p + (xi - p) e^(omega tau) - b,
//! ```
//!
//! at the planned `tau` the step adjustment's `landing_plan + (xi - xi_plan) e^(omega tau)`;
//! `p` is the plan's: `(xi_plan(T) - xi_plan(t) G) / (1 - G)`, `G = e^(omega tau_planned)`.
//! Where the step limits clip `wished(tau)`, the clipped part is what the stance's centre of
//! pressure has to take, and the sooner the foot lands the less the DCM has run. The remaining
//! swing chosen, [`remaining_swing`], is the latest on a grid of [`TIMING_GRID_S`] from the
//! planned one down to the earliest allowed ([`SwingInFlight::earliest`], set by the step
//! adjustment from `walking.min_adjusted_swing_duration`) whose clipped part ([`StepTiming`]
//! says which part counts) is within [`TIMING_TOLERANCE_M`] of the least on the grid:
//! unclipped steps keep their timing.

use super::footstep::SolePose;
use nalgebra::Vector2;

/// Which part of a clipped landing moves the touchdown earlier (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Deserialize, serde::Serialize, schemars::JsonSchema),
    serde(rename_all = "snake_case")
)]
pub enum StepTiming {
    /// The plan's timing: only the landings move.
    #[default]
    Fixed,
    /// A landing clipped sideways (the stance sole's lateral axis: the feet's width) lands
    /// earlier; a landing clipped forward or backward (the reach) keeps its timing.
    Sideways,
    /// A landing clipped in any direction lands earlier.
    Any,
}

/// The grid of remaining swing times searched [s] (module doc).
pub const TIMING_GRID_S: f64 = 0.005;

/// How much more clipped [m] than the least on the grid a later touchdown may be and still be
/// chosen (module doc).
pub const TIMING_TOLERANCE_M: f64 = 0.001;

/// A swing in flight, as the timing adaptation sees it (module doc).
#[derive(Clone, Copy, Debug)]
pub struct SwingInFlight {
    /// The planned time to the touchdown [s], > 0.
    pub remaining: f64,
    /// The earliest time to the touchdown allowed [s], > 0 (`walking::adjust`: the shortest
    /// swing's end, and the rest of the swing at most the shortest swing's pace faster).
    pub earliest: f64,
    /// The pendulum's `omega` [1/s].
    pub omega: f64,
    /// The measured DCM now (world x, y) [m].
    pub world_xi: Vector2<f64>,
    /// The plan's DCM now and at the planned touchdown (world x, y) [m].
    pub world_xi_plan: [Vector2<f64>; 2],
    /// The planned landing (world x, y) [m].
    pub world_p_landing: Vector2<f64>,
    /// The stance sole.
    pub stance: SolePose,
}

impl SwingInFlight {
    /// The landing wished for a touchdown `tau` [s] from now (module doc).
    pub fn wished_landing(&self, tau: f64) -> Vector2<f64> {
        let [xi_now, xi_touchdown] = self.world_xi_plan;
        let planned = (self.omega * self.remaining).exp();
        let world_p_cop = (xi_touchdown - xi_now * planned) / (1.0 - planned);
        let offset = xi_touchdown - self.world_p_landing;
        world_p_cop + (self.world_xi - world_p_cop) * (self.omega * tau).exp() - offset
    }
}

/// The time to the touchdown [s] chosen for `swing` under `timing` (module doc); `clip` moves
/// a landing into the step limits. The planned one when `timing` is `Fixed` or no earlier
/// touchdown is allowed.
pub fn remaining_swing(
    swing: &SwingInFlight,
    timing: StepTiming,
    clip: impl Fn(Vector2<f64>) -> Vector2<f64>,
) -> f64 {
    if timing == StepTiming::Fixed || swing.earliest > swing.remaining - TIMING_GRID_S {
        return swing.remaining;
    }
    let clipped_part = |tau: f64| {
        let wished = swing.wished_landing(tau);
        let world_error = clip(wished) - wished;
        match timing {
            StepTiming::Sideways => {
                let sole_error = swing.stance.world_r_sole().inverse() * world_error;
                sole_error.y.abs()
            }
            _ => world_error.norm(),
        }
    };
    let count = ((swing.remaining - swing.earliest) / TIMING_GRID_S).floor() as usize;
    let grid = (0..=count).map(|k| swing.remaining - k as f64 * TIMING_GRID_S);
    let parts: Vec<(f64, f64)> = grid.map(|tau| (tau, clipped_part(tau))).collect();
    let least = parts
        .iter()
        .map(|&(_, part)| part)
        .fold(f64::INFINITY, f64::min);
    parts
        .iter()
        .find(|&&(_, part)| part <= least + TIMING_TOLERANCE_M)
        .map_or(swing.remaining, |&(tau, _)| tau)
}
