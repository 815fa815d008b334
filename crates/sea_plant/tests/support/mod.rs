//! Shared helpers of the plant tests: robots (the shipped URDFs and seeded random trees), SEA
//! parameters, random states, the total energy written from its definition, and fixed-step
//! runs.

#![allow(dead_code)]

#[path = "../../../sea_dyn/tests/common/mod.rs"]
pub mod common;

use nalgebra::{DMatrix, DVector, Vector3};
use sea_dyn::sample::Lcg;
use sea_dyn::{Actuation, Actuator, Data, ElasticParameters, LoadOptions, Model};
use sea_plant::{step, Method, Plant, PlantData};
use std::collections::HashMap;
use std::path::Path;

/// A model shipped in `urdf/` (every movable joint, URDF tree order).
pub fn shipped(file: &str) -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../urdf")
        .join(file);
    Model::from_urdf_file(&path, &LoadOptions::default()).unwrap()
}

/// The model of the seeded random tree `seed` (sea_dyn's test generator).
pub fn random_tree(seed: u64) -> Model {
    common::load(&common::random_robot(seed))
}

/// SEA parameters without a torque limit.
pub fn sea(stiffness: f64, damping: f64, motor_inertia: f64, ratio: f64) -> ElasticParameters {
    ElasticParameters {
        ratio,
        motor_inertia,
        stiffness,
        damping,
        torque_limit: None,
    }
}

/// Every joint elastic with `p`.
pub fn all_elastic(model: &Model, p: ElasticParameters) -> Actuation {
    Actuation::new(model, Actuator::Elastic(p), &HashMap::new()).unwrap()
}

/// Mixed actuation: every third joint (coordinates 0, 3, 6, ...) rigid, the others elastic.
pub fn mixed(model: &Model, p: ElasticParameters) -> Actuation {
    let rigid: HashMap<String, Actuator> = model
        .joint_names
        .iter()
        .step_by(3)
        .map(|name| (name.clone(), Actuator::Rigid))
        .collect();
    Actuation::new(model, Actuator::Elastic(p), &rigid).unwrap()
}

/// A plant without contacts and without gravity.
pub fn weightless(mut model: Model, actuation: Actuation) -> Plant {
    model.gravity = Vector3::zeros();
    Plant::new(model, actuation)
}

/// A state at configuration `q` with joint and base velocities in `[-v, v]`, spring
/// deflections `Gamma theta - s` in `[-deflection, deflection]` and motor velocities (joint side,
/// `Gamma thetadot`) in `[-v, v]`.
pub fn random_state(plant: &Plant, q: &[f64], v: f64, deflection: f64, rng: &mut Lcg) -> Vec<f64> {
    let nu: Vec<f64> = (0..plant.model.nv())
        .map(|_| v * rng.next_signed())
        .collect();
    let actuation = &plant.actuation;
    let theta: Vec<f64> = actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .map(|(&j, p)| (q[7 + j] + deflection * rng.next_signed()) / p.ratio)
        .collect();
    let thetadot: Vec<f64> = actuation
        .elastic
        .iter()
        .map(|p| v * rng.next_signed() / p.ratio)
        .collect();
    plant
        .make_state(q, &nu, Some(&theta), Some(&thetadot))
        .unwrap()
}

/// A random configuration with joints in `[-spread, spread]` and a random base pose.
pub fn random_q(model: &Model, spread: f64, rng: &mut Lcg) -> Vec<f64> {
    let mut q = sea_dyn::sample::random_configuration(model, rng);
    q[7..].iter_mut().for_each(|s| *s *= spread);
    q
}

/// `M(q)` with the plant's joint inertia regularisation on the joint diagonal.
pub fn plant_mass_matrix(plant: &Plant, data: &mut Data, q: &[f64]) -> DMatrix<f64> {
    let mut m = sea_dyn::crba(&plant.model, data, q).clone();
    for i in 6..plant.model.nv() {
        m[(i, i)] += plant.joint_inertia_regularization;
    }
    m
}

/// Parts of the total energy (paper eq:elasticSystem without dissipation).
#[derive(Clone, Copy, Debug)]
pub struct Energy {
    /// Links: `0.5 nu^T M nu`.
    pub links: f64,
    /// Rotors: `sum 0.5 b thetadot^2`.
    pub motors: f64,
    /// Springs: `sum 0.5 K_S (Gamma theta - s)^2`.
    pub springs: f64,
    /// Gravity: `-m g . p_com` (g the model's gravity vector).
    pub gravity: f64,
}

impl Energy {
    /// Total.
    pub fn total(&self) -> f64 {
        self.links + self.motors + self.springs + self.gravity
    }
}

/// The energy of state `x`, from its definition (M by CRBA, the CoM by sea_dyn::com).
pub fn energy(plant: &Plant, data: &mut Data, x: &[f64]) -> Energy {
    let layout = plant.layout();
    let (q, nu) = (layout.q(x), layout.nu(x));
    let (theta, thetadot) = (layout.theta(x), layout.thetadot(x));
    let m = plant_mass_matrix(plant, data, q);
    let nu_vec = DVector::from_column_slice(nu);
    let links = 0.5 * nu_vec.dot(&(&m * &nu_vec));
    let actuation = &plant.actuation;
    let mut motors = 0.0;
    let mut springs = 0.0;
    for (e, (&j, p)) in actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .enumerate()
    {
        motors += 0.5 * p.motor_inertia * thetadot[e] * thetadot[e];
        let deflection = p.ratio * theta[e] - q[7 + j];
        springs += 0.5 * p.stiffness * deflection * deflection;
    }
    let com = sea_dyn::com(&plant.model, data, q);
    let gravity = -plant.model.total_mass() * plant.model.gravity.dot(&com);
    Energy {
        links,
        motors,
        springs,
        gravity,
    }
}

/// Integrates `n` steps of `dt` from `x0` with `u` held, calling `observe(x)` at the start and
/// after every step. Returns the final state.
pub fn run(
    plant: &Plant,
    x0: &[f64],
    u: &[f64],
    dt: f64,
    n: usize,
    method: Method,
    observe: impl FnMut(&[f64]),
) -> Vec<f64> {
    run_sharing_w(plant, x0, u, (dt, n), method, 1, observe)
}

/// [`run`] with up to `w_refresh_steps` consecutive steps sharing the implicit step's `W`.
pub fn run_sharing_w(
    plant: &Plant,
    x0: &[f64],
    u: &[f64],
    (dt, n): (f64, usize),
    method: Method,
    w_refresh_steps: usize,
    mut observe: impl FnMut(&[f64]),
) -> Vec<f64> {
    let mut pd = PlantData::new(plant);
    pd.integrator.set_w_refresh_steps(w_refresh_steps);
    let mut x = x0.to_vec();
    let mut next = x0.to_vec();
    observe(&x);
    for k in 0..n {
        step(plant, &mut pd, &x, u, dt, method, &mut next)
            .unwrap_or_else(|e| panic!("step {k} of {n} (dt {dt:e}, {method:?}) failed: {e}"));
        std::mem::swap(&mut x, &mut next);
        observe(&x);
    }
    x
}

/// Largest component difference of two states, the quaternions compared up to sign.
pub fn state_distance(a: &[f64], b: &[f64]) -> f64 {
    let sign = if (3..7).map(|i| a[i] * b[i]).sum::<f64>() < 0.0 {
        -1.0
    } else {
        1.0
    };
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(i, (x, y))| {
            let y = if (3..7).contains(&i) { sign * y } else { *y };
            (x - y).abs()
        })
        .fold(0.0, f64::max)
}

/// Observed orders `log2(e(h) / e(h/2))` of a sequence of errors at halving steps.
pub fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// `[1.234e-5, ...]` with `digits` significant decimals.
pub fn sci(values: &[f64], digits: usize) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:.digits$e}")).collect();
    format!("[{}]", items.join(", "))
}

/// `[1.23, ...]` with `digits` decimals.
pub fn fixed(values: &[f64], digits: usize) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:.digits$}")).collect();
    format!("[{}]", items.join(", "))
}
