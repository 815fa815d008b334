//! Conservation laws of the free-floating SEA robot (no contacts), checked against quantities
//! written from their definitions, not against the plant's own outputs.
//!
//! - Energy: without damping (`K_D = 0`) and with zero motor and rigid-joint inputs, the
//!   spring-damper torque `tau` does work `sdot . tau` on the links and `-Gamma thetadot tau` on
//!   the rotors (paper eq:alpha, eq:motors), so `0.5 nu^T M nu + sum 0.5 b thetadot^2 +
//!   sum 0.5 K_S (Gamma theta - s)^2 - m g . p_com` is constant. An integrator of order `p`
//!   drifts by `O(dt^p)` over a fixed time: each halving of `dt` divides the drift by about
//!   `2^p` (RK4: 16, ROS2: 4).
//! - Momentum: the plant models the motors as in eq:motors, `I_m thetaddot = tau_m - Gamma tau`,
//!   a scalar equation per rotor: the rotors' own angular momentum and the reaction of `tau_m`
//!   on the stator are not part of the multibody dynamics, whose only actuation is the internal
//!   joint torque `B tau`. So without gravity and contacts the links' centroidal momentum
//!   `H = A_G(q) nu` is conserved, whatever the motor torques; the rotors' momentum
//!   `sum b thetadot` is not (and neither is the sum).

use crate::support;

use sea_dyn::sample::Lcg;
use sea_dyn::{Data, ElasticParameters, Model};
use sea_plant::{Method, Plant};
use support::*;

/// Largest `|E(t) - E(0)|` over `duration` with step `dt`, and the largest change of the
/// spring energy (to show that the springs exchange energy during the run).
fn energy_drift(plant: &Plant, x0: &[f64], method: Method, dt: f64, duration: f64) -> (f64, f64) {
    let mut data = Data::new(&plant.model);
    let start = energy(plant, &mut data, x0);
    let (mut drift, mut spring_change) = (0.0f64, 0.0f64);
    let steps = (duration / dt).round() as usize;
    let u = vec![0.0; plant.model.n_joints()];
    run(plant, x0, &u, dt, steps, method, |x| {
        let e = energy(plant, &mut data, x);
        drift = drift.max((e.total() - start.total()).abs());
        spring_change = spring_change.max((e.springs - start.springs).abs());
    });
    (drift, spring_change)
}

/// The steps and bounds of one energy check.
struct EnergyCheck {
    /// Method under test.
    method: Method,
    /// Coarsest step [s]; the check also runs `dt/2` and `dt/4`.
    dt: f64,
    /// Simulated time [s].
    duration: f64,
    /// The method's order p: the drift order must lie in `[p - 0.2, p + 1.5]`.
    order: f64,
    /// Largest relative drift accepted at `dt/4`.
    finest_tolerance: f64,
}

/// Energy drifts at `dt, dt/2, dt/4` relative to the initial kinetic plus spring energy.
/// Checks that each halving divides the drift by `2^r` with `r` in `[p - 0.2, p + 1.5]` (p the
/// method's order; more would not be truncation error), that the finest
/// drift is small, and that the springs exchange at least 5 % of the energy (otherwise the test
/// would not see them).
///
/// Why the drift shrinks one order faster than the method's order p for even p: on an
/// oscillation the stability function satisfies `|R(iy)|^2 = 1 + O(y^(p+2))` (even in y), so
/// the energy error per step is O(dt^(p+2)) and O(dt^(p+1)) over a fixed time; RK4 shows about
/// 5, ROS2 about 3. The bounds accept p to p + 1.5.
fn check_energy(name: &str, plant: &Plant, x0: &[f64], check: &EnergyCheck) {
    let e0 = energy(plant, &mut Data::new(&plant.model), x0);
    let scale = e0.links + e0.motors + e0.springs;
    let mut drifts = Vec::new();
    let mut exchange = 0.0;
    for k in 0..3 {
        let dt = check.dt / f64::from(1 << k);
        let (drift, spring_change) = energy_drift(plant, x0, check.method, dt, check.duration);
        drifts.push(drift / scale);
        exchange = spring_change / scale;
    }
    let observed = orders(&drifts);
    let method = check.method;
    println!(
        "{name} {method:?} dt {:.1e}: relative energy drifts {}, orders {}, spring exchange {exchange:.2}",
        check.dt,
        sci(&drifts, 3),
        fixed(&observed, 2)
    );
    assert!(
        exchange > 0.05,
        "{name}: the springs exchange only {exchange:.3} of the energy"
    );
    for order in &observed {
        assert!(
            (check.order - 0.2..=check.order + 1.5).contains(order),
            "{name} {method:?}: energy drift order {order:.2} outside [{}, {}] (drifts {})",
            check.order - 0.2,
            check.order + 1.5,
            sci(&drifts, 3)
        );
    }
    assert!(
        drifts[2] < check.finest_tolerance,
        "{name} {method:?}: relative energy drift {:e} >= {:e}",
        drifts[2],
        check.finest_tolerance
    );
}

/// RK4 (order 4) from `dt` over `duration`.
fn rk4(dt: f64, duration: f64, finest_tolerance: f64) -> EnergyCheck {
    EnergyCheck {
        method: Method::Rk4,
        dt,
        duration,
        order: 4.0,
        finest_tolerance,
    }
}

/// ROS2 (order 2) from `dt` over `duration`.
fn ros2(dt: f64, duration: f64, finest_tolerance: f64) -> EnergyCheck {
    EnergyCheck {
        method: Method::Ros2,
        dt,
        duration,
        order: 2.0,
        finest_tolerance,
    }
}

/// Undamped SEA (K_D = 0).
fn undamped(stiffness: f64, motor_inertia: f64, ratio: f64) -> ElasticParameters {
    sea(stiffness, 0.0, motor_inertia, ratio)
}

fn icub_weightless() -> Plant {
    let model = shipped("icub25.urdf");
    // The paper's SEA (350 Nm/rad, 1e-5 kg m^2, 1/100) without damping.
    weightless(
        model.clone(),
        all_elastic(&model, undamped(350.0, 1e-5, 0.01)),
    )
}

fn with_gravity(model: Model, actuation: sea_dyn::Actuation) -> Plant {
    Plant::new(model, actuation)
}

#[test]
fn energy_is_conserved_on_the_icub_without_gravity() {
    let plant = icub_weightless();
    let mut rng = Lcg::new(11);
    let q = random_q(&plant.model, 0.5, &mut rng);
    let x0 = random_state(&plant, &q, 0.5, 0.02, &mut rng);
    check_energy("icub", &plant, &x0, &rk4(2e-4, 0.05, 1e-7));
    check_energy("icub", &plant, &x0, &ros2(1e-4, 0.05, 1e-3));
}

#[test]
fn energy_with_gravity_potential_is_conserved_on_small_robots() {
    let mut rng = Lcg::new(5);
    // The biped's light feet and ankles oscillate faster: smaller steps.
    for (file, dt_rk4, dt_ros2) in [
        ("pendulum2.urdf", 5e-4, 2.5e-4),
        ("mini_biped.urdf", 5e-4, 1.25e-4),
    ] {
        let model = shipped(file);
        let actuation = all_elastic(&model, undamped(50.0, 1e-4, 0.05));
        let plant = with_gravity(model, actuation);
        let q = random_q(&plant.model, 1.0, &mut rng);
        let x0 = random_state(&plant, &q, 0.5, 0.2, &mut rng);
        check_energy(file, &plant, &x0, &rk4(dt_rk4, 0.2, 1e-6));
        check_energy(file, &plant, &x0, &ros2(dt_ros2, 0.2, 1e-3));
    }
}

#[test]
fn energy_is_conserved_on_random_trees_with_mixed_actuation() {
    for seed in [2, 9, 17] {
        let model = random_tree(seed);
        let actuation = mixed(&model, undamped(30.0, 2e-4, 0.1));
        let plant = with_gravity(model, actuation);
        let mut rng = Lcg::new(100 + seed);
        let q = random_q(&plant.model, 1.0, &mut rng);
        let x0 = random_state(&plant, &q, 0.3, 0.3, &mut rng);
        let name = format!("random tree {seed}");
        check_energy(&name, &plant, &x0, &rk4(1e-3, 0.2, 1e-8));
        check_energy(&name, &plant, &x0, &ros2(5e-4, 0.2, 1e-5));
    }
}

/// Largest `|H(t) - H(0)|` (relative to `|H(0)|`) and largest relative change of the rotors'
/// momentum `sum b thetadot` over `steps` steps.
fn momentum_drift(
    plant: &Plant,
    x0: &[f64],
    u: &[f64],
    method: Method,
    dt: f64,
    steps: usize,
) -> (f64, f64) {
    let (model, layout) = (&plant.model, plant.layout());
    let mut data = Data::new(model);
    let mut momentum =
        |x: &[f64]| sea_dyn::centroidal_momentum(model, &mut data, layout.q(x), layout.nu(x));
    let rotors = |x: &[f64]| -> f64 {
        let thetadot = layout.thetadot(x);
        let elastic = &plant.actuation.elastic;
        elastic
            .iter()
            .zip(thetadot)
            .map(|(p, w)| p.motor_inertia * w)
            .sum()
    };
    let (h0, r0) = (momentum(x0), rotors(x0));
    let (mut drift, mut rotor_change) = (0.0f64, 0.0f64);
    run(plant, x0, u, dt, steps, method, |x| {
        drift = drift.max((momentum(x) - h0).amax() / h0.amax());
        rotor_change = rotor_change.max((rotors(x) - r0).abs() / r0.abs());
    });
    (drift, rotor_change)
}

#[test]
fn links_centroidal_momentum_is_conserved_without_gravity_and_contacts() {
    let plant = icub_weightless();
    let model = &plant.model;
    let mut rng = Lcg::new(23);
    let q = random_q(model, 0.5, &mut rng);
    let x0 = random_state(&plant, &q, 0.5, 0.02, &mut rng);
    // Motor torques act (the springs wind up); they must not change H.
    let u: Vec<f64> = (0..model.n_joints())
        .map(|_| 0.02 * rng.next_signed())
        .collect();
    for (method, dt, min_order, tolerance) in [
        (Method::Rk4, 2e-4, 3.7, 1e-8),
        (Method::Ros2, 1e-4, 1.8, 1e-4),
    ] {
        let coarse = momentum_drift(&plant, &x0, &u, method, dt, 250);
        let fine = momentum_drift(&plant, &x0, &u, method, dt / 2.0, 500);
        let order = (coarse.0 / fine.0).log2();
        println!(
            "{method:?}: |H| {:.3e}, relative momentum drift {:.3e} (dt {dt:.1e}), {:.3e} (dt/2), order {order:.2}; relative change of the rotors' momentum {:.3e}",
            sea_dyn::centroidal_momentum(model, &mut Data::new(model), &q, plant.layout().nu(&x0)).amax(),
            coarse.0,
            fine.0,
            fine.1
        );
        assert!(
            fine.0 < tolerance,
            "{method:?}: momentum drift {:e}",
            fine.0
        );
        assert!(
            order > min_order,
            "{method:?}: momentum drift order {order:.2} < {min_order}"
        );
        // The rotors' momentum does change: it is not part of the conserved H.
        assert!(fine.1 > 0.1, "rotor momentum barely moved: {:e}", fine.1);
    }
}
