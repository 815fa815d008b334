//! The `/scene` channel (`foxglove.SceneUpdate`): the robot drawn from the URDF's visual
//! primitives, the support polygon, the CoM and its reference, the contact wrenches.
//!
//! The static part (robot bodies and foot rectangles, frame-locked to the link frames of `/tf`)
//! is encoded once; every sample appends the moving markers. Protobuf concatenation merges
//! repeated fields, so `static ++ markers` is one `SceneUpdate` holding both entity lists, and
//! each `/scene` message is complete: a seek or a late live client shows the whole robot.

use crate::error::Error;
use crate::Result;
use ::foxglove::messages::{
    line_primitive, ArrowPrimitive, Color, CubePrimitive, CylinderPrimitive, LinePrimitive, Point3,
    Pose, Quaternion, SceneEntity, SceneUpdate, SpherePrimitive, Timestamp, Vector3,
};
use ::foxglove::Encode;
use nalgebra::Vector3 as V3;
use sea_dyn::spatial::{quaternion_from_rotation, rotation_from_rpy};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Where the scene comes from: the URDF (visuals and the MCAP attachment) and the contact
/// surface of each foot.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSource {
    /// The URDF file the model was loaded from.
    pub urdf: PathBuf,
    /// The rectangle of every contact in its own frame, drawn as the support polygon; `None`
    /// draws none.
    pub foot: Option<FootRectangle>,
}

/// A foot's contact rectangle in the contact (sole) frame [m].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootRectangle {
    /// `[min, max]` along the sole's x axis.
    pub x: [f64; 2],
    /// `[min, max]` along the sole's y axis.
    pub y: [f64; 2],
}

impl SceneSource {
    /// The scene of `scenario`: its resolved URDF and the contact surface its controller and
    /// plant share (`[controller.contact]` foot_x, foot_y).
    pub fn of_scenario(scenario: &crate::scenario::Scenario) -> Self {
        let contact = &scenario.controller.contact.surface;
        Self {
            urdf: scenario.resolve(&scenario.robot.urdf),
            foot: Some(FootRectangle {
                x: contact.foot_x,
                y: contact.foot_y,
            }),
        }
    }
}

/// The URDF text and the static scene built from it.
pub(crate) struct StaticScene {
    /// File name of the URDF (the attachment's name).
    pub file_name: String,
    /// The URDF as read.
    pub urdf_text: Vec<u8>,
    /// Entities frame-locked to link frames (bodies, support polygon), protobuf-encoded as a
    /// `SceneUpdate`.
    pub encoded: Vec<u8>,
}

/// Colour of the visuals whose material has none.
const DEFAULT_BODY_COLOR: [f64; 4] = [0.7, 0.7, 0.72, 1.0];
/// Colour of the support polygon.
const SUPPORT_COLOR: [f64; 4] = [0.1, 0.6, 1.0, 1.0];
/// Line width of the support polygon [m].
const SUPPORT_LINE_WIDTH_M: f64 = 0.004;
/// Diameter of the CoM sphere [m].
const COM_DIAMETER_M: f64 = 0.05;
/// Diameter of the CoM reference sphere [m].
const COM_REFERENCE_DIAMETER_M: f64 = 0.035;
/// Arrow length per newton of contact force [m/N]: the iCub's weight (about 330 N) is 0.5 m.
pub const ARROW_M_PER_N: f64 = 0.0015;

impl StaticScene {
    /// Reads the URDF of `source` and builds the bodies of the links in `link_frames` and the
    /// foot rectangles of `contacts` (names not in `link_frames` draw nothing).
    ///
    /// Errors: [`Error::Io`] when the URDF cannot be read, [`Error::Log`] when it does not parse.
    pub fn build(
        source: &SceneSource,
        link_frames: &[String],
        contacts: &[String],
    ) -> Result<Self> {
        let path = &source.urdf;
        let urdf_text = std::fs::read(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        let robot = urdf_rs::read_from_string(&String::from_utf8_lossy(&urdf_text))
            .map_err(|e| Error::Log(format!("{}: {e}", path.display())))?;
        let frames: HashSet<&str> = link_frames.iter().map(String::as_str).collect();
        let mut update = SceneUpdate {
            deletions: Vec::new(),
            entities: robot_entities(&robot, &frames),
        };
        if let Some(foot) = source.foot {
            let feet = contacts.iter().filter(|c| frames.contains(c.as_str()));
            update
                .entities
                .extend(feet.map(|c| support_polygon(c, foot)));
        }
        Ok(Self {
            file_name: file_name(path),
            urdf_text,
            encoded: encode_to_vec(&update),
        })
    }
}

/// The protobuf encoding of `message` (writing into a `Vec` cannot fail).
pub(crate) fn encode_to_vec(message: &impl Encode) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(message.encoded_len().unwrap_or(0));
    let _ = message.encode(&mut bytes);
    bytes
}

/// The last component of `path` (the whole path when it has none).
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// One frame-locked entity per link with visuals, id `link/<name>`; boxes, cylinders and
/// spheres are drawn, meshes and capsules skipped (the iCub model has none).
fn robot_entities(robot: &urdf_rs::Robot, frames: &HashSet<&str>) -> Vec<SceneEntity> {
    let mut entities = Vec::new();
    for link in robot
        .links
        .iter()
        .filter(|l| frames.contains(l.name.as_str()))
    {
        let mut entity = frame_locked_entity(&link.name, format!("link/{}", link.name));
        for visual in &link.visual {
            let pose = Some(visual_pose(&visual.origin));
            let color = Some(material_color(robot, visual.material.as_ref()));
            match &visual.geometry {
                urdf_rs::Geometry::Box { size } => entity.cubes.push(CubePrimitive {
                    pose,
                    size: Some(vector(size.0)),
                    color,
                }),
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    entity.cylinders.push(CylinderPrimitive {
                        pose,
                        size: Some(vector([2.0 * radius, 2.0 * radius, *length])),
                        bottom_scale: 1.0,
                        top_scale: 1.0,
                        color,
                    })
                }
                urdf_rs::Geometry::Sphere { radius } => entity.spheres.push(SpherePrimitive {
                    pose,
                    size: Some(vector([2.0 * radius; 3])),
                    color,
                }),
                _ => {}
            }
        }
        if !(entity.cubes.is_empty() && entity.cylinders.is_empty() && entity.spheres.is_empty()) {
            entities.push(entity);
        }
    }
    entities
}

/// An empty entity `id` that moves with `frame_id` (lifetime: until replaced).
fn frame_locked_entity(frame_id: &str, id: String) -> SceneEntity {
    SceneEntity {
        frame_id: frame_id.to_string(),
        id,
        frame_locked: true,
        ..Default::default()
    }
}

/// The foot rectangle of `contact`, a closed line in the contact frame, id `support/<name>`.
fn support_polygon(contact: &str, foot: FootRectangle) -> SceneEntity {
    let mut entity = frame_locked_entity(contact, format!("support/{contact}"));
    let corners = [
        [foot.x[0], foot.y[0]],
        [foot.x[1], foot.y[0]],
        [foot.x[1], foot.y[1]],
        [foot.x[0], foot.y[1]],
    ];
    entity.lines.push(LinePrimitive {
        r#type: line_primitive::Type::LineLoop as i32,
        pose: Some(identity_pose()),
        thickness: SUPPORT_LINE_WIDTH_M,
        scale_invariant: false,
        points: corners
            .iter()
            .map(|[x, y]| Point3 {
                x: *x,
                y: *y,
                z: 0.0,
            })
            .collect(),
        color: Some(color(SUPPORT_COLOR)),
        colors: Vec::new(),
        indices: Vec::new(),
    });
    entity
}

/// The visual's `origin` as a pose in its link frame (URDF rpy: fixed axes x, y, z).
fn visual_pose(origin: &urdf_rs::Pose) -> Pose {
    let [roll, pitch, yaw] = origin.rpy.0;
    let [w, x, y, z] = quaternion_from_rotation(&rotation_from_rpy(roll, pitch, yaw));
    Pose {
        position: Some(vector(origin.xyz.0)),
        orientation: Some(Quaternion { x, y, z, w }),
    }
}

/// The visual's own colour, else its named material's in the robot's material list, else
/// [`DEFAULT_BODY_COLOR`].
fn material_color(robot: &urdf_rs::Robot, material: Option<&urdf_rs::Material>) -> Color {
    let named = |m: &urdf_rs::Material| {
        robot
            .materials
            .iter()
            .find(|global| global.name == m.name)
            .and_then(|global| global.color.clone())
    };
    let rgba = material
        .and_then(|m| m.color.clone().or_else(|| named(m)))
        .map_or(DEFAULT_BODY_COLOR, |c| c.rgba.0);
    color(rgba)
}

/// The moving markers of `/scene` in the world frame: CoM, its reference, one arrow per
/// contact. Kept between samples and updated in place (no allocation per sample).
pub(crate) struct Markers {
    update: SceneUpdate,
    /// Number of contact arrows (entities after the two spheres).
    arrows: usize,
}

/// Entity ids and colours of the two CoM spheres.
const COM_ENTITIES: [(&str, f64, [f64; 4]); 2] = [
    ("com", COM_DIAMETER_M, [1.0, 0.45, 0.0, 1.0]),
    (
        "com_reference",
        COM_REFERENCE_DIAMETER_M,
        [0.1, 0.8, 0.2, 0.7],
    ),
];

impl Markers {
    /// Markers for the contacts labelled `contacts` (arrow ids `wrench/<label>`).
    pub fn new(contacts: &[String]) -> Self {
        let mut entities: Vec<SceneEntity> = COM_ENTITIES
            .iter()
            .map(|(id, diameter, rgba)| {
                let mut entity = world_entity(id.to_string());
                entity.spheres.push(SpherePrimitive {
                    pose: Some(identity_pose()),
                    size: Some(vector([*diameter; 3])),
                    color: Some(color(*rgba)),
                });
                entity
            })
            .collect();
        for contact in contacts {
            let mut entity = world_entity(format!("wrench/{contact}"));
            entity.arrows.push(ArrowPrimitive {
                pose: Some(identity_pose()),
                shaft_length: 0.0,
                shaft_diameter: 0.012,
                head_length: 0.04,
                head_diameter: 0.03,
                color: Some(color([0.9, 0.1, 0.1, 1.0])),
            });
            entities.push(entity);
        }
        Self {
            update: SceneUpdate {
                deletions: Vec::new(),
                entities,
            },
            arrows: contacts.len(),
        }
    }

    /// Sets the markers of one sample and appends their encoding to `buffer`: `com`,
    /// `com_reference`, and for contact `k` the force `wrenches[6k..6k+3]` applied at
    /// `origins[k]` (world axes). Returns `false`, appending nothing, when a value is not
    /// finite (Foxglove needs numbers).
    pub fn encode(
        &mut self,
        stamp: Timestamp,
        com: [f64; 3],
        com_reference: [f64; 3],
        wrenches: &[f64],
        origins: &[[f64; 3]],
        buffer: &mut Vec<u8>,
    ) -> bool {
        let used = 6 * self.arrows.min(origins.len());
        let finite = com
            .iter()
            .chain(&com_reference)
            .chain(&wrenches[..used.min(wrenches.len())])
            .chain(origins.iter().flatten())
            .all(|v| v.is_finite());
        if !finite {
            return false;
        }
        let (spheres, arrows) = self.update.entities.split_at_mut(COM_ENTITIES.len());
        for (entity, position) in spheres.iter_mut().zip([com, com_reference]) {
            entity.timestamp = Some(stamp);
            entity.spheres[0].pose = Some(pose_at(position, [1.0, 0.0, 0.0, 0.0]));
        }
        for (k, entity) in arrows.iter_mut().enumerate() {
            entity.timestamp = Some(stamp);
            let force = wrenches.get(6 * k..6 * k + 3).unwrap_or(&[0.0; 3]);
            let origin = origins.get(k).copied().unwrap_or([0.0; 3]);
            set_arrow(
                &mut entity.arrows[0],
                origin,
                [force[0], force[1], force[2]],
            );
        }
        Encode::encode(&self.update, buffer).is_ok()
    }
}

/// Points `arrow` from `origin` along `force`, [`ARROW_M_PER_N`] long per newton.
fn set_arrow(arrow: &mut ArrowPrimitive, origin: [f64; 3], force: [f64; 3]) {
    let f = V3::from(force);
    let magnitude = f.norm();
    // The arrow's axis is the pose's x axis: rotate x onto the force (any axis when f = 0).
    let rotation = if magnitude > 0.0 {
        nalgebra::UnitQuaternion::rotation_between(&V3::x(), &f).unwrap_or_else(|| {
            nalgebra::UnitQuaternion::from_axis_angle(&V3::z_axis(), std::f64::consts::PI)
        })
    } else {
        nalgebra::UnitQuaternion::identity()
    };
    let q = rotation.quaternion();
    arrow.pose = Some(pose_at(origin, [q.w, q.i, q.j, q.k]));
    arrow.shaft_length = magnitude * ARROW_M_PER_N;
}

/// An entity in the world frame with id `id`.
fn world_entity(id: String) -> SceneEntity {
    SceneEntity {
        frame_id: super::WORLD_FRAME.to_string(),
        id,
        ..Default::default()
    }
}

/// A pose at `position` with orientation `[w, x, y, z]`.
fn pose_at(position: [f64; 3], [w, x, y, z]: [f64; 4]) -> Pose {
    Pose {
        position: Some(vector(position)),
        orientation: Some(Quaternion { x, y, z, w }),
    }
}

/// The identity pose.
fn identity_pose() -> Pose {
    pose_at([0.0; 3], [1.0, 0.0, 0.0, 0.0])
}

/// A Foxglove vector.
fn vector([x, y, z]: [f64; 3]) -> Vector3 {
    Vector3 { x, y, z }
}

/// A Foxglove colour from `[r, g, b, a]` in `[0, 1]`.
fn color([r, g, b, a]: [f64; 4]) -> Color {
    Color { r, g, b, a }
}
