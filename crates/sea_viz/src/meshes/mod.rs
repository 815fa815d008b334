//! Triangle meshes of URDF visuals: read from STL, OBJ and COLLADA (DAE) files, scaled and
//! placed by the URDF's `<mesh scale>` and visual `<origin>`, and decimated to a triangle budget
//! so that a log or a picture stays small.
//!
//! | file | reader | why |
//! |---|---|---|
//! | [`stl`] | the `stl_io` crate | ASCII and binary STL, vertices merged into an indexed mesh |
//! | [`obj`] | the `tobj` crate | Wavefront OBJ, polygons triangulated, one index per vertex |
//! | [`dae`] | our own, on the `roxmltree` XML parser | COLLADA geometry with the node transforms and `<unit>`; the `dae-parser` crate validates the schema strictly and rejects a fifth of the DAE files of `example-robot-data` and `icub-models` (COLLADA 1.4.0, assets without `<created>`) |
//! | [`simplify`] | the `meshopt` crate (meshoptimizer) | quadric edge collapse that keeps the shape, sloppy clustering when a mesh's topology stops it |
//! | [`visuals`] | `sea_dyn::resources::PackageDirs` | every `<visual>` of a URDF resolved, read once per file, decimated to a budget per robot; a mesh that cannot be drawn is a [`visuals::MeshWarning`] naming the link, the URI and the directories searched |
//!
//! One mesh type for all: [`TriangleMesh`], `f32` positions (the files' precision) in metres.

pub mod dae;
pub mod obj;
pub mod simplify;
pub mod stl;
pub mod visuals;

use std::path::Path;

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions [m] (or the file's units before scaling).
    pub positions: Vec<[f32; 3]>,
    /// Vertex indices of each triangle, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// One normal per vertex when the file gives them (OBJ `vn`); `None` otherwise (the
    /// drawing computes face normals).
    pub normals: Option<Vec<[f32; 3]>>,
}

/// Why a mesh file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file was read but is not a mesh of its format.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// The file's extension is none of STL, OBJ, DAE.
    #[error("{path}: unsupported mesh format (the readers take .stl, .obj and .dae)")]
    Unsupported {
        /// The file.
        path: String,
    },
}

/// A rigid placement with a per-axis scale applied first: `x -> rotation (scale * x) +
/// translation`, how a URDF visual places its mesh in the link frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Rotation matrix, rows first.
    pub rotation: [[f64; 3]; 3],
    /// Translation [m].
    pub translation: [f64; 3],
    /// Scale along the mesh's own axes (URDF `<mesh scale>`).
    pub scale: [f64; 3],
}

impl Placement {
    /// The placement that changes nothing.
    pub const IDENTITY: Self = Self {
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        translation: [0.0; 3],
        scale: [1.0; 3],
    };

    /// `rotation (scale * point) + translation`.
    pub fn apply(&self, point: [f32; 3]) -> [f32; 3] {
        let scaled: [f64; 3] = std::array::from_fn(|i| self.scale[i] * f64::from(point[i]));
        std::array::from_fn(|row| {
            let r = self.rotation[row];
            (r[0] * scaled[0] + r[1] * scaled[1] + r[2] * scaled[2] + self.translation[row]) as f32
        })
    }
}

impl TriangleMesh {
    /// The mesh placed by `placement`. A scale with an odd number of negative factors mirrors
    /// the mesh: its triangles are flipped to stay counter-clockwise from outside. Normals are
    /// dropped unless the scale is uniform (they would need the inverse transpose).
    pub fn placed(&self, placement: &Placement) -> Self {
        let [sx, sy, sz] = placement.scale;
        let mirrored = sx * sy * sz < 0.0;
        let uniform = sx == sy && sy == sz && sx > 0.0;
        let rotate = |n: &[f32; 3]| {
            let turn = Placement {
                translation: [0.0; 3],
                scale: [1.0; 3],
                ..*placement
            };
            turn.apply(*n)
        };
        Self {
            positions: self.positions.iter().map(|p| placement.apply(*p)).collect(),
            triangles: self
                .triangles
                .iter()
                .map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
                .collect(),
            normals: self
                .normals
                .as_ref()
                .filter(|_| uniform)
                .map(|normals| normals.iter().map(rotate).collect()),
        }
    }

    /// The first vertex or normal with a coordinate that is NaN or infinite, described (a
    /// drawing of it would be garbage, and a bounding box of it NaN).
    fn first_non_finite(&self) -> Option<String> {
        let finite = |p: &[f32; 3]| p.iter().all(|c| c.is_finite());
        let normals = self.normals.as_deref().unwrap_or_default();
        for (what, points) in [("vertex", &self.positions[..]), ("normal", normals)] {
            if let Some(i) = points.iter().position(|p| !finite(p)) {
                return Some(format!("{what} {i} is not finite: {:?}", points[i]));
            }
        }
        None
    }

    /// Drops the triangles whose indices are out of range (a malformed file) and reports
    /// whether any was.
    fn drop_bad_triangles(&mut self) -> bool {
        let count = self.positions.len() as u32;
        let before = self.triangles.len();
        self.triangles.retain(|t| t.iter().all(|&i| i < count));
        self.triangles.len() != before
    }
}

/// Reads the mesh file at `path`, its format chosen by the extension (`.stl`, `.obj`, `.dae`,
/// any case).
///
/// Errors: [`MeshError`] naming the file.
pub fn read_mesh(path: &Path) -> Result<TriangleMesh, MeshError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let bytes =
        sea_dyn::files::read_bounded(path, sea_dyn::files::MAX_MESH_BYTES).map_err(|source| {
            MeshError::Io {
                path: path.display().to_string(),
                source,
            }
        })?;
    let format_error = |message: String| MeshError::Format {
        path: path.display().to_string(),
        message,
    };
    let mut mesh = match extension.as_deref() {
        Some("stl") => stl::read(&bytes).map_err(format_error)?,
        Some("obj") => obj::read(&bytes).map_err(format_error)?,
        Some("dae") => dae::read(&bytes).map_err(format_error)?,
        _ => {
            return Err(MeshError::Unsupported {
                path: path.display().to_string(),
            })
        }
    };
    if mesh.drop_bad_triangles() {
        return Err(format_error(
            "a triangle indexes a vertex that does not exist".into(),
        ));
    }
    if let Some(message) = mesh.first_non_finite() {
        return Err(format_error(message));
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placement_scales_then_rotates_then_translates_and_mirroring_flips_triangles() {
        let mesh = TriangleMesh {
            positions: vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            triangles: vec![[0, 1, 2]],
            normals: None,
        };
        // A quarter turn about z, scale 2 along x, moved by (0, 0, 1).
        let placement = Placement {
            rotation: [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            translation: [0.0, 0.0, 1.0],
            scale: [2.0, 1.0, 1.0],
        };
        let placed = mesh.placed(&placement);
        assert_eq!(placed.positions[0], [0.0, 2.0, 1.0]);
        assert_eq!(placed.positions[1], [-1.0, 0.0, 1.0]);
        assert_eq!(placed.triangles, vec![[0, 1, 2]]);
        let mirror = Placement {
            scale: [-1.0, 1.0, 1.0],
            ..Placement::IDENTITY
        };
        assert_eq!(mesh.placed(&mirror).triangles, vec![[0, 2, 1]]);
    }

    #[test]
    fn unknown_extensions_missing_files_and_non_finite_vertices_are_named_errors() {
        let dir = std::env::temp_dir().join(format!("sea_sim_meshes_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let ply = dir.join("part.ply");
        std::fs::write(&ply, b"ply").unwrap();
        let message = read_mesh(&ply).unwrap_err().to_string();
        assert!(
            message.contains("part.ply") && message.contains("unsupported"),
            "{message}"
        );
        let message = read_mesh(&dir.join("none.stl")).unwrap_err().to_string();
        assert!(message.contains("none.stl"), "{message}");
        // A binary STL (the ASCII reader refuses NaN itself): one facet, a NaN vertex.
        let nan = dir.join("nan.stl");
        let mut bytes = vec![0u8; 80];
        bytes.extend(1u32.to_le_bytes());
        let facet = [
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            f32::NAN,
            0.0,
        ];
        bytes.extend(facet.iter().flat_map(|v: &f32| v.to_le_bytes()));
        bytes.extend([0u8; 2]);
        std::fs::write(&nan, bytes).unwrap();
        let message = read_mesh(&nan).unwrap_err().to_string();
        assert!(
            message.contains("nan.stl") && message.contains("vertex 2 is not finite"),
            "{message}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
