//! `sea_momentum.Controller` and `sea_momentum.Scenario`: the momentum controller as an object
//! that any simulator (or a robot's state estimate) can drive tick by tick, and a scenario file
//! built into its model, plant, controller and initial state.
//!
//! Both are built by `sea_sim::scenario` (the scenario's `build`, or the same functions on a
//! model given from Python), and `Controller` is the robot's controller stack
//! ([`RobotController`]: the whole-body law, the joint torque loops, the stiffness
//! identification and its excitation, the observers) that the native loop runs: a Python
//! loop of `Controller.tick`, `Controller.inner_tick` (`controller.sampling = "multi_rate"`),
//! `Plant.step` and `Controller.end_period` is the run of `run_scenario`.

use crate::arrays::{matrix_rows_out, vector_arg, vector_out};
use crate::errors::{argument_error, to_py, warn_user};
use crate::model::PyModel;
use crate::numbers::Real;
use crate::overrides::toml_literal;
use crate::plant::PyPlant;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sea_ctrl::controller::MomentumController;
use sea_ctrl::feedback::{FeedbackLaw, Observation};
use sea_ctrl::qp::QpStatus;
use sea_ctrl::references::{ComTrajectory, PostureReference};
use sea_ctrl::robot::{ForceReadings, PeriodSensors, RobotController};
use sea_dyn::{Model, StateLayout};
use sea_sim::closed_loop::Schedule;
use sea_sim::scenario::{build, Sampling, Scenario};
use std::collections::HashMap;
use std::path::PathBuf;

/// The momentum controller with its CoM and postural references: `tick(t, x)` is the
/// closed loop's feedback law ([`FeedbackLaw`], the one the native loop runs) at time `t` and
/// plant state `x`.
///
/// State x = [q (nq), theta (n_e), nu (nv), thetadot (n_e)] (theta, thetadot: elastic joints
/// only; a rigid robot has x = [q, nu]). Build it from a `Model` with the keys of a scenario's
/// `[controller]` table (`Controller(model, contacts, q0, **settings)` or
/// `Controller.from_table`), or take a scenario's (`Scenario.load(path).controller`).
#[pyclass(name = "Controller", module = "sea_momentum._native")]
pub struct PyController {
    /// The controller stack: the whole-body law (the controller, its references and the last
    /// tick's outputs), the joint loops, the identification and the observers.
    robot: RobotController,
    contacts: Vec<String>,
    joint_names: Vec<String>,
    /// The state of the last tick, copied from Python (nx).
    x: Vec<f64>,
    /// The force readings of `end_period`, copied from Python: contact wrenches (6 per
    /// contact) and joint torques (n) at the period's start and end, and the contact
    /// wrenches' mean over the period.
    readings: [nalgebra::DVector<f64>; 5],
    /// Whether a `tick` succeeded since the last `end_period` (the period is open: its
    /// `inner_tick`s and its one `end_period` may follow).
    period_open: bool,
    /// Whether any `tick` succeeded (before it the joint loops hold nothing).
    ticked: bool,
}

impl PyController {
    /// The object of a built controller and its references, reading states of `layout`, with
    /// the stack of `scenario`'s `[controller]` ticking on `schedule` (the joint torque loops
    /// when it is `multi_rate`, the identification, the observers).
    fn new_built(
        controller: MomentumController,
        (com_reference, posture): (ComTrajectory, PostureReference),
        layout: StateLayout,
        joint_names: Vec<String>,
        (scenario, schedule): (&Scenario, &Schedule),
    ) -> PyResult<Self> {
        let settings = &scenario.controller;
        let multi_rate = settings.sampling == Sampling::MultiRate;
        let parts = settings
            .stack_parts(&controller, schedule.period, multi_rate)
            .map_err(to_py)?;
        let (n, k) = (
            controller.model().n_joints(),
            6 * controller.contact_frames().len(),
        );
        let readings = [k, n, k, n, k].map(nalgebra::DVector::zeros);
        let law = FeedbackLaw::new(controller, com_reference, posture, layout);
        Ok(Self {
            contacts: law.controller().settings().contacts.clone(),
            x: Vec::with_capacity(layout.nx()),
            robot: RobotController::new(law, parts, schedule.period),
            joint_names,
            readings,
            period_open: false,
            ticked: false,
        })
    }

    /// A controller for `model` from scenario tables given as Python dicts: `settings` is the
    /// `[controller]` table, `actuators` the `[actuators]` table, `reference` the
    /// `[reference]` table, `walking` the `[walking]` table (the gait planned from `q0`'s
    /// feet; its warnings are `UserWarning`s); the contacts are held at their pose in `q0`
    /// and the posture reference is `q0`'s joints. The tables are checked exactly as in a
    /// scenario file.
    fn from_tables(
        model: &Model,
        contacts: Vec<String>,
        q0: &Bound<'_, PyAny>,
        tables: [(&str, Option<&Bound<'_, PyDict>>); 4],
    ) -> PyResult<Self> {
        let mut q = Vec::new();
        vector_arg(q0, "q0", model.nq(), &mut q)?;
        model.check_configuration_named("q0", &q).map_err(to_py)?;
        let scenario = table_scenario(&contacts, &q[7..], tables)?;
        sea_sim::scenario::validate::against_model(
            &scenario,
            model.total_mass(),
            model.gravity.norm(),
        )
        .map_err(to_py)?;
        let actuation = build::actuation(&scenario, model).map_err(to_py)?;
        let frames = build::contact_frames(&scenario, model).map_err(to_py)?;
        let settings = scenario
            .controller_settings(&model.joint_names)
            .map_err(to_py)?;
        let mut controller =
            MomentumController::new(model, &actuation, settings, &q).map_err(to_py)?;
        let warnings =
            sea_sim::scenario::walking::set_up(&scenario, model, &frames, &q, &mut controller)
                .map_err(to_py)?;
        for warning in &warnings {
            warn_user(q0.py(), warning)?;
        }
        let com_reference = build::com_reference(&scenario, model, &q, frames[0]).map_err(to_py)?;
        let posture = build::posture_reference(&scenario, model, q[7..].to_vec()).map_err(to_py)?;
        let layout = StateLayout::new(model, &actuation);
        let schedule = scenario.schedule();
        Self::new_built(
            controller,
            (com_reference, posture),
            layout,
            model.joint_names.clone(),
            (&scenario, &schedule),
        )
    }
}

/// A tick's outputs with the CoM reference (world) they tracked, as a
/// `sea_momentum.controller.ControlOutput`; `input` is the plant input (the tick's, or the
/// joint loops' first with `multi_rate`).
fn output_object<'py>(
    py: Python<'py>,
    observation: &Observation,
    input: &[f64],
) -> PyResult<Bound<'py, PyAny>> {
    let out = &observation.output;
    let fields = PyDict::new(py);
    fields.set_item(
        "com_reference",
        vector_out(py, observation.reference.position.as_slice()),
    )?;
    fields.set_item("input", vector_out(py, input))?;
    fields.set_item("joint_command", vector_out(py, &out.joint_command))?;
    fields.set_item("thetadot_desired", vector_out(py, &out.thetadot_desired))?;
    fields.set_item("wrenches", matrix_rows_out(py, out.wrenches.as_slice(), 6))?;
    let (status, message) = match &out.qp_status {
        QpStatus::Solved => ("solved", ""),
        QpStatus::MomentumRelaxed => ("momentum_relaxed", ""),
        QpStatus::Fallback(reason) => ("fallback", reason.as_str()),
    };
    fields.set_item("qp_status", status)?;
    fields.set_item("qp_message", message)?;
    fields.set_item("com", vector_out(py, out.com.as_slice()))?;
    fields.set_item("momentum", vector_out(py, out.momentum.as_slice()))?;
    let external_wrench = out.external_wrench.as_slice();
    fields.set_item("external_wrench", vector_out(py, external_wrench))?;
    py.import("sea_momentum.controller")?
        .getattr("ControlOutput")?
        .call((), Some(&fields))
}

/// A scenario holding only the tables a controller needs: `[robot]` with `contacts` and the
/// initial posture `s0`, and the given tables (dicts, nested dicts are sub-tables), every key
/// an override of an empty text, so that it is parsed and validated as in a scenario file and
/// its error names it (`controller.postural_scale`) with no line of a text the caller never
/// wrote.
fn table_scenario(
    contacts: &[String],
    s0: &[f64],
    tables: [(&str, Option<&Bound<'_, PyDict>>); 4],
) -> PyResult<Scenario> {
    let literal = |value: toml::Value| value.to_string();
    let mut pairs = vec![
        // Never read: the model is given from Python (the scenario's build is not called).
        (
            "robot.urdf".to_string(),
            literal("(model given from Python)".into()),
        ),
        (
            "robot.contacts".to_string(),
            literal(contacts.to_vec().into()),
        ),
        (
            "robot.initial_posture".to_string(),
            literal(s0.to_vec().into()),
        ),
    ];
    let walks = tables
        .iter()
        .any(|&(name, table)| name == "walking" && table.is_some());
    if walks {
        // The controller reads no plant key; a walk needs feet that can lift off the ground,
        // which the caller's robot (or plant) has.
        let unilateral = literal("unilateral".into());
        pairs.push(("plant.contact_model".to_string(), unilateral));
    }
    for (name, table) in tables {
        match table {
            // An empty dict is the table with its defaults (`walking={}`: a walk, no command).
            Some(table) if table.is_empty() => pairs.push((name.to_string(), "{}".to_string())),
            Some(table) => flatten_table(name, table, &mut pairs)?,
            None => {}
        }
    }
    Scenario::from_toml("", &pairs, std::path::Path::new(".")).map_err(to_py)
}

/// A dict's entries as `prefix.key=value` override pairs (TOML literals), nested dicts as
/// dotted sub-keys (an empty one as an empty table).
fn flatten_table(
    prefix: &str,
    table: &Bound<'_, PyDict>,
    pairs: &mut Vec<(String, String)>,
) -> PyResult<()> {
    for (key, value) in table.iter() {
        let key: String = key
            .extract()
            .map_err(|_| argument_error(prefix, "a dict with str keys", &key))?;
        let dotted = format!("{prefix}.{key}");
        match value.cast::<PyDict>() {
            Ok(sub) if sub.is_empty() => pairs.push((dotted, "{}".to_string())),
            Ok(sub) => flatten_table(&dotted, sub, pairs)?,
            Err(_) => pairs.push((dotted.clone(), toml_literal(&value, &dotted)?)),
        }
    }
    Ok(())
}

#[pymethods]
impl PyController {
    /// A controller for `model` balancing on `contacts` (one or two frames, stance foot first),
    /// held at their pose in `q0` (nq); the postural reference is `q0`'s joints.
    ///
    /// `settings`: the keys of a scenario's `[controller]` table (kind="rigid", postural_scale,
    /// momentum_integral, contact={"friction": ...}, ...), defaults as in a scenario file.
    /// `actuators`: the `[actuators]` table (default: the paper's SEA on every joint; use
    /// {"kind": "rigid"} for a torque-controlled robot). `reference`: the `[reference]` table
    /// (CoM sinusoid, com_origin "stance_sole" (default) or "initial", postural step).
    /// `walking`: the `[walking]` table (two contacts, the feet): the robot walks the gait
    /// planned from the feet in `q0`, with the defaults of a scenario file without
    /// `robot.description` (the paper's iCub's; another robot gives its own keys, e.g. those
    /// `sea-sim init` writes); a command the step limits clip is a `UserWarning`.
    #[new]
    #[pyo3(signature = (model, contacts, q0, *, actuators=None, reference=None, walking=None, **settings))]
    fn new(
        model: PyRef<'_, PyModel>,
        contacts: Vec<String>,
        q0: &Bound<'_, PyAny>,
        actuators: Option<&Bound<'_, PyDict>>,
        reference: Option<&Bound<'_, PyDict>>,
        walking: Option<&Bound<'_, PyDict>>,
        settings: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        Self::from_tables(
            model.model(),
            contacts,
            q0,
            [
                ("controller", settings),
                ("actuators", actuators),
                ("reference", reference),
                ("walking", walking),
            ],
        )
    }

    /// The same as `Controller(model, contacts, q0, actuators=..., reference=...,
    /// walking=..., **table)` with the `[controller]` table as a dict.
    #[staticmethod]
    #[pyo3(signature = (model, table, q0, contacts, actuators=None, reference=None, walking=None))]
    fn from_table(
        model: PyRef<'_, PyModel>,
        table: &Bound<'_, PyDict>,
        q0: &Bound<'_, PyAny>,
        contacts: Vec<String>,
        actuators: Option<&Bound<'_, PyDict>>,
        reference: Option<&Bound<'_, PyDict>>,
        walking: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        Self::from_tables(
            model.model(),
            contacts,
            q0,
            [
                ("controller", Some(table)),
                ("actuators", actuators),
                ("reference", reference),
                ("walking", walking),
            ],
        )
    }

    /// The whole-body tick at time `t` [s] and measured plant state `x` (nx): a
    /// `sea_momentum.ControlOutput` (plant input, joint command, desired motor velocities,
    /// QP wrenches, QP status, CoM, momentum, CoM reference). With `multi_rate` the tick's
    /// joint torques (and the identification's excitation) are held by the joint loops and
    /// `input` is their first inner tick's. A tick that fails raises `SolverError`; the last
    /// command stays `command`.
    ///
    /// Bad input (the per-tick contract, docs/guide/robot_rate.md): a non-finite `t`, an `x` of
    /// another length, with a NaN or infinite entry or a base quaternion `x[3:7]` not of unit
    /// norm raises `ValueError` naming it (`x[12]`)
    /// and changes nothing (`command` stays the last). The clock is not checked: `t` is the
    /// references' time, so a tick called twice at the same `(t, x)` returns the same command,
    /// and a late tick (missed periods) evaluates the law at its own `t` and state; the
    /// estimators skip the missed periods' updates.
    fn tick<'py>(
        &mut self,
        py: Python<'py>,
        t: Real,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let Real(t) = t;
        sea_dyn::error::check_non_negative("t", t).map_err(to_py)?;
        let layout = self.robot.layout();
        vector_arg(x, "x", layout.nx(), &mut self.x)?;
        let model = self.robot.controller().model();
        model
            .check_configuration_named("x", &self.x[..model.nq()])
            .map_err(to_py)?;
        self.robot.tick(t, &self.x).map_err(to_py)?;
        self.period_open = true;
        self.ticked = true;
        output_object(py, self.robot.last(), self.robot.command())
    }

    /// `controller.sampling = "multi_rate"`: one tick of the joint torque loops at the
    /// measured state `x` (nx) between two `tick`s (every `Scenario.steps_per_inner_tick`
    /// plant steps after the first): the plant input (n), each elastic joint's desired motor
    /// velocity from the held joint torque and the measured deflection. Raises
    /// `RuntimeError` before the first `tick`, `ValueError` for a bad `x` (as `tick`).
    fn inner_tick<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let layout = self.robot.layout();
        if self.robot.joint_loop().is_none() {
            return Err(argument_error(
                "Controller.inner_tick",
                "a controller with controller.sampling = \"multi_rate\"",
                "another sampling",
            ));
        }
        if !self.ticked {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "Controller.inner_tick: no tick yet (call tick(t, x) first: the joint loops \
                 hold the torques of the last tick)",
            ));
        }
        vector_arg(x, "x", layout.nx(), &mut self.x)?;
        Ok(vector_out(py, self.robot.joint_tick(&self.x)))
    }

    /// After the period that began at the last `tick` (its plant steps done), before the next
    /// `tick`: the force readings of the period, each a float array: the feet's wrenches
    /// (n_contacts, 6) or (6 n_contacts,) and the joint torques (n,) at the period's start
    /// (`Plant.outputs` at the tick's state and command) and at its end (at the start of the
    /// period's last plant step). The stiffness identification
    /// (`controller.stiffness_identification`) and the observers (`controller.external_wrench`)
    /// update from them; their estimates act from the next `tick` on. Without them it does
    /// nothing. Once per period: a second call before the next `tick`, or a call before any
    /// tick, raises `RuntimeError` (the estimators would take the period twice); a reading of
    /// another size or with a non-finite entry raises `ValueError` naming it and updates
    /// nothing. `mean_wrenches` (keyword, optional): the feet's wrenches averaged over the
    /// period (read at every plant step or joint tick), which the external wrench observer
    /// then takes instead of the two instants (a foot bouncing within the period aliases them).
    #[pyo3(signature = (start_wrenches, start_joint_torques, end_wrenches, end_joint_torques, *, mean_wrenches=None))]
    fn end_period(
        &mut self,
        start_wrenches: &Bound<'_, PyAny>,
        start_joint_torques: &Bound<'_, PyAny>,
        end_wrenches: &Bound<'_, PyAny>,
        end_joint_torques: &Bound<'_, PyAny>,
        mean_wrenches: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut arguments = vec![
            ("start_wrenches", start_wrenches),
            ("start_joint_torques", start_joint_torques),
            ("end_wrenches", end_wrenches),
            ("end_joint_torques", end_joint_torques),
        ];
        arguments.extend(mean_wrenches.map(|mean| ("mean_wrenches", mean)));
        if !self.period_open {
            let when = if self.ticked {
                "called twice in one period (once after each tick)"
            } else {
                "no tick yet (call it after each tick's period)"
            };
            return Err(pyo3::exceptions::PyRuntimeError::new_err(format!(
                "Controller.end_period: {when}"
            )));
        }
        let mut values = Vec::new();
        for ((name, value), reading) in arguments.into_iter().zip(&mut self.readings) {
            // The wrenches as `Plant.outputs` gives them, (n_contacts, 6), or flat.
            let numpy = value.py().import("numpy")?;
            let flat = numpy
                .call_method1("ravel", (value,))
                .map_err(|_| argument_error(name, "an array of numbers", value))?;
            let n = reading.len();
            if flat.len()? != n {
                // The shape as given, not as flattened.
                let given = numpy.call_method1("shape", (value,))?.repr()?;
                let expected = match name.ends_with("wrenches") {
                    true => format!("shape ({}, 6) or ({n},)", n / 6),
                    false => format!("shape ({n},)"),
                };
                return Err(argument_error(name, &expected, format!("shape {given}")));
            }
            vector_arg(&flat, name, n, &mut values)?;
            reading.copy_from_slice(&values);
        }
        let [start_wrench, start_torque, end_wrench, end_torque, mean_wrench] = &self.readings;
        self.robot.end_period(PeriodSensors {
            start: ForceReadings {
                contact_wrench: start_wrench,
                joint_torque: start_torque,
            },
            end: ForceReadings {
                contact_wrench: end_wrench,
                joint_torque: end_torque,
            },
            mean_contact_wrench: mean_wrenches.map(|_| mean_wrench),
        });
        self.period_open = false;
        Ok(())
    }

    /// The motor command (n) of the last `tick` or `inner_tick` (the plant input).
    #[getter]
    fn command<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        vector_out(py, self.robot.command())
    }

    /// The stiffness estimates [Nm/rad] the stack works with, by elastic joint name: the
    /// joint loops' (identified with `controller.stiffness_identification`), or the
    /// controller's without joint loops.
    #[getter]
    fn stiffness_estimates(&self) -> HashMap<String, f64> {
        let controller = self.robot.controller();
        let names = &controller.model().joint_names;
        let elastic = &controller.actuation().elastic_joints;
        let estimates = self.robot.estimates().iter();
        elastic
            .iter()
            .zip(estimates)
            .map(|(&j, estimate)| (names[j].clone(), estimate.stiffness))
            .collect()
    }

    /// The external wrench `wrench` (6: force, moment about the CoM; world axes) [N, Nm] that
    /// the controller's dynamics take as acting on the base from the next `tick` on
    /// (`sea_ctrl::external_wrench`), e.g. a caller's estimate of a push; zeros: none. With
    /// the scenario's observer (`controller.external_wrench = "observed"`), `end_period`
    /// replaces it.
    fn set_external_wrench(&mut self, wrench: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut values = Vec::with_capacity(6);
        vector_arg(wrench, "wrench", 6, &mut values)?;
        let wrench = nalgebra::Vector6::from_column_slice(&values);
        self.robot
            .law_mut()
            .controller_mut()
            .set_external_wrench(&wrench);
        Ok(())
    }

    /// The generalized disturbance `d` (nv: base rows `[force; moment about the base origin]`
    /// in world axes, then one per joint) [N, Nm] that the controller's dynamics take from
    /// the next `tick` on (bias forces `h - d`, its wrench carried by the contacts;
    /// `sea_ctrl::generalized_disturbance`), e.g. a caller's observer's estimate of what its
    /// model misses; zeros: none. With the scenario's observer
    /// (`controller.external_wrench = "generalized"`), `end_period` replaces it.
    fn set_generalized_disturbance(&mut self, disturbance: &Bound<'_, PyAny>) -> PyResult<()> {
        let nv = self.robot.controller().model().nv();
        let mut values = Vec::with_capacity(nv);
        vector_arg(disturbance, "disturbance", nv, &mut values)?;
        let disturbance = nalgebra::DVector::from_vec(values);
        let controller = self.robot.law_mut().controller_mut();
        controller
            .set_generalized_disturbance(&disturbance)
            .map_err(to_py)
    }

    /// The robot's CoM less the model's, `offset` (3,: world) [m], that the CoM position
    /// error of the next `tick`s takes (the momentum task's integral term brings the robot's
    /// CoM to the reference; the momentum and its map stay the model's), e.g. a caller's
    /// observer's estimate of where the robot's CoM is when the model's masses are off
    /// (`sea_ctrl::generalized_disturbance::GeneralizedDisturbanceObserver::com_offset`);
    /// zeros: none. With the scenario's generalized observer, `end_period` replaces it.
    fn set_com_offset(&mut self, offset: &Bound<'_, PyAny>) -> PyResult<()> {
        let mut values = Vec::with_capacity(3);
        vector_arg(offset, "offset", 3, &mut values)?;
        let offset = nalgebra::Vector3::from_column_slice(&values);
        self.robot
            .law_mut()
            .controller_mut()
            .set_com_offset(&offset);
        Ok(())
    }

    /// The CoM reference at `t` [s]: position (3,) in world [m]; `ValueError` for a `t` not
    /// finite.
    fn com_reference<'py>(
        &self,
        py: Python<'py>,
        t: Real,
    ) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let Real(t) = t;
        sea_dyn::error::check_non_negative("t", t).map_err(to_py)?;
        let reference = self.robot.law().com_reference().sample(t);
        Ok(vector_out(py, reference.position.as_slice()))
    }

    /// "sea" or "rigid".
    #[getter]
    fn kind(&self) -> &'static str {
        sea_sim::scenario::Setting::name(self.robot.controller().settings().kind)
    }

    /// Contact frame names, the rows of `ControlOutput.wrenches`.
    #[getter]
    fn contacts(&self) -> Vec<String> {
        self.contacts.clone()
    }

    /// Joint names in coordinate order.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.joint_names.clone()
    }

    /// Size of the state `tick` reads, nq + nv + 2 n_e.
    #[getter]
    fn nx(&self) -> usize {
        self.robot.layout().nx()
    }

    /// QP solves so far that fell back to the unconstrained solution.
    #[getter]
    fn qp_failures(&self) -> usize {
        self.robot.controller().qp_failures()
    }

    fn __repr__(&self) -> String {
        format!(
            "Controller(kind='{}', model='{}', contacts={}, nx={})",
            self.kind(),
            self.robot.controller().model().name,
            crate::arrays::python_list(&self.contacts),
            self.nx(),
        )
    }
}

/// A scenario file built: the model, the plant configured as the scenario says, the
/// controller with its references, the initial state and the time grid of its closed loop.
#[pyclass(name = "Scenario", module = "sea_momentum._native")]
pub struct PyScenario {
    name: String,
    model: Py<PyModel>,
    plant: Py<PyPlant>,
    controller: Py<PyController>,
    initial_state: Vec<f64>,
    schedule: Schedule,
    method: String,
    duration: f64,
}

#[pymethods]
impl PyScenario {
    /// Builds the scenario file `path` with `overrides` ({"controller.kind": "rigid", ...}),
    /// exactly as `run_scenario` does; the build's warnings (a walking command the step
    /// limits clip) are Python `UserWarning`s.
    #[staticmethod]
    #[pyo3(signature = (path, overrides=None))]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        overrides: Option<HashMap<String, Bound<'_, PyAny>>>,
    ) -> PyResult<Self> {
        let pairs = crate::overrides::override_pairs(overrides)?;
        let scenario = Scenario::from_file(&path, &pairs).map_err(to_py)?;
        let schedule = scenario.schedule();
        let setup = build(&scenario).map_err(to_py)?;
        for warning in &setup.warnings {
            warn_user(py, warning)?;
        }
        let layout = setup.plant.layout();
        let controller = PyController::new_built(
            setup.controller,
            (setup.com_reference, setup.posture),
            layout,
            setup.model.joint_names.clone(),
            (&scenario, &schedule),
        )?;
        Ok(Self {
            name: scenario.name.clone(),
            model: Py::new(py, PyModel::from_model(setup.model))?,
            plant: Py::new(
                py,
                PyPlant::from_plant(setup.plant, scenario.plant.w_refresh_steps),
            )?,
            controller: Py::new(py, controller)?,
            initial_state: setup.x0,
            schedule,
            method: sea_sim::scenario::Setting::name(scenario.plant.method).into(),
            duration: scenario.simulation.duration_s,
        })
    }

    /// The scenario's `name`.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The robot model.
    #[getter]
    fn model(&self, py: Python<'_>) -> Py<PyModel> {
        self.model.clone_ref(py)
    }

    /// The plant (contacts held, motor input as the controller kind needs).
    #[getter]
    fn plant(&self, py: Python<'_>) -> Py<PyPlant> {
        self.plant.clone_ref(py)
    }

    /// The controller with the scenario's references.
    #[getter]
    fn controller(&self, py: Python<'_>) -> Py<PyController> {
        self.controller.clone_ref(py)
    }

    /// The initial plant state (nx): at rest, springs preloaded with the static torques.
    #[getter]
    fn initial_state<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        vector_out(py, &self.initial_state)
    }

    /// The plant step [s] of the run (at most `plant.dt`, a whole fraction of the period).
    #[getter]
    fn plant_dt(&self) -> f64 {
        self.schedule.step
    }

    /// Time between two controller ticks [s] (`1 / controller.rate_hz`; the plant step in
    /// continuous sampling).
    #[getter]
    fn control_period(&self) -> f64 {
        self.schedule.period
    }

    /// Plant steps per controller tick, `control_period / plant_dt`.
    #[getter]
    fn steps_per_tick(&self) -> usize {
        self.schedule.steps_per_period
    }

    /// Plant steps per joint-loop tick (`multi_rate`: `steps_per_tick` over the inner ticks
    /// of a period, `controller.inner_rate_hz / controller.rate_hz`; otherwise
    /// `steps_per_tick`).
    #[getter]
    fn steps_per_inner_tick(&self) -> usize {
        self.schedule.steps_per_inner_tick()
    }

    /// Number of ticks of the run after the first (`simulation.duration_s / control_period`).
    #[getter]
    fn last_tick(&self) -> usize {
        self.schedule.last_sample
    }

    /// `controller.sampling`: "zero_order_hold" (a tick / step loop is the run),
    /// "multi_rate" (a tick, then `Controller.inner_tick` every `steps_per_inner_tick` steps)
    /// or "continuous" (the controller at every integrator stage).
    #[getter]
    fn sampling(&self) -> &'static str {
        self.schedule.sampling.name()
    }

    /// The plant's integrator, `plant.method` (the `method` of `Plant.step`).
    #[getter]
    fn method(&self) -> &str {
        &self.method
    }

    /// `simulation.duration_s` [s].
    #[getter]
    fn duration(&self) -> f64 {
        self.duration
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario(name='{}', duration={:?}, plant_dt={:?}, control_period={:?})",
            self.name, self.duration, self.schedule.step, self.schedule.period,
        )
    }
}
