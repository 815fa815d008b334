//! `sea_momentum.Model`: a robot model with its workspace.

use crate::arrays::{matrix_out, vector_arg, vector_out};
use crate::errors::to_py;
use crate::numbers::Real;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use sea_dyn::{Data, LoadOptions, Model};
use std::collections::HashMap;
use std::path::PathBuf;

/// A floating-base robot model loaded from URDF, with the buffers of its algorithms.
///
/// Conventions: q = [p_B (world), quaternion (w, x, y, z), s], nu = [pdot_B (world),
/// omega_B (world), sdot], spatial vectors linear first, gravity -9.81 m/s^2 along world z.
#[pyclass(name = "Model", module = "sea_momentum._native")]
pub struct PyModel {
    model: Model,
    data: Data,
    /// Scratch copies of the arguments (nq, nv, nv), reused across calls.
    q: Vec<f64>,
    nu: Vec<f64>,
    nudot: Vec<f64>,
}

impl PyModel {
    /// The Python object of a built model (with a fresh workspace).
    pub(crate) fn from_model(model: Model) -> Self {
        let data = Data::new(&model);
        Self {
            q: Vec::with_capacity(model.nq()),
            nu: Vec::with_capacity(model.nv()),
            nudot: Vec::with_capacity(model.nv()),
            model,
            data,
        }
    }

    /// The Rust model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    fn load_q(&mut self, q: &Bound<'_, PyAny>) -> PyResult<()> {
        vector_arg(q, "q", self.model.nq(), &mut self.q)?;
        self.model.check_configuration(&self.q).map_err(to_py)
    }

    fn load_nu(&mut self, nu: &Bound<'_, PyAny>) -> PyResult<()> {
        vector_arg(nu, "nu", self.model.nv(), &mut self.nu)
    }

    fn frame(&self, frame: &str) -> PyResult<usize> {
        self.model.frame_id(frame).map_err(to_py)
    }
}

/// `values`, the result of `operation`, when every entry is finite; else a numerical error
/// (`SolverError`): finite velocities can be large enough for the result to overflow float64
/// (1e200 rad/s squared is beyond it, and 1e308 rad/s times a mass).
fn finite<'a>(operation: &str, values: &'a [f64]) -> PyResult<&'a [f64]> {
    if values.iter().all(|v| v.is_finite()) {
        return Ok(values);
    }
    let detail = "the result is not finite: the velocities are too large for float64";
    Err(to_py(sea_dyn::Error::numerical(operation, detail)))
}

/// One Python `UserWarning` per load warning, prefixed with the file (an error if the warnings
/// filter turns warnings into errors).
fn warn_each(
    py: Python<'_>,
    path: &std::path::Path,
    warnings: &[sea_dyn::Warning],
) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    for warning in warnings {
        let text = format!("{}: {warning}", path.display()).replace('\0', " ");
        let message = std::ffi::CString::new(text).unwrap_or_default();
        PyErr::warn(py, &category, &message, 1)?;
    }
    Ok(())
}

#[pymethods]
impl PyModel {
    /// Loads a URDF file. `joints` lists the moving joints in coordinate order (default: every
    /// revolute, continuous and prismatic joint in depth-first tree order); the other joints are
    /// locked at `locked[name]` (default 0). Physically doubtful inertias, massless moving
    /// subtrees, inverted limits and moving joints with a `<mimic>` (its coupling not modelled)
    /// load with a `UserWarning` each (also kept in `warnings`); `strict=True` refuses them
    /// with a `ModelError` instead.
    #[staticmethod]
    #[pyo3(signature = (path, joints=None, locked=None, strict=false))]
    fn from_urdf(
        py: Python<'_>,
        path: PathBuf,
        joints: Option<Vec<String>>,
        locked: Option<HashMap<String, Real>>,
        strict: bool,
    ) -> PyResult<Self> {
        let options = LoadOptions {
            joints,
            locked: locked
                .unwrap_or_default()
                .into_iter()
                .map(|(name, Real(value))| (name, value))
                .collect(),
            strict,
        };
        let model = Model::from_urdf_file(&path, &options).map_err(to_py)?;
        warn_each(py, &path, &model.warnings)?;
        Ok(Self::from_model(model))
    }

    /// What loading found physically doubtful but computable, one message per finding naming
    /// the link or joint (empty for a clean description).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.model.warnings.iter().map(|w| w.to_string()).collect()
    }

    /// Configuration size, 7 + n.
    #[getter]
    fn nq(&self) -> usize {
        self.model.nq()
    }

    /// Velocity size, 6 + n.
    #[getter]
    fn nv(&self) -> usize {
        self.model.nv()
    }

    /// Number of moving joints n.
    #[getter]
    fn n_joints(&self) -> usize {
        self.model.n_joints()
    }

    /// Moving joint names in coordinate order.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.model.joint_names.clone()
    }

    /// Every URDF link name (the addressable frames), root first.
    #[getter]
    fn frame_names(&self) -> Vec<String> {
        self.model.frames.iter().map(|f| f.name.clone()).collect()
    }

    /// Name of the root link, the floating base.
    #[getter]
    fn base_link(&self) -> String {
        self.model.base_link.clone()
    }

    /// Total mass [kg].
    #[getter]
    fn total_mass(&self) -> f64 {
        self.model.total_mass()
    }

    /// Neutral configuration: base at the origin, identity orientation, joints at 0.
    fn neutral<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector_out(py, &self.model.neutral())
    }

    /// Joint-space inertia matrix M(q) (nv x nv).
    fn mass_matrix<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.load_q(q)?;
        Ok(matrix_out(
            py,
            sea_dyn::crba(&self.model, &mut self.data, &self.q),
        ))
    }

    /// Bias forces h(q, nu) = C(q, nu) nu + G(q) (nv).
    fn bias_forces<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        nu: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.load_q(q)?;
        self.load_nu(nu)?;
        let h = sea_dyn::bias_forces(&self.model, &mut self.data, &self.q, &self.nu);
        Ok(vector_out(py, finite("bias_forces", h.as_slice())?))
    }

    /// Gravity forces G(q) (nv).
    fn gravity_forces<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.load_q(q)?;
        let g = sea_dyn::gravity_forces(&self.model, &mut self.data, &self.q);
        Ok(vector_out(py, g.as_slice()))
    }

    /// Inverse dynamics M(q) nudot + h(q, nu) (nv).
    fn inverse_dynamics<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        nu: &Bound<'py, PyAny>,
        nudot: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.load_q(q)?;
        self.load_nu(nu)?;
        vector_arg(nudot, "nudot", self.model.nv(), &mut self.nudot)?;
        let tau = sea_dyn::rnea(&self.model, &mut self.data, &self.q, &self.nu, &self.nudot);
        Ok(vector_out(py, finite("inverse_dynamics", tau.as_slice())?))
    }

    /// world_H_frame (4 x 4) of a link.
    fn frame_pose<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        frame: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let id = self.frame(frame)?;
        self.load_q(q)?;
        let body = self.model.frames[id].body;
        sea_dyn::forward_kinematics_path(&self.model, &mut self.data, &self.q, body);
        let pose = sea_dyn::frame_placement(&self.model, &self.data, id);
        Ok(matrix_out(py, &pose.to_homogeneous()))
    }

    /// Frame Jacobian (6 x nv): nu -> [velocity of the frame origin; angular velocity], world axes.
    fn frame_jacobian<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        frame: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let id = self.frame(frame)?;
        self.load_q(q)?;
        Ok(matrix_out(
            py,
            sea_dyn::frame_jacobian(&self.model, &mut self.data, &self.q, id),
        ))
    }

    /// Jdot nu (6): the frame's classical acceleration at nudot = 0, world axes.
    fn frame_jacobian_dot_v<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        nu: &Bound<'py, PyAny>,
        frame: &str,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let id = self.frame(frame)?;
        self.load_q(q)?;
        self.load_nu(nu)?;
        let a = sea_dyn::frame_jacobian_dot_v(&self.model, &mut self.data, &self.q, &self.nu, id);
        Ok(vector_out(
            py,
            finite("frame_jacobian_dot_v", a.as_slice())?,
        ))
    }

    /// Centre of mass in world (3).
    fn com<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.load_q(q)?;
        let c = sea_dyn::com(&self.model, &mut self.data, &self.q);
        Ok(vector_out(py, c.as_slice()))
    }

    /// CoM Jacobian (3 x nv), world axes.
    fn com_jacobian<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.load_q(q)?;
        Ok(matrix_out(
            py,
            sea_dyn::com_jacobian(&self.model, &mut self.data, &self.q),
        ))
    }

    /// Centroidal momentum matrix A_G(q) (6 x nv): H = [m pdot_com; L_com] = A_G nu.
    fn centroidal_momentum_matrix<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.load_q(q)?;
        Ok(matrix_out(
            py,
            sea_dyn::centroidal_momentum_matrix(&self.model, &mut self.data, &self.q),
        ))
    }

    /// Centroidal momentum H = [m pdot_com; L_com] (6), world axes.
    fn centroidal_momentum<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        nu: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.load_q(q)?;
        self.load_nu(nu)?;
        let h = sea_dyn::centroidal_momentum(&self.model, &mut self.data, &self.q, &self.nu);
        Ok(vector_out(py, finite("centroidal_momentum", h.as_slice())?))
    }

    /// Adot_G nu (6): rate of the centroidal momentum at nudot = 0.
    fn centroidal_momentum_bias<'py>(
        &mut self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        nu: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.load_q(q)?;
        self.load_nu(nu)?;
        let h = sea_dyn::centroidal_momentum_bias(&self.model, &mut self.data, &self.q, &self.nu);
        Ok(vector_out(
            py,
            finite("centroidal_momentum_bias", h.as_slice())?,
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "Model(name='{}', n_joints={}, nq={}, nv={}, total_mass={:.4})",
            self.model.name,
            self.model.n_joints(),
            self.model.nq(),
            self.model.nv(),
            self.model.total_mass()
        )
    }
}
