//! The SEA plant: floating-base robot with mixed rigid/elastic joints in rigid contact.
//!
//! State `x = [q (nq); theta (n_e); nu (nv); thetadot (n_e)]` (nx = nq + nv + 2 n_e); its
//! tangent `dx = [dq (nv); dtheta; dnu; dthetadot]` (nd = 2 nv + 2 n_e). Input `u` (n), per
//! joint in coordinate order: rigid joint, the joint torque; elastic joint, the motor torque
//! (`MotorInput::Torque`) or the desired motor velocity of the motor velocity loop
//! (`MotorInput::VelocityLoop`, paper eq:tauMotors:
//! `tau_m = -b K_m (thetadot - thetadot_d) + eta tau`, saturated at the torque limit).
//!
//! Equations (paper eq:elasticSystem, eq:constraints_acc):
//! - elastic joint torque `tau = k_s (eta theta - s) + k_d (eta thetadot - sdot)`,
//!   motor `b thetaddot = tau_m - eta tau`;
//! - `M nudot + h = B tau + J^T f`, `J nudot + Jdot nu = -(K_d J nu + K_p e)` (Baumgarte), where
//!   `J` stacks the contact frame Jacobians (6 rows each, `[v; omega]` of the frame origin,
//!   world axes), `e` stacks the pose errors `[p - p_ref; rotation error]` and `f` the contact
//!   wrenches `[force; moment about the frame origin]`, world axes, the Lagrange multipliers.
//!   Solved with `M = L L^T` and the Schur complement `J M^-1 J^T` (k x k).

use crate::contact::{Contact, ContactLimits};
use crate::error::{Error, Result};
use sea_dyn::actuator::Actuation;
use sea_dyn::data::Data;
use sea_dyn::error::check_vector;
use sea_dyn::kinematics::frame_placement;
use sea_dyn::model::Model;
use sea_dyn::StateLayout;

/// What the input of an elastic joint means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotorInput {
    /// `u` is the motor torque [Nm], motor side (clipped at the torque limit).
    Torque,
    /// `u` is the desired motor velocity [rad/s]; the velocity loop of gain `K_m` [1/s] is
    /// evaluated with the plant.
    VelocityLoop {
        /// Motor velocity gain `K_m` [1/s].
        gain: f64,
    },
}

/// The plant: model, actuation, contacts and constraint stabilisation.
#[derive(Clone, Debug)]
pub struct Plant {
    /// Robot model.
    pub model: Model,
    /// Actuators of every joint.
    pub actuation: Actuation,
    /// Rigid contacts (zero, one or two feet).
    pub contacts: Vec<Contact>,
    /// Baumgarte position gain `K_p` [1/s^2] (default 50, REFERENCE.md).
    pub baumgarte_kp: f64,
    /// Baumgarte velocity gain `K_d` [1/s] (default `2 sqrt(K_p)`).
    pub baumgarte_kd: f64,
    /// Meaning of the elastic joints' inputs.
    pub motor_input: MotorInput,
    /// Added to the joint diagonal of `M` (the original study used 0.1 for the reflected motor
    /// inertia); default 0.
    pub joint_inertia_regularization: f64,
    /// Limits for the reported wrench margins.
    pub contact_limits: ContactLimits,
}

impl Plant {
    /// A plant with the given actuation and no contacts, default gains, torque input.
    pub fn new(model: Model, actuation: Actuation) -> Self {
        let kp = 50.0;
        Self {
            model,
            actuation,
            contacts: Vec::new(),
            baumgarte_kp: kp,
            baumgarte_kd: 2.0 * f64::sqrt(kp),
            motor_input: MotorInput::Torque,
            joint_inertia_regularization: 0.0,
            contact_limits: ContactLimits::default(),
        }
    }

    /// State layout.
    pub fn layout(&self) -> StateLayout {
        StateLayout::new(&self.model, &self.actuation)
    }

    /// Sets the contact frames, each held at its pose in configuration `q`.
    pub fn set_contacts(&mut self, frames: &[String], q: &[f64]) -> Result<()> {
        self.model.check_configuration(q)?;
        let mut data = Data::new(&self.model);
        sea_dyn::kinematics::forward_kinematics(&self.model, &mut data, q);
        let mut contacts = Vec::with_capacity(frames.len());
        for name in frames {
            let frame = self.model.frame_id(name)?;
            if contacts.iter().any(|c: &Contact| c.frame == frame) {
                return Err(Error::input(format!(
                    "contact frame '{name}' is listed twice"
                )));
            }
            contacts.push(Contact {
                name: name.clone(),
                frame,
                reference: frame_placement(&self.model, &data, frame),
            });
        }
        self.contacts = contacts;
        Ok(())
    }

    /// Checks gains and parameters; errors name the offending setting.
    pub fn validate(&self) -> Result<()> {
        let gains = [
            ("baumgarte_kp", self.baumgarte_kp),
            ("baumgarte_kd", self.baumgarte_kd),
            (
                "joint_inertia_regularization",
                self.joint_inertia_regularization,
            ),
        ];
        for (name, value) in gains {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::input(format!(
                    "{name} must be non-negative and finite, got {value}"
                )));
            }
        }
        if let MotorInput::VelocityLoop { gain } = self.motor_input {
            if !(gain.is_finite() && gain > 0.0) {
                return Err(Error::input(format!(
                    "motor_velocity_gain must be positive and finite, got {gain}"
                )));
            }
        }
        Ok(())
    }

    /// Checks a state: size nx, finite, unit quaternion within [`crate::model::QUATERNION_TOLERANCE`].
    pub fn check_state(&self, x: &[f64]) -> Result<()> {
        check_vector("x", x, self.layout().nx())?;
        self.model.check_configuration(&x[..self.model.nq()])
    }

    /// Checks an input: size n, finite.
    pub fn check_input(&self, u: &[f64]) -> Result<()> {
        check_vector("u", u, self.model.n_joints())
    }

    /// A state from its parts; `theta = s / eta` (springs at rest) and zero velocities when
    /// `theta`/`thetadot` are `None`.
    pub fn make_state(
        &self,
        q: &[f64],
        nu: &[f64],
        theta: Option<&[f64]>,
        thetadot: Option<&[f64]>,
    ) -> Result<Vec<f64>> {
        let layout = self.layout();
        self.model.check_configuration(q)?;
        self.model.check_velocity("nu", nu)?;
        let mut x = vec![0.0; layout.nx()];
        x[..layout.nq].copy_from_slice(q);
        x[layout.nu_offset()..layout.nu_offset() + layout.nv].copy_from_slice(nu);
        match theta {
            Some(theta) => {
                check_vector("theta", theta, layout.ne)?;
                x[layout.theta_offset()..layout.theta_offset() + layout.ne].copy_from_slice(theta);
            }
            None => {
                for (e, &j) in self.actuation.elastic_joints.iter().enumerate() {
                    x[layout.theta_offset() + e] = q[7 + j] / self.actuation.elastic[e].ratio;
                }
            }
        }
        if let Some(thetadot) = thetadot {
            check_vector("thetadot", thetadot, layout.ne)?;
            x[layout.thetadot_offset()..layout.thetadot_offset() + layout.ne]
                .copy_from_slice(thetadot);
        }
        Ok(x)
    }
}
