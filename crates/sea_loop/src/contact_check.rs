//! Fall detection: the plant's rigid contacts are bilateral (they hold the feet whatever the
//! wrench), so at every sample the loop checks each foot's simulated contact wrench, in its
//! sole frame, against what a unilateral contact with friction can transmit: a positive
//! normal force, the friction cone of `controller.contact.friction` and the centre of pressure
//! inside the sole rectangle (`controller.contact.foot_x`, `foot_y`). The first violation
//! ends the run as "fell" ([`super::RunEnd::Fell`]).

use nalgebra::Vector3;
use sea_dyn::data::Data;
use sea_dyn::kinematics::{forward_kinematics, frame_placement};
use sea_plant::{Plant, PlantOutputs};

/// Tolerance of the checks, relative to the normal force: a wrench counts as outside the
/// friction cone when `|f_t| > (mu + tol) f_z`, and its centre of pressure as outside the sole
/// when it lies more than `tol` [m] per newton-normalised unit, i.e. `tol` [m], beyond an
/// edge. The controller's QP puts the wrench on the boundary when a constraint is active
/// (the CoP on an edge, the force on the cone), and the plant's wrench at the same state
/// differs from the QP's by the rounding of the solves (relative 1e-12 to 1e-9); 1e-6 keeps
/// that rounding from reading as a fall, far below any physical margin (1e-6 m of CoP, a
/// friction ratio 1e-6 over `mu`).
pub const CONTACT_CHECK_TOLERANCE: f64 = 1e-6;

/// The contact constraint a foot's wrench violated, with its value and bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ContactConstraint {
    /// The normal force `f_z` in the sole frame is not positive (the foot would lift off).
    NormalForce {
        /// `f_z` [N].
        value: f64,
        /// The bound, 0 [N].
        bound: f64,
    },
    /// The tangential force is outside the friction cone: `|f_t| / f_z > mu`.
    Friction {
        /// `|f_t| / f_z`.
        value: f64,
        /// `mu` (`controller.contact.friction`).
        bound: f64,
    },
    /// The centre of pressure is outside the sole rectangle along `axis` of the sole frame.
    CenterOfPressure {
        /// "x" or "y", the sole axis.
        axis: &'static str,
        /// The CoP coordinate along `axis` [m].
        value: f64,
        /// The edge it crossed (`foot_x` or `foot_y`'s entry) [m].
        bound: f64,
    },
}

impl ContactConstraint {
    /// A stable machine-readable name: `"normal_force"`, `"friction"` or
    /// `"center_of_pressure"`.
    pub fn kind(&self) -> &'static str {
        match self {
            ContactConstraint::NormalForce { .. } => "normal_force",
            ContactConstraint::Friction { .. } => "friction",
            ContactConstraint::CenterOfPressure { .. } => "center_of_pressure",
        }
    }

    /// The violating value.
    pub fn value(&self) -> f64 {
        match *self {
            ContactConstraint::NormalForce { value, .. }
            | ContactConstraint::Friction { value, .. }
            | ContactConstraint::CenterOfPressure { value, .. } => value,
        }
    }

    /// The bound it crossed.
    pub fn bound(&self) -> f64 {
        match *self {
            ContactConstraint::NormalForce { bound, .. }
            | ContactConstraint::Friction { bound, .. }
            | ContactConstraint::CenterOfPressure { bound, .. } => bound,
        }
    }
}

impl std::fmt::Display for ContactConstraint {
    /// `normal force -3.2 N not above 0 N`, `friction ratio 1.2 over mu = 1`, `centre of
    /// pressure x = 0.1032 m beyond the sole edge 0.1 m`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ContactConstraint::NormalForce { value, bound } => {
                write!(f, "normal force {value:.4} N not above {bound} N")
            }
            ContactConstraint::Friction { value, bound } => {
                write!(f, "friction ratio {value:.4} over mu = {bound}")
            }
            ContactConstraint::CenterOfPressure { axis, value, bound } => write!(
                f,
                "centre of pressure {axis} = {value:.4} m beyond the sole edge {bound} m"
            ),
        }
    }
}

/// A fall under bilateral contacts: which foot (its contact frame) and which constraint its
/// simulated wrench violated.
#[derive(Clone, Debug, PartialEq)]
pub struct WrenchFall {
    /// The contact frame's name (`robot.contacts`).
    pub foot: String,
    /// The violated constraint.
    pub constraint: ContactConstraint,
}

impl std::fmt::Display for WrenchFall {
    /// `foot l_sole: centre of pressure x = ...`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "foot {}: {}", self.foot, self.constraint)
    }
}

/// The first constraint `force` and `moment` (about the sole origin, sole axes) violate, in
/// the order normal force, friction, centre of pressure; `None` when the wrench is one a
/// unilateral contact with friction on the sole rectangle can transmit.
pub fn violated_constraint(
    force: &Vector3<f64>,
    moment: &Vector3<f64>,
    surface: &sea_dyn::ContactSurface,
) -> Option<ContactConstraint> {
    let fz = force.z;
    if fz.is_nan() || fz <= 0.0 {
        return Some(ContactConstraint::NormalForce {
            value: fz,
            bound: 0.0,
        });
    }
    let ratio = force.xy().norm() / fz;
    if ratio > surface.friction + CONTACT_CHECK_TOLERANCE || ratio.is_nan() {
        return Some(ContactConstraint::Friction {
            value: ratio,
            bound: surface.friction,
        });
    }
    let cop = [
        ("x", -moment.y / fz, surface.foot_x),
        ("y", moment.x / fz, surface.foot_y),
    ];
    cop.into_iter().find_map(|(axis, value, [low, high])| {
        let outside = |bound: f64| Some(ContactConstraint::CenterOfPressure { axis, value, bound });
        if value < low - CONTACT_CHECK_TOLERANCE {
            outside(low)
        } else if value > high + CONTACT_CHECK_TOLERANCE || value.is_nan() {
            outside(high)
        } else {
            None
        }
    })
}

/// The check's buffers: kinematics for the sole frames' orientations (allocated once).
#[derive(Clone, Debug)]
pub struct ContactCheck {
    data: Data,
}

impl ContactCheck {
    /// Buffers for `plant`.
    pub fn new(plant: &Plant) -> ContactCheck {
        ContactCheck {
            data: Data::new(&plant.model),
        }
    }

    /// The first foot of `plant` whose wrench in `outputs` (the evaluation at state `x`)
    /// violates a contact constraint, in the order of `plant.contacts`; allocation-free
    /// unless a foot falls.
    pub fn fall(&mut self, plant: &Plant, x: &[f64], outputs: &PlantOutputs) -> Option<WrenchFall> {
        if plant.contacts.is_empty() {
            return None;
        }
        forward_kinematics(&plant.model, &mut self.data, &x[..plant.model.nq()]);
        let w = outputs.contact_wrench.as_slice();
        plant.contacts.iter().enumerate().find_map(|(c, contact)| {
            let world_r_sole = frame_placement(&plant.model, &self.data, contact.frame).rotation;
            let force =
                world_r_sole.transpose() * Vector3::new(w[6 * c], w[6 * c + 1], w[6 * c + 2]);
            let moment =
                world_r_sole.transpose() * Vector3::new(w[6 * c + 3], w[6 * c + 4], w[6 * c + 5]);
            violated_constraint(&force, &moment, &plant.contact_limits).map(|constraint| {
                WrenchFall {
                    foot: contact.name.clone(),
                    constraint,
                }
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(force: [f64; 3], moment: [f64; 3]) -> Option<ContactConstraint> {
        let surface = sea_dyn::ContactSurface::default();
        violated_constraint(&Vector3::from(force), &Vector3::from(moment), &surface)
    }

    #[test]
    fn a_wrench_inside_every_constraint_is_no_fall() {
        // 100 N down, 50 N tangential (mu = 1), CoP (0.05, 0.01) inside [-0.05, 0.1] x
        // [-0.025, 0.025]: moment = p x f with f = (0, 0, 100) gives (1, -5, 0).
        assert_eq!(check([50.0, 0.0, 100.0], [1.0, -5.0, 0.0]), None);
    }

    #[test]
    fn each_constraint_is_named_with_its_value_and_bound() {
        assert_eq!(
            check([0.0, 0.0, -1.0], [0.0; 3]),
            Some(ContactConstraint::NormalForce {
                value: -1.0,
                bound: 0.0
            })
        );
        assert_eq!(
            check([30.0, 40.0, 40.0], [0.0; 3]),
            Some(ContactConstraint::Friction {
                value: 1.25,
                bound: 1.0
            })
        );
        // CoP x = 0.12 m (moment y = -0.12 * 100).
        let cop = check([0.0, 0.0, 100.0], [0.0, -12.0, 0.0]).unwrap();
        assert_eq!(cop.kind(), "center_of_pressure");
        assert!((cop.value() - 0.12).abs() < 1e-12 && cop.bound() == 0.1);
        // CoP y = -0.03 m (moment x = -0.03 * 100).
        let cop = check([0.0, 0.0, 100.0], [-3.0, 0.0, 0.0]).unwrap();
        assert!((cop.value() + 0.03).abs() < 1e-12 && cop.bound() == -0.025);
        assert_eq!(
            cop.to_string(),
            "centre of pressure y = -0.0300 m beyond the sole edge -0.025 m"
        );
    }

    #[test]
    fn the_tolerance_lets_rounding_on_an_edge_pass_and_no_more() {
        // CoP exactly on the front edge plus rounding, then 1e-5 m beyond it.
        assert_eq!(
            check([0.0, 0.0, 100.0], [0.0, -10.0 * (1.0 + 1e-12), 0.0]),
            None
        );
        assert!(check([0.0, 0.0, 100.0], [0.0, -10.001, 0.0]).is_some());
    }
}
