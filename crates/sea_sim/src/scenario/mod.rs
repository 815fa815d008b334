//! Scenario files (TOML): robot, actuators, plant, controller, references, simulation.
//!
//! Every table rejects unknown keys, and `--set key=value` overrides are applied to the parsed
//! TOML tree before it is checked, so a typo in a file or an override is an error naming the
//! key. Defaults come from REFERENCE.md (the paper and the original study); relative paths are
//! resolved against the scenario file's folder, then the working directory.

pub mod build;

pub use build::{build, Setup};

use crate::error::{Error, Result};
use sea_ctrl::controller::{ControllerKind, ControllerSettings};
use sea_ctrl::qp::ContactConstraints;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The 25 iCub joints of the paper, in REFERENCE.md's order.
pub const ICUB25_JOINTS: [&str; 25] = [
    "torso_pitch",
    "torso_roll",
    "torso_yaw",
    "l_shoulder_pitch",
    "l_shoulder_roll",
    "l_shoulder_yaw",
    "l_elbow",
    "l_wrist_prosup",
    "r_shoulder_pitch",
    "r_shoulder_roll",
    "r_shoulder_yaw",
    "r_elbow",
    "r_wrist_prosup",
    "l_hip_pitch",
    "l_hip_roll",
    "l_hip_yaw",
    "l_knee",
    "l_ankle_pitch",
    "l_ankle_roll",
    "r_hip_pitch",
    "r_hip_roll",
    "r_hip_yaw",
    "r_knee",
    "r_ankle_pitch",
    "r_ankle_roll",
];

/// Left-foot stance initial joints of the original study [rad], REFERENCE.md order.
pub const ICUB_LEFT_STANCE: [f64; 25] = [
    0.0462, -0.5256, -0.0269, 0.1874, 1.6258, 0.2462, 0.3053, -0.0948, -0.3553, 1.8546, 0.7323,
    0.3905, -0.1169, 0.1047, 0.2547, 0.0378, 0.0732, 0.0958, 0.1637, 0.2923, 0.8611, 1.2866,
    -1.7688, 0.4568, -0.0163,
];

/// Two-feet initial joints of the original study [deg], REFERENCE.md order.
pub const ICUB_TWO_FEET_DEG: [f64; 25] = [
    -10.0, 0.0, 0.0, -20.0, 30.0, 0.0, 45.0, 0.0, -20.0, 30.0, 0.0, 45.0, 0.0, 25.5, 0.0, 0.0,
    -18.5, -5.5, 0.0, 25.5, 0.0, 0.0, -18.5, -5.5, 0.0,
];

/// `[robot]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotConfig {
    /// URDF path.
    pub urdf: String,
    /// Moving joints (default: the paper's 25 iCub joints).
    #[serde(default)]
    pub joints: Option<Vec<String>>,
    /// Contact frames, stance foot first.
    #[serde(default = "default_contacts")]
    pub contacts: Vec<String>,
    /// "left_stance", "two_feet" (the original study's postures) or explicit radians.
    #[serde(default = "default_posture")]
    pub initial_posture: toml::Value,
}

fn default_contacts() -> Vec<String> {
    vec!["l_sole".into()]
}
fn default_posture() -> toml::Value {
    toml::Value::String("left_stance".into())
}

/// Parameters of an elastic actuator (defaults: the paper's iCub SEA).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorConfig {
    /// "elastic" or "rigid".
    #[serde(default = "default_actuator_kind")]
    pub kind: String,
    /// Transmission ratio eta.
    #[serde(default = "default_ratio")]
    pub ratio: f64,
    /// Motor inertia [kg m^2].
    #[serde(default = "default_motor_inertia")]
    pub motor_inertia: f64,
    /// Stiffness [Nm/rad].
    #[serde(default = "default_stiffness")]
    pub stiffness: f64,
    /// Damping [Nms/rad] (paper 0.25; the original code used 1).
    #[serde(default = "default_damping")]
    pub damping: f64,
    /// Motor torque limit [Nm].
    #[serde(default)]
    pub torque_limit: Option<f64>,
}

fn default_actuator_kind() -> String {
    "elastic".into()
}
fn default_ratio() -> f64 {
    0.01
}
fn default_motor_inertia() -> f64 {
    1e-5
}
fn default_stiffness() -> f64 {
    350.0
}
fn default_damping() -> f64 {
    0.25
}

/// `[actuators]`: the default actuator of every joint (same keys as [`ActuatorConfig`]) plus
/// per-joint overrides (`[actuators.overrides.NAME]`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorsConfig {
    /// "elastic" or "rigid".
    #[serde(default = "default_actuator_kind")]
    pub kind: String,
    /// Transmission ratio eta.
    #[serde(default = "default_ratio")]
    pub ratio: f64,
    /// Motor inertia [kg m^2].
    #[serde(default = "default_motor_inertia")]
    pub motor_inertia: f64,
    /// Stiffness [Nm/rad].
    #[serde(default = "default_stiffness")]
    pub stiffness: f64,
    /// Damping [Nms/rad].
    #[serde(default = "default_damping")]
    pub damping: f64,
    /// Motor torque limit [Nm].
    #[serde(default)]
    pub torque_limit: Option<f64>,
    /// Per-joint overrides, by joint name; unset keys keep the default actuator's values.
    #[serde(default)]
    pub overrides: BTreeMap<String, ActuatorOverride>,
}

/// `[actuators.overrides.NAME]`: any subset of the actuator keys.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ActuatorOverride {
    /// "elastic" or "rigid".
    pub kind: Option<String>,
    /// Transmission ratio.
    pub ratio: Option<f64>,
    /// Motor inertia [kg m^2].
    pub motor_inertia: Option<f64>,
    /// Stiffness [Nm/rad].
    pub stiffness: Option<f64>,
    /// Damping [Nms/rad].
    pub damping: Option<f64>,
    /// Motor torque limit [Nm].
    pub torque_limit: Option<f64>,
}

impl ActuatorsConfig {
    /// The actuator of a joint with override `o`.
    pub fn overridden(&self, o: &ActuatorOverride) -> ActuatorConfig {
        let d = self.default_actuator();
        ActuatorConfig {
            kind: o.kind.clone().unwrap_or(d.kind),
            ratio: o.ratio.unwrap_or(d.ratio),
            motor_inertia: o.motor_inertia.unwrap_or(d.motor_inertia),
            stiffness: o.stiffness.unwrap_or(d.stiffness),
            damping: o.damping.unwrap_or(d.damping),
            torque_limit: o.torque_limit.or(d.torque_limit),
        }
    }

    /// The default actuator.
    pub fn default_actuator(&self) -> ActuatorConfig {
        ActuatorConfig {
            kind: self.kind.clone(),
            ratio: self.ratio,
            motor_inertia: self.motor_inertia,
            stiffness: self.stiffness,
            damping: self.damping,
            torque_limit: self.torque_limit,
        }
    }
}

/// `[plant]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlantConfig {
    /// Baumgarte position gain [1/s^2] (REFERENCE.md: 50).
    #[serde(default = "default_kp")]
    pub baumgarte_kp: f64,
    /// Baumgarte velocity gain [1/s] (default 2 sqrt(kp)).
    #[serde(default)]
    pub baumgarte_kd: Option<f64>,
    /// Motor velocity loop gain K_m [1/s] (REFERENCE.md: 200).
    #[serde(default = "default_km")]
    pub motor_velocity_gain: f64,
    /// Added to the plant's joint inertia diagonal [kg m^2] (REFERENCE.md: the original study
    /// regularised the joint block of M by 0.1 I in plant and controller; without it the light
    /// wrists turn tiny torque errors into large accelerations).
    #[serde(default = "default_regularization")]
    pub joint_inertia_regularization: f64,
    /// Integration step [s].
    #[serde(default = "default_dt")]
    pub dt: f64,
    /// "ros2", "implicit_euler" or "rk4".
    #[serde(default = "default_method")]
    pub method: String,
}

fn default_regularization() -> f64 {
    0.1
}
fn default_kp() -> f64 {
    50.0
}
fn default_km() -> f64 {
    200.0
}
fn default_dt() -> f64 {
    1e-3
}
fn default_method() -> String {
    "ros2".into()
}

/// `[controller]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControllerConfig {
    /// "sea" or "rigid".
    #[serde(default = "default_controller_kind")]
    pub kind: String,
    /// Control rate [Hz] (zero-order hold between ticks).
    #[serde(default = "default_rate")]
    pub rate_hz: f64,
    /// Controller damping estimate = true damping x scale.
    #[serde(default = "one")]
    pub damping_estimate_scale: f64,
    /// Controller stiffness estimate = true stiffness x scale.
    #[serde(default = "one")]
    pub stiffness_estimate_scale: f64,
    /// Momentum integral gains (linear xyz, angular xyz).
    #[serde(default)]
    pub momentum_integral: Option<[f64; 6]>,
    /// Momentum proportional gains (default 2 sqrt(integral)).
    #[serde(default)]
    pub momentum_proportional: Option<[f64; 6]>,
    /// Postural stiffness per joint before `postural_scale` (default: REFERENCE.md by group).
    #[serde(default)]
    pub postural_stiffness: Option<Vec<f64>>,
    /// Scale of the postural stiffness (REFERENCE.md: 1/5).
    #[serde(default = "default_postural_scale")]
    pub postural_scale: f64,
    /// Pseudo-inverse damping.
    #[serde(default = "default_pinv")]
    pub pinv_damping: f64,
    /// QP Hessian regulariser.
    #[serde(default = "default_reg")]
    pub qp_regularization: f64,
    /// Skip Clarabel when the QP's minimiser without inequalities satisfies them (it is then
    /// the optimum); `false` runs Clarabel every tick.
    #[serde(default = "yes")]
    pub qp_unconstrained_first: bool,
    /// Rigid controller: include the motor reflected inertia (Remark 1).
    #[serde(default = "yes")]
    pub reflected_inertia: bool,
    /// Added to the controller model's joint inertia diagonal [kg m^2] (REFERENCE.md: 0.1).
    #[serde(default = "default_regularization")]
    pub joint_inertia_regularization: f64,
    /// Contact constraints.
    #[serde(default)]
    pub contact: ContactConfig,
}

fn default_controller_kind() -> String {
    "sea".into()
}
fn default_rate() -> f64 {
    1000.0
}
fn one() -> f64 {
    1.0
}
fn yes() -> bool {
    true
}
fn default_postural_scale() -> f64 {
    0.2
}
fn default_pinv() -> f64 {
    5e-4
}
fn default_reg() -> f64 {
    1e-3
}

/// `[controller.contact]` (REFERENCE.md defaults).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactConfig {
    /// Friction coefficient.
    #[serde(default = "one")]
    pub friction: f64,
    /// Friction cone facets.
    #[serde(default = "default_facets")]
    pub facets: usize,
    /// Torsional friction coefficient.
    #[serde(default = "default_torsional")]
    pub torsional_friction: f64,
    /// Minimum normal force [N].
    #[serde(default = "default_min_normal")]
    pub min_normal_force: f64,
    /// Foot rectangle x [m].
    #[serde(default = "default_foot_x")]
    pub foot_x: [f64; 2],
    /// Foot rectangle y [m].
    #[serde(default = "default_foot_y")]
    pub foot_y: [f64; 2],
}

impl Default for ContactConfig {
    fn default() -> Self {
        toml::from_str("").expect("defaults")
    }
}

fn default_facets() -> usize {
    12
}
fn default_torsional() -> f64 {
    2.0 / 150.0
}
fn default_min_normal() -> f64 {
    10.0
}
fn default_foot_x() -> [f64; 2] {
    [-0.05, 0.10]
}
fn default_foot_y() -> [f64; 2] {
    [-0.025, 0.025]
}

/// `[reference]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceConfig {
    /// CoM sinusoid amplitude [m].
    #[serde(default)]
    pub com_amplitude: f64,
    /// CoM sinusoid frequency [Hz].
    #[serde(default)]
    pub com_frequency: f64,
    /// CoM sinusoid direction (world).
    #[serde(default = "default_direction")]
    pub com_direction: [f64; 3],
    /// Smooth-start time constant [s].
    #[serde(default = "one")]
    pub com_smooth_start: f64,
    /// "stance_sole": CoM x, y above the stance sole origin (z initial); "initial": initial CoM.
    #[serde(default = "default_com_origin")]
    pub com_origin: String,
    /// Postural step [deg].
    #[serde(default)]
    pub posture_step_deg: f64,
    /// Joints (or groups "torso", "arms", "left_arm", "right_arm") that get the step.
    #[serde(default)]
    pub posture_step_joints: Vec<String>,
    /// Time of the step [s].
    #[serde(default)]
    pub posture_step_time: f64,
}

fn default_direction() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}
fn default_com_origin() -> String {
    "stance_sole".into()
}

/// `[simulation]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationConfig {
    /// Simulated time [s].
    #[serde(default = "default_duration")]
    pub duration_s: f64,
    /// Record (and log) every this many control ticks.
    #[serde(default = "default_record")]
    pub record_every: usize,
    /// The run is diverged when the CoM error exceeds this [m].
    #[serde(default = "default_bound")]
    pub divergence_com_error_m: f64,
    /// The run is diverged when the joint error norm exceeds this [rad].
    #[serde(default = "default_joint_bound")]
    pub divergence_joint_error_rad: f64,
}

fn default_duration() -> f64 {
    10.0
}
fn default_record() -> usize {
    10
}
fn default_bound() -> f64 {
    0.1
}
fn default_joint_bound() -> f64 {
    1.0
}

/// A whole scenario.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Free text.
    #[serde(default)]
    pub name: String,
    /// `[robot]`.
    pub robot: RobotConfig,
    /// `[actuators]`.
    #[serde(default = "default_actuators")]
    pub actuators: ActuatorsConfig,
    /// `[plant]`.
    #[serde(default = "default_plant")]
    pub plant: PlantConfig,
    /// `[controller]`.
    #[serde(default = "default_controller")]
    pub controller: ControllerConfig,
    /// `[reference]`.
    #[serde(default = "default_reference")]
    pub reference: ReferenceConfig,
    /// `[simulation]`.
    #[serde(default = "default_simulation")]
    pub simulation: SimulationConfig,
    /// Folder of the scenario file (for relative paths).
    #[serde(skip)]
    pub base_dir: PathBuf,
}

fn default_actuators() -> ActuatorsConfig {
    toml::from_str("").expect("defaults")
}
fn default_plant() -> PlantConfig {
    toml::from_str("").expect("defaults")
}
fn default_controller() -> ControllerConfig {
    toml::from_str("").expect("defaults")
}
fn default_reference() -> ReferenceConfig {
    toml::from_str("").expect("defaults")
}
fn default_simulation() -> SimulationConfig {
    toml::from_str("").expect("defaults")
}

/// Parses `value` of an override as TOML (number, bool, array, quoted string), else as a bare
/// string.
fn override_value(value: &str) -> toml::Value {
    let wrapped = format!("v = {value}");
    match toml::from_str::<toml::Table>(&wrapped) {
        Ok(mut table) => table
            .remove("v")
            .unwrap_or(toml::Value::String(value.into())),
        Err(_) => toml::Value::String(value.into()),
    }
}

/// Applies `key.path=value` to a TOML tree, creating tables as needed.
pub fn apply_override(root: &mut toml::Table, key: &str, value: &str) -> Result<()> {
    let parts: Vec<&str> = key.split('.').collect();
    if parts.iter().any(|p| p.is_empty()) {
        return Err(Error::config(key, "malformed override key"));
    }
    let mut table = root;
    for part in &parts[..parts.len() - 1] {
        let entry = table
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        table = entry
            .as_table_mut()
            .ok_or_else(|| Error::config(key, format!("'{part}' is not a table")))?;
    }
    table.insert(parts[parts.len() - 1].to_string(), override_value(value));
    Ok(())
}

/// A schema (serde) error naming the dotted key it is about. `toml` appends the path of the
/// value (`in `controller.postural_scale``); for an unknown or missing field the path is its
/// table and the field is named in the message, so the key is `table.field`.
fn schema_error(error: &toml::de::Error) -> Error {
    let text = error.to_string();
    let text = text.trim();
    let (rule, path) = match text.rsplit_once("\nin `") {
        Some((rule, path)) => (rule.trim(), path.trim_end_matches('`')),
        None => (text, ""),
    };
    let field = ["unknown field `", "missing field `"]
        .iter()
        .find_map(|prefix| rule.strip_prefix(prefix))
        .and_then(|rest| rest.split('`').next());
    let key = match (path, field) {
        ("", Some(field)) => field.to_string(),
        (path, Some(field)) => format!("{path}.{field}"),
        ("", None) => "scenario".to_string(),
        (path, None) => path.to_string(),
    };
    Error::config(key, rule)
}

/// A TOML syntax error with the line and column of its span in `text`.
fn syntax_error(error: &toml::de::Error, text: &str) -> Error {
    let (line, column) = match error.span() {
        Some(span) => {
            let (line, column) = sea_dyn::error::line_column(text, span.start);
            (Some(line), Some(column))
        }
        None => (None, None),
    };
    Error::Parse {
        file: None,
        line,
        column,
        message: format!("malformed TOML: {}", error.message().trim()),
    }
}

impl Scenario {
    /// Parses TOML text with `overrides` (`key=value`).
    pub fn from_toml(
        text: &str,
        overrides: &[(String, String)],
        base_dir: &Path,
    ) -> Result<Scenario> {
        let mut root: toml::Table = toml::from_str(text).map_err(|e| syntax_error(&e, text))?;
        for (key, value) in overrides {
            apply_override(&mut root, key, value)?;
        }
        let mut scenario: Scenario =
            toml::Value::Table(root)
                .try_into()
                .map_err(|e: toml::de::Error| schema_error(&e))?;
        scenario.base_dir = base_dir.to_path_buf();
        scenario.validate()?;
        Ok(scenario)
    }

    /// Reads a scenario file with overrides.
    pub fn from_file(path: &Path, overrides: &[(String, String)]) -> Result<Scenario> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::io(path, source))?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::from_toml(&text, overrides, base).map_err(|e| e.in_file(path))
    }

    /// Resolves a path of the scenario: relative to its folder if it exists there, else as is.
    pub fn resolve(&self, path: &str) -> PathBuf {
        let candidate = self.base_dir.join(path);
        if candidate.exists() {
            candidate
        } else {
            PathBuf::from(path)
        }
    }

    fn validate(&self) -> Result<()> {
        let positive = [
            ("plant.dt", self.plant.dt),
            ("controller.rate_hz", self.controller.rate_hz),
            ("simulation.duration_s", self.simulation.duration_s),
            ("plant.motor_velocity_gain", self.plant.motor_velocity_gain),
            (
                "controller.damping_estimate_scale",
                self.controller.damping_estimate_scale,
            ),
            (
                "controller.stiffness_estimate_scale",
                self.controller.stiffness_estimate_scale,
            ),
            (
                "simulation.divergence_com_error_m",
                self.simulation.divergence_com_error_m,
            ),
        ];
        for (key, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::invalid(key, "must be positive and finite", value));
            }
        }
        if !matches!(self.controller.kind.as_str(), "sea" | "rigid") {
            return Err(Error::config(
                "controller.kind",
                format!(
                    "expected \"sea\" or \"rigid\", got \"{}\"",
                    self.controller.kind
                ),
            ));
        }
        sea_plant::Method::parse(&self.plant.method)
            .map_err(|e| Error::config("plant.method", e.to_string()))?;
        for (key, gains) in [
            ("controller.momentum_integral", self.controller.momentum_integral),
            ("controller.momentum_proportional", self.controller.momentum_proportional),
        ] {
            if let Some(g) = gains.iter().flatten().find(|g| !(g.is_finite() && **g >= 0.0)) {
                return Err(Error::invalid(key, "gains must be finite and non-negative", g));
            }
        }
        let scale = self.controller.postural_scale;
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(Error::invalid(
                "controller.postural_scale",
                "must be finite and non-negative",
                scale,
            ));
        }
        let steps_per_tick = 1.0 / (self.controller.rate_hz * self.plant.dt);
        if (steps_per_tick - steps_per_tick.round()).abs() > 1e-9 || steps_per_tick.round() < 1.0 {
            return Err(Error::config(
                "plant.dt",
                "the control period must be a whole number of plant steps",
            ));
        }
        if self.robot.contacts.is_empty() || self.robot.contacts.len() > 2 {
            return Err(Error::config("robot.contacts", "one or two contact frames"));
        }
        Ok(())
    }

    /// Controller kind.
    pub fn controller_kind(&self) -> ControllerKind {
        if self.controller.kind == "rigid" {
            ControllerKind::Rigid
        } else {
            ControllerKind::Sea
        }
    }

    /// Contact constraints of the QP.
    pub fn contact_constraints(&self) -> ContactConstraints {
        let c = &self.controller.contact;
        ContactConstraints {
            friction: c.friction,
            facets: c.facets,
            torsional_friction: c.torsional_friction,
            min_normal_force: c.min_normal_force,
            foot_x: c.foot_x,
            foot_y: c.foot_y,
        }
    }

    /// Controller settings for a model with `joint_names`.
    pub fn controller_settings(&self, joint_names: &[String]) -> Result<ControllerSettings> {
        let one_foot = self.robot.contacts.len() == 1;
        let integral = self.controller.momentum_integral.unwrap_or(if one_foot {
            [6.0, 7.0, 6.0, 0.5, 1.0, 0.5]
        } else {
            [40.0, 45.0, 40.0, 1.0, 5.0, 1.0]
        });
        let proportional = self
            .controller
            .momentum_proportional
            .unwrap_or(integral.map(|k| 2.0 * k.sqrt()));
        let stiffness: Vec<f64> = match &self.controller.postural_stiffness {
            Some(values) if values.len() == joint_names.len() => values.clone(),
            Some(values) => {
                return Err(Error::config(
                    "controller.postural_stiffness",
                    format!("needs {} entries, got {}", joint_names.len(), values.len()),
                ))
            }
            None => joint_names
                .iter()
                .map(|name| default_postural_stiffness(name, &self.robot.contacts))
                .collect(),
        }
        .into_iter()
        .map(|k| k * self.controller.postural_scale)
        .collect();
        let damping = stiffness.iter().map(|k: &f64| 2.0 * k.sqrt()).collect();
        Ok(ControllerSettings {
            kind: self.controller_kind(),
            contacts: self.robot.contacts.clone(),
            momentum_proportional: proportional,
            momentum_integral: integral,
            postural_stiffness: stiffness,
            postural_damping: damping,
            constraints: self.contact_constraints(),
            damping_estimate_scale: self.controller.damping_estimate_scale,
            stiffness_estimate_scale: self.controller.stiffness_estimate_scale,
            pinv_damping: self.controller.pinv_damping,
            qp_regularization: self.controller.qp_regularization,
            reflected_inertia: self.controller.reflected_inertia,
            joint_inertia_regularization: self.controller.joint_inertia_regularization,
            qp_unconstrained_first: self.controller.qp_unconstrained_first,
        })
    }
}

/// REFERENCE.md's postural stiffness by joint group (one foot: the stance leg is stiffer).
fn default_postural_stiffness(name: &str, contacts: &[String]) -> f64 {
    let leg_index = |leg: &str| -> Option<usize> {
        [
            "hip_pitch",
            "hip_roll",
            "hip_yaw",
            "knee",
            "ankle_pitch",
            "ankle_roll",
        ]
        .iter()
        .position(|j| format!("{leg}_{j}") == name)
    };
    let stance = |side: &str| contacts.iter().any(|c| c.starts_with(side));
    for side in ["l", "r"] {
        if let Some(k) = leg_index(side) {
            let stance_gains = [15.0, 15.0, 15.0, 15.0, 5.0, 5.0];
            let swing_gains = [10.0, 10.0, 15.0, 15.0, 5.0, 5.0];
            return if stance(side) {
                stance_gains[k]
            } else {
                swing_gains[k]
            };
        }
    }
    match name {
        "torso_pitch" | "torso_yaw" => 10.0,
        "torso_roll" => 15.0,
        n if n.ends_with("elbow") || n.ends_with("wrist_prosup") => 2.5,
        _ => 5.0,
    }
}

/// Expands joint groups ("torso", "arms", "left_arm", "right_arm", "legs") into names.
pub fn expand_joint_groups(entries: &[String], joint_names: &[String]) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for entry in entries {
        let matches: Vec<String> = match entry.as_str() {
            "torso" => joint_names
                .iter()
                .filter(|n| n.starts_with("torso"))
                .cloned()
                .collect(),
            "left_arm" => arm(joint_names, "l_"),
            "right_arm" => arm(joint_names, "r_"),
            "arms" => [arm(joint_names, "l_"), arm(joint_names, "r_")].concat(),
            "upper_body" => {
                let mut v: Vec<String> = joint_names
                    .iter()
                    .filter(|n| n.starts_with("torso"))
                    .cloned()
                    .collect();
                v.extend(arm(joint_names, "l_"));
                v.extend(arm(joint_names, "r_"));
                v
            }
            name if joint_names.iter().any(|n| n == name) => vec![name.to_string()],
            other => {
                return Err(Error::config(
                    "reference.posture_step_joints",
                    format!("unknown joint or group '{other}'"),
                ))
            }
        };
        out.extend(matches);
    }
    Ok(out)
}

fn arm(joint_names: &[String], prefix: &str) -> Vec<String> {
    joint_names
        .iter()
        .filter(|n| {
            n.starts_with(prefix)
                && (n.contains("shoulder") || n.contains("elbow") || n.contains("wrist"))
        })
        .cloned()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_and_unknown_keys() {
        let text = "[robot]\nurdf = \"x.urdf\"\n";
        let s = Scenario::from_toml(
            text,
            &[("controller.kind".into(), "rigid".into())],
            Path::new("."),
        )
        .unwrap();
        assert_eq!(s.controller_kind(), ControllerKind::Rigid);
        let s = Scenario::from_toml(
            text,
            &[("controller.damping_estimate_scale".into(), "1.45".into())],
            Path::new("."),
        )
        .unwrap();
        assert_eq!(s.controller.damping_estimate_scale, 1.45);
        let err = Scenario::from_toml(
            text,
            &[("controller.dampnig".into(), "1".into())],
            Path::new("."),
        )
        .unwrap_err();
        assert!(err.to_string().contains("dampnig"), "{err}");
        let err = Scenario::from_toml(
            text,
            &[("controller.kind".into(), "pid".into())],
            Path::new("."),
        )
        .unwrap_err();
        assert!(err.to_string().contains("controller.kind"), "{err}");
        let err = Scenario::from_toml("[robot\n", &[], Path::new(".")).unwrap_err();
        assert!(err.to_string().contains("malformed TOML"), "{err}");
        let err = Scenario::from_toml(text, &[("plant.dt".into(), "-1".into())], Path::new("."))
            .unwrap_err();
        assert!(err.to_string().contains("plant.dt"), "{err}");
    }
}
