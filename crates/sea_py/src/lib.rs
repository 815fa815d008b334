//! PyO3 bindings of sea-momentum: thin wrappers only, numpy in and out.
//!
//! Errors are mapped once, in [`errors`]: `SeaError` is the base; model problems raise
//! `ModelError` and scenario problems `ScenarioError` (both also `ValueError`), numerical
//! failures `SolverError` (also `RuntimeError`), file failures `SeaIOError` (an `OSError`); bad
//! arguments raise `ValueError` naming the argument, the expected and the actual value.
//! Every argument is validated before it reaches the Rust core, so no panic crosses into Python.

use pyo3::prelude::*;

mod analysis;
mod arrays;
mod controller;
mod errors;
mod init;
mod interrupt;
mod model;
mod overrides;
mod plant;
mod scenario;
mod sweep;
mod visuals;

/// The native module `sea_momentum._native`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<plant::PyPlant>()?;
    m.add_class::<controller::PyController>()?;
    m.add_class::<controller::PyScenario>()?;
    m.add_function(wrap_pyfunction!(scenario::run_scenario_native, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::scenario_urdf, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::linearize_native, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::stability_margin_native, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_grid, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_batch, m)?)?;
    m.add_function(wrap_pyfunction!(init::init_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(visuals::link_meshes, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The paper's 25 iCub joints, defined once in sea_sim's presets.
    let icub25 = pyo3::types::PyTuple::new(m.py(), sea_sim::scenario::icub().joints.iter())?;
    m.add("ICUB25_JOINTS", icub25)?;
    m.add(
        "PICTURE_TRIANGLE_BUDGET",
        sea_sim::meshes::visuals::PICTURE_TRIANGLE_BUDGET,
    )?;
    Ok(())
}
