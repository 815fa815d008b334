//! The foot rectangle of a contact from the collision geometry of its foot: every collision
//! shape of the links fused into the contact's body (boxes' corners, cylinders' and
//! capsules' bounding boxes, spheres' lowest points, the vertices of STL, OBJ and COLLADA
//! meshes read by [`crate::meshes`]),
//! expressed in the contact frame; the points within [`SOLE_BAND`] of the lowest one are the
//! sole, their bounding box in x and y the rectangle.

use crate::error::{Error, Result};
use crate::scenario::robots::FootRectangle;
use nalgebra::Vector3;
use sea_dyn::spatial::Pose;
use sea_dyn::{FrameId, Model, PackageDirs};
use std::path::Path;

/// Points up to this height above the lowest collision point are on the sole [m].
pub const SOLE_BAND: f64 = 0.01;

/// The rectangle of the contact `frame` and the height of the lowest collision point in the
/// contact frame [m] (0 when the frame is on the sole), from the URDF `urdf_text` in
/// `urdf_dir`; `contact` names the contact in errors.
pub fn foot_rectangle(
    model: &Model,
    frame: FrameId,
    urdf_text: &str,
    urdf_dir: &Path,
    dirs: &PackageDirs,
    contact: &str,
) -> Result<(FootRectangle, f64)> {
    let robot = sea_dyn::urdf::parse_urdf(urdf_text).map_err(|e| {
        no_geometry(
            contact,
            &format!("the URDF's collision geometry cannot be read ({e})"),
        )
    })?;
    let body = model.frames[frame].body;
    let contact_h_body = model.frames[frame].body_h_frame.inverse();
    let mut points = Vec::new();
    for link in &robot.links {
        let Some(link_frame) = model.frames.iter().find(|f| f.name == link.name) else {
            continue;
        };
        if link_frame.body != body {
            continue;
        }
        let contact_h_link = contact_h_body.compose(&link_frame.body_h_frame);
        for collision in &link.collision {
            let origin = &collision.origin;
            let link_h_shape = Pose::from_xyz_rpy(origin.xyz.0, origin.rpy.0);
            let contact_h_shape = contact_h_link.compose(&link_h_shape);
            shape_points(
                &collision.geometry,
                &contact_h_shape,
                urdf_dir,
                dirs,
                &mut points,
            )
            .map_err(|rule| no_geometry(contact, &format!("link '{}': {rule}", link.name)))?;
        }
    }
    let (rectangle, lowest) = rectangle_of(&points).ok_or_else(|| {
        no_geometry(
            contact,
            "its link has no collision geometry to measure the sole on",
        )
    })?;
    if rectangle.x[0] >= rectangle.x[1] || rectangle.y[0] >= rectangle.y[1] {
        let rule = format!(
            "its sole (the collision points within {SOLE_BAND} m of the lowest) measures \
             {rectangle}, no area"
        );
        return Err(no_geometry(contact, &rule));
    }
    Ok((rectangle, lowest))
}

/// The error of a foot that cannot be measured.
fn no_geometry(contact: &str, rule: &str) -> Error {
    Error::config(
        "robot.contacts",
        format!(
            "cannot measure the foot of '{contact}': {rule}; give the rectangle \
             (sea-sim init --foot X0,X1,Y0,Y1; Python: foot=(x0, x1, y0, y1))"
        ),
    )
}

/// The sole rectangle of `points` (contact frame) and the lowest point's height.
fn rectangle_of(points: &[Vector3<f64>]) -> Option<(FootRectangle, f64)> {
    let lowest = points.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    if !lowest.is_finite() {
        return None;
    }
    let sole: Vec<&Vector3<f64>> = points
        .iter()
        .filter(|p| p.z <= lowest + SOLE_BAND)
        .collect();
    let range = |axis: usize| {
        let values = sole.iter().map(|p| p[axis]);
        let min = values.clone().fold(f64::INFINITY, f64::min);
        [min, values.fold(f64::NEG_INFINITY, f64::max)]
    };
    Some((
        FootRectangle {
            x: range(0),
            y: range(1),
        },
        lowest,
    ))
}

/// Appends the points of one collision shape, in the contact frame.
fn shape_points(
    geometry: &urdf_rs::Geometry,
    contact_h_shape: &Pose,
    urdf_dir: &Path,
    dirs: &PackageDirs,
    points: &mut Vec<Vector3<f64>>,
) -> std::result::Result<(), String> {
    check_shape_size(geometry)?;
    let mut local = Vec::new();
    match geometry {
        urdf_rs::Geometry::Box { size } => box_corners(size.0, &mut local),
        urdf_rs::Geometry::Cylinder { radius, length } => {
            box_corners([2.0 * radius, 2.0 * radius, *length], &mut local)
        }
        urdf_rs::Geometry::Capsule { radius, length } => box_corners(
            [2.0 * radius, 2.0 * radius, length + 2.0 * radius],
            &mut local,
        ),
        urdf_rs::Geometry::Sphere { radius } => {
            // Only its lowest point (in the contact frame) touches the ground.
            let center = contact_h_shape.translation;
            points.push(center - Vector3::z() * *radius);
            return Ok(());
        }
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let file = dirs
                .resolve(filename, urdf_dir)
                .map_err(|e| e.to_string())?;
            let scale = scale.map_or([1.0; 3], |s| [s[0], s[1], s[2]]);
            let mesh = crate::meshes::read_mesh(&file).map_err(|e| e.to_string())?;
            for vertex in &mesh.positions {
                local.push(Vector3::new(
                    f64::from(vertex[0]) * scale[0],
                    f64::from(vertex[1]) * scale[1],
                    f64::from(vertex[2]) * scale[2],
                ));
            }
        }
    }
    points.extend(local.iter().map(|p| contact_h_shape.transform_point(p)));
    Ok(())
}

/// `Err` naming the shape when one of its sizes is negative or not finite (a NaN would pass
/// every comparison of the sole's band and bounds unseen).
fn check_shape_size(geometry: &urdf_rs::Geometry) -> std::result::Result<(), String> {
    let (shape, sizes): (&str, Vec<f64>) = match geometry {
        urdf_rs::Geometry::Box { size } => ("box of size", size.0.to_vec()),
        urdf_rs::Geometry::Cylinder { radius, length } => {
            ("cylinder of radius and length", vec![*radius, *length])
        }
        urdf_rs::Geometry::Capsule { radius, length } => {
            ("capsule of radius and length", vec![*radius, *length])
        }
        urdf_rs::Geometry::Sphere { radius } => ("sphere of radius", vec![*radius]),
        // A negative scale mirrors the mesh.
        urdf_rs::Geometry::Mesh { scale, .. } => {
            let scale = scale.map_or(vec![1.0], |s| s.0.iter().map(|v| v.abs()).collect());
            ("mesh of scale", scale)
        }
    };
    if sizes.iter().all(|v| v.is_finite() && *v >= 0.0) {
        return Ok(());
    }
    Err(format!(
        "a collision {shape} {sizes:?}: finite, non-negative numbers expected"
    ))
}

/// The 8 corners of a box of `size` centred at the origin.
fn box_corners(size: [f64; 3], out: &mut Vec<Vector3<f64>>) {
    for corner in 0..8 {
        let sign = |bit: usize| if corner & (1 << bit) == 0 { -0.5 } else { 0.5 };
        out.push(Vector3::new(
            sign(0) * size[0],
            sign(1) * size[1],
            sign(2) * size[2],
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shape_size_that_is_not_a_finite_non_negative_number_is_named() {
        let boxed = |size: [f64; 3]| urdf_rs::Geometry::Box {
            size: urdf_rs::Vec3(size),
        };
        assert!(check_shape_size(&boxed([0.16, 0.08, 0.03])).is_ok());
        let nan = check_shape_size(&boxed([f64::NAN, 0.08, 0.03])).unwrap_err();
        assert_eq!(
            nan,
            "a collision box of size [NaN, 0.08, 0.03]: finite, non-negative numbers expected"
        );
        let sphere = urdf_rs::Geometry::Sphere { radius: -0.01 };
        assert!(check_shape_size(&sphere)
            .unwrap_err()
            .contains("sphere of radius [-0.01]"));
        let mirrored = urdf_rs::Geometry::Mesh {
            filename: "foot.stl".into(),
            scale: Some(urdf_rs::Vec3([-1.0, 1.0, 1.0])),
        };
        assert!(check_shape_size(&mirrored).is_ok());
        let infinite = urdf_rs::Geometry::Mesh {
            filename: "foot.stl".into(),
            scale: Some(urdf_rs::Vec3([f64::INFINITY, 1.0, 1.0])),
        };
        assert!(check_shape_size(&infinite)
            .unwrap_err()
            .contains("mesh of scale [inf, 1.0, 1.0]"));
    }

    #[test]
    fn the_sole_is_the_band_above_the_lowest_point() {
        let points = [
            Vector3::new(-0.1, -0.05, -0.02),
            Vector3::new(0.2, 0.05, -0.015),
            Vector3::new(0.5, 0.5, 0.1),
        ];
        let (rectangle, lowest) = rectangle_of(&points).unwrap();
        assert_eq!(rectangle.x, [-0.1, 0.2]);
        assert_eq!(rectangle.y, [-0.05, 0.05]);
        assert_eq!(lowest, -0.02);
        assert!(rectangle_of(&[]).is_none());
    }

    #[test]
    fn a_collada_collision_mesh_is_measured_in_metres_and_scaled() {
        // A sole 10 cm x 20 cm (centimetre units) and one vertex 5 cm above it.
        let dae = r##"<COLLADA version="1.4.1"><asset><unit meter="0.01"/></asset>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="a" count="15">0 0 0 10 0 0 10 20 0 0 20 0 5 10 5</float_array>
<technique_common><accessor source="#a" count="5" stride="3"/></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="2"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2 0 2 4</p></triangles>
</mesh></geometry></library_geometries></COLLADA>"##;
        let dir = std::env::temp_dir().join(format!("sea_sim_foot_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("sole.dae"), dae).unwrap();
        let geometry = urdf_rs::Geometry::Mesh {
            filename: "sole.dae".into(),
            scale: Some(urdf_rs::Vec3([2.0, 1.0, 1.0])),
        };
        let mut points = Vec::new();
        let dirs = PackageDirs::from_environment(Vec::<std::path::PathBuf>::new());
        shape_points(&geometry, &Pose::identity(), &dir, &dirs, &mut points).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        let (rectangle, lowest) = rectangle_of(&points).unwrap();
        assert_eq!(lowest, 0.0);
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-6;
        assert!(close(rectangle.x, [0.0, 0.2]), "{:?}", rectangle.x);
        assert!(close(rectangle.y, [0.0, 0.2]), "{:?}", rectangle.y);
    }
}
