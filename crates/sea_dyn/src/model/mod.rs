//! The immutable robot model: kinematic tree of moving bodies, their inertias and the frames.
//!
//! Bodies are the rigid groups of URDF links joined by fixed (or locked) joints. Body 0 is the
//! floating base (the root link and everything fixed to it); body `i >= 1` is moved by exactly
//! one joint. Bodies are stored in depth-first order, so `parent(i) < i`, while each joint's
//! coordinate index `coordinate(i)` follows the user's joint order: the two orders differ when
//! a `joints` list reorders the joints, and the algorithms use `coordinate` to address `s`.
//!
//! Sizes: `nq = 7 + n`, `nv = 6 + n`, with `n` the number of moving joints.

pub mod actuator;
pub mod configuration;
pub mod contact_surface;
pub mod data;
pub(crate) mod inertia_check;
pub mod resources;
pub mod state;
pub mod urdf;
mod urdf_numbers;

use crate::error::{Error, Result, Warning};
use crate::spatial::{BodyInertia, Pose};
use nalgebra::{Matrix3, Vector3};

/// How far from 1 a configuration's quaternion norm may be. The algorithms normalise it; the
/// slack admits external integrators (scipy's finite-difference Jacobians perturb the state by
/// about 1e-6) while still catching a quaternion that is not one.
pub const QUATERNION_TOLERANCE: f64 = 1e-4;

/// The motion a joint allows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about an axis (URDF revolute or continuous).
    Revolute,
    /// Translation along an axis (URDF prismatic).
    Prismatic,
}

/// One moving joint and the body it carries.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// URDF joint name.
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Index of the parent body (`< ` this body's index).
    pub parent: usize,
    /// Index of this joint's coordinate in `s` (0-based; `nu` index is `6 + coordinate`).
    pub coordinate: usize,
    /// Placement of the joint frame in the parent body frame (`parent_H_joint`).
    pub parent_h_joint: Pose,
    /// Unit joint axis in the joint frame (which is also the child body frame at s = 0).
    pub axis: Vector3<f64>,
    /// Position limits `[lower, upper]` from the URDF (rad or m; infinite when absent).
    pub position_limits: [f64; 2],
    /// Effort limit from the URDF (Nm or N; infinite when absent or zero).
    pub effort_limit: f64,
}

/// An addressable frame: a URDF link rigidly attached to a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// URDF link name.
    pub name: String,
    /// Body the link belongs to.
    pub body: usize,
    /// Placement of the link frame in the body frame (`body_H_link`).
    pub body_h_frame: Pose,
}

/// Index of a frame in [`Model::frames`].
pub type FrameId = usize;

/// The immutable robot model (Pinocchio's `Model`); buffers live in [`crate::Data`].
/// Equality is field by field (two loads of the same URDF with the same options are equal).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    /// Robot name from the URDF.
    pub name: String,
    /// Moving joints in body order: `joints[i - 1]` moves body `i`.
    pub joints: Vec<Joint>,
    /// Inertia of each body in its own frame; index 0 is the base.
    pub body_inertias: Vec<BodyInertia>,
    /// Every URDF link as a frame.
    pub frames: Vec<Frame>,
    /// Gravity acceleration in world axes [m/s^2] (default `[0, 0, -9.81]`).
    pub gravity: Vector3<f64>,
    /// Joint names in coordinate order (the order of `s`).
    pub joint_names: Vec<String>,
    /// For each coordinate, the body it moves (`body_of_coordinate[k]` is in `1..=n`).
    pub body_of_coordinate: Vec<usize>,
    /// Name of the root link (the floating base).
    pub base_link: String,
    /// For each body, the bodies from the base's first child down to the body itself
    /// (root-to-leaf order, base excluded; empty for the base).
    pub support_paths: Vec<Vec<usize>>,
    /// What loading found physically doubtful but computable (empty for a clean description;
    /// a strict load refuses instead): the links in file order, then the moving joints in
    /// depth-first order.
    pub warnings: Vec<Warning>,
}

impl Model {
    /// Number of moving joints `n`.
    pub fn n_joints(&self) -> usize {
        self.joints.len()
    }

    /// Number of bodies including the base, `n + 1`.
    pub fn n_bodies(&self) -> usize {
        self.joints.len() + 1
    }

    /// Configuration size `nq = 7 + n`.
    pub fn nq(&self) -> usize {
        7 + self.joints.len()
    }

    /// Velocity size `nv = 6 + n`.
    pub fn nv(&self) -> usize {
        6 + self.joints.len()
    }

    /// Total mass [kg].
    pub fn total_mass(&self) -> f64 {
        self.body_inertias.iter().map(|b| b.mass).sum()
    }

    /// Parent body of body `i >= 1`.
    #[inline]
    pub fn parent(&self, body: usize) -> usize {
        self.joints[body - 1].parent
    }

    /// Velocity index of the coordinate of body `i >= 1`.
    #[inline]
    pub fn velocity_index(&self, body: usize) -> usize {
        6 + self.joints[body - 1].coordinate
    }

    /// Frame index of a link name; `Error::UnknownFrame` names it otherwise.
    pub fn frame_id(&self, name: &str) -> Result<FrameId> {
        self.frames
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| Error::UnknownFrame {
                name: name.to_string(),
            })
    }

    /// Coordinate index of a joint name, if the joint moves.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joint_names.iter().position(|n| n == name)
    }

    /// The neutral configuration: base at the origin, identity orientation, joints at 0
    /// (prismatic and revolute alike).
    pub fn neutral(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.nq()];
        q[3] = 1.0;
        q
    }

    /// Root-to-leaf support path of `body` (see [`Model::support_paths`]).
    #[inline]
    pub fn support_path(&self, body: usize) -> &[usize] {
        &self.support_paths[body]
    }

    /// Bodies on the path from `body` to the base, `body` first, base (0) excluded.
    pub fn support(&self, body: usize) -> impl Iterator<Item = usize> + '_ {
        let mut current = body;
        std::iter::from_fn(move || {
            if current == 0 {
                None
            } else {
                let out = current;
                current = self.parent(current);
                Some(out)
            }
        })
    }

    /// Checks a configuration: size `nq`, finite, quaternion of unit norm within
    /// [`QUATERNION_TOLERANCE`] (the algorithms normalise it).
    pub fn check_configuration(&self, q: &[f64]) -> Result<()> {
        self.check_configuration_named("q", q)
    }

    /// [`Self::check_configuration`] of a configuration the caller calls `argument` (the
    /// leading `nq` entries of a state `x`: the quaternion is then `x[3:7]`).
    pub fn check_configuration_named(&self, argument: &str, q: &[f64]) -> Result<()> {
        crate::error::check_vector(argument, q, self.nq())?;
        let norm = (q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]).sqrt();
        if (norm - 1.0).abs() > QUATERNION_TOLERANCE {
            return Err(Error::invalid(
                format!("{argument}[3:7]"),
                "a unit quaternion (w, x, y, z)",
                format!("norm {norm}"),
            ));
        }
        Ok(())
    }

    /// Checks a velocity-sized vector (`nu`, `nudot`, generalised forces) named `argument`.
    pub fn check_velocity(&self, argument: &str, v: &[f64]) -> Result<()> {
        crate::error::check_vector(argument, v, self.nv())
    }
}

/// Rotation of a joint of `kind` about/along unit `axis` at coordinate `s`, and the
/// translation it adds, both in the joint frame.
#[inline]
pub(crate) fn joint_motion(kind: JointKind, axis: &Vector3<f64>, s: f64) -> Pose {
    match kind {
        JointKind::Revolute => Pose {
            rotation: crate::spatial::rotation_about_axis(axis, s),
            translation: Vector3::zeros(),
        },
        JointKind::Prismatic => Pose {
            rotation: Matrix3::identity(),
            translation: axis * s,
        },
    }
}
