//! `sea_momentum.init_scenario`: `sea-sim init` from Python (a two-feet balancing scenario for
//! a new robot, written to a file).

use crate::errors::to_py;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sea_sim::init::{check_foot, init, InitOptions};
use sea_sim::scenario::robots::FootRectangle;
use std::path::PathBuf;

/// Writes the scenario of `sea-sim init` and returns what it found: `out`, `robot`, `mass`,
/// `joints`, `foot_x`, `foot_y`, `measured`, `lowering_m`, `residual`, `warnings`.
#[pyfunction]
#[pyo3(signature = (urdf, contacts, out, foot=None, package_dirs=None))]
pub fn init_scenario<'py>(
    py: Python<'py>,
    urdf: String,
    contacts: (String, String),
    out: PathBuf,
    foot: Option<(f64, f64, f64, f64)>,
    package_dirs: Option<Vec<PathBuf>>,
) -> PyResult<Bound<'py, PyDict>> {
    let foot = foot
        .map(|(x0, x1, y0, y1)| {
            check_foot(&FootRectangle {
                x: [x0, x1],
                y: [y0, y1],
            })
        })
        .transpose()
        .map_err(to_py)?;
    let options = InitOptions {
        urdf,
        contacts: [contacts.0, contacts.1],
        foot,
        package_dirs: package_dirs.unwrap_or_default(),
        out,
        name: None,
    };
    let report = py.detach(|| init(&options)).map_err(to_py)?;
    let dict = PyDict::new(py);
    dict.set_item("out", report.out.display().to_string())?;
    dict.set_item("robot", &report.robot.0)?;
    dict.set_item("mass", report.robot.1)?;
    dict.set_item("joints", report.robot.2)?;
    dict.set_item("foot_x", report.feet[0].x.to_vec())?;
    dict.set_item("foot_y", report.feet[0].y.to_vec())?;
    dict.set_item("measured", report.measured)?;
    dict.set_item("lowering_m", report.lowering_m)?;
    dict.set_item("residual", report.residual)?;
    dict.set_item("warnings", report.warnings)?;
    Ok(dict)
}
