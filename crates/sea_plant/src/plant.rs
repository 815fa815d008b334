//! The SEA plant: floating-base robot with mixed rigid/elastic joints in rigid contact.
//!
//! State `x = [q (nq); theta (n_e); nu (nv); thetadot (n_e)]` (nx = nq + nv + 2 n_e); its
//! tangent `dx = [dq (nv); dtheta; dnu; dthetadot]` (nd = 2 nv + 2 n_e). Input `u` (n), per
//! joint in coordinate order: rigid joint, the joint torque; elastic joint, the motor torque
//! (`MotorInput::Torque`) or the desired motor velocity of the motor velocity loop
//! (`MotorInput::VelocityLoop`, paper eq:tauMotors:
//! `tau_m = -I_m K_m (thetadot - thetadot_d) + Gamma tau`, saturated at the torque limit).
//!
//! Equations (paper eq:elasticSystem, eq:constraints_acc):
//! - elastic joint torque `tau = K_S (Gamma theta - s) + K_D (Gamma thetadot - sdot)`,
//!   motor `I_m thetaddot = tau_m - Gamma tau`;
//! - `(M + D) nudot + h = B tau + J^T f` (`D`: `joint_inertia_regularization` on the joint
//!   rows), `J nudot + Jdot nu = -(K_d J nu + K_p e)` (Baumgarte), where
//!   `J` stacks the contact frame Jacobians (6 rows each, `[v; omega]` of the frame origin,
//!   world axes), `e` stacks the pose errors `[p - p_ref; rotation error]` and `f` the contact
//!   wrenches `[force; moment about the frame origin]`, world axes, the Lagrange multipliers.
//!   Solved with `M + D = L^T L` and the Schur complement `J (M + D)^-1 J^T` (k x k).

use crate::contact::{sole_margins, Contact, ContactLimits, WrenchMargins};
use crate::error::{Error, Result};
use crate::ground::Ground;
use crate::joint_stops::JointStops;
use crate::unilateral::{CompliantContact, UnilateralContacts};
use nalgebra::Vector3;
use sea_dyn::actuator::Actuation;
use sea_dyn::data::Data;
use sea_dyn::error::{check_non_negative, check_positive, check_vector};
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

/// How the contacts of [`Plant::contacts`] touch the world.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ContactModel {
    /// Rigid bilateral contacts (the paper's setting): each frame is held at its reference pose
    /// by the Baumgarte-stabilised constraint (paper eq:constraints_acc).
    #[default]
    Bilateral,
    /// Each sole touches the ground at points through the compliant unilateral law of
    /// [`crate::unilateral`]: lift-off, tipping, slip and impacts are physics.
    Unilateral(UnilateralContacts),
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
    /// Baumgarte position gain `K_p` [1/s^2] (default [`Plant::DEFAULT_BAUMGARTE_KP`]).
    pub baumgarte_kp: f64,
    /// Baumgarte velocity gain `K_d` [1/s] (default [`sea_dyn::critical_damping`] of `K_p`).
    pub baumgarte_kd: f64,
    /// Meaning of the elastic joints' inputs.
    pub motor_input: MotorInput,
    /// Added to the joint diagonal of `M` (the original study used 0.1 for the reflected motor
    /// inertia); default 0.
    pub joint_inertia_regularization: f64,
    /// Limits for the reported wrench margins.
    pub contact_limits: ContactLimits,
    /// How the contacts touch the world (default: bilateral).
    pub contact_model: ContactModel,
    /// The URDF's position limits as stops ([`crate::joint_stops`]); `None`: no stops.
    pub joint_stops: Option<JointStops>,
}

impl Plant {
    /// Default Baumgarte position gain `K_p` [1/s^2]: the original study's pose-correction
    /// gain (docs/references.md#original-study-plant), with `K_d` its critical damping.
    pub const DEFAULT_BAUMGARTE_KP: f64 = 50.0;

    /// A plant with the given actuation and no contacts, default gains, torque input.
    pub fn new(model: Model, actuation: Actuation) -> Self {
        let kp = Self::DEFAULT_BAUMGARTE_KP;
        Self {
            model,
            actuation,
            contacts: Vec::new(),
            baumgarte_kp: kp,
            baumgarte_kd: sea_dyn::critical_damping(kp),
            motor_input: MotorInput::Torque,
            joint_inertia_regularization: 0.0,
            contact_limits: ContactLimits::default(),
            contact_model: ContactModel::Bilateral,
            joint_stops: None,
        }
    }

    /// The unilateral contacts, if that is the contact model.
    pub fn unilateral(&self) -> Option<&UnilateralContacts> {
        match &self.contact_model {
            ContactModel::Unilateral(unilateral) => Some(unilateral),
            ContactModel::Bilateral => None,
        }
    }

    /// Contact points over all contacts (0 under bilateral contacts).
    pub fn n_contact_points(&self) -> usize {
        self.unilateral().map_or(0, UnilateralContacts::n_points)
    }

    /// The number of points of each contact, in the contacts' order (empty under bilateral
    /// contacts).
    pub fn contact_point_counts(&self) -> Vec<usize> {
        self.unilateral().map_or_else(Vec::new, |unilateral| {
            unilateral.points.iter().map(Vec::len).collect()
        })
    }

    /// Makes the contacts unilateral: `points` per contact of [`Plant::contacts`] (contact
    /// frame). Errors name the bad part.
    pub fn set_unilateral_contacts(
        &mut self,
        ground: Ground,
        law: CompliantContact,
        points: Vec<Vec<nalgebra::Vector3<f64>>>,
    ) -> Result<()> {
        law.validate()?;
        if points.len() != self.contacts.len() {
            return Err(Error::invalid(
                "contact points",
                format!("one list per contact ({})", self.contacts.len()),
                points.len(),
            ));
        }
        for (contact, list) in self.contacts.iter().zip(&points) {
            if list.is_empty() || list.iter().any(|p| !p.iter().all(|v| v.is_finite())) {
                return Err(Error::invalid(
                    format!("contact points of '{}'", contact.name),
                    "at least one point, finite coordinates",
                    format!("{list:?}"),
                ));
            }
        }
        self.contact_model = ContactModel::Unilateral(UnilateralContacts {
            ground,
            law,
            points,
        });
        Ok(())
    }

    /// State layout.
    pub fn layout(&self) -> StateLayout {
        StateLayout::new(&self.model, &self.actuation)
    }

    /// The diagonal added to `M` (nv): the joint inertia regularisation on the joints, zero on
    /// the base.
    pub fn joint_diagonal(&self, diagonal: &mut [f64]) {
        diagonal[..6].fill(0.0);
        diagonal[6..].fill(self.joint_inertia_regularization);
    }

    /// Margins of each contact's wrench in `contact_wrench` (k, e.g.
    /// [`crate::PlantOutputs::contact_wrench`]) at state `x`, in its sole frame.
    pub fn wrench_margins(&self, x: &[f64], contact_wrench: &[f64]) -> Vec<WrenchMargins> {
        let mut data = Data::new(&self.model);
        sea_dyn::kinematics::forward_kinematics(&self.model, &mut data, &x[..self.model.nq()]);
        let w = contact_wrench;
        self.contacts
            .iter()
            .enumerate()
            .map(|(c, contact)| {
                let rotation = frame_placement(&self.model, &data, contact.frame).rotation;
                let force =
                    rotation.transpose() * Vector3::new(w[6 * c], w[6 * c + 1], w[6 * c + 2]);
                let moment =
                    rotation.transpose() * Vector3::new(w[6 * c + 3], w[6 * c + 4], w[6 * c + 5]);
                sole_margins(&force, &moment, &self.contact_limits)
            })
            .collect()
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
                return Err(Error::invalid(
                    "contacts",
                    "distinct frames",
                    format!("'{name}' listed twice"),
                ));
            }
            contacts.push(Contact {
                name: name.clone(),
                frame,
                world_h_frame_desired: frame_placement(&self.model, &data, frame),
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
            check_non_negative(name, value)?;
        }
        if let MotorInput::VelocityLoop { gain } = self.motor_input {
            check_positive("motor_velocity_gain", gain)?;
        }
        if let Some(stops) = &self.joint_stops {
            stops.validate()?;
        }
        if let Some(unilateral) = self.unilateral() {
            unilateral.law.validate()?;
        }
        Ok(())
    }

    /// Checks a state: size nx, finite, unit quaternion within [`sea_dyn::model::QUATERNION_TOLERANCE`].
    pub fn check_state(&self, x: &[f64]) -> Result<()> {
        check_vector("x", x, self.layout().nx())?;
        self.model
            .check_configuration_named("x", &x[..self.model.nq()])
    }

    /// Checks an input: size n, finite.
    pub fn check_input(&self, u: &[f64]) -> Result<()> {
        check_vector("u", u, self.model.n_joints())
    }

    /// The motor angles `theta` (n_e) that make the springs hold `joint_torques` (n, coordinate
    /// order; rigid joints' entries unused) at rest in configuration `q`:
    /// [`sea_dyn::ElasticParameters::preloaded_motor_angle`] per elastic joint. With the static
    /// torques (gravity minus what the contacts carry) the robot starts in equilibrium.
    pub fn preloaded_motor_angles(&self, q: &[f64], joint_torques: &[f64]) -> Result<Vec<f64>> {
        self.model.check_configuration(q)?;
        check_vector("joint_torques", joint_torques, self.model.n_joints())?;
        let s = self.layout().s(q); // `q` is the leading block of a state
        let elastic = self
            .actuation
            .elastic_joints
            .iter()
            .zip(&self.actuation.elastic);
        Ok(elastic
            .map(|(&j, p)| p.preloaded_motor_angle(s[j], joint_torques[j]))
            .collect())
    }

    /// A state from its parts; springs at rest
    /// ([`sea_dyn::ElasticParameters::preloaded_motor_angle`] with zero torque) and zero motor
    /// velocities when `theta`/`thetadot` are `None`.
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
        layout.q_mut(&mut x).copy_from_slice(q);
        layout.nu_mut(&mut x).copy_from_slice(nu);
        match theta {
            Some(theta) => {
                check_vector("theta", theta, layout.ne)?;
                layout.theta_mut(&mut x).copy_from_slice(theta);
            }
            None => {
                let s = layout.s(q); // `q` is the leading block of a state
                let elastic = self
                    .actuation
                    .elastic_joints
                    .iter()
                    .zip(&self.actuation.elastic);
                for (theta, (&j, p)) in layout.theta_mut(&mut x).iter_mut().zip(elastic) {
                    *theta = p.preloaded_motor_angle(s[j], 0.0);
                }
            }
        }
        if let Some(thetadot) = thetadot {
            check_vector("thetadot", thetadot, layout.ne)?;
            layout.thetadot_mut(&mut x).copy_from_slice(thetadot);
        }
        Ok(x)
    }
}
