//! Summary statistics of a run, computed online (constant memory whatever the run length),
//! and the run's [`Summary`].

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
        reason: String,
    },
    /// The cancellation flag was raised; the run stopped at the next sample.
    Interrupted,
}

impl RunEnd {
    /// `"completed"`, `"diverged"` or `"interrupted"`.
    pub fn status(&self) -> &'static str {
        match self {
            RunEnd::Completed => "completed",
            RunEnd::Diverged { .. } => "diverged",
            RunEnd::Interrupted => "interrupted",
        }
    }
}

/// The summary of a run (also written as JSON by `sea-sim`).
#[derive(Clone, Debug)]
pub struct Summary {
    /// "completed", "diverged" or "interrupted".
    pub status: String,
    /// Time of divergence [s].
    pub diverged_at_s: Option<f64>,
    /// Why it diverged (the quantity and its value) or "interrupted"; empty when completed.
    pub reason: String,
    /// Control sampling: "zero_order_hold" or "continuous".
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
    /// QP solves done by the active-set solver.
    pub qp_active_set_solves: usize,
    /// QP solves done by Clarabel (selected, or the active set's fallback; the ticks solved
    /// by neither: the minimiser without inequalities was feasible, hence optimal).
    pub qp_clarabel_solves: usize,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
    /// Simulated time / wall time.
    pub realtime_factor: f64,
}

/// Counters and timing of a run that the statistics do not hold.
#[derive(Clone, Copy, Debug)]
pub struct RunTotals {
    /// Simulated time reached [s].
    pub duration_s: f64,
    /// QP solves that fell back.
    pub qp_failures: usize,
    /// QP solves done by the active-set solver.
    pub qp_active_set_solves: usize,
    /// QP solves done by Clarabel.
    pub qp_clarabel_solves: usize,
    /// Wall-clock time [s].
    pub wall_time_s: f64,
}

impl Summary {
    /// The summary of a run that ended with `end`.
    pub fn new(
        end: &RunEnd,
        sampling: &str,
        statistics: &RunningStatistics,
        totals: RunTotals,
    ) -> Summary {
        let (diverged_at_s, reason) = match end {
            RunEnd::Completed => (None, String::new()),
            RunEnd::Diverged { at_s, reason } => (Some(*at_s), reason.clone()),
            RunEnd::Interrupted => (None, "interrupted".to_string()),
        };
        let wall = totals.wall_time_s;
        Summary {
            status: end.status().to_string(),
            diverged_at_s,
            reason,
            sampling: sampling.to_string(),
            duration_s: totals.duration_s,
            com_error_rms_m: statistics.com_error_rms(),
            com_error_max_m: statistics.com_error_max,
            com_error_lateral_max_m: statistics.com_error_lateral_max,
            joint_error_norm_final_rad: statistics.joint_error_last,
            motor_velocity_peak_rad_s: statistics.motor_velocity_peak,
            qp_failures: totals.qp_failures,
            qp_active_set_solves: totals.qp_active_set_solves,
            qp_clarabel_solves: totals.qp_clarabel_solves,
            wall_time_s: wall,
            realtime_factor: if wall > 0.0 {
                totals.duration_s / wall
            } else {
                0.0
            },
        }
    }

    /// As JSON.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "status": self.status,
            "diverged_at_s": self.diverged_at_s,
            "reason": self.reason,
            "sampling": self.sampling,
            "duration_s": self.duration_s,
            "com_error_rms_m": self.com_error_rms_m,
            "com_error_max_m": self.com_error_max_m,
            "com_error_lateral_max_m": self.com_error_lateral_max_m,
            "joint_error_norm_final_rad": self.joint_error_norm_final_rad,
            "motor_velocity_peak_rad_s": self.motor_velocity_peak_rad_s,
            "qp_failures": self.qp_failures,
            "qp_active_set_solves": self.qp_active_set_solves,
            "qp_clarabel_solves": self.qp_clarabel_solves,
            "wall_time_s": self.wall_time_s,
            "realtime_factor": self.realtime_factor,
        })
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
}
