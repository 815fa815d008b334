//! Spatial algebra: rigid transforms, spatial motion and force vectors, spatial inertias.
//!
//! Conventions (docs/reference/conventions.md): spatial vectors store the linear
//! part first and the angular part second. The algorithms of this crate express every spatial
//! quantity in world-aligned axes at one fixed reference point `O` (the base origin at the
//! current instant), so a motion vector
//! `v = [v_O; omega]` holds the velocity of the body-fixed point coincident with `O` and the
//! angular velocity, and a force vector `f = [F; n_O]` holds the resultant and the moment about
//! `O`. With one common point no spatial transform is needed between bodies (Featherstone,
//! *Rigid Body Dynamics Algorithms*, 2008, section 2.8; Pinocchio's world-frame algorithms).
//!
//! Operations:
//! - motion cross motion `v x m = [w x m_lin + v_lin x m_ang; w x m_ang]`,
//! - motion cross force `v x* f = [w x f_lin; w x f_ang + v_lin x f_lin]`,
//! - inertia times motion `I v = [m v_lin + w x h; h x v_lin + I_O w]`, with `h = m c` the first
//!   moment of mass about `O` and `I_O` the rotational inertia about `O`.

use crate::linalg::mul_add;
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// `a x b + c` with fused multiply-adds (`linalg::mul_add`): the spatial algebra's inner
/// operations, written out so that each entry is two fused operations instead of two products
/// and two sums.
#[inline(always)]
fn cross_add(a: &Vector3<f64>, b: &Vector3<f64>, c: Vector3<f64>) -> Vector3<f64> {
    Vector3::new(
        mul_add(a.y, b.z, mul_add(-a.z, b.y, c.x)),
        mul_add(a.z, b.x, mul_add(-a.x, b.z, c.y)),
        mul_add(a.x, b.y, mul_add(-a.y, b.x, c.z)),
    )
}

/// `m v + c` with fused multiply-adds.
#[inline(always)]
pub(crate) fn mat_vec_add(m: &Matrix3<f64>, v: &Vector3<f64>, c: Vector3<f64>) -> Vector3<f64> {
    Vector3::from_fn(|r, _| {
        mul_add(
            m[(r, 2)],
            v.z,
            mul_add(m[(r, 1)], v.y, mul_add(m[(r, 0)], v.x, c[r])),
        )
    })
}

/// `a b` (3 x 3) with fused multiply-adds, column by column.
#[inline(always)]
pub(crate) fn mat_mul(a: &Matrix3<f64>, b: &Matrix3<f64>) -> Matrix3<f64> {
    let column = |j: usize| mat_vec_add(a, &b.column(j).into_owned(), Vector3::zeros());
    let (c0, c1, c2) = (column(0), column(1), column(2));
    Matrix3::from_columns(&[c0, c1, c2])
}

/// Skew-symmetric matrix `[v]x` such that `[v]x u = v x u`.
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Rotation matrix of URDF roll-pitch-yaw angles: `R = Rz(yaw) Ry(pitch) Rx(roll)`.
pub fn rotation_from_rpy(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = yaw.sin_cos();
    Matrix3::new(
        cy * cp,
        cy * sp * sr - sy * cr,
        cy * sp * cr + sy * sr,
        sy * cp,
        sy * sp * sr + cy * cr,
        sy * sp * cr - cy * sr,
        -sp,
        cp * sr,
        cp * cr,
    )
}

/// Rotation of `angle` about the unit vector `axis` (Rodrigues' formula).
#[inline]
pub fn rotation_about_axis(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    let versine = 1.0 - c;
    let sine_axis = axis * s;
    // c I + s [a]x + (1 - c) a a^T, entry by entry with fused multiply-adds.
    let outer = |i: usize, j: usize| versine * axis[i] * axis[j];
    let (xy, xz, yz) = (outer(0, 1), outer(0, 2), outer(1, 2));
    Matrix3::new(
        mul_add(versine * axis.x, axis.x, c),
        xy - sine_axis.z,
        xz + sine_axis.y,
        xy + sine_axis.z,
        mul_add(versine * axis.y, axis.y, c),
        yz - sine_axis.x,
        xz - sine_axis.y,
        yz + sine_axis.x,
        mul_add(versine * axis.z, axis.z, c),
    )
}

/// Rotation matrix of a quaternion given as (w, x, y, z); the quaternion is normalised first.
#[inline]
pub fn rotation_from_quaternion(w: f64, x: f64, y: f64, z: f64) -> Matrix3<f64> {
    let n = (w * w + x * x + y * y + z * z).sqrt();
    let (w, x, y, z) = (w / n, x / n, y / n, z / n);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// The heading of a rotation `a_R_b` about `a`'s z axis [rad], in [-pi, pi]: the angle of
/// `b`'s x axis projected on `a`'s x-y plane (for a sole or a base on flat ground, its yaw).
#[inline]
pub fn heading(r: &Matrix3<f64>) -> f64 {
    r[(1, 0)].atan2(r[(0, 0)])
}

/// Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method: pivot on the largest
/// of the four squared components, so it is accurate for every rotation). `w >= 0`.
pub fn quaternion_from_rotation(r: &Matrix3<f64>) -> [f64; 4] {
    let trace = r[(0, 0)] + r[(1, 1)] + r[(2, 2)];
    let candidates = [trace, r[(0, 0)], r[(1, 1)], r[(2, 2)]];
    let pivot = (0..4)
        .max_by(|a, b| candidates[*a].total_cmp(&candidates[*b]))
        .unwrap_or(0);
    let q = match pivot {
        0 => {
            let s = 2.0 * (1.0 + trace).sqrt();
            [
                0.25 * s,
                (r[(2, 1)] - r[(1, 2)]) / s,
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(1, 0)] - r[(0, 1)]) / s,
            ]
        }
        1 => {
            let s = 2.0 * (1.0 + r[(0, 0)] - r[(1, 1)] - r[(2, 2)]).sqrt();
            [
                (r[(2, 1)] - r[(1, 2)]) / s,
                0.25 * s,
                (r[(0, 1)] + r[(1, 0)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
            ]
        }
        2 => {
            let s = 2.0 * (1.0 + r[(1, 1)] - r[(0, 0)] - r[(2, 2)]).sqrt();
            [
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(0, 1)] + r[(1, 0)]) / s,
                0.25 * s,
                (r[(1, 2)] + r[(2, 1)]) / s,
            ]
        }
        _ => {
            let s = 2.0 * (1.0 + r[(2, 2)] - r[(0, 0)] - r[(1, 1)]).sqrt();
            [
                (r[(1, 0)] - r[(0, 1)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
                (r[(1, 2)] + r[(2, 1)]) / s,
                0.25 * s,
            ]
        }
    };
    let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    q.map(|c| sign * c / norm)
}

/// A rigid transform `a_H_b`: rotation `a_R_b` and the position of `b`'s origin in `a`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Rotation `a_R_b` (columns: axes of `b` in `a`).
    pub rotation: Matrix3<f64>,
    /// Origin of `b` expressed in `a` [m].
    pub translation: Vector3<f64>,
}

impl Pose {
    /// The identity transform.
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// Transform from a URDF `<origin xyz rpy>`.
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        Self {
            rotation: rotation_from_rpy(rpy[0], rpy[1], rpy[2]),
            translation: Vector3::new(xyz[0], xyz[1], xyz[2]),
        }
    }

    /// Composition `a_H_c = a_H_b * b_H_c`.
    #[inline]
    pub fn compose(&self, b_h_c: &Pose) -> Pose {
        Pose {
            rotation: self.rotation * b_h_c.rotation,
            translation: self.translation + self.rotation * b_h_c.translation,
        }
    }

    /// Inverse transform `b_H_a`.
    pub fn inverse(&self) -> Pose {
        let rt = self.rotation.transpose();
        Pose {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// Maps a point from `b` coordinates to `a` coordinates.
    #[inline]
    pub fn transform_point(&self, p_b: &Vector3<f64>) -> Vector3<f64> {
        self.translation + self.rotation * p_b
    }

    /// Homogeneous 4x4 matrix.
    pub fn to_homogeneous(&self) -> nalgebra::Matrix4<f64> {
        let mut h = nalgebra::Matrix4::identity();
        h.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotation);
        h.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        h
    }
}

/// A spatial motion vector (velocity or acceleration) `[linear; angular]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Linear part (velocity of the body point coincident with the reference point).
    pub lin: Vector3<f64>,
    /// Angular part.
    pub ang: Vector3<f64>,
}

/// A spatial force vector (wrench or momentum) `[linear; angular]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Force {
    /// Resultant force (or linear momentum).
    pub lin: Vector3<f64>,
    /// Moment about the reference point (or angular momentum).
    pub ang: Vector3<f64>,
}

impl Motion {
    /// The zero motion.
    pub fn zero() -> Self {
        Self {
            lin: Vector3::zeros(),
            ang: Vector3::zeros(),
        }
    }

    /// Motion from its parts.
    #[inline]
    pub fn new(lin: Vector3<f64>, ang: Vector3<f64>) -> Self {
        Self { lin, ang }
    }

    /// `self x m` (spatial motion cross product).
    #[inline]
    pub fn cross_motion(&self, m: &Motion) -> Motion {
        Motion {
            lin: cross_add(
                &self.ang,
                &m.lin,
                cross_add(&self.lin, &m.ang, Vector3::zeros()),
            ),
            ang: cross_add(&self.ang, &m.ang, Vector3::zeros()),
        }
    }

    /// `self x* f` (spatial force cross product).
    #[inline]
    pub fn cross_force(&self, f: &Force) -> Force {
        Force {
            lin: cross_add(&self.ang, &f.lin, Vector3::zeros()),
            ang: cross_add(
                &self.ang,
                &f.ang,
                cross_add(&self.lin, &f.lin, Vector3::zeros()),
            ),
        }
    }

    /// Power pairing `m . f`.
    #[inline]
    pub fn dot(&self, f: &Force) -> f64 {
        let (l, a) = (&self.lin, &self.ang);
        let lin = mul_add(l.z, f.lin.z, mul_add(l.y, f.lin.y, l.x * f.lin.x));
        let ang = mul_add(a.z, f.ang.z, mul_add(a.y, f.ang.y, a.x * f.ang.x));
        lin + ang
    }

    /// Scales by a scalar.
    #[inline]
    pub fn scale(&self, s: f64) -> Motion {
        Motion {
            lin: self.lin * s,
            ang: self.ang * s,
        }
    }

    /// Linear velocity of the body point at `r` (relative to the reference point).
    #[inline]
    pub fn point_velocity(&self, r: &Vector3<f64>) -> Vector3<f64> {
        cross_add(&self.ang, r, self.lin)
    }

    /// As a 6-vector `[lin; ang]`.
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(
            self.lin.x, self.lin.y, self.lin.z, self.ang.x, self.ang.y, self.ang.z,
        )
    }
}

impl std::ops::Add for Motion {
    type Output = Motion;
    #[inline]
    fn add(self, o: Motion) -> Motion {
        Motion::new(self.lin + o.lin, self.ang + o.ang)
    }
}

impl std::ops::Sub for Motion {
    type Output = Motion;
    #[inline]
    fn sub(self, o: Motion) -> Motion {
        Motion::new(self.lin - o.lin, self.ang - o.ang)
    }
}

impl Force {
    /// The zero force.
    pub fn zero() -> Self {
        Self {
            lin: Vector3::zeros(),
            ang: Vector3::zeros(),
        }
    }

    /// Force from its parts.
    #[inline]
    pub fn new(lin: Vector3<f64>, ang: Vector3<f64>) -> Self {
        Self { lin, ang }
    }

    /// The same force with its moment taken about the point `r` (relative to the current
    /// reference point) instead: `n_r = n - r x F`.
    #[inline]
    pub fn moment_about(&self, r: &Vector3<f64>) -> Force {
        Force::new(self.lin, self.ang - r.cross(&self.lin))
    }

    /// As a 6-vector `[lin; ang]`.
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(
            self.lin.x, self.lin.y, self.lin.z, self.ang.x, self.ang.y, self.ang.z,
        )
    }
}

impl std::ops::Add for Force {
    type Output = Force;
    #[inline]
    fn add(self, o: Force) -> Force {
        Force::new(self.lin + o.lin, self.ang + o.ang)
    }
}

impl std::ops::AddAssign for Force {
    #[inline]
    fn add_assign(&mut self, o: Force) {
        self.lin += o.lin;
        self.ang += o.ang;
    }
}

/// Inertia of a rigid body about its centre of mass, in some body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyInertia {
    /// Mass [kg].
    pub mass: f64,
    /// Centre of mass in the body frame [m].
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, body axes [kg m^2].
    pub inertia_com: Matrix3<f64>,
}

impl BodyInertia {
    /// A massless body.
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            com: Vector3::zeros(),
            inertia_com: Matrix3::zeros(),
        }
    }

    /// The same inertia expressed in frame `a`, given `a_H_b` with `self` in `b`.
    pub fn transformed(&self, a_h_b: &Pose) -> BodyInertia {
        let r = &a_h_b.rotation;
        BodyInertia {
            mass: self.mass,
            com: a_h_b.transform_point(&self.com),
            inertia_com: r * self.inertia_com * r.transpose(),
        }
    }

    /// Sum of two bodies rigidly joined (both in the same frame); parallel axis theorem.
    pub fn merged(&self, other: &BodyInertia) -> BodyInertia {
        let mass = self.mass + other.mass;
        if mass <= 0.0 {
            return BodyInertia {
                mass: 0.0,
                com: Vector3::zeros(),
                inertia_com: self.inertia_com + other.inertia_com,
            };
        }
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shift = |b: &BodyInertia| parallel_axis(b.mass, &(b.com - com));
        BodyInertia {
            mass,
            com,
            inertia_com: self.inertia_com + shift(self) + other.inertia_com + shift(other),
        }
    }
}

/// `R S R^T` for a symmetric `S`: `A = R S`, then only the six distinct entries of `A R^T`
/// (`(A R^T)_ij = A_i . R_j`, rows), mirrored; 45 multiplications instead of 54 and no
/// transposed copy. Runs once per body and evaluation (RNEA's inertias at `O`).
#[inline]
pub fn rotate_symmetric(r: &Matrix3<f64>, s: &Matrix3<f64>) -> Matrix3<f64> {
    let a = mat_mul(r, s);
    let entry = |i: usize, j: usize| {
        mul_add(
            a[(i, 2)],
            r[(j, 2)],
            mul_add(a[(i, 1)], r[(j, 1)], a[(i, 0)] * r[(j, 0)]),
        )
    };
    let (xx, yy, zz) = (entry(0, 0), entry(1, 1), entry(2, 2));
    let (xy, xz, yz) = (entry(0, 1), entry(0, 2), entry(1, 2));
    Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz)
}

/// Parallel axis term `m (|d|^2 I - d d^T)` of a point mass at offset `d`.
#[inline]
pub fn parallel_axis(mass: f64, d: &Vector3<f64>) -> Matrix3<f64> {
    let md = d * mass;
    let d2 = mul_add(md.z, d.z, mul_add(md.y, d.y, md.x * d.x));
    // d2 I - m d d^T, the diagonal fused.
    let (xy, xz, yz) = (-md.x * d.y, -md.x * d.z, -md.y * d.z);
    Matrix3::new(
        mul_add(-md.x, d.x, d2),
        xy,
        xz,
        xy,
        mul_add(-md.y, d.y, d2),
        yz,
        xz,
        yz,
        mul_add(-md.z, d.z, d2),
    )
}

/// Spatial inertia about the common reference point `O`: mass `m`, first moment `h = m c`
/// (c: centre of mass relative to `O`) and rotational inertia `I_O` about `O`. Additive, so
/// composite inertias are plain sums.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpatialInertia {
    /// Mass [kg].
    pub mass: f64,
    /// First moment of mass about `O`, `m c` [kg m].
    pub first_moment: Vector3<f64>,
    /// Rotational inertia about `O` [kg m^2].
    pub rotational: Matrix3<f64>,
}

impl SpatialInertia {
    /// Zero inertia.
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            first_moment: Vector3::zeros(),
            rotational: Matrix3::zeros(),
        }
    }

    /// Spatial inertia about `O` of a body whose frame is at `r` with rotation `o_R_body`.
    #[inline]
    pub fn from_body(body: &BodyInertia, o_r_body: &Matrix3<f64>, r: &Vector3<f64>) -> Self {
        let c = mat_vec_add(o_r_body, &body.com, *r);
        let rotational =
            rotate_symmetric(o_r_body, &body.inertia_com) + parallel_axis(body.mass, &c);
        Self {
            mass: body.mass,
            first_moment: c * body.mass,
            rotational,
        }
    }

    /// `I v` (momentum of a body moving with spatial velocity `v`).
    #[inline]
    pub fn mul_motion(&self, v: &Motion) -> Force {
        Force {
            lin: cross_add(&v.ang, &self.first_moment, v.lin * self.mass),
            ang: cross_add(
                &self.first_moment,
                &v.lin,
                mat_vec_add(&self.rotational, &v.ang, Vector3::zeros()),
            ),
        }
    }

    /// The 6x6 matrix `[[m I, -[h]x], [[h]x, I_O]]`.
    pub fn to_matrix(&self) -> Matrix6<f64> {
        let mut out = Matrix6::zeros();
        let hx = skew(&self.first_moment);
        out.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Matrix3::identity() * self.mass));
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(-hx));
        out.fixed_view_mut::<3, 3>(3, 0).copy_from(&hx);
        out.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.rotational);
        out
    }

    /// Centre of mass relative to `O` (zero for a massless inertia).
    pub fn com(&self) -> Vector3<f64> {
        if self.mass > 0.0 {
            self.first_moment / self.mass
        } else {
            Vector3::zeros()
        }
    }
}

impl std::ops::AddAssign for SpatialInertia {
    #[inline]
    fn add_assign(&mut self, o: SpatialInertia) {
        self.mass += o.mass;
        self.first_moment += o.first_moment;
        self.rotational += o.rotational;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rnd(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    fn v3(seed: &mut u64) -> Vector3<f64> {
        Vector3::new(rnd(seed), rnd(seed), rnd(seed))
    }

    #[test]
    fn the_heading_is_the_yaw_whatever_the_roll_and_a_pitch_short_of_vertical() {
        let mut seed = 7;
        for _ in 0..100 {
            let (roll, pitch, yaw) = (
                3.0 * rnd(&mut seed),
                1.5 * rnd(&mut seed),
                3.1 * rnd(&mut seed),
            );
            let r = rotation_from_rpy(roll, pitch, yaw);
            assert!((heading(&r) - yaw).abs() < 1e-12, "{roll} {pitch} {yaw}");
        }
        // Past a half turn the heading wraps.
        let r = rotation_from_rpy(0.0, 0.0, 3.5);
        assert!((heading(&r) - (3.5 - 2.0 * std::f64::consts::PI)).abs() < 1e-12);
    }

    fn body(seed: &mut u64) -> BodyInertia {
        let a = v3(seed).normalize();
        let r = rotation_about_axis(&a, rnd(seed) * 3.0);
        let d = Matrix3::from_diagonal(&Vector3::new(0.3, 0.4, 0.5));
        BodyInertia {
            mass: 1.0 + rnd(seed).abs(),
            com: v3(seed),
            inertia_com: r * d * r.transpose(),
        }
    }

    #[test]
    fn rpy_matches_axis_rotations() {
        let r = rotation_from_rpy(0.3, -0.7, 1.1);
        let expected = rotation_about_axis(&Vector3::z(), 1.1)
            * rotation_about_axis(&Vector3::y(), -0.7)
            * rotation_about_axis(&Vector3::x(), 0.3);
        assert!((r - expected).norm() < 1e-14);
        assert!((r * r.transpose() - Matrix3::identity()).norm() < 1e-14);
    }

    #[test]
    fn quaternion_rotation_matches_axis_angle() {
        let axis = Vector3::new(1.0, -2.0, 0.5).normalize();
        let angle: f64 = 0.83;
        let (s, c) = (angle / 2.0).sin_cos();
        let r = rotation_from_quaternion(c, s * axis.x, s * axis.y, s * axis.z);
        assert!((r - rotation_about_axis(&axis, angle)).norm() < 1e-14);
    }

    #[test]
    fn quaternion_round_trip() {
        let mut seed = 17;
        for k in 0..50 {
            // Include rotations near pi, where the trace pivot would lose precision.
            let angle = if k % 5 == 0 {
                std::f64::consts::PI - 1e-5
            } else {
                rnd(&mut seed) * 3.0
            };
            let axis = v3(&mut seed).normalize();
            let r = rotation_about_axis(&axis, angle);
            let q = quaternion_from_rotation(&r);
            assert!((rotation_from_quaternion(q[0], q[1], q[2], q[3]) - r).norm() < 1e-12);
        }
    }

    #[test]
    fn pose_inverse_and_composition() {
        let mut seed = 3;
        let a = Pose {
            rotation: rotation_from_rpy(rnd(&mut seed), rnd(&mut seed), rnd(&mut seed)),
            translation: v3(&mut seed),
        };
        let id = a.compose(&a.inverse());
        assert!((id.rotation - Matrix3::identity()).norm() < 1e-14);
        assert!(id.translation.norm() < 1e-14);
    }

    #[test]
    fn cross_products_are_dual() {
        // (v x m) . f = -m . (v x* f), the defining duality of the two cross products.
        let mut seed = 11;
        for _ in 0..20 {
            let v = Motion::new(v3(&mut seed), v3(&mut seed));
            let m = Motion::new(v3(&mut seed), v3(&mut seed));
            let f = Force::new(v3(&mut seed), v3(&mut seed));
            let lhs = v.cross_motion(&m).dot(&f);
            let rhs = -m.dot(&v.cross_force(&f));
            assert!((lhs - rhs).abs() < 1e-12);
            assert!(v.cross_motion(&v).lin.norm() < 1e-12);
        }
    }

    #[test]
    fn spatial_inertia_matrix_matches_product_and_is_symmetric() {
        let mut seed = 5;
        for _ in 0..20 {
            let b = body(&mut seed);
            let r = rotation_from_rpy(rnd(&mut seed), rnd(&mut seed), rnd(&mut seed));
            let i = SpatialInertia::from_body(&b, &r, &v3(&mut seed));
            let v = Motion::new(v3(&mut seed), v3(&mut seed));
            let m = i.to_matrix();
            assert!((m * v.to_vector() - i.mul_motion(&v).to_vector()).norm() < 1e-12);
            assert!((m - m.transpose()).norm() < 1e-12);
            // Kinetic energy is positive and matches the one computed at the centre of mass.
            let c = i.com();
            let vc = v.point_velocity(&c);
            let energy_com = 0.5 * b.mass * vc.norm_squared()
                + 0.5 * v.ang.dot(&(r * b.inertia_com * r.transpose() * v.ang));
            assert!((0.5 * v.dot(&i.mul_motion(&v)) - energy_com).abs() < 1e-12);
        }
    }

    #[test]
    fn merging_conserves_inertia_about_any_point() {
        let mut seed = 9;
        let (a, b) = (body(&mut seed), body(&mut seed));
        let merged = a.merged(&b);
        let id = Matrix3::identity();
        let p = v3(&mut seed);
        let mut sum = SpatialInertia::from_body(&a, &id, &p);
        sum += SpatialInertia::from_body(&b, &id, &p);
        let whole = SpatialInertia::from_body(&merged, &id, &p);
        assert!((sum.to_matrix() - whole.to_matrix()).norm() < 1e-12);
    }

    #[test]
    fn force_moment_shift() {
        let f = Force::new(Vector3::new(0.0, 0.0, 1.0), Vector3::zeros());
        let r = Vector3::new(1.0, 0.0, 0.0);
        // A vertical force through O has moment -r x F about r.
        assert!((f.moment_about(&r).ang - Vector3::new(0.0, 1.0, 0.0)).norm() < 1e-15);
    }
}
