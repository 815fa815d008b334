//! The visuals of a URDF, ready to draw: primitives as they are, meshes resolved
//! (`package://`, `file://`, paths: [`PackageDirs`]), read once per file, decimated to a
//! triangle budget per robot and placed in their link frame.
//!
//! A mesh that cannot be drawn (unresolvable URI, missing or unreadable file) is a
//! [`MeshWarning`] naming the link, the URI and why (for a URI, every directory searched); the
//! other visuals are still drawn. Callers decide: the MCAP log keeps the warnings in its
//! metadata and `sea-sim` prints them, a strict caller turns them into an error.

use super::{read_mesh, simplify::decimate, Placement, TriangleMesh};
use sea_dyn::resources::PackageDirs;
use sea_dyn::spatial::rotation_from_rpy;
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Triangles of all the meshes of one robot in the `/robot` scene of an MCAP log: about 1 MB
/// of protobuf, written once per log (Talos: 159k triangles in its files, G1: 290k).
pub const SCENE_TRIANGLE_BUDGET: usize = 60_000;

/// Triangles of all the meshes of one robot in a picture (matplotlib draws every triangle of
/// every frame of a GIF in Python: this keeps a 40-frame GIF within seconds).
pub const PICTURE_TRIANGLE_BUDGET: usize = 4_000;

/// No mesh is cut below this many triangles, however small its share of the budget.
pub const MIN_TRIANGLES_PER_MESH: usize = 24;

/// Colour of the visuals whose material has none, `[r, g, b, a]`.
pub const DEFAULT_VISUAL_RGBA: [f64; 4] = [0.7, 0.7, 0.72, 1.0];

/// What a visual draws.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A box of this size [m], centred on its placement.
    Box {
        /// Edge lengths along x, y, z [m].
        size: [f64; 3],
    },
    /// A cylinder along its placement's z axis, centred.
    Cylinder {
        /// Radius [m].
        radius: f64,
        /// Length [m].
        length: f64,
    },
    /// A sphere, centred.
    Sphere {
        /// Radius [m].
        radius: f64,
    },
    /// A triangle mesh already scaled and placed in the link frame (its placement is the
    /// identity).
    Mesh(TriangleMesh),
}

/// One `<visual>` of a link.
#[derive(Clone, Debug, PartialEq)]
pub struct Visual {
    /// The link (a frame of the model, of `/tf`).
    pub link: String,
    /// Placement of the shape in the link frame: the visual's `<origin>` for a primitive, the
    /// identity for a mesh.
    pub link_placement: Placement,
    /// The shape.
    pub shape: Shape,
    /// Colour `[r, g, b, a]`: the visual's material colour, else its named material's in the
    /// robot, else [`DEFAULT_VISUAL_RGBA`].
    pub rgba: [f64; 4],
}

/// A mesh visual that is not drawn, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshWarning {
    /// The link of the visual.
    pub link: String,
    /// The mesh's `filename` as the URDF writes it.
    pub uri: String,
    /// Why (for an unresolved URI: the directories searched).
    pub reason: String,
}

impl fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "link '{}': mesh '{}' not drawn: {}",
            self.link, self.uri, self.reason
        )
    }
}

/// The visuals of a robot and the meshes that could not be drawn.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RobotVisuals {
    /// Every visual drawn, in URDF order (links, then visuals).
    pub visuals: Vec<Visual>,
    /// Every mesh visual not drawn.
    pub warnings: Vec<MeshWarning>,
}

/// Where the meshes come from and how many triangles they may have.
#[derive(Clone, Debug)]
pub struct VisualOptions<'a> {
    /// Folder of the URDF file (relative mesh paths and the search above the URDF).
    pub urdf_dir: &'a Path,
    /// Package directories for `package://` URIs.
    pub package_dirs: &'a PackageDirs,
    /// Triangles of all the robot's meshes together (each mesh gets its share, at least
    /// [`MIN_TRIANGLES_PER_MESH`]).
    pub triangle_budget: usize,
}

/// A mesh visual waiting for its file.
struct PendingMesh {
    /// Index of its visual in the drawn list.
    index: usize,
    file: PathBuf,
    placement: Placement,
    link: String,
    uri: String,
}

/// The visuals of `robot`'s links (only those named in `links`, when given); capsules are
/// skipped (URDF 1.0 has none).
pub fn robot_visuals(
    robot: &urdf_rs::Robot,
    links: Option<&HashSet<&str>>,
    options: &VisualOptions<'_>,
) -> RobotVisuals {
    let mut found = RobotVisuals::default();
    let mut pending = Vec::new();
    let wanted = |name: &str| links.is_none_or(|set| set.contains(name));
    for link in robot.links.iter().filter(|l| wanted(&l.name)) {
        for visual in &link.visual {
            let rgba = visual_rgba(robot, visual.material.as_ref());
            let link_placement = origin_placement(&visual.origin);
            let shape = match &visual.geometry {
                urdf_rs::Geometry::Box { size } => Shape::Box { size: size.0 },
                urdf_rs::Geometry::Cylinder { radius, length } => Shape::Cylinder {
                    radius: *radius,
                    length: *length,
                },
                urdf_rs::Geometry::Sphere { radius } => Shape::Sphere { radius: *radius },
                urdf_rs::Geometry::Capsule { .. } => continue,
                urdf_rs::Geometry::Mesh { filename, scale } => {
                    let scale = scale.as_ref().map_or([1.0; 3], |s| s.0);
                    if let Some(reason) = non_finite_placement(&visual.origin, scale) {
                        found.warnings.push(MeshWarning {
                            link: link.name.clone(),
                            uri: filename.clone(),
                            reason,
                        });
                        continue;
                    }
                    match options.package_dirs.resolve(filename, options.urdf_dir) {
                        Ok(file) => pending.push(PendingMesh {
                            index: found.visuals.len(),
                            file,
                            link: link.name.clone(),
                            uri: filename.clone(),
                            placement: Placement {
                                scale,
                                ..link_placement
                            },
                        }),
                        Err(e) => {
                            found.warnings.push(MeshWarning {
                                link: link.name.clone(),
                                uri: filename.clone(),
                                reason: e.to_string(),
                            });
                            continue;
                        }
                    }
                    Shape::Mesh(TriangleMesh::default())
                }
            };
            let link_placement = match shape {
                Shape::Mesh(_) => Placement::IDENTITY,
                _ => link_placement,
            };
            found.visuals.push(Visual {
                link: link.name.clone(),
                link_placement,
                shape,
                rgba,
            });
        }
    }
    fill_meshes(&mut found, pending, options.triangle_budget);
    found
}

/// Reads each file of `pending` once, cuts each mesh to its share of `budget`, places it, and
/// drops the visuals whose file cannot be read (a warning each).
fn fill_meshes(found: &mut RobotVisuals, pending: Vec<PendingMesh>, budget: usize) {
    let mut cache: HashMap<PathBuf, Result<Arc<TriangleMesh>, String>> = HashMap::new();
    for mesh in &pending {
        cache.entry(mesh.file.clone()).or_insert_with(|| {
            read_mesh(&mesh.file)
                .map(Arc::new)
                .map_err(|e| e.to_string())
        });
    }
    let total: usize = pending
        .iter()
        .filter_map(|m| cache[&m.file].as_ref().ok())
        .map(|mesh| mesh.triangles.len())
        .sum();
    let mut unreadable = Vec::new();
    for mesh in &pending {
        match &cache[&mesh.file] {
            Ok(source) => {
                let count = source.triangles.len();
                let share = if total <= budget {
                    count
                } else {
                    (count * budget / total).max(MIN_TRIANGLES_PER_MESH)
                };
                found.visuals[mesh.index].shape =
                    Shape::Mesh(decimate(source, share).placed(&mesh.placement));
            }
            Err(reason) => unreadable.push((
                mesh.index,
                MeshWarning {
                    link: mesh.link.clone(),
                    uri: mesh.uri.clone(),
                    reason: reason.clone(),
                },
            )),
        }
    }
    for (index, _) in unreadable.iter().rev() {
        found.visuals.remove(*index);
    }
    found
        .warnings
        .extend(unreadable.into_iter().map(|(_, warning)| warning));
}

/// Why a mesh at `origin` with `scale` cannot be placed (a number of either not finite, which
/// would make every vertex NaN); `None` when it can.
fn non_finite_placement(origin: &urdf_rs::Pose, scale: [f64; 3]) -> Option<String> {
    let mut numbers = origin.xyz.0.iter().chain(&origin.rpy.0).chain(&scale);
    (!numbers.all(|v| v.is_finite())).then(|| {
        format!(
            "its origin (xyz {:?}, rpy {:?}) or scale {scale:?} is not finite",
            origin.xyz.0, origin.rpy.0
        )
    })
}

/// The visual's `<origin>` as a placement (URDF rpy: fixed axes x, y, z).
fn origin_placement(origin: &urdf_rs::Pose) -> Placement {
    let [roll, pitch, yaw] = origin.rpy.0;
    let rotation = rotation_from_rpy(roll, pitch, yaw);
    Placement {
        rotation: std::array::from_fn(|r| std::array::from_fn(|c| rotation[(r, c)])),
        translation: origin.xyz.0,
        scale: [1.0; 3],
    }
}

/// The visual's own colour, else its named material's in the robot's material list, else
/// [`DEFAULT_VISUAL_RGBA`].
pub fn visual_rgba(robot: &urdf_rs::Robot, material: Option<&urdf_rs::Material>) -> [f64; 4] {
    let named = |m: &urdf_rs::Material| {
        robot
            .materials
            .iter()
            .find(|global| global.name == m.name)
            .and_then(|global| global.color.clone())
    };
    material
        .and_then(|m| m.color.clone().or_else(|| named(m)))
        .map_or(DEFAULT_VISUAL_RGBA, |c| c.rgba.0)
}

/// The visuals of the URDF file `urdf` (all links), with the package directories of `user_dirs`
/// then the environment's, and the mesh warnings.
///
/// Errors: [`crate::Error::Io`] when the file cannot be read, [`crate::Error::Dynamics`] when
/// it does not parse.
pub fn urdf_file_visuals(
    urdf: &Path,
    user_dirs: &[PathBuf],
    triangle_budget: usize,
) -> crate::Result<RobotVisuals> {
    let text = sea_dyn::files::read_text(urdf).map_err(|source| crate::Error::Io {
        path: urdf.display().to_string(),
        source,
    })?;
    let robot = sea_dyn::urdf::parse_urdf(&text).map_err(|e| e.in_file(urdf))?;
    let dirs = PackageDirs::from_environment(user_dirs.iter().cloned());
    let urdf_dir = urdf.parent().unwrap_or(Path::new("."));
    Ok(robot_visuals(
        &robot,
        None,
        &VisualOptions {
            urdf_dir,
            package_dirs: &dirs,
            triangle_budget,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An ASCII STL of `n` separate triangles (a strip along x).
    fn strip_stl(n: usize) -> String {
        let mut text = String::from("solid strip\n");
        for k in 0..n {
            let x = k as f32;
            text += &format!(
                "facet normal 0 0 1\nouter loop\nvertex {x} 0 0\nvertex {} 0 0\nvertex {x} 1 0\nendloop\nendfacet\n",
                x + 1.0
            );
        }
        text + "endsolid strip\n"
    }

    /// A robot whose `base` has a box, the STL `pkg/meshes/a.stl` through `package://` (twice,
    /// scaled by 2 the second time), a missing file, an unknown package and the STL again with
    /// a NaN scale and with an infinite origin.
    fn robot(dir: &Path) -> urdf_rs::Robot {
        std::fs::create_dir_all(dir.join("pkg/meshes")).unwrap();
        std::fs::write(dir.join("pkg/meshes/a.stl"), strip_stl(100)).unwrap();
        let mesh = |file: &str, scale: &str| {
            format!(
                r#"<visual><origin xyz="0 0 1"/><geometry><mesh filename="{file}" scale="{scale}"/></geometry></visual>"#
            )
        };
        let text = format!(
            r#"<robot name="r"><link name="base">
            <visual><geometry><box size="1 2 3"/></geometry></visual>
            {}{}{}{}{}
            <visual><origin xyz="0 inf 1"/><geometry><mesh filename="package://pkg/meshes/a.stl"/></geometry></visual>
            </link></robot>"#,
            mesh("package://pkg/meshes/a.stl", "1 1 1"),
            mesh("package://pkg/meshes/a.stl", "2 2 2"),
            mesh("missing.stl", "1 1 1"),
            mesh("package://nowhere/a.stl", "1 1 1"),
            mesh("package://pkg/meshes/a.stl", "nan 1 1"),
        );
        urdf_rs::read_from_string(&text).unwrap()
    }

    #[test]
    fn meshes_are_placed_cut_to_the_budget_and_bad_ones_are_warnings() {
        let dir = std::env::temp_dir().join(format!("sea_sim_visuals_{}", std::process::id()));
        let robot = robot(&dir);
        let dirs = PackageDirs::new([dir.clone()]);
        let options = VisualOptions {
            urdf_dir: &dir,
            package_dirs: &dirs,
            triangle_budget: 100,
        };
        let found = robot_visuals(&robot, None, &options);
        assert_eq!(found.visuals.len(), 3, "the box and the two drawn meshes");
        assert!(matches!(
            found.visuals[0].shape,
            Shape::Box {
                size: [1.0, 2.0, 3.0]
            }
        ));
        for (visual, scale) in found.visuals[1..].iter().zip([1.0, 2.0]) {
            let Shape::Mesh(mesh) = &visual.shape else {
                panic!("a mesh")
            };
            assert!(mesh.triangles.len() <= 50, "half the budget each");
            assert_eq!(visual.link_placement, Placement::IDENTITY);
            // Scaled, then moved by the origin (z + 1) into the link frame.
            let top = mesh.positions.iter().map(|p| p[1]).fold(0.0, f32::max);
            assert_eq!(top, scale as f32);
            assert!(mesh.positions.iter().all(|p| p[2] == 1.0));
        }
        let warnings: Vec<String> = found.warnings.iter().map(ToString::to_string).collect();
        assert_eq!(warnings.len(), 4, "{warnings:?}");
        let warned = |text: &str| warnings.iter().find(|w| w.contains(text)).unwrap();
        assert!(warned("missing.stl").starts_with("link 'base': mesh 'missing.stl' not drawn: "));
        assert!(
            warned("package://nowhere/a.stl").contains(&dir.display().to_string()),
            "the dirs searched"
        );
        assert!(
            warned("NaN").contains("'package://pkg/meshes/a.stl' not drawn: its origin"),
            "{warnings:?}"
        );
        assert!(warned("inf").contains("not finite"), "{warnings:?}");
        std::fs::remove_dir_all(dir).unwrap();
    }
}
