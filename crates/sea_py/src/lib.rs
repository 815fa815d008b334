//! PyO3 bindings of sea-momentum: thin wrappers only, numpy in and out.
//!
//! Errors are mapped once, in `errors`: `SeaError` is the base; model problems raise
//! `ModelError` and scenario problems `ScenarioError` (both also `ValueError`), numerical
//! failures `SolverError` (also `RuntimeError`), file failures `SeaIOError` (an `OSError`); bad
//! arguments raise `ValueError` naming the argument, the expected and the actual value.
//! Every argument is validated before it reaches the Rust core, so no panic crosses into Python.

use pyo3::prelude::*;

mod actuators;
mod analysis;
mod arrays;
mod controller;
mod errors;
mod init;
mod interrupt;
mod model;
mod numbers;
mod overrides;
mod paths;
mod plant;
mod push;
mod scenario;
mod sweep;
mod template;
mod visuals;

/// The native module `sea_momentum._native`, exported by every build (the baseline module of
/// the wheel, a native build of `pip install .`).
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_module_contents(m)
}

/// The same module under the name `_native_v3`: the wheel's second build, for x86-64-v3 (AVX2,
/// FMA, BMI2; `scripts/build_wheel.sh`), which `sea_momentum` imports instead of the baseline
/// where [`cpu_supports_x86_64_v3`] holds. Exported only by builds whose target has AVX2 and FMA,
/// so that a baseline build shipped under this name fails to import instead of running slowly.
#[cfg(all(
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
))]
#[pymodule]
fn _native_v3(m: &Bound<'_, PyModule>) -> PyResult<()> {
    add_module_contents(m)
}

/// Whether this CPU (and the operating system, which must save the AVX registers) has every
/// feature of the x86-64-v3 level (x86-64 psABI: SSE3 to SSE4.2, POPCNT, CMPXCHG16B, AVX, AVX2,
/// BMI1, BMI2, F16C, FMA, LZCNT, MOVBE, XSAVE), so that the `_native_v3` module runs here.
/// Always false on other architectures.
#[pyfunction]
fn cpu_supports_x86_64_v3() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        has!("sse3")
            && has!("ssse3")
            && has!("sse4.1")
            && has!("sse4.2")
            && has!("popcnt")
            && has!("cmpxchg16b")
            && has!("avx")
            && has!("avx2")
            && has!("bmi1")
            && has!("bmi2")
            && has!("f16c")
            && has!("fma")
            && has!("lzcnt")
            && has!("movbe")
            && has!("xsave")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Registers the running interpreter's `sys.path` folders with sea_dyn, so that `package://`
/// URIs resolve in its cmeel prefix (example-robot-data) whether or not `VIRTUAL_ENV` is set.
fn register_interpreter_folders(py: Python<'_>) -> PyResult<()> {
    let sys_path = py.import("sys")?.getattr("path")?;
    let folders: Vec<std::path::PathBuf> = sys_path
        .try_iter()?
        .filter_map(|entry| entry.ok()?.extract::<std::path::PathBuf>().ok())
        .filter(|folder| !folder.as_os_str().is_empty())
        .collect();
    sea_dyn::resources::register_python_site_packages(folders);
    Ok(())
}

/// The classes, functions and constants of the native module (both names).
fn add_module_contents(m: &Bound<'_, PyModule>) -> PyResult<()> {
    register_interpreter_folders(m.py())?;
    errors::register(m)?;
    m.add_class::<model::PyModel>()?;
    m.add_class::<plant::PyPlant>()?;
    m.add_class::<controller::PyController>()?;
    m.add_class::<controller::PyScenario>()?;
    m.add_function(wrap_pyfunction!(scenario::run_scenario_native, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::scenario_urdf, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::linearize_native, m)?)?;
    m.add_function(wrap_pyfunction!(analysis::stability_margin_native, m)?)?;
    m.add_function(wrap_pyfunction!(push::push_table_native, m)?)?;
    m.add_function(wrap_pyfunction!(template::template_push_native, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_grid, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_batch, m)?)?;
    m.add_function(wrap_pyfunction!(init::init_scenario, m)?)?;
    m.add_function(wrap_pyfunction!(visuals::link_meshes, m)?)?;
    m.add_function(wrap_pyfunction!(cpu_supports_x86_64_v3, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The paper's 25 iCub joints, defined once in sea_sim's presets.
    let icub25 = pyo3::types::PyTuple::new(m.py(), sea_sim::scenario::icub().joints.iter())?;
    m.add("ICUB25_JOINTS", icub25)?;
    m.add(
        "PICTURE_TRIANGLE_BUDGET",
        sea_sim::meshes::visuals::PICTURE_TRIANGLE_BUDGET,
    )?;
    m.add("MAX_SWEEP_WORKERS", sea_sim::sweep::MAX_WORKERS)?;
    Ok(())
}
