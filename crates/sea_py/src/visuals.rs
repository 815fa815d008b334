//! The URDF's mesh visuals for the pictures: `link_meshes`.

use crate::errors::{argument_error, to_py};
use crate::numbers::Integer;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use sea_sim::meshes::visuals::{urdf_file_visuals, Shape};
use std::path::PathBuf;

// The default of `link_meshes`' `triangle_budget`, written as a literal for Python's signature.
const _: () = assert!(sea_sim::meshes::visuals::PICTURE_TRIANGLE_BUDGET == 4000);

/// One mesh visual: link, vertices (n, 3) in the link frame [m], triangles (m, 3) vertex
/// indices, colour.
type LinkMesh<'py> = (
    String,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<i64>>,
    (f64, f64, f64, f64),
);

/// The mesh visuals of the URDF file `urdf`, decimated to about `triangle_budget` triangles
/// for the whole robot, as `(meshes, warnings)`: `meshes` a list of `(link, vertices (n, 3)
/// float64 in the link frame [m], triangles (m, 3) int64, rgba)`, `warnings` one message per
/// mesh not drawn (link, URI, why). `package:// ` URIs are looked up in `package_dirs` first,
/// then the environment's package directories, then above the URDF. `strict=True` raises
/// `ModelError` instead of warning.
#[pyfunction]
#[pyo3(text_signature = "(urdf, package_dirs=None, triangle_budget=4000, strict=False)")]
#[pyo3(signature = (urdf, package_dirs=None, triangle_budget=Integer(4000), strict=false))]
pub fn link_meshes<'py>(
    py: Python<'py>,
    urdf: PathBuf,
    package_dirs: Option<Vec<PathBuf>>,
    triangle_budget: Integer,
    strict: bool,
) -> PyResult<(Vec<LinkMesh<'py>>, Vec<String>)> {
    let Integer(triangle_budget) = triangle_budget;
    let budget = usize::try_from(triangle_budget)
        .ok()
        .filter(|b| *b > 0)
        .ok_or_else(|| argument_error("triangle_budget", "a positive integer", triangle_budget))?;
    let dirs = crate::paths::package_dirs(package_dirs)?;
    let visuals = py
        .detach(|| urdf_file_visuals(&urdf, &dirs, budget))
        .map_err(to_py)?;
    let warnings: Vec<String> = visuals.warnings.iter().map(ToString::to_string).collect();
    if strict && !warnings.is_empty() {
        let error = sea_dyn::Error::model("robot", warnings.join("; ")).in_file(&urdf);
        return Err(to_py(error));
    }
    let mut meshes = Vec::new();
    for visual in visuals.visuals {
        let Shape::Mesh(mesh) = visual.shape else {
            continue;
        };
        let vertices = Array2::from_shape_fn((mesh.positions.len(), 3), |(i, k)| {
            f64::from(mesh.positions[i][k])
        });
        let triangles = Array2::from_shape_fn((mesh.triangles.len(), 3), |(i, k)| {
            i64::from(mesh.triangles[i][k])
        });
        let [r, g, b, a] = visual.rgba;
        meshes.push((
            visual.link,
            vertices.into_pyarray(py),
            triangles.into_pyarray(py),
            (r, g, b, a),
        ));
    }
    Ok((meshes, warnings))
}
