//! Before `sea-sim init` writes anything: every mesh the URDF names (visual and collision)
//! resolves (`package://`, `file://`, relative, as [`PackageDirs`] resolves them) to an
//! existing file. A run only warns about a missing mesh (the dynamics do not need it, the
//! robot is drawn without it), but a robot being set up should be complete: the error names
//! the link, the URI and why.

use crate::error::{Error, Result};
use sea_dyn::PackageDirs;
use std::path::{Path, PathBuf};

// `PackageDirs::resolve` returns only existing files: an error covers both cases.

/// Checks every mesh of the URDF `urdf_text` (file in `urdf_dir`) against `dirs`; the first
/// missing or unresolvable one is an error naming its link and URI. Returns each mesh's file
/// with what it is (`link 'l_foot' collision mesh`), inputs the scenario written must not
/// replace.
pub fn check_mesh_files(
    urdf_text: &str,
    urdf_dir: &Path,
    dirs: &PackageDirs,
) -> Result<Vec<(String, PathBuf)>> {
    let robot = sea_dyn::urdf::parse_urdf(urdf_text).map_err(|e| {
        Error::argument(
            "urdf",
            "a URDF urdf-rs reads",
            format!("{e} (in {})", urdf_dir.display()),
        )
    })?;
    let mut meshes = Vec::new();
    for link in &robot.links {
        let visuals = link.visual.iter().map(|v| (&v.geometry, "visual"));
        let collisions = link.collision.iter().map(|c| (&c.geometry, "collision"));
        for (geometry, kind) in visuals.chain(collisions) {
            let urdf_rs::Geometry::Mesh { filename, .. } = geometry else {
                continue;
            };
            let file = dirs.resolve(filename, urdf_dir).map_err(|e| {
                let mesh = format!("link '{}' {kind} mesh '{filename}': {e}", link.name);
                Error::argument("urdf", "meshes that can be found", mesh)
            })?;
            meshes.push((format!("the link '{}' {kind} mesh", link.name), file));
        }
    }
    Ok(meshes)
}
