//! `sea_momentum.Plant`: the SEA plant with rigid contacts and its integrators.

use crate::actuators::actuator_from_py;
use crate::arrays::{matrix_rows_out, result_object, table_out, vector_arg, vector_out};
use crate::errors::{argument_error, to_py};
use crate::interrupt::run_interruptible;
use crate::model::PyModel;
use crate::numbers::{count_arg, real_or_none, Real};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sea_dyn::error::check_positive;
use sea_dyn::{Actuation, Actuator};
use sea_plant::{ContactLimits, Method, MotorInput, Plant, PlantData};
use sea_sim::scenario::Setting;
use std::collections::HashMap;
use std::sync::atomic::Ordering;

/// The integrator called `name` ("ros2", "implicit_euler" or "rk4").
fn method_arg(name: &str) -> PyResult<Method> {
    Method::from_name(name).ok_or_else(|| {
        argument_error(
            "method",
            &format!("one of {}", Method::allowed()),
            format!("'{name}'"),
        )
    })
}

/// What `gravity` must be.
const GRAVITY_RULE: &str = "three finite numbers [m/s^2]";
/// What `foot_x` and `foot_y` must be.
const RECTANGLE_RULE: &str = "(min, max) of finite numbers with min < max (sole frame) [m]";

/// An optional argument of `N` finite numbers (a tuple, list or array), named `name` in the
/// `ValueError` that says it must be `expected` and shows the value given.
fn numbers_arg<const N: usize>(
    value: Option<&Bound<'_, PyAny>>,
    name: &str,
    expected: &str,
) -> PyResult<Option<[f64; N]>> {
    let Some(value) = value else {
        return Ok(None);
    };
    let numbers: Vec<Real> = value
        .extract()
        .map_err(|_| argument_error(name, expected, value))?;
    let numbers: Vec<f64> = numbers.into_iter().map(|Real(number)| number).collect();
    let shown = numbers.iter().map(f64::to_string).collect::<Vec<_>>();
    let shown = format!("({})", shown.join(", "));
    if numbers.len() != N || !numbers.iter().all(|v| v.is_finite()) {
        return Err(argument_error(name, expected, shown));
    }
    Ok(Some(std::array::from_fn(|i| numbers[i])))
}

/// Checks the arguments of `Plant(...)` that the Rust plant does not check itself (its gains
/// are checked by [`Plant::validate`]; the numbers' count and finiteness by [`numbers_arg`]):
/// a positive finite friction coefficient, foot rectangles `(min, max)` with `min < max`.
fn check_surface(
    friction: Option<f64>,
    foot_x: Option<[f64; 2]>,
    foot_y: Option<[f64; 2]>,
) -> PyResult<()> {
    if let Some(mu) = friction {
        check_positive("friction", mu).map_err(to_py)?;
    }
    for (name, rectangle) in [("foot_x", foot_x), ("foot_y", foot_y)] {
        if let Some([low, high]) = rectangle {
            if low >= high {
                return Err(argument_error(
                    name,
                    RECTANGLE_RULE,
                    format!("({low}, {high})"),
                ));
            }
        }
    }
    Ok(())
}

/// A floating-base robot with series elastic (or rigid) actuators and rigid contacts.
///
/// State x = [q (nq), theta (n_e), nu (nv), thetadot (n_e)]; input u (n), per joint in
/// coordinate order: rigid joint torque, or for elastic joints the motor torque (default) or
/// the desired motor velocity when `motor_velocity_gain` is set (the motor velocity loop).
#[pyclass(name = "Plant", module = "sea_momentum._native")]
pub struct PyPlant {
    plant: Plant,
    data: PlantData,
    x: Vec<f64>,
    u: Vec<f64>,
    /// The start state and outputs of the last step (`Plant.step_outputs`), once one was
    /// taken.
    last_step: Option<(Vec<f64>, sea_plant::PlantOutputs)>,
}

impl PyPlant {
    /// `outputs` as a `PlantOutputs` object, with the wrench margins at `x` (the state they
    /// were evaluated at).
    fn outputs_object<'py>(
        &self,
        py: Python<'py>,
        x: &[f64],
        outputs: &sea_plant::PlantOutputs,
    ) -> PyResult<Bound<'py, PyAny>> {
        let fields = PyDict::new(py);
        fields.set_item(
            "contact_wrenches",
            matrix_rows_out(py, outputs.contact_wrench.as_slice(), 6),
        )?;
        fields.set_item(
            "joint_torques",
            vector_out(py, outputs.joint_torque.as_slice()),
        )?;
        fields.set_item(
            "motor_torques",
            vector_out(py, outputs.motor_torque.as_slice()),
        )?;
        fields.set_item("drift_position", outputs.drift_position)?;
        fields.set_item("drift_rotation", outputs.drift_rotation)?;
        fields.set_item(
            "step_contact_wrenches",
            matrix_rows_out(py, outputs.step_contact_wrench.as_slice(), 6),
        )?;
        fields.set_item(
            "contact_point_positions",
            matrix_rows_out(py, outputs.contact_point_position.as_slice(), 3),
        )?;
        fields.set_item(
            "contact_point_forces",
            matrix_rows_out(py, outputs.contact_point_force.as_slice(), 3),
        )?;
        fields.set_item(
            "contact_point_active",
            PyArray1::from_vec(py, outputs.contact_point_active.clone()),
        )?;
        fields.set_item(
            "joint_stop_torques",
            vector_out(py, outputs.joint_stop_torque.as_slice()),
        )?;
        let margins = self
            .plant
            .wrench_margins(x, outputs.contact_wrench.as_slice());
        let column =
            |f: fn(&sea_plant::WrenchMargins) -> f64| margins.iter().map(f).collect::<Vec<f64>>();
        fields.set_item("normal_force", vector_out(py, &column(|m| m.normal_force)))?;
        fields.set_item("friction_margin", vector_out(py, &column(|m| m.friction)))?;
        fields.set_item(
            "cop_margin",
            vector_out(py, &column(|m| m.center_of_pressure)),
        )?;
        result_object(py, "PlantOutputs", &fields)
    }

    /// The Python object of a built plant (e.g. a scenario's), with a fresh workspace whose
    /// steps share `W` over `w_refresh_steps` steps (`plant.w_refresh_steps`).
    pub(crate) fn from_plant(plant: Plant, w_refresh_steps: usize) -> Self {
        let mut data = PlantData::new(&plant);
        data.integrator.set_w_refresh_steps(w_refresh_steps);
        Self {
            plant,
            data,
            x: Vec::new(),
            u: Vec::new(),
            last_step: None,
        }
    }

    fn load(&mut self, x: &Bound<'_, PyAny>, u: &Bound<'_, PyAny>) -> PyResult<()> {
        vector_arg(x, "x", self.plant.layout().nx(), &mut self.x)?;
        self.plant.check_state(&self.x).map_err(to_py)?;
        vector_arg(u, "u", self.plant.model.n_joints(), &mut self.u)
    }

    /// The pushes of `Plant.step(..., external=...)` into the workspace's external wrenches
    /// (all active), checked first: each key a frame of the model, each value 3 (a force) or 6
    /// (`[force; moment]`) finite numbers; nothing is loaded when one is bad.
    fn load_external(&mut self, external: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        self.data.workspace.external.clear();
        let Some(external) = external else {
            return Ok(());
        };
        let mut wrenches = Vec::with_capacity(external.len());
        for (link, value) in external.iter() {
            let link: String = link
                .extract()
                .map_err(|_| argument_error("external", "a dict with link names as keys", &link))?;
            let name = format!("external['{link}']");
            let frame = self.plant.model.frame_id(&link).map_err(|_| {
                argument_error(&name, "a link (frame) of the model", format!("'{link}'"))
            })?;
            wrenches.push(sea_plant::ExternalWrench {
                frame,
                wrench: external_wrench_arg(&value, &name)?,
                active: true,
            });
        }
        self.data.workspace.external.extend(wrenches);
        Ok(())
    }

    /// Loads `x` and `u` and evaluates the plant there (outputs in `self.data.outputs`).
    fn evaluate_at(&mut self, x: &Bound<'_, PyAny>, u: &Bound<'_, PyAny>) -> PyResult<()> {
        self.load(x, u)?;
        sea_plant::evaluate(
            &self.plant,
            &mut self.data.workspace,
            &self.x,
            &self.u,
            &mut self.data.outputs,
        )
        .map_err(to_py)?;
        let outputs = &self.data.outputs;
        let finite = |v: &f64| v.is_finite();
        if outputs.xdot.iter().all(finite) && outputs.contact_wrench.iter().all(finite) {
            return Ok(());
        }
        // Finite but huge states or inputs (velocities of 1e200, torques of 1e308) overflow.
        let detail = "the result is not finite: the state or the input is too large for float64";
        Err(to_py(sea_dyn::Error::numerical(
            "evaluating the plant",
            detail,
        )))
    }
}

#[pymethods]
impl PyPlant {
    /// Builds a plant.
    ///
    /// `actuator`: the default actuator of every joint, "rigid", "elastic" (the paper's iCub
    /// SEA) or a dict of a scenario's actuator keys (kind, ratio, motor_inertia, stiffness,
    /// damping, torque_limit; missing keys the paper's SEA's); `actuators`: per-joint
    /// overrides by name. `contacts`: frame names held at their pose in `contact_q`
    /// (None: no contacts).
    /// `friction`, `foot_x`, `foot_y`: the sole's friction coefficient and rectangle (sole
    /// frame) for the wrench margins; unset, the default contact surface.
    #[new]
    #[pyo3(
        text_signature = "(model, *, actuator=None, actuators=None, contacts=None, contact_q=None, baumgarte_kp=None, baumgarte_kd=None, motor_velocity_gain=None, joint_inertia_regularization=0.0, gravity=None, friction=None, foot_x=None, foot_y=None)"
    )]
    #[pyo3(signature = (
        model, *, actuator=None, actuators=None,
        contacts=None, contact_q=None, baumgarte_kp=None, baumgarte_kd=None,
        motor_velocity_gain=None, joint_inertia_regularization=Real(0.0), gravity=None,
        friction=None, foot_x=None, foot_y=None
    ))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        model: PyRef<'_, PyModel>,
        actuator: Option<Bound<'_, PyAny>>,
        actuators: Option<Bound<'_, PyDict>>,
        contacts: Option<Vec<String>>,
        contact_q: Option<Bound<'_, PyAny>>,
        baumgarte_kp: Option<Real>,
        baumgarte_kd: Option<Real>,
        motor_velocity_gain: Option<Real>,
        joint_inertia_regularization: Real,
        gravity: Option<Bound<'_, PyAny>>,
        friction: Option<Real>,
        foot_x: Option<Bound<'_, PyAny>>,
        foot_y: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (baumgarte_kp, baumgarte_kd) = (real_or_none(baumgarte_kp), real_or_none(baumgarte_kd));
        let motor_velocity_gain = real_or_none(motor_velocity_gain);
        let Real(joint_inertia_regularization) = joint_inertia_regularization;
        let friction = real_or_none(friction);
        let gravity = numbers_arg::<3>(gravity.as_ref(), "gravity", GRAVITY_RULE)?;
        let foot_x = numbers_arg::<2>(foot_x.as_ref(), "foot_x", RECTANGLE_RULE)?;
        let foot_y = numbers_arg::<2>(foot_y.as_ref(), "foot_y", RECTANGLE_RULE)?;
        check_surface(friction, foot_x, foot_y)?;
        let mut rigid_model = model.model().clone();
        if let Some(gravity) = gravity {
            rigid_model.gravity = nalgebra::Vector3::from(gravity);
        }
        let default = match actuator {
            Some(actuator) => actuator_from_py(&actuator, "actuator")?,
            None => Actuator::Rigid,
        };
        let mut overrides = HashMap::new();
        if let Some(actuators) = actuators {
            for (name, value) in actuators.iter() {
                let name: String = name.extract()?;
                let actuator = actuator_from_py(&value, &format!("actuators['{name}']"))?;
                overrides.insert(name, actuator);
            }
        }
        let actuation = Actuation::new(&rigid_model, default, &overrides).map_err(to_py)?;
        let mut plant = Plant::new(rigid_model, actuation);
        // Unset gains keep the plant's defaults (Plant::DEFAULT_BAUMGARTE_KP, critical damping).
        plant.baumgarte_kp = baumgarte_kp.unwrap_or(plant.baumgarte_kp);
        plant.baumgarte_kd = baumgarte_kd.unwrap_or(sea_dyn::critical_damping(plant.baumgarte_kp));
        plant.motor_input = match motor_velocity_gain {
            Some(gain) => MotorInput::VelocityLoop { gain },
            None => MotorInput::Torque,
        };
        plant.joint_inertia_regularization = joint_inertia_regularization;
        // Unset values keep the one default contact surface (sea_dyn's ContactSurface).
        let defaults = ContactLimits::default();
        plant.contact_limits = ContactLimits {
            friction: friction.unwrap_or(defaults.friction),
            foot_x: foot_x.unwrap_or(defaults.foot_x),
            foot_y: foot_y.unwrap_or(defaults.foot_y),
            ..defaults
        };
        plant.validate().map_err(to_py)?;
        let contacts = contacts.unwrap_or_default();
        if !contacts.is_empty() {
            let contact_q = contact_q.ok_or_else(|| {
                argument_error(
                    "contact_q",
                    "the configuration to hold the contacts at (required with contacts)",
                    "None",
                )
            })?;
            let mut q = Vec::new();
            vector_arg(&contact_q, "contact_q", plant.model.nq(), &mut q)?;
            plant
                .model
                .check_configuration_named("contact_q", &q)
                .map_err(to_py)?;
            plant.set_contacts(&contacts, &q).map_err(to_py)?;
        }
        let data = PlantData::new(&plant);
        Ok(Self {
            plant,
            data,
            x: Vec::new(),
            u: Vec::new(),
            last_step: None,
        })
    }

    /// State size nq + nv + 2 n_e.
    #[getter]
    fn nx(&self) -> usize {
        self.plant.layout().nx()
    }

    /// Tangent state size 2 nv + 2 n_e.
    #[getter]
    fn nd(&self) -> usize {
        self.plant.layout().nd()
    }

    /// Input size n, one per joint: the length of the input `u` of `dynamics(x, u)` (`u` for
    /// input; not the velocity `nu`).
    #[getter]
    fn nu_input(&self) -> usize {
        self.plant.model.n_joints()
    }

    /// Names of the elastic joints, in the order of theta.
    #[getter]
    fn elastic_joints(&self) -> Vec<String> {
        let names = &self.plant.model.joint_names;
        self.plant
            .actuation
            .elastic_joints
            .iter()
            .map(|&j| names[j].clone())
            .collect()
    }

    /// The parameters of each elastic joint, in the order of theta: dicts with the keys of an
    /// actuator table (`ratio`, `motor_inertia`, `stiffness`, `damping`, `torque_limit`, None
    /// for no limit), as the scenario resolved them.
    #[getter]
    fn elastic_parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        pythonize::pythonize(py, &self.plant.actuation.elastic).map_err(PyErr::from)
    }

    /// Contact frame names.
    #[getter]
    fn contact_frames(&self) -> Vec<String> {
        self.plant.contacts.iter().map(|c| c.name.clone()).collect()
    }

    /// The number of points of each contact, in `contact_frames`' order: the rows of the
    /// outputs' `contact_point_*` arrays, contact by contact. Empty under bilateral contacts.
    #[getter]
    fn contact_point_counts(&self) -> Vec<usize> {
        self.plant.contact_point_counts()
    }

    fn __repr__(&self) -> String {
        format!(
            "Plant(model='{}', nx={}, elastic_joints={}, contacts={})",
            self.plant.model.name,
            self.plant.layout().nx(),
            self.plant.actuation.elastic_joints.len(),
            crate::arrays::python_list(&self.contact_frames()),
        )
    }

    /// A state from its parts: theta defaults to s / Gamma (springs at rest), velocities to 0.
    #[pyo3(signature = (q, nu=None, theta=None, thetadot=None, joint_torques=None))]
    fn make_state<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        nu: Option<&Bound<'py, PyAny>>,
        theta: Option<&Bound<'py, PyAny>>,
        thetadot: Option<&Bound<'py, PyAny>>,
        joint_torques: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let layout = self.plant.layout();
        let mut q_v = Vec::new();
        vector_arg(q, "q", layout.nq, &mut q_v)?;
        let mut nu_v = vec![0.0; layout.nv];
        if let Some(nu) = nu {
            vector_arg(nu, "nu", layout.nv, &mut nu_v)?;
        }
        let mut theta_v = Vec::new();
        if let Some(theta) = theta {
            vector_arg(theta, "theta", layout.ne, &mut theta_v)?;
        } else if let Some(joint_torques) = joint_torques {
            let mut torques = Vec::new();
            vector_arg(
                joint_torques,
                "joint_torques",
                self.plant.model.n_joints(),
                &mut torques,
            )?;
            theta_v = self
                .plant
                .preloaded_motor_angles(&q_v, &torques)
                .map_err(to_py)?;
        }
        let mut thetadot_v = Vec::new();
        if let Some(thetadot) = thetadot {
            vector_arg(thetadot, "thetadot", layout.ne, &mut thetadot_v)?;
        }
        let x = self
            .plant
            .make_state(
                &q_v,
                &nu_v,
                (theta.is_some() || joint_torques.is_some()).then_some(theta_v.as_slice()),
                thetadot.map(|_| thetadot_v.as_slice()),
            )
            .map_err(to_py)?;
        Ok(vector_out(py, &x))
    }

    /// Splits a state into a dict with q, theta, nu, thetadot.
    fn split_state<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let layout = self.plant.layout();
        vector_arg(x, "x", layout.nx(), &mut self.x)?;
        let dict = PyDict::new(py);
        let x = &self.x;
        dict.set_item("q", vector_out(py, &x[..layout.nq]))?;
        dict.set_item("theta", vector_out(py, layout.theta(x)))?;
        dict.set_item("nu", vector_out(py, layout.nu(x)))?;
        dict.set_item("thetadot", vector_out(py, layout.thetadot(x)))?;
        Ok(dict)
    }

    /// dx/dt (nx) of the state vector itself (quaternion rate included), for scipy.
    fn dynamics<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.evaluate_at(x, u)?;
        let mut out = vec![0.0; self.plant.layout().nx()];
        sea_plant::state_derivative(&self.plant, &self.x, &self.data.outputs.xdot, &mut out);
        Ok(PyArray1::from_vec(py, out))
    }

    /// Outputs at (x, u) as a `sea_momentum.results.PlantOutputs`: contact wrenches
    /// (n_contacts, 6), joint torques (n,), motor torques (n_e,), drift, wrench margins
    /// (n_contacts,) each; float64 arrays.
    fn outputs<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.evaluate_at(x, u)?;
        self.outputs_object(py, &self.x, &self.data.outputs)
    }

    /// The outputs of the last `step` as a `sea_momentum.results.PlantOutputs`: those at the
    /// step's start state and input, with `step_contact_wrenches` the wrenches the step
    /// delivered (under unilateral contacts a stiff contact's force follows a new input within
    /// the step: this is what the feet's force/torque sensors read over it). Raises
    /// `RuntimeError` before any step.
    fn step_outputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let Some((x, last)) = &self.last_step else {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "step_outputs: no step taken yet (call Plant.step first)",
            ));
        };
        self.outputs_object(py, x, last)
    }

    /// One step of size dt with u held: method "ros2" (default), "implicit_euler" or "rk4".
    ///
    /// `external`: pushes acting during this step, a dict `{link: wrench}` with `wrench` a
    /// force (3,) [N] or a wrench (6,) `[force; moment]` [N, N m], world axes, acting at the
    /// link frame's origin (a URDF link or any frame of the model): the convention of a
    /// scenario's `[[disturbances]]`, applied by the same code (`J^T w`,
    /// `sea_plant::external`). They act for this step only. A link that is not in the model or
    /// a wrench of another length or with a non-finite entry raises `ValueError` naming it.
    #[pyo3(signature = (x, u, dt, method="ros2", external=None))]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        dt: Real,
        method: &str,
        external: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let Real(dt) = dt;
        let method = method_arg(method)?;
        check_positive("dt", dt).map_err(to_py)?;
        self.load(x, u)?;
        self.load_external(external)?;
        let mut out = vec![0.0; self.x.len()];
        let stepped = sea_plant::step(
            &self.plant,
            &mut self.data,
            &self.x,
            &self.u,
            dt,
            method,
            &mut out,
        );
        // The pushes act for this step only (not in a later `outputs` or `dynamics`).
        self.data.workspace.external.clear();
        stepped.map_err(to_py)?;
        match &mut self.last_step {
            Some((x, last)) => {
                x.copy_from_slice(&self.x);
                last.copy_from(&self.data.outputs);
            }
            None => self.last_step = Some((self.x.clone(), self.data.outputs.clone())),
        }
        Ok(PyArray1::from_vec(py, out))
    }

    /// Simulates n_steps of size dt from x0 with u held (GIL released). Returns a
    /// `sea_momentum.results.SimulationResult` (m recorded rows): time (m,), x (m, nx),
    /// contact_wrenches (m, n_contacts, 6), motor_torques (m, n_e), drift_position (m,),
    /// drift_rotation (m,) as float64 arrays; status ("completed" or "diverged"), diverged_at
    /// (float or None), message. Data up to a divergence is kept. n_steps (>= 0),
    /// record_every (>= 1; None: every step) and the record's size are checked before
    /// anything is allocated (`ValueError` naming the argument, and giving the memory needed;
    /// an integer of any size).
    /// Ctrl-C stops the loop within a fraction of a second and raises `KeyboardInterrupt`
    /// whose `partial` attribute is the result so far (status "interrupted").
    #[pyo3(signature = (x0, u, dt, n_steps, method="ros2", record_every=None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &mut self,
        py: Python<'py>,
        x0: &Bound<'py, PyAny>,
        u: &Bound<'py, PyAny>,
        dt: Real,
        n_steps: &Bound<'py, PyAny>,
        method: &str,
        record_every: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let Real(dt) = dt;
        let method = method_arg(method)?;
        let n_steps = count_arg("n_steps", n_steps, 0)?;
        let record_every = match record_every {
            Some(value) => count_arg("record_every", value, 1)?,
            None => 1,
        };
        check_record_size(&self.plant, n_steps, record_every)?;
        self.load(x0, u)?;
        let (plant, data, x, u) = (&self.plant, &mut self.data, &self.x, &self.u);
        let (log, interrupt) = run_interruptible(py, |cancel| {
            sea_plant::simulate(plant, data, x, u, dt, n_steps, method, record_every, |_| {
                !cancel.load(Ordering::Relaxed)
            })
        })?;
        let log = log.map_err(to_py)?;
        let result = self.simulation_result(py, &log)?;
        match interrupt {
            Some(error) => {
                error.value(py).setattr("partial", result)?;
                Err(error)
            }
            None => Ok(result),
        }
    }
}

/// One push of `Plant.step(..., external=...)`: a force (3,) or a wrench (6,) `[force;
/// moment]` of finite numbers (world axes, at the link origin) as `[force; moment]`; errors
/// name the argument `name` (`external['root_link']`) and the length allowed.
fn external_wrench_arg(value: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 6]> {
    let length = value.len().ok();
    let Some(expected @ (3 | 6)) = length else {
        let actual = match length {
            Some(length) => format!("length {length}"),
            None => value.repr()?.to_string(),
        };
        let expected = "a force (3,) or a wrench [force; moment] (6,) [N, N m], world axes";
        return Err(argument_error(name, expected, actual));
    };
    let mut values = Vec::new();
    vector_arg(value, name, expected, &mut values)?;
    let mut wrench = [0.0; 6];
    wrench[..expected].copy_from_slice(&values);
    Ok(wrench)
}

/// Most plant steps one `Plant.simulate` call takes (the closed loop's bound,
/// [`sea_sim::scenario::validate::MAX_RUN_STEPS`]): beyond it a step count is a typo or a
/// wrapped negative number, not a run anyone waits for.
const MAX_SIMULATE_STEPS: f64 = sea_sim::scenario::validate::MAX_RUN_STEPS;

/// Largest record `Plant.simulate` allocates [bytes]; the numpy copy doubles it at the end.
const MAX_RECORD_BYTES: f64 = 4.0 * (1u64 << 30) as f64;

/// Checks `n_steps` and the record it needs before anything is allocated: a `ValueError`
/// naming the argument and, for the record, the memory it would need.
fn check_record_size(plant: &Plant, n_steps: usize, record_every: usize) -> PyResult<()> {
    if n_steps as f64 > MAX_SIMULATE_STEPS {
        return Err(argument_error(
            "n_steps",
            &format!("at most {MAX_SIMULATE_STEPS:e} steps"),
            n_steps,
        ));
    }
    let rows = (n_steps / record_every.max(1)) as f64 + 2.0;
    let columns =
        1 + plant.layout().nx() + 6 * plant.contacts.len() + plant.actuation.n_elastic() + 2;
    let bytes = rows * columns as f64 * 8.0;
    if bytes > MAX_RECORD_BYTES {
        return Err(argument_error(
            "n_steps",
            &format!(
                "a record of at most {:.1} GiB (raise record_every)",
                MAX_RECORD_BYTES / (1u64 << 30) as f64
            ),
            format!(
                "{n_steps} steps recording every {record_every}: {rows:.0} rows, {:.1} GiB",
                bytes / (1u64 << 30) as f64
            ),
        ));
    }
    Ok(())
}

impl PyPlant {
    /// The `sea_momentum.results.SimulationResult` of a simulation log.
    fn simulation_result<'py>(
        &self,
        py: Python<'py>,
        log: &sea_plant::SimulationLog,
    ) -> PyResult<Bound<'py, PyAny>> {
        let fields = PyDict::new(py);
        let nx = self.plant.layout().nx();
        let rows = log.time.len();
        fields.set_item("time", vector_out(py, &log.time))?;
        fields.set_item("x", table_out(py, &log.state, rows, nx))?;
        let wrenches = matrix_rows_out(py, &log.contact_wrench, 6);
        fields.set_item(
            "contact_wrenches",
            wrenches.reshape([rows, self.plant.contacts.len(), 6])?,
        )?;
        let n_elastic = self.plant.actuation.n_elastic();
        fields.set_item(
            "motor_torques",
            table_out(py, &log.motor_torque, rows, n_elastic),
        )?;
        fields.set_item("drift_position", vector_out(py, &log.drift_position))?;
        fields.set_item("drift_rotation", vector_out(py, &log.drift_rotation))?;
        let (status, diverged_at, message) = match &log.status {
            sea_plant::Status::Completed => ("completed", None, String::new()),
            sea_plant::Status::Diverged { time, reason } => {
                ("diverged", Some(*time), reason.clone())
            }
            sea_plant::Status::Interrupted { time } => {
                ("interrupted", None, format!("interrupted at t = {time} s"))
            }
        };
        fields.set_item("status", status)?;
        fields.set_item("diverged_at", diverged_at)?;
        fields.set_item("message", message)?;
        result_object(py, "SimulationResult", &fields)
    }
}
