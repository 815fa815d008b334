//! `plant.contact_model` and the `[ground]` table: how the feet touch the world, and the
//! unilateral contacts built from them ([`sea_plant::unilateral`]).

use crate::bounded::{Finite, NonNegative, Positive};
use crate::Scenario;
use nalgebra::Vector3;
use sea_dyn::data::Data;
use sea_dyn::kinematics::{forward_kinematics, frame_placement};
use sea_loop::{Error, Result};
use sea_plant::{CompliantContact, Ground, JointStops, Plant, UnilateralContacts};
use serde::{Deserialize, Serialize};

sea_dyn::number_bound!(
    /// [`GroundConfig::incline_rad`]: an angle in `[0, pi/2)` rad.
    Incline,
    "must be an angle in [0, pi/2) [rad]",
    |v| (0.0..std::f64::consts::FRAC_PI_2).contains(&v),
    { "type": "number", "minimum": 0.0, "exclusiveMaximum": std::f64::consts::FRAC_PI_2 }
);

/// `plant.contact_model`: how the contacts of `robot.contacts` touch the world.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum ContactModelKind {
    /// Rigid bilateral contacts (the paper's setting): the feet are held at their initial
    /// pose and the run ends as "fell" when a foot's wrench leaves what a unilateral contact
    /// with friction could transmit.
    #[default]
    Bilateral,
    /// Each sole touches the `[ground]` at points (its rectangle's corners unless
    /// `ground.points`) with a unilateral normal force, Coulomb friction and inelastic impacts:
    /// lift-off, tipping and slip are physics, and a fall is the base dropping or tilting, or a
    /// link touching the ground.
    Unilateral,
}

/// `[ground]`: the plane the soles touch under `plant.contact_model = "unilateral"`.
#[derive(Clone, Debug, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct GroundConfig {
    /// Coulomb friction coefficient between the soles and the ground (default 1, MuJoCo's
    /// default and the original study's controller value).
    #[serde(deserialize_with = "NonNegative::read")]
    #[schemars(with = "NonNegative")]
    pub friction: f64,
    /// Incline of the plane [rad], in [0, pi/2) (default 0: flat).
    #[serde(deserialize_with = "Incline::read")]
    #[schemars(with = "Incline")]
    pub incline_rad: f64,
    /// Horizontal direction the inclined plane rises along [rad] (0: +x, pi/2: +y).
    #[serde(deserialize_with = "Finite::read")]
    #[schemars(with = "Finite")]
    pub incline_heading_rad: f64,
    /// Height of the plane at the world origin [m] (default: where the soles' points rest at
    /// the static penetration in the initial posture).
    #[serde(deserialize_with = "Finite::read_option")]
    #[schemars(with = "Option<Finite>")]
    pub height_m: Option<f64>,
    /// How far the robot sinks into the ground standing still [m], which sets the default
    /// stiffness (default 0.5 mm).
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub static_penetration_m: f64,
    /// Normal stiffness per contact point [N/m] (default: the robot's weight over its points
    /// at the static penetration).
    #[serde(deserialize_with = "Positive::read_option")]
    #[schemars(with = "Option<Positive>")]
    pub stiffness_n_per_m: Option<f64>,
    /// Hunt-Crossley dissipation [s/m]: the normal damping is stiffness x dissipation x
    /// penetration (default: the robot's vertical mode on the ground critically damped at
    /// rest).
    #[serde(deserialize_with = "NonNegative::read_option")]
    #[schemars(with = "Option<NonNegative>")]
    pub dissipation_s_per_m: Option<f64>,
    /// Stiction velocity of the regularised friction [m/s] (default 1e-4): a sticking foot
    /// creeps at about this times its friction ratio.
    #[serde(deserialize_with = "Positive::read")]
    #[schemars(with = "Positive")]
    pub stiction_velocity_m_s: f64,
    /// Contact points `[x, y]` in every sole frame [m], inside the sole rectangle
    /// (`controller.contact.foot_x`, `foot_y`) (default: the rectangle's four corners).
    pub points: Option<Vec<[f64; 2]>>,
}

impl Default for GroundConfig {
    fn default() -> Self {
        Self {
            friction: 1.0,
            incline_rad: 0.0,
            incline_heading_rad: 0.0,
            height_m: None,
            static_penetration_m: 5e-4,
            stiffness_n_per_m: None,
            dissipation_s_per_m: None,
            stiction_velocity_m_s: CompliantContact::DEFAULT_STICTION_VELOCITY,
            points: None,
        }
    }
}

/// Tolerance on a contact point outside the sole rectangle [m] (rounding of the written
/// numbers).
const POINT_TOLERANCE: f64 = 1e-9;
/// A contact point may start at most this deep in the ground [m]: deeper, the ground is
/// taken as misplaced.
const DEEPEST_START: f64 = 0.01;

/// The contact points of every sole (`ground.points` or the rectangle's corners), checked
/// against the sole rectangle.
pub fn contact_points(scenario: &Scenario) -> Result<Vec<Vector3<f64>>> {
    let surface = scenario.controller.contact.surface;
    let Some(points) = &scenario.ground.points else {
        return Ok(UnilateralContacts::rectangle_corners(
            surface.foot_x,
            surface.foot_y,
        ));
    };
    if points.is_empty() {
        return Err(Error::config("ground.points", "at least one point [x, y]"));
    }
    let inside = |v: f64, [low, high]: [f64; 2]| {
        v.is_finite() && v >= low - POINT_TOLERANCE && v <= high + POINT_TOLERANCE
    };
    for (i, &[x, y]) in points.iter().enumerate() {
        if !(inside(x, surface.foot_x) && inside(y, surface.foot_y)) {
            return Err(Error::config(
                format!("ground.points[{i}]"),
                format!(
                    "[{x}, {y}] is outside the sole rectangle x in {:?}, y in {:?} \
                     (controller.contact.foot_x, foot_y)",
                    surface.foot_x, surface.foot_y
                ),
            ));
        }
    }
    Ok(points
        .iter()
        .map(|&[x, y]| Vector3::new(x, y, 0.0))
        .collect())
}

/// Makes `plant`'s contacts (already set at `q`) unilateral on the `[ground]` and adds the
/// joint stops `plant.joint_stops` asks for.
pub fn make_unilateral(plant: &mut Plant, scenario: &Scenario, q: &[f64]) -> Result<()> {
    let config = &scenario.ground;
    let points = contact_points(scenario)?;
    let n_points = points.len() * plant.contacts.len();
    let gravity = plant.model.gravity.norm();
    let weight = plant.model.total_mass() * gravity;
    let sized =
        CompliantContact::for_weight(weight, n_points, config.static_penetration_m, gravity);
    let law = CompliantContact {
        stiffness: config.stiffness_n_per_m.unwrap_or(sized.stiffness),
        dissipation: config.dissipation_s_per_m.unwrap_or(sized.dissipation),
        stiction_velocity: config.stiction_velocity_m_s,
    };
    let penetration = weight / (n_points as f64 * law.stiffness);
    let world_points = world_points(plant, &points, q);
    let ground = ground_plane(config, &world_points, penetration)?;
    check_ground_below_robot(&ground, &world_points, q)?;
    let per_contact = vec![points; plant.contacts.len()];
    plant.set_unilateral_contacts(ground, law, per_contact)?;
    Ok(())
}

/// The joint stops of `plant.joint_stops` (default: on under unilateral contacts).
pub fn joint_stops(scenario: &Scenario) -> Option<JointStops> {
    let config = &scenario.plant;
    let unilateral = config.contact_model == ContactModelKind::Unilateral;
    config
        .joint_stops
        .unwrap_or(unilateral)
        .then_some(JointStops {
            stiffness: config.joint_stop_stiffness,
            dissipation: config.joint_stop_dissipation,
        })
}

/// Every contact point in the world at `q` (contacts in order).
fn world_points(plant: &Plant, points: &[Vector3<f64>], q: &[f64]) -> Vec<Vector3<f64>> {
    let mut data = Data::new(&plant.model);
    forward_kinematics(&plant.model, &mut data, q);
    let mut world = Vec::new();
    for contact in &plant.contacts {
        let pose = frame_placement(&plant.model, &data, contact.frame);
        world.extend(points.iter().map(|r| pose.translation + pose.rotation * r));
    }
    world
}

/// The plane of `[ground]`: at `ground.height_m`, or through the points' centroid sunk by
/// the static `penetration` along the normal.
fn ground_plane(
    config: &GroundConfig,
    world_points: &[Vector3<f64>],
    penetration: f64,
) -> Result<Ground> {
    let tilted = |height| {
        Ground::inclined(
            height,
            config.incline_rad,
            config.incline_heading_rad,
            config.friction,
        )
        .map_err(Error::from)
    };
    if let Some(height) = config.height_m {
        return tilted(height);
    }
    let unit = tilted(0.0)?;
    let centroid = world_points.iter().sum::<Vector3<f64>>() / world_points.len() as f64;
    // The plane through (0, 0, h): n . (c - (0, 0, h)) = -penetration.
    let height = (unit.normal.dot(&centroid) + penetration) / unit.normal.z;
    tilted(height)
}

/// Refuses a ground above the robot's base or one the soles start deep inside.
fn check_ground_below_robot(
    ground: &Ground,
    world_points: &[Vector3<f64>],
    q: &[f64],
) -> Result<()> {
    let base = Vector3::new(q[0], q[1], q[2]);
    if ground.height_of(&base) <= 0.0 {
        return Err(Error::config(
            "ground.height_m",
            format!(
                "the ground is above the robot's base ({:.4} m below the plane)",
                -ground.height_of(&base)
            ),
        ));
    }
    let deepest = world_points
        .iter()
        .map(|p| -ground.height_of(p))
        .fold(f64::NEG_INFINITY, f64::max);
    if deepest > DEEPEST_START {
        return Err(Error::config(
            "ground.height_m",
            format!(
                "the soles would start {deepest:.4} m inside the ground (at most {DEEPEST_START} m)"
            ),
        ));
    }
    Ok(())
}
