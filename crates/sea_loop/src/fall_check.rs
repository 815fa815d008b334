//! Falls as physics, under unilateral contacts: the run ends as "fell" when the base drops
//! below a fraction of its initial height above the ground, when the base tilts past a bound
//! from its initial orientation, or when a link other than the feet reaches the ground (its
//! body origin, the joint centre, below the plane). Under bilateral contacts the feet cannot
//! leave the ground, and [`super::contact_check`] stands in for these.

use crate::contact_check::WrenchFall;
use nalgebra::{Matrix3, Vector3};
use sea_dyn::data::Data;
use sea_dyn::kinematics::forward_kinematics;
use sea_plant::{Ground, Plant};

/// When a run under unilateral contacts has fallen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FallBounds {
    /// The base has fallen below this fraction of its initial height above the ground.
    pub base_height_fraction: f64,
    /// The base has tilted more than this from its initial orientation [rad].
    pub tilt_rad: f64,
}

impl Default for FallBounds {
    /// 0.6 of the initial height (a squat keeps more), 60 degrees of tilt.
    fn default() -> Self {
        Self {
            base_height_fraction: 0.6,
            tilt_rad: std::f64::consts::FRAC_PI_3,
        }
    }
}

/// A fall under unilateral contacts.
#[derive(Clone, Debug, PartialEq)]
pub enum PhysicalFall {
    /// The base's height above the ground [m] fell below the bound [m].
    BaseHeight {
        /// Height [m].
        height: f64,
        /// Bound [m].
        bound: f64,
    },
    /// The base tilted by `angle` [rad] past `bound` [rad].
    Tilt {
        /// Tilt [rad].
        angle: f64,
        /// Bound [rad].
        bound: f64,
    },
    /// A link's origin reached the ground (`height` [m] above it, negative: below).
    LinkOnGround {
        /// The link (its body's name).
        link: String,
        /// Its origin's height above the ground [m].
        height: f64,
    },
}

impl PhysicalFall {
    /// `"base_height"`, `"tilt"` or `"link_on_ground"`.
    pub fn kind(&self) -> &'static str {
        match self {
            PhysicalFall::BaseHeight { .. } => "base_height",
            PhysicalFall::Tilt { .. } => "tilt",
            PhysicalFall::LinkOnGround { .. } => "link_on_ground",
        }
    }

    /// The crossing value (m, rad or m).
    pub fn value(&self) -> f64 {
        match *self {
            PhysicalFall::BaseHeight { height, .. } => height,
            PhysicalFall::Tilt { angle, .. } => angle,
            PhysicalFall::LinkOnGround { height, .. } => height,
        }
    }

    /// The bound it crossed.
    pub fn bound(&self) -> f64 {
        match *self {
            PhysicalFall::BaseHeight { bound, .. } | PhysicalFall::Tilt { bound, .. } => bound,
            PhysicalFall::LinkOnGround { .. } => 0.0,
        }
    }
}

impl std::fmt::Display for PhysicalFall {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PhysicalFall::BaseHeight { height, bound } => {
                write!(f, "base {height:.4} m above the ground, below {bound:.4} m")
            }
            PhysicalFall::Tilt { angle, bound } => {
                write!(f, "base tilted {angle:.3} rad, past {bound:.3} rad")
            }
            PhysicalFall::LinkOnGround { link, height } => {
                write!(f, "link {link} on the ground ({height:.4} m)")
            }
        }
    }
}

/// How a run fell: a foot's wrench outside a unilateral contact (bilateral contacts, the
/// proxy) or the robot on the ground (unilateral contacts, physics).
#[derive(Clone, Debug, PartialEq)]
pub enum Fall {
    /// Bilateral contacts: a foot's simulated wrench violated a contact constraint.
    Wrench(WrenchFall),
    /// Unilateral contacts: the base dropped or tilted, or a link reached the ground.
    Physical(PhysicalFall),
}

impl Fall {
    /// The constraint's kind (`"normal_force"`, `"friction"`, `"center_of_pressure"`) or the
    /// physical fall's (`"base_height"`, `"tilt"`, `"link_on_ground"`).
    pub fn kind(&self) -> &'static str {
        match self {
            Fall::Wrench(fall) => fall.constraint.kind(),
            Fall::Physical(fall) => fall.kind(),
        }
    }

    /// The crossing value.
    pub fn value(&self) -> f64 {
        match self {
            Fall::Wrench(fall) => fall.constraint.value(),
            Fall::Physical(fall) => fall.value(),
        }
    }

    /// The bound it crossed.
    pub fn bound(&self) -> f64 {
        match self {
            Fall::Wrench(fall) => fall.constraint.bound(),
            Fall::Physical(fall) => fall.bound(),
        }
    }

    /// The foot whose wrench fell (wrench falls), else empty.
    pub fn foot(&self) -> &str {
        match self {
            Fall::Wrench(fall) => &fall.foot,
            Fall::Physical(_) => "",
        }
    }

    /// The link on the ground (`link_on_ground`), else empty.
    pub fn link(&self) -> &str {
        match self {
            Fall::Physical(PhysicalFall::LinkOnGround { link, .. }) => link,
            _ => "",
        }
    }
}

impl std::fmt::Display for Fall {
    /// `foot l_sole: centre of pressure x = ...` or the physical fall.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Fall::Wrench(fall) => fall.fmt(f),
            Fall::Physical(fall) => fall.fmt(f),
        }
    }
}

/// The check: the ground, the initial base height and orientation, the links to watch, and
/// its own kinematics buffers.
#[derive(Clone, Debug)]
pub struct FallCheck {
    ground: Ground,
    bounds: FallBounds,
    initial_height: f64,
    world_r_base_initial: Matrix3<f64>,
    /// Bodies that are not a foot (index, name).
    watched: Vec<(usize, String)>,
    data: Data,
}

impl FallCheck {
    /// The check of `plant` started at `x0`; `None` unless its contacts are unilateral.
    pub fn new(plant: &Plant, x0: &[f64], bounds: FallBounds) -> Option<FallCheck> {
        let ground = plant.unilateral()?.ground;
        let model = &plant.model;
        let mut data = Data::new(model);
        forward_kinematics(model, &mut data, &x0[..model.nq()]);
        let feet: Vec<usize> = plant
            .contacts
            .iter()
            .map(|c| model.frames[c.frame].body)
            .collect();
        let watched = (1..model.n_bodies())
            .filter(|body| !feet.contains(body))
            .map(|body| {
                let link = model.frames.iter().find(|frame| frame.body == body);
                let name =
                    link.map_or_else(|| model.joints[body - 1].name.clone(), |f| f.name.clone());
                (body, name)
            })
            .collect();
        Some(FallCheck {
            ground,
            bounds,
            initial_height: ground.height_of(&data.p_base_world),
            world_r_base_initial: data.world_r_body[0],
            watched,
            data,
        })
    }

    /// The fall at state `x`, if any (base height, then tilt, then links).
    pub fn fall(&mut self, plant: &Plant, x: &[f64]) -> Option<PhysicalFall> {
        let model = &plant.model;
        forward_kinematics(model, &mut self.data, &x[..model.nq()]);
        let height = self.ground.height_of(&self.data.p_base_world);
        let bound = self.bounds.base_height_fraction * self.initial_height;
        if height < bound {
            return Some(PhysicalFall::BaseHeight { height, bound });
        }
        let up = self.world_r_base_initial.transpose() * Vector3::z();
        let tilted = self.data.world_r_body[0] * up;
        let angle = tilted.dot(&Vector3::z()).clamp(-1.0, 1.0).acos();
        if angle > self.bounds.tilt_rad {
            let bound = self.bounds.tilt_rad;
            return Some(PhysicalFall::Tilt { angle, bound });
        }
        self.watched.iter().find_map(|(body, name)| {
            let origin = self.data.p_base_world + self.data.p_body_rel[*body];
            let height = self.ground.height_of(&origin);
            (height < 0.0).then(|| PhysicalFall::LinkOnGround {
                link: name.clone(),
                height,
            })
        })
    }
}
