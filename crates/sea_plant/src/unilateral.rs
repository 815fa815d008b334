//! Unilateral contacts: each sole touches the [`Ground`] at points of its rectangle through a
//! compliant contact, a linear Hunt-Crossley normal force with regularised Coulomb friction.
//!
//! Per point `p` (world), with the depth `delta = -n . (p - p_ground)` below the plane and its
//! rate `deltadot = -n . v`:
//! - normal force `f_n = max(0, k delta (1 + d deltadot))` when `delta > 0`, else 0 (Hunt and
//!   Crossley, J. Appl. Mech. 42, 1975, with a linear spring, as Drake's point contact): the
//!   force grows from zero at touchdown (no jump at a contact switch), and the dissipation
//!   `k d delta` makes impacts inelastic: a point leaves the ground only when it moves up faster
//!   than `1 / d`, so a landing sticks;
//! - friction `f_t = -mu f_n v_t / sqrt(|v_t|^2 + v_s^2)`, `v_t` the tangential velocity: the
//!   Coulomb cone `|f_t| <= mu f_n` with full force when sliding faster than the stiction
//!   velocity `v_s`, a steep viscous law below it (a sticking point creeps at
//!   `v_s r / sqrt(1 - r^2)`, `r` the friction ratio).
//!
//! Why compliant and not a time-stepping solve on the impulses: the forces are functions of the
//! state, so the contact is one more stiff term of the same ODE the fixed-step Rosenbrock-W
//! integrator already handles for the springs, dampers and the motor loop. `W` takes the
//! contact's stiffness and damping exactly (frozen over the step, [`foot_stiffness`]), which
//! keeps the step L-stable; redundant points and redundant legs are no special case (no
//! constraint is solved); the motor states never jump. Each foot's forces reach the dynamics as
//! the generalised force `J^T w` of its wrench at the sole origin.

use crate::ground::Ground;
use nalgebra::{Matrix3, Matrix6, Vector3};
use sea_dyn::error::{check_non_negative, check_positive};

/// The contact law's parameters (per point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompliantContact {
    /// Normal stiffness `k` [N/m] per point.
    pub stiffness: f64,
    /// Hunt-Crossley dissipation `d` [s/m]: the damping is `k d delta`.
    pub dissipation: f64,
    /// Stiction velocity `v_s` [m/s] of the regularised friction.
    pub stiction_velocity: f64,
}

impl CompliantContact {
    /// Default stiction velocity [m/s] (Drake's default stiction tolerance): a sticking foot
    /// under a friction ratio of 0.3 creeps at 0.03 mm/s.
    pub const DEFAULT_STICTION_VELOCITY: f64 = 1e-4;

    /// A law for a robot of weight `weight` [N] standing on `points` points: the stiffness
    /// that sinks it by `penetration` [m] at rest (`k = weight / (points penetration)`), and
    /// the dissipation that damps its vertical mode critically at rest
    /// (`k d delta_0 = 2 sqrt(k m / points)`, i.e. `d = 2 omega / g`, `omega` that mode's
    /// angular frequency).
    pub fn for_weight(weight: f64, points: usize, penetration: f64, gravity: f64) -> Self {
        let points = points.max(1) as f64;
        let stiffness = weight / (points * penetration);
        let omega = (gravity / penetration).sqrt();
        Self {
            stiffness,
            dissipation: 2.0 * omega / gravity,
            stiction_velocity: Self::DEFAULT_STICTION_VELOCITY,
        }
    }

    /// Checks the parameters; errors name the key.
    pub fn validate(&self) -> crate::Result<()> {
        check_positive("ground.stiffness_n_per_m", self.stiffness)?;
        check_non_negative("ground.dissipation_s_per_m", self.dissipation)?;
        check_positive("ground.stiction_velocity_m_s", self.stiction_velocity)
    }
}

/// The unilateral contact model of a plant: the ground, the law and, per contact of
/// [`crate::Plant::contacts`], its points in the contact frame.
#[derive(Clone, Debug, PartialEq)]
pub struct UnilateralContacts {
    /// The ground.
    pub ground: Ground,
    /// The contact law.
    pub law: CompliantContact,
    /// Per contact, its points in the contact frame [m].
    pub points: Vec<Vec<Vector3<f64>>>,
}

impl UnilateralContacts {
    /// The four corners of the sole rectangle `foot_x` x `foot_y` (contact frame, z = 0).
    pub fn rectangle_corners(foot_x: [f64; 2], foot_y: [f64; 2]) -> Vec<Vector3<f64>> {
        let mut corners = Vec::with_capacity(4);
        for x in foot_x {
            for y in foot_y {
                corners.push(Vector3::new(x, y, 0.0));
            }
        }
        corners
    }

    /// Points over all contacts.
    pub fn n_points(&self) -> usize {
        self.points.iter().map(Vec::len).sum()
    }
}

/// One point's contact at a state: its force and its linearisation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointContact {
    /// Force on the foot (world axes) [N].
    pub force: Vector3<f64>,
    /// `d f_n / d delta` [N/m] (0 when inactive).
    pub normal_stiffness: f64,
    /// `d f_n / d deltadot` [N s/m].
    pub normal_damping: f64,
    /// `d f_t / d v_t` [N s/m] at zero slip (the viscous slope of the friction).
    pub tangent_damping: f64,
    /// Whether it carries a force.
    pub active: bool,
}

/// The contact of a point at world `position` moving at `velocity` (module doc).
pub fn point_contact(
    ground: &Ground,
    law: &CompliantContact,
    position: &Vector3<f64>,
    velocity: &Vector3<f64>,
) -> PointContact {
    let depth = -ground.height_of(position);
    if depth <= 0.0 {
        return PointContact::default();
    }
    let n = ground.normal;
    let normal_speed = n.dot(velocity);
    let depth_rate = -normal_speed;
    let spring = law.stiffness * depth;
    let normal = spring * (1.0 + law.dissipation * depth_rate);
    if normal <= 0.0 {
        return PointContact::default();
    }
    let tangential = velocity - n * normal_speed;
    let regularised = (tangential.norm_squared() + law.stiction_velocity.powi(2)).sqrt();
    let tangent_damping = ground.friction * normal / regularised;
    PointContact {
        force: n * normal - tangential * tangent_damping,
        normal_stiffness: law.stiffness * (1.0 + law.dissipation * depth_rate),
        normal_damping: spring * law.dissipation,
        tangent_damping,
        active: true,
    }
}

/// A point's share of its foot's stiffness and damping, at the sole origin (6 x 6 in
/// `[v; omega]`, world axes): with `A = [I, -[s]x]` mapping the sole's velocity to the point's
/// (`s` the point from the sole origin, world axes), adds `A^T K A` to `stiffness` and
/// `A^T D A` to `damping`, `K = k_n n n^T`, `D = d_n n n^T + d_t (I - n n^T)`. These are
/// `-d w / d (pose, velocity)` of the foot's wrench, which the implicit step's `W` takes.
pub fn foot_stiffness(
    contact: &PointContact,
    normal: &Vector3<f64>,
    offset: &Vector3<f64>,
    stiffness: &mut Matrix6<f64>,
    damping: &mut Matrix6<f64>,
) {
    let nn = normal * normal.transpose();
    let k = nn * contact.normal_stiffness;
    let d = nn * (contact.normal_damping - contact.tangent_damping)
        + Matrix3::identity() * contact.tangent_damping;
    add_transported(&k, offset, stiffness);
    add_transported(&d, offset, damping);
}

/// `out += A^T X A`, `A = [I, -S]`, `S = [s]x`: `[[X, -X S], [S X, -S X S]]`.
fn add_transported(x: &Matrix3<f64>, offset: &Vector3<f64>, out: &mut Matrix6<f64>) {
    let s = offset.cross_matrix();
    let xs = x * s;
    let sx = s * x;
    let mut block = out.fixed_view_mut::<3, 3>(0, 0);
    block += x;
    let mut block = out.fixed_view_mut::<3, 3>(0, 3);
    block -= xs;
    let mut block = out.fixed_view_mut::<3, 3>(3, 0);
    block += sx;
    let mut block = out.fixed_view_mut::<3, 3>(3, 3);
    block -= s * xs;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> CompliantContact {
        CompliantContact {
            stiffness: 1e5,
            dissipation: 20.0,
            stiction_velocity: 1e-3,
        }
    }

    #[test]
    fn a_point_above_the_ground_or_leaving_fast_carries_nothing() {
        let ground = Ground::flat(0.0, 0.8).unwrap();
        let above = point_contact(
            &ground,
            &law(),
            &Vector3::new(0.0, 0.0, 1e-6),
            &Vector3::zeros(),
        );
        assert!(!above.active);
        // Leaving faster than 1 / d: the dissipation cancels the spring.
        let leaving = point_contact(
            &ground,
            &law(),
            &Vector3::new(0.0, 0.0, -1e-4),
            &Vector3::new(0.0, 0.0, 0.06),
        );
        assert!(!leaving.active);
        let pressed = point_contact(
            &ground,
            &law(),
            &Vector3::new(0.0, 0.0, -1e-4),
            &Vector3::new(0.0, 0.0, 0.01),
        );
        assert!((pressed.force.z - 1e5 * 1e-4 * (1.0 - 0.2)).abs() < 1e-9);
    }

    #[test]
    fn friction_stays_inside_the_cone_and_opposes_slip() {
        let ground = Ground::flat(0.0, 0.8).unwrap();
        let sliding = Vector3::new(0.3, -0.4, 0.0);
        let c = point_contact(&ground, &law(), &Vector3::new(0.0, 0.0, -1e-3), &sliding);
        let tangential = c.force.xy();
        assert!(tangential.norm() <= 0.8 * c.force.z);
        assert!(tangential.norm() > 0.8 * c.force.z * 0.999_99);
        assert!(tangential.dot(&sliding.xy()) < 0.0);
    }

    #[test]
    fn the_foot_stiffness_is_the_derivative_of_the_wrench() {
        // A point offset from the sole origin: perturb the sole's pose, compare the wrench
        // change with -K dx.
        let ground = Ground::flat(0.0, 0.8).unwrap();
        let law = law();
        let origin = Vector3::new(0.0, 0.0, 0.0);
        let offset = Vector3::new(0.1, -0.03, -2e-4);
        // The wrench about the sole origin, moment arm held at `arm` (W keeps the material
        // stiffness only, not the change of the arm under a force).
        let wrench = |arm: &Vector3<f64>, point: &Vector3<f64>| {
            let c = point_contact(&ground, &law, &(origin + point), &Vector3::zeros());
            let moment = arm.cross(&c.force);
            [
                c.force.x, c.force.y, c.force.z, moment.x, moment.y, moment.z,
            ]
        };
        let at_rest = point_contact(&ground, &law, &(origin + offset), &Vector3::zeros());
        let (mut k, mut d) = (Matrix6::zeros(), Matrix6::zeros());
        foot_stiffness(&at_rest, &ground.normal, &offset, &mut k, &mut d);
        let h = 1e-7;
        let base = wrench(&offset, &offset);
        for column in 0..6 {
            // The sole moved by `h` along `column` of `[dp; dtheta]`: the point moves by
            // `dp + dtheta x offset`.
            let mut motion = [0.0; 6];
            motion[column] = h;
            let dp = Vector3::new(motion[0], motion[1], motion[2]);
            let dtheta = Vector3::new(motion[3], motion[4], motion[5]);
            let moved = wrench(&offset, &(offset + dp + dtheta.cross(&offset)));
            for r in 0..6 {
                let numeric = (moved[r] - base[r]) / h;
                let linear = -k[(r, column)];
                assert!(
                    (numeric - linear).abs() < 1e-3 * (1.0 + linear.abs()),
                    "{r} {column}"
                );
            }
        }
    }
}
