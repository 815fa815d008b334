//! Scenario files (TOML): robot, actuators, plant, controller, references, simulation.
//!
//! Every table rejects unknown keys, and `--set key=value` overrides are applied to the parsed
//! TOML tree before it is checked, so a typo in a file or an override is an error naming the
//! key. Relative paths are resolved against the scenario file's folder, then the working
//! directory.
//!
//! Defaults are written once, in the domain types: each table's `Default` impl is built from
//! [`ElasticParameters::default`], [`ContactConstraints::default`],
//! [`Plant::DEFAULT_BAUMGARTE_KP`], [`sea_dyn::critical_damping`] and the iCub data of
//! [`presets`] (docs/references.md), and every table is `#[serde(default)]`, so a missing key takes
//! the table's default.

pub mod build;
pub mod presets;
pub mod validate;

pub use build::{build, Setup};
pub use presets::{ICUB25_JOINTS, ICUB_LEFT_STANCE, ICUB_TWO_FEET_DEG};

use crate::error::{Error, Result};
use sea_ctrl::controller::{ControllerKind, ControllerSettings};
use sea_ctrl::qp::{ContactConstraints, QpSolver};
use sea_dyn::{critical_damping, Actuator, ContactSurface, ElasticParameters};
use sea_plant::Plant;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// `[robot]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotConfig {
    /// URDF path (required).
    pub urdf: String,
    /// Moving joints (default: the paper's 25 iCub joints, [`ICUB25_JOINTS`]).
    #[serde(default)]
    pub joints: Option<Vec<String>>,
    /// Contact frames, stance foot first (default [`presets::ICUB_STANCE_CONTACTS`]).
    #[serde(default = "stance_contacts")]
    pub contacts: Vec<String>,
    /// "left_stance", "two_feet" (the original study's postures), "zero" or explicit radians.
    #[serde(default = "left_stance")]
    pub initial_posture: toml::Value,
    /// The springs at the start: "preloaded" (default) or "at_rest" ([`InitialSprings`]).
    #[serde(default)]
    pub initial_springs: InitialSprings,
}

/// `robot.initial_springs`: the spring deflections of the initial state (the robot is at rest
/// in `robot.initial_posture` either way).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialSprings {
    /// Deflected by the static joint torques, so the run starts in equilibrium.
    #[default]
    Preloaded,
    /// Undeflected (`Gamma theta = s`): the controller must first load the springs, the
    /// original study's start of the saturation experiment
    /// (docs/references.md#original-study-experiments), which drives the large initial motor
    /// velocity peak the paper shows.
    AtRest,
}

/// [`presets::ICUB_STANCE_CONTACTS`] as owned names (serde default of `robot.contacts`).
fn stance_contacts() -> Vec<String> {
    presets::ICUB_STANCE_CONTACTS.map(String::from).to_vec()
}

/// The original study's one-foot posture (serde default of `robot.initial_posture`).
fn left_stance() -> toml::Value {
    toml::Value::String("left_stance".into())
}

/// One actuator: `[actuators]` (every joint's) or `[actuators.overrides.NAME]` (one joint's,
/// its keys on top of `[actuators]`). Defaults: the paper's iCub SEA,
/// [`ElasticParameters::paper_icub`].
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ActuatorConfig {
    /// "elastic" or "rigid".
    pub kind: String,
    /// Transmission ratio `Gamma` (joint angle per motor angle).
    pub ratio: f64,
    /// Motor inertia `I_m` [kg m^2], motor side.
    pub motor_inertia: f64,
    /// Stiffness `K_S` [Nm/rad].
    pub stiffness: f64,
    /// Damping `K_D` [Nms/rad].
    pub damping: f64,
    /// Motor torque limit [Nm], motor side.
    pub torque_limit: Option<f64>,
}

impl Default for ActuatorConfig {
    fn default() -> Self {
        let p = ElasticParameters::default();
        Self {
            kind: "elastic".into(),
            ratio: p.ratio,
            motor_inertia: p.motor_inertia,
            stiffness: p.stiffness,
            damping: p.damping,
            torque_limit: p.torque_limit,
        }
    }
}

impl ActuatorConfig {
    /// The actuator this table describes; `key` names the table in errors.
    pub fn actuator(&self, key: &str) -> Result<Actuator> {
        match self.kind.as_str() {
            "rigid" => Ok(Actuator::Rigid),
            "elastic" => Ok(Actuator::Elastic(ElasticParameters {
                ratio: self.ratio,
                motor_inertia: self.motor_inertia,
                stiffness: self.stiffness,
                damping: self.damping,
                torque_limit: self.torque_limit,
            })),
            other => Err(Error::config(
                format!("{key}.kind"),
                format!("expected \"elastic\" or \"rigid\", got \"{other}\""),
            )),
        }
    }
}

/// `[actuators]`: the default actuator of every joint (the keys of [`ActuatorConfig`]) plus
/// per-joint overrides (`[actuators.overrides.NAME]`, any subset of the same keys).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ActuatorsConfig {
    /// The actuator of every joint without an override.
    pub default: ActuatorConfig,
    /// Per-joint actuators by joint name, each `[actuators]` with its override's keys replaced.
    pub overrides: BTreeMap<String, ActuatorConfig>,
}

impl<'de> Deserialize<'de> for ActuatorsConfig {
    /// `[actuators]` without `overrides` is parsed as an [`ActuatorConfig`] (so unknown keys
    /// are errors: serde's `flatten` would not allow `deny_unknown_fields`); each override is
    /// that table with the override's keys replaced, parsed the same way.
    fn deserialize<D>(deserializer: D) -> std::result::Result<Self, D::Error>
    where
        D: serde::Deserializer<'de>,
    {
        use serde::de::Error as _;
        let mut table = toml::Table::deserialize(deserializer)?;
        let overrides = match table.remove("overrides") {
            None => toml::Table::new(),
            Some(toml::Value::Table(overrides)) => overrides,
            Some(other) => {
                return Err(D::Error::custom(format!(
                    "`overrides` must be a table of joint names, got {}",
                    other.type_str()
                )))
            }
        };
        let default = ActuatorConfig::deserialize(toml::Value::Table(table.clone()))
            .map_err(|e| D::Error::custom(actuator_table_message(&e, "")))?;
        let mut resolved = BTreeMap::new();
        for (name, value) in overrides {
            let toml::Value::Table(keys) = value else {
                return Err(D::Error::custom(format!(
                    "`overrides.{name}` must be a table of actuator keys, got {}",
                    value.type_str()
                )));
            };
            let mut merged = table.clone();
            merged.extend(keys);
            let actuator =
                ActuatorConfig::deserialize(toml::Value::Table(merged)).map_err(|e| {
                    D::Error::custom(actuator_table_message(&e, &format!("overrides.{name}.")))
                })?;
            resolved.insert(name, actuator);
        }
        Ok(Self {
            default,
            overrides: resolved,
        })
    }
}

/// A schema error of one actuator table deserialised on its own, relative to `[actuators]`:
/// `within` is "" for `[actuators]` and "overrides.NAME." for an override. The field is kept
/// so the key names it: "unknown field `overrides.NAME.x`" or "in `overrides.NAME.x`: rule"
/// (read back by [`schema_error`]).
fn actuator_table_message(error: &toml::de::Error, within: &str) -> String {
    let text = error.to_string();
    let (rule, field) = match text.trim().rsplit_once("\nin `") {
        Some((rule, path)) => (rule.trim(), Some(path.trim_end_matches('`'))),
        None => (text.trim(), None),
    };
    if let Some(rest) = rule.strip_prefix("unknown field `") {
        return format!("unknown field `{within}{rest}");
    }
    match field {
        Some(field) => format!("in `{within}{field}`: {rule}"),
        None if within.is_empty() => rule.to_string(),
        None => format!("in `{}`: {rule}", within.trim_end_matches('.')),
    }
}

/// `[plant]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlantConfig {
    /// Baumgarte position gain [1/s^2] (default [`Plant::DEFAULT_BAUMGARTE_KP`]).
    pub baumgarte_kp: f64,
    /// Baumgarte velocity gain [1/s] (default: [`sea_dyn::critical_damping`] of the kp).
    pub baumgarte_kd: Option<f64>,
    /// Motor velocity loop gain K_m [1/s] (default [`presets::ICUB_MOTOR_VELOCITY_GAIN`]).
    pub motor_velocity_gain: f64,
    /// Added to the plant's joint inertia diagonal [kg m^2] (default
    /// [`presets::ICUB_JOINT_INERTIA_REGULARIZATION`]).
    pub joint_inertia_regularization: f64,
    /// Integration step [s].
    pub dt: f64,
    /// "ros2", "implicit_euler" or "rk4".
    pub method: String,
}

impl Default for PlantConfig {
    fn default() -> Self {
        Self {
            baumgarte_kp: Plant::DEFAULT_BAUMGARTE_KP,
            baumgarte_kd: None,
            motor_velocity_gain: presets::ICUB_MOTOR_VELOCITY_GAIN,
            joint_inertia_regularization: presets::ICUB_JOINT_INERTIA_REGULARIZATION,
            dt: 1e-3,
            method: "ros2".into(),
        }
    }
}

impl PlantConfig {
    /// The Baumgarte velocity gain: `baumgarte_kd`, or the critical damping of the kp.
    pub fn baumgarte_kd(&self) -> f64 {
        self.baumgarte_kd
            .unwrap_or_else(|| critical_damping(self.baumgarte_kp))
    }
}

/// `[controller]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ControllerConfig {
    /// "sea" or "rigid".
    pub kind: String,
    /// Control rate [Hz] with zero-order hold (unused in continuous sampling).
    pub rate_hz: f64,
    /// "zero_order_hold" (the controller at `rate_hz`, its input held; the default) or
    /// "continuous" (the controller at every integrator stage, as in the paper).
    pub sampling: String,
    /// Controller damping estimate = true damping x scale.
    pub damping_estimate_scale: f64,
    /// Controller stiffness estimate = true stiffness x scale.
    pub stiffness_estimate_scale: f64,
    /// Momentum integral gains (linear xyz, angular xyz; default
    /// [`presets::icub_momentum_integral`]).
    pub momentum_integral: Option<[f64; 6]>,
    /// Momentum proportional gains (default: the critical damping of the integral gains).
    pub momentum_proportional: Option<[f64; 6]>,
    /// Postural stiffness per joint before `postural_scale` (default
    /// [`presets::icub_postural_stiffness`] by group).
    pub postural_stiffness: Option<Vec<f64>>,
    /// Scale of the postural stiffness (default [`presets::ICUB_POSTURAL_SCALE`]).
    pub postural_scale: f64,
    /// Pseudo-inverse damping (default [`presets::ICUB_PINV_DAMPING`]).
    pub pinv_damping: f64,
    /// QP Hessian regulariser (default [`presets::ICUB_QP_REGULARIZATION`]).
    pub qp_regularization: f64,
    /// Skip the QP solver when the QP's minimiser without inequalities satisfies them (it is
    /// then the optimum); `false` runs the solver every tick.
    pub qp_unconstrained_first: bool,
    /// The QP solver: "active_set" (Goldfarb-Idnani, Clarabel as fallback) or "clarabel"
    /// (default [`QpSolver::default`]).
    pub qp_solver: String,
    /// Rigid controller: include the motor reflected inertia (Remark 1).
    pub reflected_inertia: bool,
    /// Added to the controller model's joint inertia diagonal [kg m^2] (default
    /// [`presets::ICUB_JOINT_INERTIA_REGULARIZATION`]).
    pub joint_inertia_regularization: f64,
    /// Contact constraints.
    pub contact: ContactConfig,
}

impl Default for ControllerConfig {
    fn default() -> Self {
        Self {
            kind: "sea".into(),
            rate_hz: 1000.0,
            sampling: "zero_order_hold".into(),
            damping_estimate_scale: 1.0,
            stiffness_estimate_scale: 1.0,
            momentum_integral: None,
            momentum_proportional: None,
            postural_stiffness: None,
            postural_scale: presets::ICUB_POSTURAL_SCALE,
            pinv_damping: presets::ICUB_PINV_DAMPING,
            qp_regularization: presets::ICUB_QP_REGULARIZATION,
            qp_unconstrained_first: true,
            qp_solver: QpSolver::default().name().into(),
            reflected_inertia: true,
            joint_inertia_regularization: presets::ICUB_JOINT_INERTIA_REGULARIZATION,
            contact: ContactConfig::default(),
        }
    }
}

/// `[controller.contact]`: the QP's [`ContactConstraints`], whose contact surface the plant also
/// uses for its wrench margins (defaults: [`ContactConstraints::default`]).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContactConfig {
    /// Friction coefficient.
    pub friction: f64,
    /// Friction cone facets.
    pub facets: usize,
    /// Torsional friction coefficient [m].
    pub torsional_friction: f64,
    /// Minimum normal force [N].
    pub min_normal_force: f64,
    /// Foot rectangle x [m], sole frame.
    pub foot_x: [f64; 2],
    /// Foot rectangle y [m], sole frame.
    pub foot_y: [f64; 2],
}

impl Default for ContactConfig {
    fn default() -> Self {
        let ContactConstraints {
            surface,
            facets,
            min_normal_force,
        } = ContactConstraints::default();
        Self {
            friction: surface.friction,
            facets,
            torsional_friction: surface.torsional_friction,
            min_normal_force,
            foot_x: surface.foot_x,
            foot_y: surface.foot_y,
        }
    }
}

impl ContactConfig {
    /// The contact surface (plant margins and controller constraints).
    pub fn surface(&self) -> ContactSurface {
        ContactSurface {
            friction: self.friction,
            torsional_friction: self.torsional_friction,
            foot_x: self.foot_x,
            foot_y: self.foot_y,
        }
    }

    /// The QP's contact constraints.
    pub fn constraints(&self) -> ContactConstraints {
        ContactConstraints {
            surface: self.surface(),
            facets: self.facets,
            min_normal_force: self.min_normal_force,
        }
    }
}

/// `[reference]`: the CoM sinusoid `origin + (1 - exp(-t / smooth_start)) A sin(2 pi f t)
/// direction` and the postural step (defaults: no motion; the direction and the 1 s smooth
/// start are the original study's, docs/references.md#original-study-com-reference).
#[derive(Clone, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReferenceConfig {
    /// CoM sinusoid amplitude [m].
    pub com_amplitude: f64,
    /// CoM sinusoid frequency [Hz].
    pub com_frequency: f64,
    /// CoM sinusoid direction (world).
    pub com_direction: [f64; 3],
    /// Smooth-start time constant [s].
    pub com_smooth_start: f64,
    /// "stance_sole": CoM x, y above the stance sole origin (z initial); "initial": initial CoM.
    pub com_origin: String,
    /// Postural step [deg].
    pub posture_step_deg: f64,
    /// Joints (or groups "torso", "arms", "left_arm", "right_arm") that get the step.
    pub posture_step_joints: Vec<String>,
    /// Time of the step [s].
    pub posture_step_time: f64,
}

impl Default for ReferenceConfig {
    fn default() -> Self {
        Self {
            com_amplitude: 0.0,
            com_frequency: 0.0,
            com_direction: [0.0, 1.0, 0.0],
            com_smooth_start: 1.0,
            com_origin: "stance_sole".into(),
            posture_step_deg: 0.0,
            posture_step_joints: Vec::new(),
            posture_step_time: 0.0,
        }
    }
}

/// `[simulation]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimulationConfig {
    /// Simulated time [s].
    pub duration_s: f64,
    /// Record (and log) every this many samples: control ticks with zero-order hold, plant
    /// steps in continuous sampling (the last sample and a diverging one are always recorded).
    pub record_every: usize,
    /// The run is diverged when the CoM error exceeds this [m].
    pub divergence_com_error_m: f64,
    /// The run is diverged when the joint error norm exceeds this [rad].
    pub divergence_joint_error_rad: f64,
}

impl Default for SimulationConfig {
    fn default() -> Self {
        Self {
            duration_s: 10.0,
            record_every: 10,
            divergence_com_error_m: 0.1,
            divergence_joint_error_rad: 1.0,
        }
    }
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
    #[serde(default)]
    pub actuators: ActuatorsConfig,
    /// `[plant]`.
    #[serde(default)]
    pub plant: PlantConfig,
    /// `[controller]`.
    #[serde(default)]
    pub controller: ControllerConfig,
    /// `[reference]`.
    #[serde(default)]
    pub reference: ReferenceConfig,
    /// `[simulation]`.
    #[serde(default)]
    pub simulation: SimulationConfig,
    /// Folder of the scenario file (for relative paths).
    #[serde(skip)]
    pub base_dir: PathBuf,
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
    // A nested table's message may name its field: "in `overrides.l_knee.stiffness`: rule".
    let nested = rule
        .strip_prefix("in `")
        .and_then(|rest| rest.split_once("`: "));
    let (rule, path) = match nested {
        Some((inner, rest)) if !path.is_empty() => (rest, format!("{path}.{inner}")),
        _ => (rule, path.to_string()),
    };
    let path = path.as_str();
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
        let mut scenario: Scenario = toml::Value::Table(root)
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

    /// Checks every value against its meaning ([`validate::scenario`]).
    fn validate(&self) -> Result<()> {
        validate::scenario(self)
    }

    /// Controller kind.
    pub fn controller_kind(&self) -> ControllerKind {
        if self.controller.kind == "rigid" {
            ControllerKind::Rigid
        } else {
            ControllerKind::Sea
        }
    }

    /// The QP solver of `controller.qp_solver`.
    pub fn qp_solver(&self) -> Result<QpSolver> {
        let name = &self.controller.qp_solver;
        QpSolver::parse(name).ok_or_else(|| {
            let names: Vec<String> = QpSolver::ALL
                .iter()
                .map(|solver| format!("{:?}", solver.name()))
                .collect();
            Error::invalid(
                "controller.qp_solver",
                format!("expected {}", names.join(" or ")),
                format!("{name:?}"),
            )
        })
    }

    /// Contact constraints of the QP.
    pub fn contact_constraints(&self) -> ContactConstraints {
        self.controller.contact.constraints()
    }

    /// Controller settings for a model with `joint_names`.
    pub fn controller_settings(&self, joint_names: &[String]) -> Result<ControllerSettings> {
        let one_foot = self.robot.contacts.len() == 1;
        let integral = self
            .controller
            .momentum_integral
            .unwrap_or_else(|| presets::icub_momentum_integral(one_foot));
        let proportional = self
            .controller
            .momentum_proportional
            .unwrap_or(integral.map(critical_damping));
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
                .map(|name| presets::icub_postural_stiffness(name, &self.robot.contacts))
                .collect(),
        }
        .into_iter()
        .map(|k| k * self.controller.postural_scale)
        .collect();
        let damping = stiffness.iter().copied().map(critical_damping).collect();
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
            qp_solver: self.qp_solver()?,
        })
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

    #[test]
    fn initial_springs_default_to_preloaded_and_name_the_key_when_unknown() {
        let text = "[robot]\nurdf = \"x.urdf\"\n";
        let parse = |value: &str| {
            let overrides = [("robot.initial_springs".to_string(), value.to_string())];
            Scenario::from_toml(text, &overrides, Path::new("."))
        };
        let s = Scenario::from_toml(text, &[], Path::new(".")).unwrap();
        assert_eq!(s.robot.initial_springs, InitialSprings::Preloaded);
        assert_eq!(
            parse("at_rest").unwrap().robot.initial_springs,
            InitialSprings::AtRest
        );
        let err = parse("relaxed").unwrap_err().to_string();
        assert!(
            err.contains("robot.initial_springs") && err.contains("at_rest"),
            "{err}"
        );
    }

    #[test]
    fn defaults_come_from_the_domain_types() {
        let s = Scenario::from_toml("[robot]\nurdf = \"x.urdf\"\n", &[], Path::new(".")).unwrap();
        let sea = s.actuators.default.actuator("actuators").unwrap();
        assert_eq!(sea, Actuator::Elastic(ElasticParameters::default()));
        assert_eq!(s.contact_constraints(), ContactConstraints::default());
        assert_eq!(s.plant.baumgarte_kp, Plant::DEFAULT_BAUMGARTE_KP);
        assert_eq!(
            s.plant.baumgarte_kd(),
            critical_damping(Plant::DEFAULT_BAUMGARTE_KP)
        );
    }

    #[test]
    fn actuator_overrides_replace_only_their_keys() {
        let text = "[robot]\nurdf = \"x.urdf\"\n[actuators]\nstiffness = 100.0\n\
                    [actuators.overrides.l_knee]\ndamping = 2.0\n";
        let s = Scenario::from_toml(text, &[], Path::new(".")).unwrap();
        let knee = &s.actuators.overrides["l_knee"];
        assert_eq!((knee.stiffness, knee.damping), (100.0, 2.0));
        assert_eq!(
            s.actuators.default.damping,
            ElasticParameters::default().damping
        );
        assert_eq!(knee.ratio, s.actuators.default.ratio);
    }

    #[test]
    fn unknown_actuator_keys_are_errors_naming_the_key() {
        let text = "[robot]\nurdf = \"x.urdf\"\n";
        for (key, named) in [
            ("actuators.stifness", "actuators.stifness"),
            (
                "actuators.overrides.l_knee.stifness",
                "actuators.overrides.l_knee.stifness",
            ),
        ] {
            let err =
                Scenario::from_toml(text, &[(key.into(), "1".into())], Path::new(".")).unwrap_err();
            assert!(err.to_string().contains(named), "{err}");
        }
        let err = Scenario::from_toml(
            text,
            &[("actuators.overrides.l_knee".into(), "3".into())],
            Path::new("."),
        )
        .unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("actuators") && message.contains("overrides.l_knee"),
            "{message}"
        );
    }
}
