//! Summary statistics of a run, computed online (constant memory whatever the run length),
//! and the run's [`Summary`].

use super::fall_check::Fall;
use super::impacts::{Impact, ImpactKind};
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

/// Time after which the lateral CoM error counts (the reference's smooth start is over) [s].
const LATERAL_ERROR_FROM_S: f64 = 1.0;

/// Running statistics over every evaluated sample (recorded or not).
#[derive(Clone, Debug, Default)]
pub struct RunningStatistics {
    samples: usize,
    com_error_square_sum: f64,
    com_error_max: f64,
    com_error_lateral_max: f64,
    joint_error_last: f64,
    motor_velocity_peak: f64,
}

impl RunningStatistics {
    /// Adds one sample at `time_s`: the CoM error norm `|p_com - p_com_d|` and its lateral
    /// (world y) component [m], `|s - s_d|` [rad] and the motor velocities `thetadot` [rad/s].
    pub fn add(
        &mut self,
        time_s: f64,
        com_error_norm: f64,
        com_error_lateral: f64,
        joint_error_norm: f64,
        thetadot: &[f64],
    ) {
        self.samples += 1;
        self.com_error_square_sum += com_error_norm * com_error_norm;
        self.com_error_max = self.com_error_max.max(com_error_norm);
        if time_s >= LATERAL_ERROR_FROM_S {
            self.com_error_lateral_max = self.com_error_lateral_max.max(com_error_lateral.abs());
        }
        self.joint_error_last = joint_error_norm;
        self.motor_velocity_peak = thetadot
            .iter()
            .fold(self.motor_velocity_peak, |m, v| m.max(v.abs()));
    }

    /// RMS of the CoM error norm [m] (0 before the first sample).
    pub fn com_error_rms(&self) -> f64 {
        (self.com_error_square_sum / self.samples.max(1) as f64).sqrt()
    }
}

/// Why a run diverged: a bound crossed, a non-finite state, or a failure of the controller or
/// the plant. [`std::fmt::Display`] gives the summary's `reason`, [`Divergence::kind`] a
/// stable machine-readable name (the summary JSON's `reason_kind`).
#[derive(Clone, Debug, PartialEq)]
pub enum Divergence {
    /// The CoM error norm crossed `simulation.divergence_com_error_m` (a NaN error counts).
    ComErrorOverBound {
        /// `|p_com - p_com_d|` [m].
        value: f64,
        /// The bound [m].
        bound: f64,
    },
    /// The joint error norm crossed `simulation.divergence_joint_error_rad` (a NaN error
    /// counts).
    JointErrorOverBound {
        /// `|s - s_d|` [rad].
        value: f64,
        /// The bound [rad].
        bound: f64,
    },
    /// With `simulation.stop_at_joint_limits`: a joint left its URDF position limits.
    JointOutsideLimits {
        /// The joint's URDF name.
        joint: String,
        /// Its position [rad or m].
        value: f64,
        /// The limit it crossed [rad or m].
        limit: f64,
    },
    /// A plant step gave a state that is not finite.
    NonFiniteState,
    /// The controller failed at the sample (its error message).
    ControllerFailed(String),
    /// The plant's evaluation at the last sample failed (its error message).
    PlantFailed(String),
    /// A plant step with the input held failed (its error message).
    PlantStepFailed(String),
    /// Continuous sampling: the step with the controller at its stages failed, in the
    /// controller at a later stage or in the plant (the error message).
    StepFailed(String),
}

impl Divergence {
    /// A stable machine-readable name: `"com_error_over_bound"`, `"joint_error_over_bound"`,
    /// `"joint_outside_limits"`, `"non_finite_state"`, `"controller_failed"`,
    /// `"plant_failed"`, `"plant_step_failed"` or `"step_failed"`.
    pub fn kind(&self) -> &'static str {
        match self {
            Divergence::ComErrorOverBound { .. } => "com_error_over_bound",
            Divergence::JointErrorOverBound { .. } => "joint_error_over_bound",
            Divergence::JointOutsideLimits { .. } => "joint_outside_limits",
            Divergence::NonFiniteState => "non_finite_state",
            Divergence::ControllerFailed(_) => "controller_failed",
            Divergence::PlantFailed(_) => "plant_failed",
            Divergence::PlantStepFailed(_) => "plant_step_failed",
            Divergence::StepFailed(_) => "step_failed",
        }
    }
}

impl std::fmt::Display for Divergence {
    /// The quantity, its value and the bound, or the failure: `CoM error 0.0051 m over the
    /// bound 0.005 m`, `joint error norm 1.0312 rad over the bound 1 rad`, `joint l_knee at
    /// -1.9512 beyond its limit -1.9000 (URDF)`, `non-finite state`,
    /// `controller: ...`, `plant: ...`, `plant step: ...`, `step: ...`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Divergence::ComErrorOverBound { value, bound } => {
                write!(f, "CoM error {value:.4} m over the bound {bound} m")
            }
            Divergence::JointErrorOverBound { value, bound } => {
                write!(
                    f,
                    "joint error norm {value:.4} rad over the bound {bound} rad"
                )
            }
            Divergence::JointOutsideLimits {
                joint,
                value,
                limit,
            } => write!(
                f,
                "joint {joint} at {value:.4} beyond its limit {limit:.4} (URDF)"
            ),
            Divergence::NonFiniteState => f.write_str("non-finite state"),
            Divergence::ControllerFailed(error) => write!(f, "controller: {error}"),
            Divergence::PlantFailed(error) => write!(f, "plant: {error}"),
            Divergence::PlantStepFailed(error) => write!(f, "plant step: {error}"),
            Divergence::StepFailed(error) => write!(f, "step: {error}"),
        }
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum RunEnd {
    /// The whole duration was simulated.
    Completed,
    /// A bound was crossed or the controller or the plant failed at `at_s`.
    Diverged {
        /// Time of the sample that diverged [s].
        at_s: f64,
        /// The quantity and its value, or the failure.
        reason: Divergence,
    },
    /// The cancellation flag was raised; the run stopped at the next sample.
    Interrupted,
    /// The robot fell at `at_s`: under bilateral contacts a foot's simulated wrench left what
    /// a unilateral contact with friction can transmit ([`super::contact_check`]), under
    /// unilateral ones the robot reached the ground ([`super::fall_check`]).
    Fell {
        /// Time of the sample [s].
        at_s: f64,
        /// The foot and the violated constraint.
        fall: Fall,
    },
}

impl RunEnd {
    /// `"completed"`, `"diverged"`, `"interrupted"` or `"fell"`.
    pub fn status(&self) -> &'static str {
        match self {
            RunEnd::Completed => "completed",
            RunEnd::Diverged { .. } => "diverged",
            RunEnd::Interrupted => "interrupted",
            RunEnd::Fell { .. } => "fell",
        }
    }

    /// The machine-readable reason: `None` when completed, `"interrupted"`, the
    /// [`Divergence::kind`] or the fall's [`super::ContactConstraint::kind`].
    pub fn reason_kind(&self) -> Option<&'static str> {
        match self {
            RunEnd::Completed => None,
            RunEnd::Diverged { reason, .. } => Some(reason.kind()),
            RunEnd::Interrupted => Some("interrupted"),
            RunEnd::Fell { fall, .. } => Some(fall.kind()),
        }
    }
}

impl std::fmt::Display for RunEnd {
    /// The summary's `reason`: empty when completed, `interrupted`, the divergence's text or
    /// the fall's (`foot l_sole: centre of pressure x = ...`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunEnd::Completed => Ok(()),
            RunEnd::Diverged { reason, .. } => reason.fmt(f),
            RunEnd::Interrupted => f.write_str("interrupted"),
            RunEnd::Fell { fall, .. } => fall.fmt(f),
        }
    }
}

/// The summary of a run: serialised once, by serde, to the summary JSON of `sea-sim` (its keys
/// are the field names, `fall` spread into `fell_at_s`, `fall_foot`, ... and `null` unless the
/// run fell), the Python `RunSummary` (built from the same keys) and the sweep's columns.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// "completed", "diverged", "interrupted" or "fell".
    pub status: String,
    /// Time of divergence [s].
    pub diverged_at_s: Option<f64>,
    /// The fall, when the run fell ([`RunEnd::Fell`]).
    #[serde(flatten, serialize_with = "fall_keys")]
    pub fall: Option<FallSummary>,
    /// Why it diverged (the quantity and its value) or "interrupted"; empty when completed
    /// (the text of [`RunEnd`]).
    pub reason: String,
    /// The reason's machine-readable kind ([`RunEnd::reason_kind`]): `None` when completed.
    pub reason_kind: Option<&'static str>,
    /// Control sampling: "zero_order_hold", "continuous" or "multi_rate".
    pub sampling: String,
    /// Simulated time reached [s].
    pub duration_s: f64,
    /// RMS of the CoM error norm [m].
    pub com_error_rms_m: f64,
    /// Maximum CoM error norm [m].
    pub com_error_max_m: f64,
    /// Maximum lateral (y) CoM error after the first second [m].
    pub com_error_lateral_max_m: f64,
    /// |s - s_d| at the last evaluated sample [rad].
    pub joint_error_norm_final_rad: f64,
    /// Largest |thetadot| [rad/s].
    pub motor_velocity_peak_rad_s: f64,
    /// QP solves that fell back.
    pub qp_failures: usize,
    /// Ticks whose momentum equality was infeasible and that the relaxed momentum task solved
    /// (`controller.momentum_relaxation = "when_infeasible"`).
    pub qp_relaxed_solves: usize,
    /// QP solves done by the active-set solver.
    pub qp_active_set_solves: usize,
    /// QP solves done by Clarabel (selected, or the active set's fallback; the ticks solved
    /// by neither: the minimiser without inequalities was feasible, hence optimal).
    pub qp_clarabel_solves: usize,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
    /// Simulated time / wall time.
    pub realtime_factor: f64,
    /// Unilateral contacts: samples whose delivered wrenches the bilateral contacts' wrench
    /// check would have called a fall (a foot lifted, tipping or slipping: what the proxy
    /// measured); 0 under bilateral contacts, where the check ends the run.
    pub contact_check_violations: usize,
    /// Time of the first such sample [s]; `None` without one.
    pub contact_check_first_s: Option<f64>,
    /// Touchdowns of the feet (unilateral contacts; [`crate::impacts`]): a foot whose points
    /// carried no force at a plant step and carry force at the next.
    pub touchdowns: usize,
    /// Largest velocity jump of a touchdown [m/s]: the foot's normal speed towards the ground
    /// at its touching points over the millisecond before it minus that over the millisecond
    /// ending 5 ms after it ([`crate::impacts`]); `None` without a touchdown.
    pub touchdown_velocity_jump_m_s: Option<f64>,
    /// Largest spring torque `|K_S (Gamma theta - s)|` of an elastic joint over the 50 ms
    /// after a touchdown [Nm]; `None` without a touchdown.
    pub touchdown_peak_spring_torque_nm: Option<f64>,
    /// Largest `|thetadot|` over the 50 ms after a touchdown [rad/s]; `None` without a
    /// touchdown.
    pub touchdown_peak_motor_velocity_rad_s: Option<f64>,
    /// `[walking]`: the planned steps whose touchdown time the run reached; `None` when the
    /// robot does not walk.
    pub steps_taken: Option<usize>,
    /// `[walking]`: the horizontal distance from the feet's mid-point at the start to the
    /// feet's mid-point at the run's end (true state) [m]; `None` when it does not walk.
    pub distance_walked_m: Option<f64>,
    /// `[walking]`: `distance_walked_m` over the time from the first lift-off to the run's
    /// end (the walk's last touchdown when it ended standing) [m/s]; `None` when it does not
    /// walk or no foot lifted.
    pub walking_speed_m_s: Option<f64>,
    /// `[walking]`: the yaw the feet turned, start to end: the mean heading of the soles at
    /// the run's end (true state) minus the walking frame's at the start, counter-clockwise
    /// positive, wrapped into (-pi, pi] [rad]; `None` when it does not walk.
    pub turned_rad: Option<f64>,
    /// Multi-rate sampling: the joint loops' stiffness estimates at the run's end [Nm/rad] by
    /// elastic joint name (identified with `controller.stiffness_identification`, else the
    /// controller's); empty otherwise. Not a sweep column ([`NON_SCALAR_FIELDS`]).
    #[serde(rename = "stiffness_estimates_nm_per_rad", serialize_with = "by_name")]
    pub stiffness_estimates: Vec<(String, f64)>,
}

/// Writes `fall`'s keys, each `null` when the run did not fall (the JSON has the same keys
/// whatever the outcome).
fn fall_keys<S: Serializer>(fall: &Option<FallSummary>, serializer: S) -> Result<S::Ok, S::Error> {
    if let Some(fall) = fall {
        return fall.serialize(serializer);
    }
    let keys = match serde_json::to_value(FallSummary::default()) {
        Ok(serde_json::Value::Object(keys)) => keys,
        _ => serde_json::Map::new(),
    };
    let mut map = serializer.serialize_map(Some(keys.len()))?;
    for key in keys.keys() {
        map.serialize_entry(key, &())?;
    }
    map.end()
}

/// Writes `(name, value)` pairs as a map by name.
fn by_name<S: Serializer>(pairs: &[(String, f64)], serializer: S) -> Result<S::Ok, S::Error> {
    serializer.collect_map(pairs.iter().map(|(name, value)| (name, value)))
}

/// The summary's JSON keys that are not one number or text each, left out of the sweep
/// tables' columns.
pub const NON_SCALAR_FIELDS: [&str; 1] = ["stiffness_estimates_nm_per_rad"];

/// A fall in the summary: when, which foot, which constraint with its value and bound (the
/// summary JSON's keys `fell_at_s`, `fall_foot`, `fall_constraint`, `fall_value`,
/// `fall_bound`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FallSummary {
    /// Time of the sample [s].
    #[serde(rename = "fell_at_s")]
    pub at_s: f64,
    /// The contact frame's name (a foot's wrench fell, bilateral contacts), else empty.
    #[serde(rename = "fall_foot")]
    pub foot: String,
    /// The link that reached the ground (`"link_on_ground"`), else empty.
    #[serde(rename = "fall_link")]
    pub link: String,
    /// `"normal_force"`, `"friction"` or `"center_of_pressure"` (a foot's wrench, bilateral
    /// contacts); `"base_height"`, `"tilt"` or `"link_on_ground"` (unilateral contacts).
    #[serde(rename = "fall_constraint")]
    pub constraint: &'static str,
    /// The violating value (N, friction ratio or CoP coordinate [m]).
    #[serde(rename = "fall_value")]
    pub value: f64,
    /// The bound it crossed.
    #[serde(rename = "fall_bound")]
    pub bound: f64,
}

/// Counters and timing of a run that the statistics do not hold (zero by default).
#[derive(Clone, Copy, Debug, Default)]
pub struct RunTotals {
    /// Simulated time reached [s].
    pub duration_s: f64,
    /// QP solves that fell back.
    pub qp_failures: usize,
    /// Ticks whose momentum equality was infeasible and that the relaxed momentum task solved
    /// (`controller.momentum_relaxation = "when_infeasible"`).
    pub qp_relaxed_solves: usize,
    /// QP solves done by the active-set solver.
    pub qp_active_set_solves: usize,
    /// QP solves done by Clarabel.
    pub qp_clarabel_solves: usize,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
}

impl Summary {
    /// Whether the run reached its duration ([`RunEnd::Completed`]): the test of a recovered
    /// push, a stable sample and a usable benchmark run.
    pub fn completed(&self) -> bool {
        self.status == RunEnd::Completed.status()
    }

    /// Whether the run was stopped by its cancellation flag ([`RunEnd::Interrupted`]): it
    /// says nothing about the closed loop.
    pub fn interrupted(&self) -> bool {
        self.status == RunEnd::Interrupted.status()
    }

    /// The summary of a run that ended with `end`.
    pub fn new(
        end: &RunEnd,
        sampling: &str,
        statistics: &RunningStatistics,
        totals: RunTotals,
    ) -> Summary {
        let diverged_at_s = match end {
            RunEnd::Diverged { at_s, .. } => Some(*at_s),
            RunEnd::Completed | RunEnd::Interrupted | RunEnd::Fell { .. } => None,
        };
        let fall = match end {
            RunEnd::Fell { at_s, fall } => Some(FallSummary {
                at_s: *at_s,
                foot: fall.foot().to_string(),
                link: fall.link().to_string(),
                constraint: fall.kind(),
                value: fall.value(),
                bound: fall.bound(),
            }),
            _ => None,
        };
        let wall = totals.wall_time_s;
        Summary {
            status: end.status().to_string(),
            diverged_at_s,
            fall,
            reason: end.to_string(),
            reason_kind: end.reason_kind(),
            sampling: sampling.to_string(),
            duration_s: totals.duration_s,
            com_error_rms_m: statistics.com_error_rms(),
            com_error_max_m: statistics.com_error_max,
            com_error_lateral_max_m: statistics.com_error_lateral_max,
            joint_error_norm_final_rad: statistics.joint_error_last,
            motor_velocity_peak_rad_s: statistics.motor_velocity_peak,
            qp_failures: totals.qp_failures,
            qp_relaxed_solves: totals.qp_relaxed_solves,
            qp_active_set_solves: totals.qp_active_set_solves,
            qp_clarabel_solves: totals.qp_clarabel_solves,
            wall_time_s: wall,
            realtime_factor: if wall > 0.0 {
                totals.duration_s / wall
            } else {
                0.0
            },
            stiffness_estimates: Vec::new(),
            contact_check_violations: 0,
            contact_check_first_s: None,
            touchdowns: 0,
            touchdown_velocity_jump_m_s: None,
            touchdown_peak_spring_torque_nm: None,
            touchdown_peak_motor_velocity_rad_s: None,
            steps_taken: None,
            distance_walked_m: None,
            walking_speed_m_s: None,
            turned_rad: None,
        }
    }

    /// Counts the touchdowns among `impacts` and keeps their largest figures (a NaN figure,
    /// from a window closed at once, is skipped).
    pub fn add_impacts(&mut self, impacts: &[Impact]) {
        let larger = |kept: Option<f64>, value: f64| match kept {
            _ if value.is_nan() => kept,
            Some(kept) => Some(kept.max(value)),
            None => Some(value),
        };
        let touchdowns = impacts.iter().filter(|i| i.kind == ImpactKind::Touchdown);
        for impact in touchdowns {
            self.touchdowns += 1;
            self.touchdown_velocity_jump_m_s =
                larger(self.touchdown_velocity_jump_m_s, impact.velocity_jump());
            self.touchdown_peak_spring_torque_nm = larger(
                self.touchdown_peak_spring_torque_nm,
                impact.peak_spring_torque_after_nm,
            );
            self.touchdown_peak_motor_velocity_rad_s = larger(
                self.touchdown_peak_motor_velocity_rad_s,
                impact.peak_motor_velocity_after_rad_s,
            );
        }
    }

    /// As JSON (serde: the keys are the fields' serde names).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("a summary is plain numbers and text")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_statistics_match_the_batch_formulas() {
        // (CoM error norm, lateral error) at 0.5 s, 1 s and 1.5 s.
        let errors = [(0.005, -0.004), (0.002, 0.002), (0.01, 0.0)];
        let times = [0.5, 1.0, 1.5];
        let mut statistics = RunningStatistics::default();
        for (k, ((norm, lateral), time)) in errors.iter().zip(times).enumerate() {
            statistics.add(time, *norm, *lateral, k as f64, &[-3.0 * k as f64, 1.0]);
        }
        let norms = [0.005, 0.002, 0.01];
        let rms = (norms.iter().map(|e| e * e).sum::<f64>() / 3.0).sqrt();
        assert!((statistics.com_error_rms() - rms).abs() < 1e-15);
        assert_eq!(statistics.com_error_max, 0.01);
        // The lateral error before the first second (0.004) does not count.
        assert_eq!(statistics.com_error_lateral_max, 0.002);
        assert_eq!(statistics.joint_error_last, 2.0);
        assert_eq!(statistics.motor_velocity_peak, 6.0);
    }

    #[test]
    fn reasons_read_as_the_summary_texts_with_stable_kinds() {
        let cases = [
            (
                Divergence::ComErrorOverBound {
                    value: 0.00512345,
                    bound: 0.005,
                },
                "CoM error 0.0051 m over the bound 0.005 m",
                "com_error_over_bound",
            ),
            (
                Divergence::JointErrorOverBound {
                    value: 1.03121,
                    bound: 1.0,
                },
                "joint error norm 1.0312 rad over the bound 1 rad",
                "joint_error_over_bound",
            ),
            (
                Divergence::JointOutsideLimits {
                    joint: "torso_pitch".into(),
                    value: -0.34951,
                    limit: -0.3490658503988659,
                },
                "joint torso_pitch at -0.3495 beyond its limit -0.3491 (URDF)",
                "joint_outside_limits",
            ),
            (
                Divergence::NonFiniteState,
                "non-finite state",
                "non_finite_state",
            ),
            (
                Divergence::ControllerFailed("x has 3 entries".into()),
                "controller: x has 3 entries",
                "controller_failed",
            ),
            (
                Divergence::PlantFailed("e".into()),
                "plant: e",
                "plant_failed",
            ),
            (
                Divergence::PlantStepFailed("e".into()),
                "plant step: e",
                "plant_step_failed",
            ),
            (Divergence::StepFailed("e".into()), "step: e", "step_failed"),
        ];
        for (reason, text, kind) in cases {
            assert_eq!(reason.to_string(), text);
            assert_eq!(reason.kind(), kind);
            let end = RunEnd::Diverged { at_s: 0.5, reason };
            assert_eq!(end.to_string(), text);
            assert_eq!(end.reason_kind(), Some(kind));
        }
        assert_eq!(RunEnd::Completed.to_string(), "");
        assert_eq!(RunEnd::Completed.reason_kind(), None);
        assert_eq!(RunEnd::Interrupted.to_string(), "interrupted");
        assert_eq!(RunEnd::Interrupted.reason_kind(), Some("interrupted"));
    }
}
