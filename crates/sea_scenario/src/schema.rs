//! The tables of a scenario file, typed: each key is read once, by serde, into its type
//! (domain types where one exists: [`ElasticParameters`], [`ContactConstraints`] with its
//! [`sea_dyn::ContactSurface`], the settings of [`super::settings`]). Every table rejects
//! unknown keys and is `#[serde(default)]`: a missing key takes the table's default, built
//! from the domain types' defaults and the robot description ([`super::robots::icub()`]).

use super::bounded::{AtLeastOne, Finite, NonNegative, Positive};
use super::parse::{table_as, take, TableError, TableResult};
use super::robots::icub;
use super::settings::{
    ActuatorKind, ComOrigin, ControllerKind, IdentificationWrenches, Method, Sampling, Setting,
};
use super::split_tables::{contact_constraints, contact_constraints_table};
use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use sea_ctrl::controller::ControllerTuning;
use sea_ctrl::excitation::ExcitationSettings;
use sea_ctrl::external_wrench::ExternalWrenchSettings;
use sea_ctrl::joint_loop::JointLoopSettings;
use sea_ctrl::qp::ContactConstraints;
use sea_ctrl::stiffness_id::IdentificationSettings;
use sea_dyn::{critical_damping, Actuator, ElasticParameters};
use sea_plant::Plant;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;

/// `[robot]`. Its key `description` names the robot description the scenario's defaults come
/// from (a built-in name, "icub_paper" by default, a file or an inline table:
/// [`super::robots::source`]); it is read before this table ([`super::robots::defaults`]).
#[derive(Clone, Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(transform = robot_table_schema)]
pub struct RobotConfig {
    /// URDF: a path (relative to the scenario's folder, else the working directory) or a
    /// `package://NAME/PATH` or `file://` URI (required unless the description names one).
    pub urdf: String,
    /// Folders searched first for `package://` URIs (relative to the scenario's folder),
    /// before the environment's ([`sea_dyn::PackageDirs::from_environment`]).
    #[serde(default)]
    pub package_dirs: Vec<String>,
    /// Moving joints (default: the robot description's, the paper's 25 iCub joints).
    #[serde(default)]
    pub joints: Option<Vec<String>>,
    /// Contacts, stance foot first: frame names or `LINK:x,y,z` points of a link
    /// ([`super::robots::ContactSpec`]; default: the robot description's).
    #[serde(default = "default_contacts")]
    pub contacts: Vec<String>,
    /// A posture of the robot description ("left_stance", "two_feet": the original study's),
    /// "zero" or explicit radians.
    #[serde(default = "left_stance")]
    #[schemars(schema_with = "posture_schema")]
    pub initial_posture: toml::Value,
    /// The springs at the start: "preloaded" (default) or "at_rest" ([`InitialSprings`]).
    #[serde(default)]
    pub initial_springs: InitialSprings,
}

/// `robot.initial_springs`: the spring deflections of the initial state (the robot is at rest
/// in `robot.initial_posture` either way).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum InitialSprings {
    /// Deflected by the static joint torques, so the run starts in equilibrium.
    #[default]
    Preloaded,
    /// Undeflected (`Gamma theta = s`): the controller must first load the springs, the
    /// original study's start of the saturation experiment, which drives the large initial
    /// motor velocity peak the paper shows.
    AtRest,
}

/// The robot description's contact frames (serde default of `robot.contacts`).
fn default_contacts() -> Vec<String> {
    icub().contacts.clone()
}

/// The original study's one-foot posture (serde default of `robot.initial_posture`).
fn left_stance() -> toml::Value {
    toml::Value::String("left_stance".into())
}

/// One actuator: `[actuators]` (every joint's) or `[actuators.overrides.NAME]` (one joint's,
/// its keys on top of `[actuators]`): `kind` and the keys of [`ElasticParameters`] (defaults:
/// the paper's iCub SEA, [`ElasticParameters::paper_icub`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ActuatorConfig {
    /// Elastic or rigid.
    pub kind: ActuatorKind,
    /// The parameters of an elastic actuator.
    pub parameters: ElasticParameters,
}

impl ActuatorConfig {
    /// Reads an actuator table on its own (`kind` and the parameters' keys); the error's key
    /// is relative to the table. The scenario's `[actuators]` and the Python bindings'
    /// actuator dicts are read here.
    pub fn from_table(mut table: toml::Table) -> TableResult<Self> {
        let kind = take(&mut table, "kind")?.unwrap_or_default();
        let parameters = table_as(table, &["kind"])?;
        Ok(Self { kind, parameters })
    }

    /// The first of an actuator table's own `keys` that this actuator ignores, when it is
    /// rigid: any key but `kind` (a rigid joint has no spring, damper or motor). An override
    /// of `[actuators]` or a Python actuator dict that gives one is refused.
    pub fn ignored_key<'a>(
        &self,
        keys: impl IntoIterator<Item = &'a String>,
    ) -> Option<&'a String> {
        match self.kind {
            ActuatorKind::Rigid => keys.into_iter().find(|key| *key != "kind"),
            ActuatorKind::Elastic => None,
        }
    }

    /// The actuator this table describes.
    pub fn actuator(&self) -> Actuator {
        match self.kind {
            ActuatorKind::Rigid => Actuator::Rigid,
            ActuatorKind::Elastic => Actuator::Elastic(self.parameters),
        }
    }
}

/// The rule an elastic actuator's key given to a rigid one breaks
/// ([`ActuatorConfig::ignored_key`]).
pub const RIGID_IGNORES: &str =
    "an elastic actuator's key, given with kind = \"rigid\" (a rigid joint has no spring, \
     damper or motor)";

/// The key of [`ActuatorsConfig::torque_limit_from_urdf`].
pub const TORQUE_LIMIT_FROM_URDF: &str = "torque_limit_from_urdf";

/// `[actuators]`: the default actuator of every joint (the keys of [`ActuatorConfig`]) plus
/// per-joint overrides (`[actuators.overrides.NAME]`, any subset of the same keys).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ActuatorsConfig {
    /// The actuator of every joint without an override.
    pub default: ActuatorConfig,
    /// Per-joint actuators by joint name, each `[actuators]` with its override's keys replaced.
    pub overrides: BTreeMap<String, ActuatorConfig>,
    /// `torque_limit_from_urdf`: each elastic joint's motor torque limit is `ratio` times the
    /// effort limit of its URDF `<limit>` (joint side), where the URDF gives one and the
    /// joint's override sets no `torque_limit`.
    pub torque_limit_from_urdf: bool,
}

impl<'de> Deserialize<'de> for ActuatorsConfig {
    /// `[actuators]` without `overrides` is read as an [`ActuatorConfig`]; each override is
    /// that table with the override's keys replaced, read the same way.
    fn deserialize<D>(deserializer: D) -> std::result::Result<Self, D::Error>
    where
        D: Deserializer<'de>,
    {
        let mut table = toml::Table::deserialize(deserializer)?;
        let torque_limit_from_urdf = take(&mut table, TORQUE_LIMIT_FROM_URDF)
            .map_err(|e| D::Error::custom(e.within("")))?
            .unwrap_or(false);
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
        let default = ActuatorConfig::from_table(table.clone())
            .map_err(|e| D::Error::custom(e.within("")))?;
        let mut resolved = BTreeMap::new();
        for (name, value) in overrides {
            let toml::Value::Table(keys) = value else {
                return Err(D::Error::custom(format!(
                    "`overrides.{name}` must be a table of actuator keys, got {}",
                    value.type_str()
                )));
            };
            let own_keys: Vec<String> = keys.keys().cloned().collect();
            let mut merged = table.clone();
            merged.extend(keys);
            let within = format!("overrides.{name}.");
            let actuator = ActuatorConfig::from_table(merged)
                .map_err(|e| D::Error::custom(e.within(&within)))?;
            if let Some(key) = actuator.ignored_key(&own_keys) {
                let error = TableError {
                    key: key.clone(),
                    rule: RIGID_IGNORES.to_string(),
                };
                return Err(D::Error::custom(error.within(&within)));
            }
            resolved.insert(name, actuator);
        }
        Ok(Self {
            default,
            overrides: resolved,
            torque_limit_from_urdf,
        })
    }
}

impl JsonSchema for ActuatorConfig {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "ActuatorConfig".into()
    }

    /// The keys of [`ElasticParameters`] with `kind`, as [`ActuatorConfig::from_table`] reads
    /// them.
    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        let mut schema = ElasticParameters::json_schema(generator);
        let kind = json_schema!({
            "allOf": [generator.subschema_for::<ActuatorKind>()],
            "default": ActuatorKind::default().name(),
        });
        insert_property(&mut schema, "kind", kind);
        schema.insert(
            "description".into(),
            "One actuator: `kind` and the parameters of an elastic actuator (defaults: the \
             robot description's, the paper's iCub SEA)."
                .into(),
        );
        schema
    }
}

impl JsonSchema for ActuatorsConfig {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "ActuatorsConfig".into()
    }

    /// [`ActuatorConfig`]'s keys with `overrides`, a table of them per joint name.
    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        let mut schema = ActuatorConfig::json_schema(generator);
        let one = generator.subschema_for::<ActuatorConfig>();
        let overrides = json_schema!({
            "type": "object",
            "description": "Per joint name, the keys of `[actuators]` that differ for that \
                joint (`[actuators.overrides.NAME]`).",
            "additionalProperties": one,
        });
        insert_property(&mut schema, "overrides", overrides);
        let from_urdf = json_schema!({
            "type": "boolean",
            "default": false,
            "description": "Whether each elastic joint's `torque_limit` (motor side) is `ratio` \
                times the effort of its URDF `<limit>` (joint side), where the URDF gives a \
                positive one and the joint's override sets no `torque_limit`; rigid joints \
                stay unlimited. Exclusive with `torque_limit` in `[actuators]`.",
        });
        insert_property(&mut schema, TORQUE_LIMIT_FROM_URDF, from_urdf);
        schema.insert(
            "description".into(),
            "The actuator of every joint, with per-joint overrides.".into(),
        );
        schema
    }
}

/// Adds the property `name` with `value`'s schema to the object schema `schema`.
fn insert_property(schema: &mut Schema, name: &str, value: Schema) {
    let properties = schema
        .ensure_object()
        .entry("properties")
        .or_insert_with(|| serde_json::Value::Object(Default::default()));
    if let Some(properties) = properties.as_object_mut() {
        properties.insert(name.into(), value.into());
    }
}

/// Schema transform of a table whose keys may all be left out (their defaults come from the
/// robot description, written into the tree before serde reads it:
/// [`super::robots::defaults`]).
pub(crate) fn optional_keys(schema: &mut Schema) {
    schema.remove("required");
}

/// Schema of `[robot]`: every key optional ([`optional_keys`]) and `description`, read before
/// the table ([`super::robots::source`]).
fn robot_table_schema(schema: &mut Schema) {
    optional_keys(schema);
    let description = json_schema!({
        "description": "The robot description the scenario's defaults come from: \
            \"icub_paper\" (the default), the path of a robot description file (TOML, relative \
            to the scenario's folder) or an inline table of one.",
        "default": super::robots::icub::ICUB_PAPER,
        "type": ["string", "object"],
    });
    insert_property(schema, "description", description);
}

/// Schema of `robot.initial_posture`: a posture's name or the joint angles [rad].
fn posture_schema(_: &mut SchemaGenerator) -> Schema {
    json_schema!({
        "description": "A posture of the robot description (\"left_stance\", \"two_feet\": the \
            original study's), \"zero\", or explicit joint angles [rad], one per moving joint.",
        "default": "left_stance",
        "anyOf": [
            { "type": "string" },
            { "type": "array", "items": { "type": "number" } },
        ],
    })
}

/// The JSON Schema of a scenario file (draft 7, as editors read it: Taplo / Even Better TOML
/// through the `#:schema` header of the shipped scenarios), derived from [`super::Scenario`]
/// and the types it reads; the doc comments are the descriptions.
pub fn json_schema() -> serde_json::Value {
    let generator = schemars::generate::SchemaSettings::draft07().into_generator();
    let mut schema = generator.into_root_schema_for::<super::Scenario>().into();
    tidy(&mut schema);
    schema
}

/// Readies derived schema for editors and the reference page: descriptions on one line,
/// without rustdoc's link brackets; no default of a whole table (its keys have theirs) and no
/// `null` default (TOML has no null: the key is left out).
fn tidy(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Object(object) => {
            if let Some(serde_json::Value::String(text)) = object.get_mut("description") {
                *text = one_line(text);
            }
            let table_default = object
                .get("default")
                .is_some_and(|d| d.is_object() || d.is_null());
            if table_default {
                object.remove("default");
            }
            object.values_mut().for_each(tidy);
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(tidy),
        _ => {}
    }
}

/// A doc comment as one line of text: lines joined, "[`x`]" written "`x`".
fn one_line(text: &str) -> String {
    let words: Vec<&str> = text.split_whitespace().collect();
    words.join(" ").replace("[`", "`").replace("`]", "`")
}

/// [`json_schema()`] as the text of `schemas/scenario.schema.json` (pretty, one final newline).
pub fn json_schema_text() -> String {
    let mut text = serde_json::to_string_pretty(&json_schema()).expect("a JSON value");
    text.push('\n');
    text
}

/// `[plant]`.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PlantConfig {
    /// Baumgarte position gain [1/s^2] (default [`Plant::DEFAULT_BAUMGARTE_KP`]).
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub baumgarte_kp: f64,
    /// Baumgarte velocity gain [1/s] (default: [`sea_dyn::critical_damping`] of the kp).
    #[serde(deserialize_with = "NonNegative::read_option")]
    #[schemars(with = "Option<NonNegative>")]
    pub baumgarte_kd: Option<f64>,
    /// Motor velocity loop gain K_m [1/s] (default: the robot description's).
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub motor_velocity_gain: f64,
    /// Added to the plant's joint inertia diagonal [kg m^2] (default: the robot
    /// description's).
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub joint_inertia_regularization: f64,
    /// The longest integration step [s]: the plant takes the longest step at most this long
    /// that divides the joint loops' period (`controller.inner_rate_hz` under "multi_rate"),
    /// the control period (`controller.rate_hz`, "zero_order_hold") or the run
    /// (`simulation.duration_s`, "continuous") into whole steps.
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub dt: f64,
    /// The integrator: "ros2" (default), "implicit_euler" or "rk4".
    pub method: Method,
    /// Consecutive steps of the linearly implicit methods that may share the step matrix `W`
    /// and its factors, prepared at the first one's start (default 10; 1: every step its own;
    /// at least 1). Any `W` keeps the method's order; it is prepared afresh when a motor's
    /// saturation changes (`sea_plant::IntegratorCache::set_w_refresh_steps`).
    #[serde(deserialize_with = "AtLeastOne::read")]
    #[schemars(with = "AtLeastOne")]
    pub w_refresh_steps: usize,
    /// How the feet touch the world: "bilateral" (default; the paper's rigid contacts) or
    /// "unilateral" (points of the soles on the `[ground]`, with friction and impacts).
    pub contact_model: crate::ground::ContactModelKind,
    /// The URDF's position limits as stops in the plant (default: on under unilateral
    /// contacts, off under bilateral ones).
    pub joint_stops: Option<bool>,
    /// Stiffness of the joint stops [N m/rad] (default 2000).
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub joint_stop_stiffness: f64,
    /// Hunt-Crossley dissipation of the joint stops [s/rad] (default 10: a joint leaves its
    /// stop only faster than 0.1 rad/s).
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub joint_stop_dissipation: f64,
}

impl Default for PlantConfig {
    fn default() -> Self {
        Self {
            baumgarte_kp: Plant::DEFAULT_BAUMGARTE_KP,
            baumgarte_kd: None,
            motor_velocity_gain: icub().motor_velocity_gain,
            joint_inertia_regularization: icub().joint_inertia_regularization,
            dt: 1e-3,
            method: Method::Ros2,
            w_refresh_steps: 10,
            contact_model: crate::ground::ContactModelKind::Bilateral,
            joint_stops: None,
            joint_stop_stiffness: sea_plant::JointStops::default().stiffness,
            joint_stop_dissipation: sea_plant::JointStops::default().dissipation,
        }
    }
}

impl PlantConfig {
    /// Buffers to step `plant` with these settings (`w_refresh_steps`).
    pub fn plant_data(&self, plant: &Plant) -> sea_plant::PlantData {
        let mut data = sea_plant::PlantData::new(plant);
        data.integrator.set_w_refresh_steps(self.w_refresh_steps);
        data
    }

    /// The Baumgarte velocity gain: `baumgarte_kd`, or the critical damping of the kp.
    pub fn baumgarte_kd(&self) -> f64 {
        self.baumgarte_kd
            .unwrap_or_else(|| critical_damping(self.baumgarte_kp))
    }
}

/// `[controller]`: one flat table, the scenario's own keys (the controller's kind, its
/// sampling and rates, whether the identification runs and on which wrenches) and those of
/// the `sea_ctrl` settings it reads directly ([`JointLoopSettings`],
/// [`IdentificationSettings`], [`ExcitationSettings`], [`ExternalWrenchSettings`],
/// [`ControllerTuning`]; the table is split by their keys when read).
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ControllerConfig {
    /// "sea" (default) or "rigid".
    pub kind: ControllerKind,
    /// Control rate [Hz] with zero-order hold, the whole-body rate in `multi_rate` (unused in
    /// continuous sampling); default [`Sampling::default_rate_hz`], read through
    /// [`ControllerConfig::rate_hz`].
    #[serde(deserialize_with = "Positive::read_option")]
    #[schemars(with = "Option<Positive>")]
    pub rate_hz: Option<f64>,
    /// "zero_order_hold" (the controller at `rate_hz`, its input held; the default),
    /// "continuous" (the controller at every integrator stage, as in the paper) or
    /// "multi_rate" (the whole-body controller at `rate_hz`, the joint torque loops at
    /// `inner_rate_hz`).
    pub sampling: Sampling,
    /// `multi_rate`: rate of the joint torque loops [Hz], a whole multiple of `rate_hz`
    /// (default 1 kHz, the iCub's motor boards).
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub inner_rate_hz: f64,
    /// The joint torque loops, `sea_ctrl`'s settings read directly: the keys
    /// `torque_bandwidth_hz`, `torque_loop_paper_law` and `joint_stiffness` of this table
    /// ([`JointLoopSettings`]).
    #[serde(skip_serializing)]
    #[schemars(flatten)]
    pub joint_loops: JointLoopSettings,
    /// `multi_rate`: identify each elastic joint's spring stiffness online from the encoders
    /// and the model ([`sea_ctrl::stiffness_id`]) and give it to the joint loops, starting
    /// from the estimate `stiffness_estimate_scale` x the true stiffness (default false).
    pub stiffness_identification: bool,
    /// `multi_rate` with `stiffness_identification`: the contact wrenches it takes,
    /// "measured" (foot force/torque sensors; the default) or "commanded" (the QP's `f*`).
    pub identification_wrenches: IdentificationWrenches,
    /// The identification's tuning, `sea_ctrl`'s settings read directly: the keys
    /// `identification_time_s`, `identification_deflection_noise_rad`, `identification_hold_s`,
    /// `identification_prior_deflection_rad`, `identification_filter_hz`,
    /// `identification_range_factor` and `identification_acceleration` of this table
    /// ([`IdentificationSettings`]; the table is split by its keys when read,
    /// `split_tables::controller_table`).
    #[serde(skip_serializing)]
    #[schemars(flatten)]
    pub identification: IdentificationSettings,
    /// `multi_rate`: the identification's excitation, `sea_ctrl`'s settings read directly:
    /// the keys `identification_excitation_nm`, `identification_excitation_hz` and
    /// `identification_excitation_s` of this table ([`ExcitationSettings`]).
    #[serde(skip_serializing)]
    #[schemars(flatten)]
    pub excitation: ExcitationSettings,
    /// The observer of an unmodelled external wrench, `sea_ctrl`'s settings read directly:
    /// the keys `external_wrench` and `external_wrench_bandwidth_hz` of this table
    /// ([`ExternalWrenchSettings`]).
    #[serde(skip_serializing)]
    #[schemars(flatten)]
    pub wrench_observer: ExternalWrenchSettings,
    /// The controller's tuning, `sea_ctrl`'s settings read directly: the estimate scales,
    /// gains, regularisers and QP choices of this table ([`ControllerTuning`]; the defaults
    /// the robot description decides are written into the file's tree before it is read,
    /// [`super::robots::defaults`]).
    #[serde(skip_serializing)]
    #[schemars(flatten)]
    pub tuning: ControllerTuning,
    /// `[controller.contact]`: the QP's contact constraints, whose contact surface the plant
    /// also uses for its wrench margins (one flat table: `facets`, `min_normal_force`,
    /// `cop_margin` and the keys of [`sea_dyn::ContactSurface`]; defaults
    /// [`ContactConstraints::default`]).
    #[serde(
        deserialize_with = "contact_constraints",
        serialize_with = "contact_constraints_table"
    )]
    #[schemars(with = "ContactConstraints")]
    pub contact: ContactConstraints,
}

impl Default for ControllerConfig {
    fn default() -> Self {
        let robot = icub();
        Self {
            kind: ControllerKind::Sea,
            rate_hz: None,
            sampling: Sampling::default(),
            inner_rate_hz: 1000.0,
            joint_loops: JointLoopSettings::default(),
            stiffness_identification: false,
            identification_wrenches: IdentificationWrenches::default(),
            identification: IdentificationSettings::default(),
            excitation: ExcitationSettings::default(),
            wrench_observer: ExternalWrenchSettings::default(),
            tuning: ControllerTuning {
                postural_scale: robot.postural_scale,
                pinv_damping: robot.pinv_damping,
                qp_regularization: robot.qp_regularization,
                joint_inertia_regularization: robot.joint_inertia_regularization,
                ..ControllerTuning::default()
            },
            contact: ContactConstraints::default(),
        }
    }
}

impl ControllerConfig {
    /// `[controller]` as a scenario file writes it: one flat table, the keys of the settings
    /// read directly ([`IdentificationSettings`], [`ControllerTuning`], ...) among the
    /// table's own.
    pub fn table(&self) -> std::result::Result<toml::Table, toml::ser::Error> {
        super::split_tables::controller_flat_table(self)
    }

    /// `controller.rate_hz`, or its default under `controller.sampling`
    /// ([`Sampling::default_rate_hz`]) [Hz].
    pub fn rate_hz(&self) -> f64 {
        self.rate_hz
            .unwrap_or_else(|| self.sampling.default_rate_hz())
    }

    /// `multi_rate`: the joint loops' bandwidth [rad/s], `None` for the paper's `K_S^ / K_D^`
    /// per joint ([`JointLoopSettings::bandwidth`]).
    pub fn torque_bandwidth(&self) -> Option<f64> {
        self.joint_loops.bandwidth()
    }
}

/// Reads `reference.com_direction`: finite entries, not zero.
fn direction<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> std::result::Result<[f64; 3], D::Error> {
    let direction: [f64; 3] = Finite::read_entries(deserializer)?;
    let norm = direction.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm > 1e-12 && norm.is_finite() {
        Ok(direction)
    } else {
        Err(D::Error::custom(format!(
            "must be a non-zero finite vector, got {direction:?}"
        )))
    }
}

/// `[reference]`: the CoM sinusoid `origin + (1 - exp(-t / smooth_start)) A sin(2 pi f t)
/// direction` and the postural step (defaults: no motion; the direction and the 1 s smooth
/// start are the original study's).
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct ReferenceConfig {
    /// CoM sinusoid amplitude [m].
    #[serde(deserialize_with = "Finite::read")]
    #[schemars(with = "Finite")]
    pub com_amplitude: f64,
    /// CoM sinusoid frequency [Hz].
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub com_frequency: f64,
    /// CoM sinusoid direction (world), a non-zero finite vector.
    #[serde(deserialize_with = "direction")]
    pub com_direction: [f64; 3],
    /// Smooth-start time constant [s].
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub com_smooth_start: f64,
    /// "stance_sole" (default): CoM x, y above the stance sole origin (z initial); "initial":
    /// the initial CoM.
    pub com_origin: ComOrigin,
    /// Postural step [deg].
    #[serde(deserialize_with = "Finite::read")]
    #[schemars(with = "Finite")]
    pub posture_step_deg: f64,
    /// Joints (or groups of the robot description: "torso", "arms", "left_arm", "right_arm",
    /// "upper_body") that get the step.
    pub posture_step_joints: Vec<String>,
    /// Time of the step [s].
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub posture_step_time: f64,
}

impl Default for ReferenceConfig {
    fn default() -> Self {
        Self {
            com_amplitude: 0.0,
            com_frequency: 0.0,
            com_direction: [0.0, 1.0, 0.0],
            com_smooth_start: 1.0,
            com_origin: ComOrigin::default(),
            posture_step_deg: 0.0,
            posture_step_joints: Vec::new(),
            posture_step_time: 0.0,
        }
    }
}

/// `[simulation]`.
#[derive(Clone, Debug, Deserialize, Serialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SimulationConfig {
    /// Simulated time [s].
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub duration_s: f64,
    /// Record (and log) every this many samples: control ticks with zero-order hold, plant
    /// steps in continuous sampling (the last sample and a diverging one are always recorded).
    #[serde(deserialize_with = "AtLeastOne::read")]
    #[schemars(with = "AtLeastOne")]
    pub record_every: usize,
    /// The run is diverged when the CoM error exceeds this [m].
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub divergence_com_error_m: f64,
    /// The run is diverged when the joint error norm exceeds this [rad].
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub divergence_joint_error_rad: f64,
    /// A fall ends the run as "fell" (default `true`): under bilateral contacts a foot's
    /// wrench that a unilateral contact with friction cannot transmit, under unilateral ones
    /// the robot reaching the ground (`fall_base_height_fraction`, `fall_tilt_rad`, a link
    /// other than the feet on the ground). `false` keeps the plant's bilateral contacts as the
    /// whole truth, as in the paper's setting: used to measure the growth of an unstable mode
    /// past the moment the real robot would have fallen.
    pub stop_on_fall: bool,
    /// Unilateral contacts: the run has fallen when the base is below this fraction of its
    /// initial height above the ground (default 0.6).
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub fall_base_height_fraction: f64,
    /// Unilateral contacts: the run has fallen when the base tilts more than this from its
    /// initial orientation [rad] (default pi/3).
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub fall_tilt_rad: f64,
    /// A joint of the true state outside its URDF position limits ends the run as diverged
    /// (`joint_outside_limits`; default `false`: under bilateral contacts the paper's plant
    /// has no joint limits, and the tracking scenarios are bounded by the joint error norm;
    /// under unilateral contacts the joints rest on stops at those limits).
    pub stop_at_joint_limits: bool,
}

impl Default for SimulationConfig {
    fn default() -> Self {
        Self {
            duration_s: 10.0,
            record_every: 10,
            divergence_com_error_m: 0.1,
            divergence_joint_error_rad: 1.0,
            stop_on_fall: true,
            fall_base_height_fraction: sea_loop::FallBounds::default().base_height_fraction,
            fall_tilt_rad: sea_loop::FallBounds::default().tilt_rad,
            stop_at_joint_limits: false,
        }
    }
}
