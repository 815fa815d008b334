//! `sea_scenario`: scenario files (TOML): robot, actuators, plant, controller, references, simulation,
//! disturbances, sensing.
//!
//! Reading one is three steps: the TOML text is parsed into a tree and the `--set key=value`
//! overrides are applied to it ([`parse`]); serde reads the tree into the typed tables of
//! [`schema`] (enum-like settings are the types of [`settings`], so a name that is not one of
//! them is refused there); [`validate`] checks every value against its meaning. A typo in a
//! file or an override is an error naming the key. Relative paths are resolved against the
//! scenario file's folder, then the working directory.
//!
//! Defaults are written once: in the domain types ([`ElasticParameters::default`],
//! [`ContactConstraints::default`], [`sea_plant::Plant::DEFAULT_BAUMGARTE_KP`],
//! [`sea_dyn::critical_damping`]) and in the robot description the scenario names
//! (`robot.description`, [`robots`]; the paper's iCub, `robots/icub_paper.toml`, by default).

#![forbid(unsafe_code)]

/// Bounded values, read with the file (`sea_dyn::bounded`, where the domain types' fields
/// declare theirs).
pub use sea_dyn::bounded;
pub mod build;
pub mod ground;
mod locate;
pub use locate::Origin;
/// `[[disturbances]]` (typed by the loop), at its former path.
pub use sea_loop::disturbance_schedule as disturbances;
pub mod parse;
pub mod reference;
pub mod robots;
pub mod run;
pub mod schema;
pub mod settings;
mod split_tables;
mod stack;
pub mod validate;
pub mod walking;

pub use build::{build, Setup};
pub use disturbances::{DisturbanceConfig, DisturbanceSchedule};
pub use ground::{ContactModelKind, GroundConfig};
pub use parse::{apply_override, TableError};
pub use robots::{icub, RobotDescription};
pub use schema::{
    ActuatorConfig, ActuatorsConfig, ControllerConfig, InitialSprings, PlantConfig,
    ReferenceConfig, RobotConfig, SimulationConfig,
};
/// `[sensing]` (typed by the loop).
pub use sea_loop::SensingConfig;
pub use settings::{
    ActuatorKind, ComOrigin, ControllerKind, ExternalWrench, IdentificationAcceleration,
    IdentificationWrenches, Method, QpSolver, Sampling, Setting,
};
pub use std::sync::Arc;

use parse::{schema_error, syntax_error};
use sea_ctrl::controller::ControllerSettings;
use sea_ctrl::qp::ContactConstraints;
use sea_dyn::files::{read_text_within, MAX_TOML_BYTES};
#[cfg(doc)]
use sea_dyn::ElasticParameters;
use sea_dyn::{critical_damping, Model};
/// The one error type (`sea_loop`'s).
pub use sea_loop::error;
pub use sea_loop::{Error, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A whole scenario.
#[derive(Clone, Debug, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "sea-momentum scenario", transform = schema::optional_keys)]
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
    /// `[ground]`: the plane the soles touch under `plant.contact_model = "unilateral"`.
    #[serde(default)]
    pub ground: GroundConfig,
    /// `[controller]`.
    #[serde(default, deserialize_with = "split_tables::controller_table")]
    pub controller: ControllerConfig,
    /// `[reference]`.
    #[serde(default)]
    pub reference: ReferenceConfig,
    /// `[simulation]`.
    #[serde(default)]
    pub simulation: SimulationConfig,
    /// `[[disturbances]]`: external wrenches on links over time windows (none by default).
    #[serde(default)]
    pub disturbances: Vec<DisturbanceConfig>,
    /// `[sensing]`: measurement noise and delay of the controller's state (default: perfect).
    #[serde(default)]
    pub sensing: SensingConfig,
    /// `[walking]`: the robot walks the gait of these settings (`sea_ctrl`'s
    /// `WalkingSettings`, read as they stand: the footsteps, their timing, the swing);
    /// absent: it stands (docs/explanation/walking.md).
    #[serde(default)]
    pub walking: Option<sea_ctrl::walking::WalkingSettings>,
    /// The keys `[walking]` gives (after the overrides) when the robot description is not the
    /// paper's iCub: at build the keys it leaves out take the defaults scaled to the robot
    /// (`WalkingSettings::scaled_to`, [`walking::walking_settings`]); `None`: `walking` as
    /// read (the iCub-sized defaults).
    #[serde(skip)]
    pub walking_given: Option<toml::Table>,
    /// Folder of the scenario file (for relative paths).
    #[serde(skip)]
    pub base_dir: PathBuf,
    /// The file, text and overrides the scenario was read from ([`Origin::locate`] gives a
    /// key's error found later its file and line).
    #[serde(skip)]
    pub origin: Arc<Origin>,
    /// The file of the robot description, when `robot.description` names one (its keys'
    /// errors name it, [`Scenario::description_key`]).
    #[serde(skip)]
    pub description_file: Option<PathBuf>,
    /// The robot description of `robot.description` (the paper's iCub by default), read
    /// before the tables: their defaults come from it.
    #[serde(skip, default = "paper_icub")]
    pub description: Arc<RobotDescription>,
}

/// The built-in description (serde default of [`Scenario::description`], replaced when read).
fn paper_icub() -> Arc<RobotDescription> {
    Arc::new(icub().clone())
}

impl Scenario {
    /// Parses TOML text with `overrides` (`key=value`). A key's error gives its line in
    /// `text` unless an override set it.
    pub fn from_toml(
        text: &str,
        overrides: &[(String, String)],
        base_dir: &Path,
    ) -> Result<Scenario> {
        let root: toml::Table = toml::from_str(text).map_err(|e| syntax_error(&e, text))?;
        let origin = Origin::of_text(text, overrides);
        let mut scenario =
            Self::from_tree(root, overrides, base_dir).map_err(|e| origin.locate(e))?;
        scenario.origin = Arc::new(origin);
        Ok(scenario)
    }

    /// [`Scenario::from_toml`] from the parsed text `root`.
    fn from_tree(
        mut root: toml::Table,
        overrides: &[(String, String)],
        base_dir: &Path,
    ) -> Result<Scenario> {
        for (key, value) in overrides {
            apply_override(&mut root, key, value)?;
        }
        let source = robots::defaults::take_and_apply(&mut root, base_dir)?;
        let walking_given = match root.get("walking") {
            Some(toml::Value::Table(given)) if source.description != *icub() => Some(given.clone()),
            _ => None,
        };
        let mut scenario: Scenario = parse::read_value(toml::Value::Table(root.clone()))
            .map_err(|e| schema_error(e, &root))?;
        scenario.walking_given = walking_given;
        scenario.base_dir = base_dir.to_path_buf();
        scenario.description = Arc::new(source.description);
        scenario.description_file = source.file;
        scenario.resolve_urdf_uri()?;
        scenario.validate()?;
        Ok(scenario)
    }

    /// Replaces a `package://` or `file://` URI in `robot.urdf` by the file it names (the
    /// scenario's `robot.package_dirs` first, then the environment's); an error names the key
    /// the URI came from (the robot description's `urdf`, [`Scenario::description_key`], when
    /// the description gave it) and where a scenario lists its folders.
    fn resolve_urdf_uri(&mut self) -> Result<()> {
        let uri = &self.robot.urdf;
        if !uri.contains("://") {
            return Ok(());
        }
        let user = self.robot.package_dirs.iter().map(|d| self.resolve(d));
        let dirs = sea_dyn::PackageDirs::from_environment(user);
        let key = if self.description.urdf.as_deref() == Some(uri.as_str()) {
            self.description_key("urdf")
        } else {
            "robot.urdf".to_string()
        };
        let path = dirs.resolve(uri, &self.base_dir).map_err(|e| {
            let rule = format!("{e}; a scenario lists its folders in robot.package_dirs");
            Error::invalid(key, rule, uri)
        })?;
        self.robot.urdf = path.display().to_string();
        Ok(())
    }

    /// The key of the robot description's `name` in an error: `robot description FILE: name`
    /// when the description is a file of its own (as its own errors say when it is read),
    /// else `robot.description.name` (built in, or inline in the scenario).
    pub fn description_key(&self, name: &str) -> String {
        match &self.description_file {
            Some(file) => format!("robot description {}: {name}", file.display()),
            None => format!("robot.description.{name}"),
        }
    }

    /// Reads a scenario file with overrides.
    pub fn from_file(path: &Path, overrides: &[(String, String)]) -> Result<Scenario> {
        let text =
            read_text_within(path, MAX_TOML_BYTES).map_err(|source| Error::io(path, source))?;
        Self::from_file_text(path, &text, overrides)
    }

    /// [`Scenario::from_file`] of `text`, already read from `path` (relative paths resolved
    /// from its folder, errors naming it).
    pub fn from_file_text(
        path: &Path,
        text: &str,
        overrides: &[(String, String)],
    ) -> Result<Scenario> {
        let base = path.parent().unwrap_or(Path::new("."));
        let mut scenario = Self::from_toml(text, overrides, base).map_err(|e| e.in_file(path))?;
        Arc::make_mut(&mut scenario.origin).file = Some(path.to_path_buf());
        Ok(scenario)
    }

    /// The robot's URDF file: `robot.urdf` (from the scenario or its robot description, a
    /// `package://` or `file://` URI already resolved when read) through [`Scenario::resolve`].
    pub fn urdf_path(&self) -> PathBuf {
        self.resolve(&self.robot.urdf)
    }

    /// The files the scenario was read from, each with its role in an error message: the
    /// scenario file (when it was read from one), the robot description's file (when
    /// `robot.description` names one) and the URDF. An output must be none of them.
    pub fn input_files(&self) -> Vec<(&'static str, PathBuf)> {
        let scenario = self
            .origin
            .file
            .clone()
            .map(|file| ("the scenario file", file));
        let description = self
            .description_file
            .clone()
            .map(|file| ("the robot description file", file));
        scenario
            .into_iter()
            .chain(description)
            .chain([("the URDF", self.urdf_path())])
            .collect()
    }

    /// Resolves a path of the scenario: relative to its folder if it exists there, else as is
    /// if it exists so (from the working directory); a path found at neither is named from the
    /// scenario's folder, where the scenario's relative paths belong (the error of a file not
    /// found then says where it was looked for).
    pub fn resolve(&self, path: &str) -> PathBuf {
        let candidate = self.base_dir.join(path);
        if candidate.exists() || !Path::new(path).exists() {
            candidate
        } else {
            PathBuf::from(path)
        }
    }

    /// Checks every value against its meaning ([`validate::scenario`]).
    fn validate(&self) -> Result<()> {
        validate::scenario(self)
    }

    /// Contact constraints of the QP.
    pub fn contact_constraints(&self) -> ContactConstraints {
        self.controller.contact.clone()
    }

    /// The link of each `[[disturbances]]` entry, in order (the logs name and draw pushes by
    /// them).
    pub fn disturbance_links(&self) -> Vec<String> {
        self.disturbances.iter().map(|d| d.link.clone()).collect()
    }

    /// `controller.stiffness_estimate_joint_scales` as one factor per joint (n, coordinate
    /// order; empty when none is given); an unknown joint name is an error naming it.
    fn stiffness_estimate_joint_scales(&self, joint_names: &[String]) -> Result<Vec<f64>> {
        let scales = &self.controller.tuning.stiffness_estimate_joint_scales;
        if scales.is_empty() {
            return Ok(Vec::new());
        }
        let mut out = vec![1.0; joint_names.len()];
        for (name, &scale) in scales {
            let key = format!("controller.stiffness_estimate_joint_scales.{name}");
            let Some(j) = joint_names.iter().position(|joint| joint == name) else {
                return Err(Error::config(key, "is not a joint of the model"));
            };
            out[j] = scale;
        }
        Ok(out)
    }

    /// The controller's model: `model` with the masses and rotational inertias scaled by
    /// `controller.mass_estimate_scale` and `controller.link_mass_estimate_scales` (an unknown
    /// link is an error naming its key; the factors are bounded when the file is read).
    pub fn controller_model(&self, model: &Model) -> Result<Model> {
        let tuning = &self.controller.tuning;
        let mut scales = vec![tuning.mass_estimate_scale; model.body_inertias.len()];
        for (link, &scale) in &tuning.link_mass_estimate_scales {
            let key = format!("controller.link_mass_estimate_scales.{link}");
            let Ok(frame) = model.frame_id(link) else {
                return Err(Error::config(key, "is not a link of the model"));
            };
            scales[model.frames[frame].body] *= scale;
        }
        let mut scaled = model.clone();
        for (inertia, scale) in scaled.body_inertias.iter_mut().zip(scales) {
            inertia.mass *= scale;
            inertia.inertia_com *= scale;
        }
        Ok(scaled)
    }

    /// Controller settings for a model with `joint_names`: `controller`'s tuning as read, the
    /// gains it leaves out from the robot description.
    pub fn controller_settings(&self, joint_names: &[String]) -> Result<ControllerSettings> {
        let one_foot = self.robot.contacts.len() == 1;
        let tuning = &self.controller.tuning;
        let integral = tuning
            .momentum_integral
            .unwrap_or_else(|| self.description.momentum_integral.gains(one_foot));
        let proportional = tuning
            .momentum_proportional
            .unwrap_or(integral.map(critical_damping));
        let stiffness: Vec<f64> = match &tuning.postural_stiffness {
            Some(values) if values.len() == joint_names.len() => values.clone(),
            Some(values) => {
                return Err(Error::config(
                    "controller.postural_stiffness",
                    format!("needs {} entries, got {}", joint_names.len(), values.len()),
                ))
            }
            None => joint_names
                .iter()
                .map(|name| {
                    let stiffness = &self.description.postural_stiffness;
                    stiffness.of(name, &self.robot.contacts)
                })
                .collect(),
        }
        .into_iter()
        .map(|k| k * tuning.postural_scale)
        .collect();
        let damping = stiffness.iter().copied().map(critical_damping).collect();
        let stiffness_estimate_joint_scales = self.stiffness_estimate_joint_scales(joint_names)?;
        Ok(ControllerSettings {
            kind: self.controller.kind,
            contacts: self.robot.contacts.clone(),
            momentum_proportional: proportional,
            momentum_integral: integral,
            postural_stiffness: stiffness,
            postural_damping: damping,
            constraints: self.contact_constraints(),
            stiffness_estimate_joint_scales,
            tuning: tuning.clone(),
        })
    }
}

/// Expands joint names and groups of the robot description `robot` (the iCub's: "torso",
/// "arms", "left_arm", "right_arm", "upper_body") into joint names, in order.
pub fn expand_joint_groups(
    robot: &RobotDescription,
    entries: &[String],
    joint_names: &[String],
) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for entry in entries {
        if let Some(group) = robot.group(entry, joint_names) {
            out.extend(group);
        } else if joint_names.contains(entry) {
            out.push(entry.clone());
        } else {
            return Err(Error::config(
                "reference.posture_step_joints",
                format!("unknown joint or group '{entry}'"),
            ));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sea_dyn::{Actuator, ElasticParameters};
    use sea_plant::Plant;

    #[test]
    fn overrides_and_unknown_keys() {
        let text = "[robot]\nurdf = \"x.urdf\"\n";
        let s = Scenario::from_toml(
            text,
            &[("controller.kind".into(), "rigid".into())],
            Path::new("."),
        )
        .unwrap();
        assert_eq!(s.controller.kind, ControllerKind::Rigid);
        let s = Scenario::from_toml(
            text,
            &[("controller.damping_estimate_scale".into(), "1.45".into())],
            Path::new("."),
        )
        .unwrap();
        assert_eq!(s.controller.tuning.damping_estimate_scale, 1.45);
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
        let err = Scenario::from_toml(
            text,
            &[("robot.urdf".into(), "\"\"".into())],
            Path::new("."),
        )
        .unwrap_err();
        assert!(
            err.to_string().contains("'robot.urdf': must name a URDF"),
            "{err}"
        );
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
        let sea = s.actuators.default.actuator();
        assert_eq!(sea, Actuator::Elastic(ElasticParameters::default()));
        assert_eq!(s.contact_constraints(), ContactConstraints::default());
        assert_eq!(s.plant.baumgarte_kp, Plant::DEFAULT_BAUMGARTE_KP);
        assert_eq!(
            s.plant.baumgarte_kd(),
            critical_damping(Plant::DEFAULT_BAUMGARTE_KP)
        );
        // The tuning's own defaults (the schema's) are the paper's iCub, the default robot.
        let tuning = sea_ctrl::controller::ControllerTuning::default();
        assert_eq!(s.controller.tuning, tuning);
        assert_eq!(ControllerConfig::default().tuning, tuning);
        let excitation = &s.controller.excitation;
        assert_eq!(
            *excitation,
            sea_ctrl::excitation::ExcitationSettings::default()
        );
        let observer = sea_ctrl::external_wrench::ExternalWrenchSettings::default();
        assert_eq!(s.controller.wrench_observer, observer);
    }

    #[test]
    fn actuator_overrides_replace_only_their_keys() {
        let text = "[robot]\nurdf = \"x.urdf\"\n[actuators]\nstiffness = 100.0\n\
                    [actuators.overrides.l_knee]\ndamping = 2.0\n";
        let s = Scenario::from_toml(text, &[], Path::new(".")).unwrap();
        let knee = &s.actuators.overrides["l_knee"].parameters;
        assert_eq!((knee.stiffness, knee.damping), (100.0, 2.0));
        let default = &s.actuators.default.parameters;
        assert_eq!(default.damping, ElasticParameters::default().damping);
        assert_eq!(knee.ratio, default.ratio);
    }

    #[test]
    fn a_rigid_override_given_an_elastic_key_is_refused_naming_it() {
        let text = "[robot]\nurdf = \"x.urdf\"\n[actuators]\nstiffness = 100.0\n\
                    [actuators.overrides.l_knee]\nkind = \"rigid\"\ndamping = 2.0\n";
        let message = Scenario::from_toml(text, &[], Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("actuators.overrides.l_knee.damping")
                && message.contains("given with kind = \"rigid\""),
            "{message}"
        );
        // The default's keys stay the default's: a rigid override inherits them unread.
        let inherits = "[robot]\nurdf = \"x.urdf\"\n[actuators]\nstiffness = 100.0\n\
                        [actuators.overrides.l_knee]\nkind = \"rigid\"\n";
        Scenario::from_toml(inherits, &[], Path::new(".")).unwrap();
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

    /// The scenario error of the base scenario with `key = value`.
    fn refusal(key: &str, value: &str) -> (String, String) {
        let text = "[robot]\nurdf = \"x.urdf\"\n";
        let overrides = [(key.to_string(), value.to_string())];
        match Scenario::from_toml(text, &overrides, Path::new(".")) {
            Err(error @ Error::Scenario { .. }) => {
                let message = error.to_string();
                let Error::Scenario { key, .. } = error else {
                    unreachable!()
                };
                (key, message)
            }
            other => panic!("{key} = {value}: {other:?}"),
        }
    }

    #[test]
    fn unknown_setting_names_are_refused_with_the_allowed_names() {
        for (key, value, allowed) in [
            ("actuators.kind", "hydraulic", "'elastic', 'rigid'"),
            ("actuators.overrides.l_knee.kind", "x", "'elastic', 'rigid'"),
            ("plant.method", "euler", "'ros2', 'implicit_euler', 'rk4'"),
            ("controller.kind", "pid", "'sea', 'rigid'"),
            (
                "controller.sampling",
                "zoh",
                "'continuous', 'zero_order_hold', 'multi_rate'",
            ),
            (
                "controller.qp_solver",
                "quadprog",
                "'active_set', 'clarabel'",
            ),
            ("reference.com_origin", "origin", "'stance_sole', 'initial'"),
        ] {
            let (named, message) = refusal(key, value);
            assert_eq!(named, key, "{message}");
            let expected = format!("must be one of {allowed}, got '{value}'");
            assert!(message.ends_with(&expected), "{message}");
        }
        for key in ["controller.kind", "actuators.overrides.l_knee.kind"] {
            let (named, message) = refusal(key, "3");
            assert_eq!(named, key, "{message}");
            assert!(
                message.ends_with("integer `3`, expected a string"),
                "{message}"
            );
        }
    }

    #[test]
    fn w_refresh_steps_below_one_are_refused_naming_the_key() {
        for value in ["0", "-1", "2.5"] {
            let (named, message) = refusal("plant.w_refresh_steps", value);
            assert_eq!(named, "plant.w_refresh_steps", "{message}");
        }
    }

    #[test]
    fn unknown_keys_list_every_key_of_their_table() {
        let (_, message) = refusal("actuators.stifness", "1");
        assert!(message.contains("one of `kind`, `ratio`"), "{message}");
        let (_, message) = refusal("controller.contact.frictoin", "1");
        assert!(
            message.contains("`facets`, `min_normal_force`, `cop_margin`, `friction`"),
            "{message}"
        );
    }

    #[test]
    fn settings_are_read_into_their_types() {
        let text = "[robot]\nurdf = \"x.urdf\"\n";
        let overrides = [
            ("actuators.kind", "rigid"),
            ("plant.method", "implicit_euler"),
            ("controller.kind", "rigid"),
            ("controller.sampling", "continuous"),
            ("controller.qp_solver", "clarabel"),
            ("reference.com_origin", "initial"),
        ]
        .map(|(k, v)| (k.to_string(), v.to_string()));
        let s = Scenario::from_toml(text, &overrides, Path::new(".")).unwrap();
        assert_eq!(s.actuators.default.kind, ActuatorKind::Rigid);
        assert_eq!(s.plant.method, Method::LinearlyImplicitEuler);
        assert_eq!(s.controller.kind, ControllerKind::Rigid);
        assert_eq!(s.controller.sampling, Sampling::Continuous);
        assert_eq!(s.controller.tuning.qp_solver, QpSolver::Clarabel);
        assert_eq!(s.reference.com_origin, ComOrigin::Initial);
    }

    #[test]
    fn the_joint_loop_settings_are_read_directly_from_the_flat_table() {
        let text = "[robot]\nurdf = \"x.urdf\"\n[controller]\ntorque_loop_paper_law = true\n\
                    joint_stiffness = 30.0\n";
        let s = Scenario::from_toml(text, &[], Path::new(".")).unwrap();
        let joint_loops = &s.controller.joint_loops;
        assert!(joint_loops.paper_law);
        assert_eq!(joint_loops.joint_stiffness, 30.0);
        assert_eq!(s.controller.torque_bandwidth(), None);
        let defaults = sea_ctrl::joint_loop::JointLoopSettings::default();
        assert_eq!(
            joint_loops.torque_bandwidth_hz,
            defaults.torque_bandwidth_hz
        );
        let table = s.controller.table().unwrap();
        assert_eq!(table["torque_loop_paper_law"].as_bool(), Some(true));
        assert_eq!(table["joint_stiffness"].as_float(), Some(30.0));
        let (named, message) = refusal("controller.joint_loops", "1");
        assert_eq!(named, "controller.joint_loops", "{message}");
    }

    #[test]
    fn the_identification_settings_are_read_directly_from_the_flat_table() {
        let text = "[robot]\nurdf = \"x.urdf\"\n[controller]\nidentification_time_s = 2.5\n\
                    identification_range_factor = 4.0\nqp_solver = \"clarabel\"\n";
        let s = Scenario::from_toml(text, &[], Path::new(".")).unwrap();
        let identification = &s.controller.identification;
        assert_eq!(identification.time_constant, 2.5);
        assert_eq!(identification.range_factor, 4.0);
        let defaults = sea_ctrl::stiffness_id::IdentificationSettings::default();
        assert_eq!(identification.filter_bandwidth, defaults.filter_bandwidth);
        assert_eq!(s.controller.tuning.qp_solver, QpSolver::Clarabel);
        let table = s.controller.table().unwrap();
        assert_eq!(table["identification_time_s"].as_float(), Some(2.5));
        assert!(!table.contains_key("identification"));
        // The field holding them is no key of the file.
        let (named, message) = refusal("controller.identification.time_constant", "1");
        assert_eq!(named, "controller.identification", "{message}");
        assert!(
            message.contains("unknown field `identification`"),
            "{message}"
        );
        let (named, message) = refusal("controller.identification_time_s", "0");
        assert_eq!(named, "controller.identification_time_s", "{message}");
        assert!(
            message.ends_with("must be positive and finite, got 0"),
            "{message}"
        );
    }

    #[test]
    fn contact_table_errors_name_the_key() {
        for (key, value) in [
            ("controller.contact.frictoin", "1.0"),
            ("controller.contact.facets", "\"many\""),
            ("controller.contact.friction", "false"),
            ("controller.contact.foot_x", "[1.0]"),
        ] {
            let (named, message) = refusal(key, value);
            assert_eq!(named, key, "{message}");
        }
        let text = "[robot]\nurdf = \"x.urdf\"\n[controller.contact]\nfriction = 0.5\nfacets = 8\n";
        let s = Scenario::from_toml(text, &[], Path::new(".")).unwrap();
        let contact = &s.controller.contact;
        assert_eq!((contact.surface.friction, contact.facets), (0.5, 8));
        assert_eq!(
            contact.min_normal_force,
            ContactConstraints::default().min_normal_force
        );
    }
}
