//! `[[disturbances]]`: external wrenches on links over time windows (pushes), applied by the
//! plant as generalised forces `J^T w` ([`sea_plant::external`]). Each table names a `link`
//! (a URDF link), a `force` [N] and an optional `torque` [N m], world axes at the link origin,
//! a `start_s` and a `duration_s` [s]. The wrench is constant over its window, and the window
//! must start and end on plant steps (a whole number of steps of the run's plant step, see
//! [`DisturbanceSchedule::new`]), so that the impulse applied is exactly
//! `force * duration_s`.

use crate::error::{Error, Result};
use schemars::JsonSchema;
use sea_dyn::model::Model;
use sea_plant::{ExternalWrench, Workspace};
use serde::Deserialize;

/// Relative tolerance of "a whole number of plant steps" (the rounding of a decimal time).
const STEP_ALIGNMENT_TOLERANCE: f64 = 1e-9;

/// One `[[disturbances]]` table.
#[derive(Clone, Debug, Deserialize, PartialEq, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DisturbanceConfig {
    /// The link it acts on (its origin).
    pub link: String,
    /// Force [N], world axes.
    pub force: [f64; 3],
    /// Moment [N m], world axes (default zero).
    #[serde(default)]
    pub torque: [f64; 3],
    /// Start of the window [s].
    pub start_s: f64,
    /// Length of the window [s].
    pub duration_s: f64,
}

impl DisturbanceConfig {
    /// The impulse of the force over the window [N s].
    pub fn impulse(&self) -> [f64; 3] {
        self.force.map(|f| f * self.duration_s)
    }
}

/// Checks what the file alone decides: finite force and torque, `start_s >= 0`,
/// `duration_s > 0`; errors name `disturbances[i].key`.
pub fn validate(disturbances: &[DisturbanceConfig]) -> Result<()> {
    for (i, d) in disturbances.iter().enumerate() {
        let key = |name: &str| format!("disturbances[{i}].{name}");
        for (name, values) in [("force", d.force), ("torque", d.torque)] {
            if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
                return Err(Error::invalid(key(name), "entries must be finite", bad));
            }
        }
        if !(d.start_s.is_finite() && d.start_s >= 0.0) {
            let rule = "must be finite and non-negative";
            return Err(Error::invalid(key("start_s"), rule, d.start_s));
        }
        if !(d.duration_s.is_finite() && d.duration_s > 0.0) {
            let rule = "must be positive and finite";
            return Err(Error::invalid(key("duration_s"), rule, d.duration_s));
        }
    }
    Ok(())
}

/// The windows of the disturbances in plant steps: the wrench of entry `i` of the workspace's
/// external wrenches acts during the steps `k` with `start_step <= k < end_step`.
#[derive(Clone, Debug, Default)]
pub struct DisturbanceSchedule {
    windows: Vec<(u64, u64)>,
    /// The wrench `[force; torque]` of each disturbance (world axes, at its link origin).
    wrenches: Vec<[f64; 6]>,
    step: f64,
}

/// `time / step` as a whole number of steps, or `None` when `time` is not one (beyond the
/// rounding of a decimal time).
pub fn whole_steps_of(time: f64, step: f64) -> Option<u64> {
    let steps = time / step;
    let whole = steps.round();
    ((steps - whole).abs() <= STEP_ALIGNMENT_TOLERANCE * whole.max(1.0)).then_some(whole as u64)
}

/// `time / step` as a whole number of steps, or an error naming `key`, the rule and `time`.
fn whole_steps(key: String, time: f64, step: f64) -> Result<u64> {
    whole_steps_of(time, step).ok_or_else(|| {
        let rule = format!("must be a whole number of plant steps of {step} s");
        Error::invalid(key, rule, time)
    })
}

impl DisturbanceSchedule {
    /// The schedule of `disturbances` on `model` with plant step `step` [s], and their
    /// wrenches added (inactive) to `ws`. Errors name an unknown link
    /// (`disturbances[i].link`) or a window that does not start or end on a plant step
    /// (`disturbances[i].start_s` / `duration_s`).
    pub fn new(
        disturbances: &[DisturbanceConfig],
        model: &Model,
        step: f64,
        ws: &mut Workspace,
    ) -> Result<DisturbanceSchedule> {
        let mut windows = Vec::with_capacity(disturbances.len());
        let mut wrenches = Vec::with_capacity(disturbances.len());
        for (i, d) in disturbances.iter().enumerate() {
            let key = |name: &str| format!("disturbances[{i}].{name}");
            let frame = model
                .frame_id(&d.link)
                .map_err(|_| Error::invalid(key("link"), "must be a link of the robot", &d.link))?;
            let start = whole_steps(key("start_s"), d.start_s, step)?;
            let end = start + whole_steps(key("duration_s"), d.duration_s, step)?;
            windows.push((start, end));
            let [fx, fy, fz] = d.force;
            let [nx, ny, nz] = d.torque;
            let wrench = [fx, fy, fz, nx, ny, nz];
            wrenches.push(wrench);
            ws.external.push(ExternalWrench {
                frame,
                wrench,
                active: false,
            });
        }
        Ok(DisturbanceSchedule {
            windows,
            wrenches,
            step,
        })
    }

    /// Switches each wrench of `ws` on or off for the plant step that starts at `time_s`;
    /// allocation-free.
    pub fn apply(&self, ws: &mut Workspace, time_s: f64) {
        if self.windows.is_empty() {
            return;
        }
        let k = (time_s / self.step).round() as u64;
        for (external, &(start, end)) in ws.external.iter_mut().zip(&self.windows) {
            external.active = start <= k && k < end;
        }
    }

    /// The number of disturbances.
    pub fn len(&self) -> usize {
        self.windows.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.windows.is_empty()
    }

    /// The wrench of each disturbance during the plant step that starts at `time_s` into
    /// `out` (6 per disturbance, `[[disturbances]]` order: `[force; torque]`, world axes at the
    /// link origin; zero when inactive); allocation-free.
    pub fn wrenches_at(&self, time_s: f64, out: &mut [f64]) {
        out.fill(0.0);
        for i in self.active(time_s) {
            out[6 * i..6 * i + 6].copy_from_slice(&self.wrenches[i]);
        }
    }

    /// The indices (in `[[disturbances]]` order) of the disturbances acting during the plant
    /// step that starts at `time_s`.
    pub fn active(&self, time_s: f64) -> impl Iterator<Item = usize> + '_ {
        let k = if self.step > 0.0 {
            (time_s / self.step).round() as u64
        } else {
            0
        };
        self.windows
            .iter()
            .enumerate()
            .filter(move |(_, &(start, end))| start <= k && k < end)
            .map(|(i, _)| i)
    }
}
