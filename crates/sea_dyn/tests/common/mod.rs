//! Shared helpers of the integration tests: a seeded LCG, a random URDF tree generator that
//! keeps its own description of the robot (so tests can recompute kinematics and inertias
//! independently of the parser), random states, finite differences and small linear algebra.

#![allow(dead_code)]

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use std::fmt::Write;

/// Knuth's MMIX linear congruential generator; 53 high bits give a uniform double.
pub struct Lcg(u64);

impl Lcg {
    /// A generator from `seed` (scrambled so that small seeds differ at once).
    pub fn new(seed: u64) -> Self {
        let mut g = Lcg(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03);
        for _ in 0..4 {
            g.next_u64();
        }
        g
    }

    /// Next raw state.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }

    /// Uniform integer in [0, n).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() >> 33) as usize) % n
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// Vector with entries uniform in [a, b).
    pub fn vec3(&mut self, a: f64, b: f64) -> [f64; 3] {
        [self.range(a, b), self.range(a, b), self.range(a, b)]
    }

    /// Vector of `n` entries uniform in [a, b).
    pub fn vector(&mut self, n: usize, a: f64, b: f64) -> Vec<f64> {
        (0..n).map(|_| self.range(a, b)).collect()
    }

    /// A uniformly random unit quaternion (w, x, y, z) (Shoemake).
    pub fn unit_quaternion(&mut self) -> [f64; 4] {
        let (u1, u2, u3) = (self.uniform(), self.uniform(), self.uniform());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        [
            b * (tau * u3).cos(),
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
        ]
    }
}

// ---------------------------------------------------------------------------------------------
// Rotations, written here independently of `sea_dyn::spatial`.

/// `[v]x`.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Rotation of `angle` about the unit `axis`.
pub fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let k = skew(axis);
    Matrix3::identity() + k * angle.sin() + k * k * (1.0 - angle.cos())
}

/// URDF roll-pitch-yaw: `Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn rpy(r: [f64; 3]) -> Matrix3<f64> {
    axis_angle(&Vector3::z(), r[2])
        * axis_angle(&Vector3::y(), r[1])
        * axis_angle(&Vector3::x(), r[0])
}

/// Rotation matrix of a unit quaternion (w, x, y, z).
pub fn quat_to_matrix(q: [f64; 4]) -> Matrix3<f64> {
    let (w, v) = (q[0], Vector3::new(q[1], q[2], q[3]));
    // R = (w^2 - v.v) I + 2 v v^T + 2 w [v]x
    Matrix3::identity() * (w * w - v.dot(&v)) + v * v.transpose() * 2.0 + skew(&v) * (2.0 * w)
}

/// Rotation vector of a rotation matrix (angle < pi), accurate for small angles.
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    let v = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let s = v.norm();
    let c = 0.5 * (r.trace() - 1.0);
    let angle = s.atan2(c);
    if s < 1e-300 {
        return Vector3::zeros();
    }
    v * (angle / s)
}

// ---------------------------------------------------------------------------------------------
// Random robot description.

/// `<inertial>` of a link: mass, frame origin, inertia about the CoM in that frame.
#[derive(Clone, Debug)]
pub struct Inertial {
    /// Mass [kg].
    pub mass: f64,
    /// Inertial frame origin (the CoM) in the link frame.
    pub xyz: [f64; 3],
    /// Inertial frame orientation in the link frame.
    pub rpy: [f64; 3],
    /// Inertia in the inertial frame (symmetric).
    pub inertia: Matrix3<f64>,
}

/// One URDF link.
#[derive(Clone, Debug)]
pub struct LinkDesc {
    /// Name.
    pub name: String,
    /// `None`: massless (no `<inertial>`).
    pub inertial: Option<Inertial>,
}

/// URDF joint types used by the generator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointType {
    /// revolute (with limits)
    Revolute,
    /// continuous
    Continuous,
    /// prismatic (with limits)
    Prismatic,
    /// fixed
    Fixed,
}

impl JointType {
    /// URDF spelling.
    pub fn urdf(self) -> &'static str {
        match self {
            JointType::Revolute => "revolute",
            JointType::Continuous => "continuous",
            JointType::Prismatic => "prismatic",
            JointType::Fixed => "fixed",
        }
    }

    /// True for joints that move by default.
    pub fn moves(self) -> bool {
        self != JointType::Fixed
    }
}

/// One URDF joint; `parent` and `child` index `RobotDesc::links`.
#[derive(Clone, Debug)]
pub struct JointDesc {
    /// Name.
    pub name: String,
    /// Type.
    pub kind: JointType,
    /// Parent link index.
    pub parent: usize,
    /// Child link index.
    pub child: usize,
    /// Origin translation.
    pub xyz: [f64; 3],
    /// Origin rotation.
    pub rpy: [f64; 3],
    /// Axis as written in the file (not normalised).
    pub axis: [f64; 3],
}

/// A robot: links (root is link 0) and joints, plus the order in which they are written.
#[derive(Clone, Debug)]
pub struct RobotDesc {
    /// Links; link 0 is the root.
    pub links: Vec<LinkDesc>,
    /// Joints; joint `j` has child link `j + 1`.
    pub joints: Vec<JointDesc>,
    /// Order of the links in the file.
    pub link_file_order: Vec<usize>,
    /// Order of the joints in the file.
    pub joint_file_order: Vec<usize>,
}

/// Random inertia about the CoM: principal moments `y+z, x+z, x+y` (triangle inequality
/// holds strictly) from random second moments, rotated by a random rotation.
pub fn random_inertia(rng: &mut Lcg, mass: f64) -> Matrix3<f64> {
    let second = rng.vec3(0.002, 0.03);
    let d = Matrix3::from_diagonal(&Vector3::new(
        mass * (second[1] + second[2]),
        mass * (second[0] + second[2]),
        mass * (second[0] + second[1]),
    ));
    let r = quat_to_matrix(rng.unit_quaternion());
    let i = r * d * r.transpose();
    (i + i.transpose()) * 0.5
}

fn random_rpy(rng: &mut Lcg) -> [f64; 3] {
    let pi = std::f64::consts::PI;
    [
        rng.range(-pi, pi),
        rng.range(-0.5 * pi, 0.5 * pi),
        rng.range(-pi, pi),
    ]
}

fn random_inertial(rng: &mut Lcg) -> Inertial {
    let mass = rng.range(0.2, 3.0);
    Inertial {
        mass,
        xyz: rng.vec3(-0.2, 0.2),
        rpy: random_rpy(rng),
        inertia: random_inertia(rng, mass),
    }
}

/// A random branching tree of 6..=15 links (including 1..=3 massless leaves on fixed joints),
/// seeded.
pub fn random_robot(seed: u64) -> RobotDesc {
    let mut rng = Lcg::new(seed);
    let n_massive = 5 + rng.below(8); // 5..=12 massive links (with the root)
    let n_leaves = 1 + rng.below(3); // 1..=3 massless fixed leaves
    let mut links = vec![LinkDesc {
        name: "base_link".into(),
        inertial: Some(random_inertial(&mut rng)),
    }];
    let mut joints: Vec<JointDesc> = Vec::new();
    for i in 1..n_massive + n_leaves {
        let leaf = i >= n_massive;
        // Favour recent links (chains) but allow branching anywhere among massive links.
        let parent = if !leaf && rng.chance(0.5) {
            i - 1
        } else {
            rng.below(n_massive.min(i))
        };
        let kind = if leaf {
            JointType::Fixed
        } else {
            match rng.below(10) {
                0..=3 => JointType::Revolute,
                4..=5 => JointType::Continuous,
                6..=7 => JointType::Prismatic,
                _ => JointType::Fixed,
            }
        };
        let mut axis = rng.vec3(-1.0, 1.0);
        while Vector3::from(axis).norm() < 0.2 {
            axis = rng.vec3(-1.0, 1.0);
        }
        let scale = rng.range(0.3, 3.0);
        let axis = [axis[0] * scale, axis[1] * scale, axis[2] * scale];
        links.push(LinkDesc {
            name: if leaf {
                format!("tip_{i}")
            } else {
                format!("link_{i}")
            },
            inertial: if leaf {
                None
            } else {
                Some(random_inertial(&mut rng))
            },
        });
        joints.push(JointDesc {
            name: format!("joint_{i}"),
            kind,
            parent,
            child: i,
            xyz: rng.vec3(-0.3, 0.3),
            rpy: random_rpy(&mut rng),
            axis,
        });
    }
    // Keep at least two moving joints.
    let mut moving = joints.iter().filter(|j| j.kind.moves()).count();
    for joint in joints.iter_mut() {
        if moving >= 2 {
            break;
        }
        if joint.kind == JointType::Fixed && links[joint.child].inertial.is_some() {
            joint.kind = JointType::Revolute;
            moving += 1;
        }
    }
    let mut link_file_order: Vec<usize> = (0..links.len()).collect();
    let mut joint_file_order: Vec<usize> = (0..joints.len()).collect();
    shuffle(&mut rng, &mut link_file_order);
    shuffle(&mut rng, &mut joint_file_order);
    RobotDesc {
        links,
        joints,
        link_file_order,
        joint_file_order,
    }
}

/// Fisher-Yates shuffle.
pub fn shuffle<T>(rng: &mut Lcg, v: &mut [T]) {
    for i in (1..v.len()).rev() {
        let j = rng.below(i + 1);
        v.swap(i, j);
    }
}

fn fmt3(v: [f64; 3]) -> String {
    format!("{} {} {}", v[0], v[1], v[2])
}

impl RobotDesc {
    /// URDF text (numbers printed exactly, links and joints in file order).
    pub fn to_urdf(&self) -> String {
        let mut s = String::from("<?xml version=\"1.0\"?>\n<robot name=\"random\">\n");
        for &l in &self.link_file_order {
            let link = &self.links[l];
            match &link.inertial {
                None => writeln!(s, "  <link name=\"{}\"/>", link.name).unwrap(),
                Some(i) => {
                    let m = &i.inertia;
                    writeln!(
                        s,
                        "  <link name=\"{}\">\n    <inertial>\n      <origin xyz=\"{}\" rpy=\"{}\"/>\n      <mass value=\"{}\"/>\n      <inertia ixx=\"{}\" ixy=\"{}\" ixz=\"{}\" iyy=\"{}\" iyz=\"{}\" izz=\"{}\"/>\n    </inertial>\n  </link>",
                        link.name,
                        fmt3(i.xyz),
                        fmt3(i.rpy),
                        i.mass,
                        m[(0, 0)],
                        m[(0, 1)],
                        m[(0, 2)],
                        m[(1, 1)],
                        m[(1, 2)],
                        m[(2, 2)]
                    )
                    .unwrap()
                }
            }
        }
        for &j in &self.joint_file_order {
            let joint = &self.joints[j];
            write!(
                s,
                "  <joint name=\"{}\" type=\"{}\">\n    <origin xyz=\"{}\" rpy=\"{}\"/>\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n",
                joint.name,
                joint.kind.urdf(),
                fmt3(joint.xyz),
                fmt3(joint.rpy),
                self.links[joint.parent].name,
                self.links[joint.child].name
            )
            .unwrap();
            if joint.kind != JointType::Fixed {
                writeln!(s, "    <axis xyz=\"{}\"/>", fmt3(joint.axis)).unwrap();
            }
            if matches!(joint.kind, JointType::Revolute | JointType::Prismatic) {
                writeln!(
                    s,
                    "    <limit lower=\"-2\" upper=\"2\" effort=\"50\" velocity=\"5\"/>"
                )
                .unwrap();
            }
            s.push_str("  </joint>\n");
        }
        s.push_str("</robot>\n");
        s
    }

    /// Names of the moving joints.
    pub fn moving_joints(&self) -> Vec<String> {
        self.joints
            .iter()
            .filter(|j| j.kind.moves())
            .map(|j| j.name.clone())
            .collect()
    }

    /// Independent forward kinematics: `(world_R_link, world_p_link)` for every link, given the
    /// base pose and a value for every joint (`joint_value(j)`, ignored for fixed joints).
    pub fn link_poses(
        &self,
        base_p: Vector3<f64>,
        base_q: [f64; 4],
        joint_value: impl Fn(usize) -> f64,
    ) -> Vec<(Matrix3<f64>, Vector3<f64>)> {
        let mut poses = vec![None; self.links.len()];
        poses[0] = Some((quat_to_matrix(base_q), base_p));
        // Joints are generated parent-before-child (parent index < child index).
        for (j, joint) in self.joints.iter().enumerate() {
            let (rp, pp) = poses[joint.parent].expect("parent before child");
            let r_joint = rp * rpy(joint.rpy);
            let p_joint = pp + rp * Vector3::from(joint.xyz);
            let axis = Vector3::from(joint.axis).normalize();
            let s = joint_value(j);
            poses[joint.child] = Some(match joint.kind {
                JointType::Fixed => (r_joint, p_joint),
                JointType::Revolute | JointType::Continuous => {
                    (r_joint * axis_angle(&axis, s), p_joint)
                }
                JointType::Prismatic => (r_joint, p_joint + r_joint * axis * s),
            });
        }
        poses.into_iter().map(|p| p.unwrap()).collect()
    }

    /// Total mass.
    pub fn total_mass(&self) -> f64 {
        self.links
            .iter()
            .filter_map(|l| l.inertial.as_ref())
            .map(|i| i.mass)
            .sum()
    }
}

// ---------------------------------------------------------------------------------------------
// States.

/// Random configuration: base position in [-1, 1]^3, uniform unit quaternion, joints in [-1, 1].
pub fn random_q(rng: &mut Lcg, nq: usize) -> Vec<f64> {
    let mut q = rng.vector(nq, -1.0, 1.0);
    let quat = rng.unit_quaternion();
    q[3..7].copy_from_slice(&quat);
    q
}

/// Random velocity-sized vector in [-a, a].
pub fn random_v(rng: &mut Lcg, nv: usize, a: f64) -> Vec<f64> {
    rng.vector(nv, -a, a)
}

/// Loads the model of a description (panics with the URDF text on error).
pub fn load(desc: &RobotDesc) -> sea_dyn::Model {
    let text = desc.to_urdf();
    match sea_dyn::Model::from_urdf_str(&text, &sea_dyn::LoadOptions::default()) {
        Ok(m) => m,
        Err(e) => panic!("random URDF rejected: {e}\n{text}"),
    }
}

/// Value of URDF joint `j` of `desc` in configuration `q` of `model` (0 if it does not move).
pub fn joint_value(model: &sea_dyn::Model, desc: &RobotDesc, q: &[f64], j: usize) -> f64 {
    model
        .joint_index(&desc.joints[j].name)
        .map_or(0.0, |k| q[7 + k])
}

// ---------------------------------------------------------------------------------------------
// Numerics.

/// `q(t) = integrate(q, nu, t)`.
pub fn flow(model: &sea_dyn::Model, q: &[f64], nu: &[f64], t: f64) -> Vec<f64> {
    let mut out = vec![0.0; q.len()];
    sea_dyn::integrate(model, q, nu, t, &mut out);
    out
}

/// Fourth-order central difference `d/dt f(t)` at 0 from `f(±h), f(±2h)`.
pub fn central_diff<F>(h: f64, mut f: F) -> DVector<f64>
where
    F: FnMut(f64) -> DVector<f64>,
{
    let (p1, m1, p2, m2) = (f(h), f(-h), f(2.0 * h), f(-2.0 * h));
    ((p1 - m1) * 8.0 - (p2 - m2)) / (12.0 * h)
}

/// Same as [`central_diff`] for matrices.
pub fn central_diff_mat<F>(h: f64, mut f: F) -> DMatrix<f64>
where
    F: FnMut(f64) -> DMatrix<f64>,
{
    let (p1, m1, p2, m2) = (f(h), f(-h), f(2.0 * h), f(-2.0 * h));
    ((p1 - m1) * 8.0 - (p2 - m2)) / (12.0 * h)
}

/// Angular velocity of `r(t)` at 0 (world axes, `Rdot = [w]x R`): Richardson-extrapolated
/// `log(R(h) R(-h)^T) / (2h)`.
pub fn angular_velocity<F>(h: f64, mut r: F) -> Vector3<f64>
where
    F: FnMut(f64) -> Matrix3<f64>,
{
    let mut g = |h: f64| log_so3(&(r(h) * r(-h).transpose())) / (2.0 * h);
    let (g1, g2) = (g(h), g(2.0 * h));
    (g1 * 4.0 - g2) / 3.0
}

/// `|a - b| <= tol * (scale + 1e-12)`, with a useful panic message.
#[track_caller]
pub fn assert_close_vec(what: &str, a: &DVector<f64>, b: &DVector<f64>, tol: f64, scale: f64) {
    let err = (a - b).amax();
    assert!(
        err <= tol * (scale + 1e-12),
        "{what}: max error {err:e} > {tol:e} * {scale:e}\n a = {}\n b = {}",
        a.transpose(),
        b.transpose()
    );
}

/// Matrix version of [`assert_close_vec`].
#[track_caller]
pub fn assert_close_mat(what: &str, a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64, scale: f64) {
    assert_eq!(a.shape(), b.shape(), "{what}: shapes differ");
    let err = (a - b).amax();
    assert!(
        err <= tol * (scale + 1e-12),
        "{what}: max error {err:e} > {tol:e} * {scale:e}\n a = {a}\n b = {b}"
    );
}

/// Seeds used by the randomised tests.
pub fn seeds() -> std::ops::Range<u64> {
    1..21
}
