//! Fall detection: the plant's rigid contacts are bilateral (they hold the feet whatever the
//! wrench), so at every sample the loop checks each foot's simulated contact wrench, in its
//! sole frame, against what a unilateral contact with friction can transmit: a positive
//! normal force, the friction cone of `controller.contact.friction` and the centre of pressure
//! inside the sole rectangle (`controller.contact.foot_x`, `foot_y`). The first violation
//! ends the run as "fell" ([`super::RunEnd::Fell`]). Under unilateral contacts the check of
//! the delivered wrenches is a diagnostic: each foot's [`WrenchCheck`] at every sample, and
//! a [`ContactCheckEvent`] when a foot starts or stops violating a constraint
//! ([`ViolationEpisodes`]).

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
    WrenchCheck::of(force, moment, surface).violated
}

/// One foot's wrench checked against a unilateral contact with friction on its sole
/// rectangle: every quantity the check reads with its bounds, and the first constraint
/// violated (what [`violated_constraint`] returns). The friction ratio and the centre of
/// pressure need a positive normal force: without one they are NaN and not checked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WrenchCheck {
    /// The normal force `f_z` in the sole frame [N]; the bound is `> 0`.
    pub normal_force: f64,
    /// `|f_t| / f_z` (NaN when `f_z` is not positive).
    pub friction_ratio: f64,
    /// Its bound `mu` (`controller.contact.friction`).
    pub friction: f64,
    /// The centre of pressure `(x, y)` in the sole frame [m] (NaN when `f_z` is not
    /// positive).
    pub center_of_pressure: [f64; 2],
    /// The sole rectangle's `[low, high]` along x [m] (`foot_x`).
    pub foot_x: [f64; 2],
    /// The sole rectangle's `[low, high]` along y [m] (`foot_y`).
    pub foot_y: [f64; 2],
    /// The first constraint violated, in the order normal force, friction, centre of
    /// pressure x, y (each with [`CONTACT_CHECK_TOLERANCE`]); `None` when none is.
    pub violated: Option<ContactConstraint>,
}

impl WrenchCheck {
    /// The check of `force` and `moment` (about the sole origin, sole axes) against a
    /// unilateral contact on `surface`.
    pub fn of(
        force: &Vector3<f64>,
        moment: &Vector3<f64>,
        surface: &sea_dyn::ContactSurface,
    ) -> WrenchCheck {
        let fz = force.z;
        let loaded = fz > 0.0;
        let (friction_ratio, center_of_pressure) = if loaded {
            (force.xy().norm() / fz, [-moment.y / fz, moment.x / fz])
        } else {
            (f64::NAN, [f64::NAN; 2])
        };
        let mut check = WrenchCheck {
            normal_force: fz,
            friction_ratio,
            friction: surface.friction,
            center_of_pressure,
            foot_x: surface.foot_x,
            foot_y: surface.foot_y,
            violated: None,
        };
        check.violated = check.first_violation();
        check
    }

    /// Whether the normal force is not positive (or NaN).
    pub fn normal_force_violated(&self) -> bool {
        self.normal_force.is_nan() || self.normal_force <= 0.0
    }

    /// Whether a loaded foot's tangential force is outside the friction cone (a NaN ratio
    /// counts as outside).
    pub fn friction_violated(&self) -> bool {
        !self.normal_force_violated()
            && (self.friction_ratio > self.friction + CONTACT_CHECK_TOLERANCE
                || self.friction_ratio.is_nan())
    }

    /// The edge of the sole a loaded foot's centre of pressure is beyond along `axis` (0: x,
    /// 1: y), `None` when inside (a NaN coordinate counts as beyond the high edge).
    pub fn center_of_pressure_beyond(&self, axis: usize) -> Option<f64> {
        if self.normal_force_violated() {
            return None;
        }
        let value = self.center_of_pressure[axis];
        let [low, high] = if axis == 0 { self.foot_x } else { self.foot_y };
        if value < low - CONTACT_CHECK_TOLERANCE {
            Some(low)
        } else if value > high + CONTACT_CHECK_TOLERANCE || value.is_nan() {
            Some(high)
        } else {
            None
        }
    }

    /// The first constraint violated (see [`WrenchCheck::violated`]).
    fn first_violation(&self) -> Option<ContactConstraint> {
        if self.normal_force_violated() {
            return Some(ContactConstraint::NormalForce {
                value: self.normal_force,
                bound: 0.0,
            });
        }
        if self.friction_violated() {
            return Some(ContactConstraint::Friction {
                value: self.friction_ratio,
                bound: self.friction,
            });
        }
        [(0, "x"), (1, "y")].into_iter().find_map(|(k, axis)| {
            self.center_of_pressure_beyond(k)
                .map(|bound| ContactConstraint::CenterOfPressure {
                    axis,
                    value: self.center_of_pressure[k],
                    bound,
                })
        })
    }
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
        (0..plant.contacts.len()).find_map(|c| {
            let (force, moment) = self.sole_wrench(plant, outputs, c);
            violated_constraint(&force, &moment, &plant.contact_limits).map(|constraint| {
                WrenchFall {
                    foot: plant.contacts[c].name.clone(),
                    constraint,
                }
            })
        })
    }

    /// Every foot's check at state `x` with the evaluation `outputs`, into `checks` (cleared
    /// first; in the order of `plant.contacts`); allocation-free once `checks` holds as
    /// many.
    pub fn check_all(
        &mut self,
        plant: &Plant,
        x: &[f64],
        outputs: &PlantOutputs,
        checks: &mut Vec<WrenchCheck>,
    ) {
        checks.clear();
        if plant.contacts.is_empty() {
            return;
        }
        forward_kinematics(&plant.model, &mut self.data, &x[..plant.model.nq()]);
        for c in 0..plant.contacts.len() {
            let (force, moment) = self.sole_wrench(plant, outputs, c);
            checks.push(WrenchCheck::of(&force, &moment, &plant.contact_limits));
        }
    }

    /// Contact `c`'s force and moment in `outputs`, in its sole frame (the kinematics
    /// computed).
    fn sole_wrench(
        &self,
        plant: &Plant,
        outputs: &PlantOutputs,
        c: usize,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let w = outputs.contact_wrench.as_slice();
        let frame = plant.contacts[c].frame;
        let world_r_sole = frame_placement(&plant.model, &self.data, frame).rotation;
        let force = world_r_sole.transpose() * Vector3::new(w[6 * c], w[6 * c + 1], w[6 * c + 2]);
        let moment =
            world_r_sole.transpose() * Vector3::new(w[6 * c + 3], w[6 * c + 4], w[6 * c + 5]);
        (force, moment)
    }
}

/// How a foot's verdict changed under unilateral contacts, where the check is a diagnostic
/// and the run goes on ([`ContactCheckEvent`]).
#[derive(Clone, Debug, PartialEq)]
pub enum VerdictChange {
    /// From this sample on the foot's wrench violates `0` (the first constraint in the
    /// check's order; at the sample before it violated none, or this is the first sample).
    Violated(ContactConstraint),
    /// From this sample on the foot's wrench violates none, after `samples` samples that
    /// violated one, from `since_s` on.
    Satisfied {
        /// The first violating sample's time [s].
        since_s: f64,
        /// The violating samples.
        samples: usize,
    },
}

/// A foot whose delivered wrench starts or stops violating a contact constraint, at a sample
/// of a run under unilateral contacts.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactCheckEvent {
    /// The sample's time [s].
    pub time_s: f64,
    /// The contact frame's name (`robot.contacts`).
    pub foot: String,
    /// What changed.
    pub change: VerdictChange,
}

impl std::fmt::Display for ContactCheckEvent {
    /// `contact check: foot l_sole violates it: normal force 0.0000 N not above 0 N` and
    /// `contact check: foot l_sole satisfies it again after 12 samples from t = 1.2 s`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let foot = &self.foot;
        match &self.change {
            VerdictChange::Violated(constraint) => {
                write!(f, "contact check: foot {foot} violates it: {constraint}")
            }
            VerdictChange::Satisfied { since_s, samples } => write!(
                f,
                "contact check: foot {foot} satisfies it again after {samples} samples from \
                 t = {since_s} s"
            ),
        }
    }
}

/// Each foot's open violation, to turn the checks of successive samples into
/// [`ContactCheckEvent`]s.
#[derive(Clone, Debug, Default)]
pub struct ViolationEpisodes {
    /// Per foot: the first violating sample's time and the violating samples so far, while
    /// it violates.
    open: Vec<Option<(f64, usize)>>,
}

impl ViolationEpisodes {
    /// Compares each foot's check at `time_s` with the sample before and pushes the changes
    /// to `events` (`names`: the feet, in the order of `checks`). Allocates only for an
    /// event.
    pub fn update(
        &mut self,
        time_s: f64,
        checks: &[WrenchCheck],
        names: impl Fn(usize) -> String,
        events: &mut Vec<ContactCheckEvent>,
    ) {
        if self.open.len() < checks.len() {
            self.open.resize(checks.len(), None);
        }
        for (c, (check, open)) in checks.iter().zip(&mut self.open).enumerate() {
            let change = match (check.violated, open.as_mut()) {
                (Some(_), Some((_, samples))) => {
                    *samples += 1;
                    None
                }
                (Some(constraint), None) => {
                    *open = Some((time_s, 1));
                    Some(VerdictChange::Violated(constraint))
                }
                (None, Some(&mut (since_s, samples))) => {
                    *open = None;
                    Some(VerdictChange::Satisfied { since_s, samples })
                }
                (None, None) => None,
            };
            if let Some(change) = change {
                events.push(ContactCheckEvent {
                    time_s,
                    foot: names(c),
                    change,
                });
            }
        }
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
    fn the_report_flags_each_constraint_and_names_the_first() {
        let surface = sea_dyn::ContactSurface::default();
        // Friction ratio 1.25 and CoP x = 0.12 m: both flagged, friction named first.
        let report = WrenchCheck::of(
            &Vector3::new(30.0, 40.0, 40.0),
            &Vector3::new(0.0, -4.8, 0.0),
            &surface,
        );
        assert!(!report.normal_force_violated() && report.friction_violated());
        assert!((report.center_of_pressure[0] - 0.12).abs() < 1e-12);
        assert_eq!(report.center_of_pressure_beyond(0), Some(0.1));
        assert_eq!(report.center_of_pressure_beyond(1), None);
        assert_eq!(report.violated.map(|c| c.kind()), Some("friction"));
        // No load: only the normal force is checked, the rest is NaN.
        let lifted = WrenchCheck::of(&Vector3::zeros(), &Vector3::zeros(), &surface);
        assert!(lifted.normal_force_violated() && !lifted.friction_violated());
        assert!(lifted.friction_ratio.is_nan() && lifted.center_of_pressure[1].is_nan());
        assert_eq!(lifted.center_of_pressure_beyond(0), None);
        assert_eq!(lifted.violated.map(|c| c.kind()), Some("normal_force"));
    }

    #[test]
    fn episodes_give_one_event_when_a_foot_starts_and_one_when_it_stops_violating() {
        let surface = sea_dyn::ContactSurface::default();
        let fine = WrenchCheck::of(&Vector3::new(0.0, 0.0, 100.0), &Vector3::zeros(), &surface);
        let lifted = WrenchCheck::of(&Vector3::zeros(), &Vector3::zeros(), &surface);
        let names = |c: usize| ["left", "right"][c].to_string();
        let (mut episodes, mut events) = (ViolationEpisodes::default(), Vec::new());
        let samples = [
            [fine, lifted],
            [lifted, lifted],
            [lifted, fine],
            [fine, fine],
        ];
        for (k, checks) in samples.iter().enumerate() {
            episodes.update(0.01 * k as f64, checks, names, &mut events);
        }
        let summary: Vec<(f64, &str, bool)> = events
            .iter()
            .map(|e| {
                let started = matches!(e.change, VerdictChange::Violated(_));
                (e.time_s, e.foot.as_str(), started)
            })
            .collect();
        assert_eq!(
            summary,
            [
                (0.0, "right", true),
                (0.01, "left", true),
                (0.02, "right", false),
                (0.03, "left", false)
            ]
        );
        assert_eq!(
            events[2].change,
            VerdictChange::Satisfied {
                since_s: 0.0,
                samples: 2
            }
        );
        assert_eq!(
            events[2].to_string(),
            "contact check: foot right satisfies it again after 2 samples from t = 0 s"
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
