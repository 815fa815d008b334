//! The swing sole's trajectory from its lift-off pose to its touchdown pose over the single
//! support ([`SwingTrajectory`]): x, y and yaw follow the quintic `s(u) = 10 u^3 - 15 u^4 +
//! 6 u^5` of the normalised time `u` (zero velocity and acceleration at both ends), z the
//! sextic `64 h u^3 (1 - u)^3` above the ground (zero height, velocity and acceleration at
//! both ends, apex `h` at `u = 1/2`). The sole stays flat (roll and pitch zero), so its
//! angular velocity and acceleration are along world z, unless the swing has a toe-off
//! ([`ToeOff`]): then over the first part of the swing the sole pitches toe down about its toe
//! and back flat, `theta(u) = theta_max 64 v^3 (1 - v)^3` with `v = u / u_end`, the toe
//! following the flat sole's toe (the origin lifted by `x_toe sin theta` and moved forward by
//! `x_toe (1 - cos theta)`). A swing re-aimed in flight ([`SwingTrajectory::reaim`], step
//! adjustment) follows, from then on, a quintic in x, y from its flat sample then (position,
//! velocity, acceleration) to the new landing at rest; one retimed in flight
//! ([`SwingTrajectory::retime`], step timing adaptation) follows quintics in x, y, height and
//! yaw to its landing at rest at the earlier touchdown.

use super::footstep::{wrap_angle, Footstep, FootstepPlan, SolePose};
use super::settings::WalkingSettings;
use nalgebra::{Rotation3, SVector, Vector2, Vector3};
use sea_dyn::ContactSurface;

/// The swing sole's pose, velocity and acceleration at one instant (world).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingSample {
    /// Sole origin [m].
    pub world_p_sole: Vector3<f64>,
    /// Its velocity [m/s].
    pub world_v_sole: Vector3<f64>,
    /// Its acceleration [m/s^2].
    pub world_a_sole: Vector3<f64>,
    /// Sole yaw about world z [rad].
    pub world_yaw_sole: f64,
    /// Angular velocity of the sole [rad/s] (along z).
    pub world_omega_sole: Vector3<f64>,
    /// Angular acceleration of the sole [rad/s^2] (along z).
    pub world_omegadot_sole: Vector3<f64>,
    /// Sole pitch about its own y axis after the yaw [rad] (positive: toe down; zero but
    /// in a toe-off).
    pub pitch: f64,
}

impl SwingSample {
    /// The sole's orientation, world from sole: the yaw about world z, then the pitch.
    pub fn world_r_sole(&self) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Vector3::z_axis(), self.world_yaw_sole)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), self.pitch)
    }

    /// This flat sample pitched toe down by `theta` with its rate and acceleration
    /// (`[theta, theta_dot, theta_ddot]`) about the toe at `sole_x_toe` on the sole's x axis,
    /// the toe where the flat sole's is: the origin moved by `R_z(yaw) d`, `d = x_toe (1 -
    /// cos theta, 0, sin theta)`, its velocity and acceleration with the yaw's rotation of `d`.
    fn pitched_about_toe(mut self, [theta, rate, accel]: [f64; 3], sole_x_toe: f64) -> Self {
        let (sin, cos) = theta.sin_cos();
        let yaw_d = Vector3::new(1.0 - cos, 0.0, sin) * sole_x_toe;
        let yaw_d_dot = Vector3::new(sin, 0.0, cos) * (sole_x_toe * rate);
        let yaw_d_ddot = (Vector3::new(sin, 0.0, cos) * accel
            + Vector3::new(cos, 0.0, -sin) * (rate * rate))
            * sole_x_toe;
        let world_r_yaw = Rotation3::from_axis_angle(&Vector3::z_axis(), self.world_yaw_sole);
        let (z, yaw_rate, yaw_accel) = (
            Vector3::z(),
            self.world_omega_sole.z,
            self.world_omegadot_sole.z,
        );
        let d = world_r_yaw * yaw_d;
        let d_dot = world_r_yaw * yaw_d_dot;
        self.world_p_sole += d;
        self.world_v_sole += d_dot + z.cross(&d) * yaw_rate;
        self.world_a_sole += world_r_yaw * yaw_d_ddot
            + z.cross(&d_dot) * (2.0 * yaw_rate)
            + z.cross(&d) * yaw_accel
            + z.cross(&z.cross(&d)) * (yaw_rate * yaw_rate);
        let world_y_sole = world_r_yaw * Vector3::y();
        self.world_omega_sole += world_y_sole * rate;
        self.world_omegadot_sole +=
            world_y_sole * accel + z.cross(&world_y_sole) * (yaw_rate * rate);
        self.pitch = theta;
        self
    }
}

/// A swing's toe-off (module doc): the sole pitched toe down about its toe over the first
/// `end_phase` of the swing, most at half of it. As the knee folds in the swing's start a
/// flat sole asks the ankle for more dorsiflexion than its stop allows; the toe-off asks
/// less and lifts the heel (docs/findings/walking.md, "0.4 m/s: a toe-off", where which of
/// the two carries the iCub's 0.4 m/s gaits is left open).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToeOff {
    /// The largest pitch, toe down [rad] (0: the sole stays flat).
    pub pitch: f64,
    /// The fraction of the swing by which the sole is flat again, in (0, 1].
    pub end_phase: f64,
    /// The pivot: the toe's x on the sole's x axis [m].
    pub sole_x_toe: f64,
}

impl ToeOff {
    /// The toe-off `settings` ask for (`walking.swing_toe_off_pitch`,
    /// `walking.swing_toe_off_end`) about the front edge of the sole's contact rectangle.
    pub fn of(settings: &WalkingSettings, surface: &ContactSurface) -> Self {
        Self {
            pitch: settings.swing_toe_off_pitch,
            end_phase: settings.swing_toe_off_end,
            sole_x_toe: surface.foot_x[1],
        }
    }

    /// The pitch, its rate and acceleration at the swing's normalised time `u` with
    /// `u_rate = du/dt` [1/s]; `None` when the sole is flat.
    fn sample(&self, u: f64, u_rate: f64) -> Option<[f64; 3]> {
        if self.pitch == 0.0 || u >= self.end_phase {
            return None;
        }
        let v_rate = u_rate / self.end_phase;
        let [b, db, ddb] = apex_profile(u / self.end_phase, 1.0);
        Some([
            self.pitch * b,
            self.pitch * db * v_rate,
            self.pitch * ddb * v_rate * v_rate,
        ])
    }
}

/// A swing (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwingTrajectory {
    /// Lift-off pose.
    pub lift_off: SolePose,
    /// Touchdown pose as planned at lift-off (its yaw reached the short way round); a re-aimed
    /// swing lands where its [`Self::reaimed`] quintic ends.
    pub touchdown: SolePose,
    /// Lift-off time [s].
    pub start: f64,
    /// Swing duration as planned at lift-off [s], > 0: the shape's (height, toe-off) time
    /// scale; a retimed swing lands earlier ([`Self::touchdown_time`]).
    pub duration: f64,
    /// Apex height above the ground [m].
    pub height: f64,
    /// The sole's toe-off.
    pub toe_off: ToeOff,
    /// Ground height in world [m].
    pub world_z_ground: f64,
    /// The x, y of the sole from a re-aim in flight on (`None`: the quintic from lift-off).
    pub reaimed: Option<PlanarQuintic>,
    /// The height above the ground and the yaw of the sole from a retiming in flight on
    /// ([`Self::retime`]; `None`: the sextic and the quintic from lift-off).
    pub retimed: Option<Quintic<2>>,
}

/// A quintic in `D` dimensions over `[start, start + duration]`: `sum c_k tau^k`, `tau` the
/// time from `start` (held at its end value after, at its start value before).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quintic<const D: usize> {
    /// Start time [s].
    pub start: f64,
    /// Duration [s], > 0.
    pub duration: f64,
    /// Coefficients `c_0..c_5`.
    pub coefficients: [SVector<f64, D>; 6],
}

/// A quintic in the plane: a re-aimed swing's x, y.
pub type PlanarQuintic = Quintic<2>;

impl<const D: usize> Quintic<D> {
    /// The quintic from position `p0`, velocity `v0`, acceleration `a0` at `start` to `p1`
    /// at rest (zero velocity and acceleration) at `start + duration`.
    pub fn to_rest(
        start: f64,
        duration: f64,
        [p0, v0, a0]: [SVector<f64, D>; 3],
        p1: SVector<f64, D>,
    ) -> Self {
        let t = duration;
        let d = p1 - p0;
        let c3 = (d * 20.0 - v0 * (12.0 * t) - a0 * (3.0 * t * t)) / (2.0 * t.powi(3));
        let c4 = (-d * 30.0 + v0 * (16.0 * t) + a0 * (3.0 * t * t)) / (2.0 * t.powi(4));
        let c5 = (d * 12.0 - v0 * (6.0 * t) - a0 * (t * t)) / (2.0 * t.powi(5));
        Self {
            start,
            duration,
            coefficients: [p0, v0, a0 * 0.5, c3, c4, c5],
        }
    }

    /// Position, velocity and acceleration at time `t` [s].
    pub fn sample(&self, t: f64) -> [SVector<f64, D>; 3] {
        let tau = (t - self.start).clamp(0.0, self.duration);
        let c = &self.coefficients;
        let mut out = [SVector::<f64, D>::zeros(); 3];
        for k in (0..6).rev() {
            out[2] = out[2] * tau + out[1] * 2.0;
            out[1] = out[1] * tau + out[0];
            out[0] = out[0] * tau + c[k];
        }
        out
    }
}

impl SwingTrajectory {
    /// The swing of `plan.steps[index]` with apex `height` and `toe_off` over ground at
    /// `world_z_ground`.
    pub fn of_step(
        plan: &FootstepPlan,
        index: usize,
        (height, toe_off): (f64, ToeOff),
        world_z_ground: f64,
    ) -> Self {
        let step: &Footstep = &plan.steps[index];
        Self {
            lift_off: plan.stances[index].get(step.foot),
            touchdown: step.pose,
            start: step.lift_off,
            duration: step.touchdown - step.lift_off,
            height,
            toe_off,
            world_z_ground,
            reaimed: None,
            retimed: None,
        }
    }

    /// Re-aims the swing in flight at time `t` [s] (before its touchdown) to land at
    /// `world_p_landing` (x, y; the yaw kept): from `t` on x and y follow a
    /// [`PlanarQuintic`] from this swing's sample at `t` to the landing at rest at the
    /// touchdown time ([`Self::touchdown_time`]), so the sole's reference has no jump in
    /// position, velocity or acceleration; the height is unchanged.
    pub fn reaim(&mut self, t: f64, world_p_landing: Vector2<f64>) {
        let remaining = self.touchdown_time() - t;
        if remaining <= 0.0 {
            return;
        }
        let now = self.flat_sample(t);
        let planar = [now.world_p_sole, now.world_v_sole, now.world_a_sole].map(|v| v.xy());
        self.reaimed = Some(PlanarQuintic::to_rest(
            t,
            remaining,
            planar,
            world_p_landing,
        ));
    }

    /// Moves the touchdown in flight at time `t` [s] to `touchdown` [s] (after `t`): from
    /// `t` on x, y follow a [`PlanarQuintic`] and the height and yaw a [`Quintic`] from the
    /// swing's sample at `t` to the landing at rest at the new touchdown, so the sole's
    /// reference has no jump in position, velocity or acceleration; a toe-off keeps its
    /// timing (the swing's `duration` stays the planned one, [`Self::touchdown_time`] is the
    /// new). Nothing is done at or after the touchdown.
    pub fn retime(&mut self, t: f64, touchdown: f64) {
        let remaining = touchdown - t;
        if remaining <= 0.0 || t >= self.touchdown_time() {
            return;
        }
        let now = self.flat_sample(t);
        let landing = self.flat_sample(self.touchdown_time());
        let planar = [now.world_p_sole, now.world_v_sole, now.world_a_sole].map(|v| v.xy());
        let vertical = [
            Vector2::new(now.world_p_sole.z - self.world_z_ground, now.world_yaw_sole),
            Vector2::new(now.world_v_sole.z, now.world_omega_sole.z),
            Vector2::new(now.world_a_sole.z, now.world_omegadot_sole.z),
        ];
        let aim = landing.world_p_sole.xy();
        self.reaimed = Some(PlanarQuintic::to_rest(t, remaining, planar, aim));
        let rest = Vector2::new(0.0, landing.world_yaw_sole);
        self.retimed = Some(Quintic::to_rest(t, remaining, vertical, rest));
    }

    /// The time the sole lands [s]: the end of a retiming ([`Self::retime`]), or the planned
    /// `start + duration`.
    pub fn touchdown_time(&self) -> f64 {
        self.retimed
            .map_or(self.start + self.duration, |q| q.start + q.duration)
    }

    /// The sole at time `t` [s] (held at the lift-off pose before, at the touchdown pose
    /// after), with its toe-off.
    pub fn sample(&self, t: f64) -> SwingSample {
        let flat = self.flat_sample(t);
        let u = ((t - self.start) / self.duration).clamp(0.0, 1.0);
        match self.toe_off.sample(u, 1.0 / self.duration) {
            Some(theta) => flat.pitched_about_toe(theta, self.toe_off.sole_x_toe),
            None => flat,
        }
    }

    /// The sole at time `t` [s] without the toe-off.
    fn flat_sample(&self, t: f64) -> SwingSample {
        let u = ((t - self.start) / self.duration).clamp(0.0, 1.0);
        let rate = 1.0 / self.duration;
        let [s, ds, dds] = minimum_jerk(u);
        let [z, dz, ddz] = apex_profile(u, self.height);
        let delta_p = self.touchdown.world_p_sole - self.lift_off.world_p_sole;
        let delta_yaw = wrap_angle(self.touchdown.world_yaw_sole - self.lift_off.world_yaw_sole);
        let [p, v, a] = match &self.reaimed {
            Some(planar) if t >= planar.start => planar.sample(t),
            _ => [
                self.lift_off.world_p_sole + delta_p * s,
                delta_p * (ds * rate),
                delta_p * (dds * rate * rate),
            ],
        };
        let [z, dz, ddz, yaw, dyaw, ddyaw] = match &self.retimed {
            Some(vertical) if t >= vertical.start => {
                let [q, dq, ddq] = vertical.sample(t);
                [q.x, dq.x, ddq.x, q.y, dq.y, ddq.y]
            }
            _ => [
                z,
                dz * rate,
                ddz * rate * rate,
                self.lift_off.world_yaw_sole + delta_yaw * s,
                delta_yaw * ds * rate,
                delta_yaw * dds * rate * rate,
            ],
        };
        SwingSample {
            world_p_sole: Vector3::new(p.x, p.y, self.world_z_ground + z),
            world_v_sole: Vector3::new(v.x, v.y, dz),
            world_a_sole: Vector3::new(a.x, a.y, ddz),
            world_yaw_sole: yaw,
            world_omega_sole: Vector3::new(0.0, 0.0, dyaw),
            world_omegadot_sole: Vector3::new(0.0, 0.0, ddyaw),
            pitch: 0.0,
        }
    }
}

/// `s(u) = 10 u^3 - 15 u^4 + 6 u^5` and its first two derivatives in `u`.
fn minimum_jerk(u: f64) -> [f64; 3] {
    let (u2, u3) = (u * u, u * u * u);
    [
        u3 * (10.0 - 15.0 * u + 6.0 * u2),
        30.0 * u2 * (1.0 - 2.0 * u + u2),
        60.0 * u * (1.0 - 3.0 * u + 2.0 * u2),
    ]
}

/// `z(u) = 64 h u^3 (1 - u)^3` and its first two derivatives in `u`.
fn apex_profile(u: f64, height: f64) -> [f64; 3] {
    let (a, b) = (u, 1.0 - u);
    let k = 64.0 * height;
    [
        k * a.powi(3) * b.powi(3),
        k * 3.0 * a * a * b * b * (b - a),
        k * 6.0 * a * b * (b * b - 3.0 * a * b + a * a),
    ]
}
