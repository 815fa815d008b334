//! The robot's scene: `/robot` (`foxglove.SceneUpdate`, once) draws the URDF's visuals, boxes,
//! cylinders, spheres and meshes, one frame-locked entity per link; `/scene` (every sample)
//! draws the support polygon, the CoM and its reference, the contact wrenches.
//!
//! Why two topics: meshes weigh about a megabyte (a budget of
//! [`SCENE_TRIANGLE_BUDGET`] triangles per robot), too much to repeat in every sample. The
//! robot's entities have lifetime 0 (kept until replaced) and are frame-locked, so one message
//! draws the robot for the whole run, moving with `/tf`. After a seek Foxglove reads, for each
//! topic, the last message at or before the new time, i.e. this one: the robot stays drawn.
//! The live view republishes it every second for clients that connect late.
//!
//! The static part of `/scene` (the foot rectangles, frame-locked to the soles) is encoded
//! once; every sample appends the moving markers. Protobuf concatenation merges repeated
//! fields, so `static ++ markers` is one `SceneUpdate` holding both entity lists, and each
//! `/scene` message is complete.
//!
//! Meshes are drawn as `TriangleListPrimitive`s (points and indices in the link frame), not as
//! embedded model files (`ModelPrimitive`): no up-axis convention to match (Foxglove turns
//! glTF and STL models from y-up to z-up), flat shading and both faces lit by Foxglove, and
//! readable back by any protobuf reader. A mesh that cannot be drawn is a warning (kept in the
//! log's metadata), the rest of the robot is drawn; [`SceneSource::strict`] makes it an error.

use crate::error::Error;
use crate::meshes::visuals::{
    robot_visuals, MeshWarning, Shape, Visual, VisualOptions, SCENE_TRIANGLE_BUDGET,
};
use crate::meshes::{Placement, TriangleMesh};
use crate::Result;
use ::foxglove::messages::{
    line_primitive, ArrowPrimitive, Color, CubePrimitive, CylinderPrimitive, LinePrimitive, Point3,
    Pose, Quaternion, SceneEntity, SceneUpdate, SpherePrimitive, Timestamp, TriangleListPrimitive,
    Vector3,
};
use ::foxglove::Encode;
use nalgebra::Vector3 as V3;
use sea_dyn::resources::PackageDirs;
use sea_dyn::spatial::quaternion_from_rotation;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, RecvTimeoutError};
use std::time::Duration;

/// How often a scene built on its own thread looks at the run's cancellation flag.
const CANCEL_POLL: Duration = Duration::from_millis(50);

/// Where the scene comes from: the URDF (visuals and the MCAP attachment), where its meshes
/// are, and the contact surface of each foot.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneSource {
    /// The URDF file the model was loaded from.
    pub urdf: PathBuf,
    /// The rectangle of every contact in its own frame, drawn as the support polygon; `None`
    /// draws none.
    pub foot: Option<FootRectangle>,
    /// Where `package://` mesh URIs are looked for (and then above the URDF).
    pub package_dirs: PackageDirs,
    /// A mesh that cannot be drawn is an error (default: a warning, the rest is drawn).
    pub strict: bool,
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
    /// The scene of `urdf` with no feet, the package directories of the environment, and
    /// warnings for meshes that cannot be drawn.
    pub fn new(urdf: impl Into<PathBuf>) -> Self {
        Self {
            urdf: urdf.into(),
            foot: None,
            package_dirs: PackageDirs::from_environment(Vec::<PathBuf>::new()),
            strict: false,
        }
    }

    /// The scene of a run: its resolved URDF, the package directories of the environment and
    /// the contact surface its controller and plant share (a scenario's `[controller.contact]`
    /// foot_x, foot_y).
    pub fn of_run(scene: &sea_loop::RunScene) -> Self {
        Self {
            foot: scene.foot.map(|(x, y)| FootRectangle { x, y }),
            ..Self::new(scene.urdf.clone())
        }
    }

    /// The same scene with `dirs` searched first for `package://` URIs (then the
    /// environment's, then above the URDF).
    pub fn with_package_dirs(mut self, dirs: &[PathBuf]) -> Self {
        let mut all = dirs.to_vec();
        all.extend(
            self.package_dirs
                .dirs
                .iter()
                .filter(|d| !dirs.contains(d))
                .cloned(),
        );
        self.package_dirs = PackageDirs::new(all);
        self
    }
}

/// The URDF text and the static scene built from it.
pub(crate) struct StaticScene {
    /// File name of the URDF (the attachment's name).
    pub file_name: String,
    /// The URDF as read.
    pub urdf_text: Vec<u8>,
    /// The robot: one frame-locked entity per link with visuals, protobuf-encoded as a
    /// `SceneUpdate` (the `/robot` message).
    pub robot: Vec<u8>,
    /// The static part of `/scene`: the support polygon, protobuf-encoded as a `SceneUpdate`.
    pub encoded: Vec<u8>,
    /// The mesh visuals not drawn.
    pub warnings: Vec<MeshWarning>,
    /// Number of visuals drawn.
    pub visuals_drawn: usize,
}

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
    /// Reads the URDF of `source` and builds the bodies of the links in `link_frames` (meshes
    /// decimated to [`SCENE_TRIANGLE_BUDGET`] triangles) and the foot rectangles of `contacts`
    /// (names not in `link_frames` draw nothing).
    ///
    /// Errors: [`Error::Io`] when the URDF cannot be read, [`Error::Log`] when it does not parse
    /// or, with [`SceneSource::strict`], when a mesh cannot be drawn.
    pub fn build(
        source: &SceneSource,
        link_frames: &[String],
        contacts: &[String],
    ) -> Result<Self> {
        let path = &source.urdf;
        let urdf_text = sea_dyn::files::read_bounded(path, sea_dyn::files::MAX_TEXT_BYTES)
            .map_err(|source| Error::Io {
                path: path.display().to_string(),
                source,
            })?;
        let robot = sea_dyn::urdf::parse_urdf(&String::from_utf8_lossy(&urdf_text))
            .map_err(|e| Error::Log(format!("{}: {e}", path.display())))?;
        let frames: HashSet<&str> = link_frames.iter().map(String::as_str).collect();
        let options = VisualOptions {
            urdf_dir: path.parent().unwrap_or(Path::new(".")),
            package_dirs: &source.package_dirs,
            triangle_budget: SCENE_TRIANGLE_BUDGET,
        };
        let visuals = robot_visuals(&robot, Some(&frames), &options);
        if source.strict && !visuals.warnings.is_empty() {
            return Err(Error::Log(format!(
                "{}: {}",
                path.display(),
                visuals
                    .warnings
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join("; ")
            )));
        }
        let mut support = SceneUpdate::default();
        if let Some(foot) = source.foot {
            let feet = contacts.iter().filter(|c| frames.contains(c.as_str()));
            support.entities = feet.map(|c| support_polygon(c, foot)).collect();
        }
        let robot_update = SceneUpdate {
            deletions: Vec::new(),
            entities: link_entities(&visuals.visuals),
        };
        Ok(Self {
            file_name: file_name(path),
            urdf_text,
            robot: encode_to_vec(&robot_update),
            encoded: encode_to_vec(&support),
            warnings: visuals.warnings,
            visuals_drawn: visuals.visuals.len(),
        })
    }

    /// [`StaticScene::build`] on a thread of its own, given up when `cancel` is raised before
    /// it ends: `Ok(None)` (the thread is left to finish its read and is dropped; a mesh
    /// reader cannot be interrupted, and a mesh of a hundred megabytes takes seconds).
    pub fn build_unless_cancelled(
        source: &SceneSource,
        link_frames: &[String],
        contacts: &[String],
        cancel: &AtomicBool,
    ) -> Result<Option<Self>> {
        if cancel.load(Ordering::Relaxed) {
            return Ok(None);
        }
        let (source, frames, contacts) = (source.clone(), link_frames.to_vec(), contacts.to_vec());
        let (sender, receiver) = sync_channel(1);
        std::thread::Builder::new()
            .name("scene".into())
            .spawn(move || {
                let build = || Self::build(&source, &frames, &contacts);
                let built = std::panic::catch_unwind(std::panic::AssertUnwindSafe(build))
                    .unwrap_or_else(|panic| {
                        let what = sea_loop::error::panic_message(panic.as_ref());
                        Err(Error::Output(format!(
                            "the robot's scene: building it panicked: {what}"
                        )))
                    });
                // The receiver is gone when the run gave the scene up: nothing to hand over.
                let _ = sender.send(built);
            })
            .map_err(|e| Error::Output(format!("the robot's scene: starting its thread: {e}")))?;
        loop {
            match receiver.recv_timeout(CANCEL_POLL) {
                Ok(built) => return built.map(Some),
                Err(RecvTimeoutError::Timeout) if cancel.load(Ordering::Relaxed) => {
                    return Ok(None)
                }
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(Error::Output("the robot's scene: its thread ended".into()))
                }
            }
        }
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

/// One frame-locked entity per link with visuals, id `link/<name>`, in the order of the links'
/// first visuals.
fn link_entities(visuals: &[Visual]) -> Vec<SceneEntity> {
    let mut entities: Vec<SceneEntity> = Vec::new();
    for visual in visuals {
        let id = format!("link/{}", visual.link);
        let index = match entities.iter().position(|e| e.id == id) {
            Some(index) => index,
            None => {
                entities.push(frame_locked_entity(&visual.link, id));
                entities.len() - 1
            }
        };
        add_visual(&mut entities[index], visual);
    }
    entities
}

/// Adds the primitive that draws `visual` to `entity`.
fn add_visual(entity: &mut SceneEntity, visual: &Visual) {
    let pose = Some(placement_pose(&visual.link_placement));
    let color = Some(color(visual.rgba));
    match &visual.shape {
        Shape::Box { size } => entity.cubes.push(CubePrimitive {
            pose,
            size: Some(vector(*size)),
            color,
        }),
        Shape::Cylinder { radius, length } => entity.cylinders.push(CylinderPrimitive {
            pose,
            size: Some(vector([2.0 * radius, 2.0 * radius, *length])),
            bottom_scale: 1.0,
            top_scale: 1.0,
            color,
        }),
        Shape::Sphere { radius } => entity.spheres.push(SpherePrimitive {
            pose,
            size: Some(vector([2.0 * radius; 3])),
            color,
        }),
        Shape::Mesh(mesh) => entity.triangles.push(triangle_list(mesh, pose, color)),
    }
}

/// A mesh as an indexed triangle list.
fn triangle_list(
    mesh: &TriangleMesh,
    pose: Option<Pose>,
    color: Option<Color>,
) -> TriangleListPrimitive {
    TriangleListPrimitive {
        pose,
        points: mesh
            .positions
            .iter()
            .map(|p| Point3 {
                x: f64::from(p[0]),
                y: f64::from(p[1]),
                z: f64::from(p[2]),
            })
            .collect(),
        color,
        colors: Vec::new(),
        indices: mesh.triangles.iter().flatten().copied().collect(),
    }
}

/// An empty entity `id` that moves with `frame_id` (lifetime: until replaced).
pub(super) fn frame_locked_entity(frame_id: &str, id: String) -> SceneEntity {
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

/// A placement's rotation and translation as a pose (the scale is not a pose's: meshes carry
/// theirs in their points).
fn placement_pose(placement: &Placement) -> Pose {
    let rotation = nalgebra::Matrix3::from_fn(|r, c| placement.rotation[r][c]);
    pose_at(placement.translation, quaternion_from_rotation(&rotation))
}

/// The moving markers of `/scene` in the world frame: CoM, its reference, one arrow per
/// contact (from the sole along its force), one per `[[disturbances]]` push (pointing at its
/// link's origin, zero length while the push is off), and under unilateral contacts the
/// entity `contact_points`: a sphere at each contact point (green while it carries force,
/// grey while not) and an arrow from it along its force. Kept between samples and updated in
/// place (no allocation per sample).
pub(crate) struct Markers {
    update: SceneUpdate,
    /// Number of contact arrows (entities after the two spheres).
    arrows: usize,
    /// Number of push arrows (entities after the contact arrows).
    pushes: usize,
    /// Number of contact points (0: no `contact_points` entity; else it is the last entity).
    points: usize,
}

/// The contact points to draw: 3 values per point of positions and forces (world axes), and
/// whether each carries a force.
pub(crate) struct ContactPoints<'a> {
    /// Positions [m].
    pub positions: &'a [f64],
    /// Forces on the feet [N].
    pub forces: &'a [f64],
    /// Whether each point carries a force.
    pub active: &'a [bool],
}

/// Colour of a contact point carrying a force.
const POINT_ACTIVE_COLOR: [f64; 4] = [0.1, 0.8, 0.2, 1.0];

/// Colour of a contact point off the ground (or carrying no force).
const POINT_IDLE_COLOR: [f64; 4] = [0.6, 0.6, 0.6, 0.8];

/// Diameter of a contact point's sphere [m].
const POINT_DIAMETER_M: f64 = 0.012;

/// Forces to draw: 6 entries per force (the first 3 the force [N], world axes) and the
/// world point each applies at [m].
pub(crate) struct ForceArrows<'a> {
    /// `[force; torque]` per arrow (6 each).
    pub wrenches: &'a [f64],
    /// The application points.
    pub points: &'a [[f64; 3]],
}

impl ForceArrows<'_> {
    /// The force of arrow `k` and its point (zeros beyond the given ones).
    fn get(&self, k: usize) -> ([f64; 3], [f64; 3]) {
        let force = self.wrenches.get(6 * k..6 * k + 3).unwrap_or(&[0.0; 3]);
        let point = self.points.get(k).copied().unwrap_or([0.0; 3]);
        ([force[0], force[1], force[2]], point)
    }

    /// Whether the first `arrows` forces and points are finite.
    fn finite(&self, arrows: usize) -> bool {
        let used = (6 * arrows.min(self.points.len())).min(self.wrenches.len());
        self.wrenches[..used]
            .iter()
            .chain(self.points.iter().flatten())
            .all(|v| v.is_finite())
    }
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
            entities.push(arrow_entity(
                format!("wrench/{contact}"),
                [0.9, 0.1, 0.1, 1.0],
            ));
        }
        Self {
            update: SceneUpdate {
                deletions: Vec::new(),
                entities,
            },
            arrows: contacts.len(),
            pushes: 0,
            points: 0,
        }
    }

    /// Draws `points` contact points (the entity `contact_points`; none when 0), replacing
    /// earlier ones.
    pub fn set_contact_points(&mut self, points: usize) {
        if self.points > 0 {
            self.update.entities.pop();
        }
        self.points = points;
        if points == 0 {
            return;
        }
        let mut entity = world_entity("contact_points".to_string());
        let arrow = arrow_entity(String::new(), [1.0, 0.7, 0.0, 1.0]).arrows[0];
        entity.arrows = vec![
            ArrowPrimitive {
                shaft_diameter: 0.006,
                head_length: 0.02,
                head_diameter: 0.015,
                ..arrow
            };
            points
        ];
        let sphere = SpherePrimitive {
            pose: Some(identity_pose()),
            size: Some(vector([POINT_DIAMETER_M; 3])),
            color: Some(color(POINT_IDLE_COLOR)),
        };
        entity.spheres = vec![sphere; points];
        self.update.entities.push(entity);
    }

    /// Adds one push arrow per link of `links` (ids `push/<k>/<link>`, `[[disturbances]]`
    /// order), replacing earlier ones.
    pub fn set_pushes(&mut self, links: &[String]) {
        let points = (self.points > 0).then(|| self.update.entities.pop());
        let kept = COM_ENTITIES.len() + self.arrows;
        self.update.entities.truncate(kept);
        for (k, link) in links.iter().enumerate() {
            let id = format!("push/{k}/{link}");
            let entity = arrow_entity(id, [0.2, 0.4, 1.0, 1.0]);
            self.update.entities.push(entity);
        }
        self.pushes = links.len();
        self.update.entities.extend(points.flatten());
    }

    /// Sets the markers of one sample and appends their encoding to `buffer`: `com`,
    /// `com_reference`, for contact `k` the force of `contacts` applied at its point, for push
    /// `k` the force of `pushes` ending at its point, the contact points of `points` (world
    /// axes). Returns `false`, appending nothing, when a value is not finite (Foxglove needs
    /// numbers).
    pub fn encode(
        &mut self,
        stamp: Timestamp,
        [com, com_reference]: [[f64; 3]; 2],
        (contacts, pushes, points): (ForceArrows<'_>, ForceArrows<'_>, ContactPoints<'_>),
        buffer: &mut Vec<u8>,
    ) -> bool {
        let finite = com.iter().chain(&com_reference).all(|v| v.is_finite())
            && contacts.finite(self.arrows)
            && pushes.finite(self.pushes)
            && points
                .positions
                .iter()
                .chain(points.forces)
                .all(|v| v.is_finite());
        if !finite {
            return false;
        }
        if self.points > 0 {
            if let Some(entity) = self.update.entities.last_mut() {
                set_points(entity, stamp, &points);
            }
        }
        let (spheres, arrows) = self.update.entities.split_at_mut(COM_ENTITIES.len());
        for (entity, position) in spheres.iter_mut().zip([com, com_reference]) {
            entity.timestamp = Some(stamp);
            entity.spheres[0].pose = Some(pose_at(position, [1.0, 0.0, 0.0, 0.0]));
        }
        let (contact_arrows, push_arrows) = arrows.split_at_mut(self.arrows);
        for (k, entity) in contact_arrows.iter_mut().enumerate() {
            entity.timestamp = Some(stamp);
            let (force, point) = contacts.get(k);
            set_arrow(&mut entity.arrows[0], point, force);
        }
        for (k, entity) in push_arrows.iter_mut().enumerate() {
            entity.timestamp = Some(stamp);
            let (force, point) = pushes.get(k);
            // Drawn ending at the pushed link: its tail one arrow length before the point.
            let tail = std::array::from_fn(|i| point[i] - force[i] * ARROW_M_PER_N);
            set_arrow(&mut entity.arrows[0], tail, force);
        }
        Encode::encode(&self.update, buffer).is_ok()
    }
}

/// The spheres and arrows of the `contact_points` entity at `points` (points beyond the
/// given ones keep their last markers).
fn set_points(entity: &mut SceneEntity, stamp: Timestamp, points: &ContactPoints<'_>) {
    entity.timestamp = Some(stamp);
    let markers = entity.spheres.iter_mut().zip(entity.arrows.iter_mut());
    let values = points
        .positions
        .chunks_exact(3)
        .zip(points.forces.chunks_exact(3));
    for (k, ((sphere, arrow), (position, force))) in markers.zip(values).enumerate() {
        let position = [position[0], position[1], position[2]];
        let active = points.active.get(k).copied().unwrap_or(false);
        sphere.pose = Some(pose_at(position, [1.0, 0.0, 0.0, 0.0]));
        let rgba = if active {
            POINT_ACTIVE_COLOR
        } else {
            POINT_IDLE_COLOR
        };
        sphere.color = Some(color(rgba));
        set_arrow(arrow, position, [force[0], force[1], force[2]]);
    }
}

/// A world entity `id` with one arrow of colour `rgba`, zero length until set.
fn arrow_entity(id: String, rgba: [f64; 4]) -> SceneEntity {
    let mut entity = world_entity(id);
    entity.arrows.push(ArrowPrimitive {
        pose: Some(identity_pose()),
        shaft_length: 0.0,
        shaft_diameter: 0.012,
        head_length: 0.04,
        head_diameter: 0.03,
        color: Some(color(rgba)),
    });
    entity
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
pub(super) fn world_entity(id: String) -> SceneEntity {
    SceneEntity {
        frame_id: super::WORLD_FRAME.to_string(),
        id,
        ..Default::default()
    }
}

/// A pose at `position` with orientation `[w, x, y, z]`.
pub(super) fn pose_at(position: [f64; 3], [w, x, y, z]: [f64; 4]) -> Pose {
    Pose {
        position: Some(vector(position)),
        orientation: Some(Quaternion { x, y, z, w }),
    }
}

/// The identity pose.
pub(super) fn identity_pose() -> Pose {
    pose_at([0.0; 3], [1.0, 0.0, 0.0, 0.0])
}

/// A Foxglove vector.
pub(super) fn vector([x, y, z]: [f64; 3]) -> Vector3 {
    Vector3 { x, y, z }
}

/// A Foxglove colour from `[r, g, b, a]` in `[0, 1]`.
pub(super) fn color([r, g, b, a]: [f64; 4]) -> Color {
    Color { r, g, b, a }
}
