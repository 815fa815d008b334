//! The integrators: convergence order against a reference solution at a much smaller step,
//! and stability on stiff springs.
//!
//! - Order: the error at a fixed time, measured against RK4 at a step at least 80 times smaller,
//!   shrinks per halving of `dt` by about `2^p`: p = 2 for ROS2 (a W-method: second order for
//!   any W, so also with the frozen `M`, `J` of its W-matrix), 1 for the linearly implicit
//!   Euler step, 4 for RK4 (on the rotation as Runge-Kutta-Munthe-Kaas).
//! - Stiffness: with `K_S = 1e4 Nm/rad` on light links the spring modes reach thousands of
//!   rad/s; at `dt = 1 ms` RK4 is outside its stability region (`|dt lambda| < 2.79` on the
//!   imaginary axis) and blows up, while the L-stable ROS2 stays bounded.

use crate::support;

use sea_dyn::sample::Lcg;
use sea_dyn::Data;
use sea_plant::{simulate, Method, MotorInput, Plant, PlantData, Status};
use support::*;

/// An initial value problem: plant, initial state, held input, final time and the reference
/// solution at the final time.
struct Problem {
    plant: Plant,
    x0: Vec<f64>,
    u: Vec<f64>,
    final_time: f64,
    reference: Vec<f64>,
}

impl Problem {
    /// The problem with its reference: RK4 with `reference_steps` steps.
    fn new(
        plant: Plant,
        x0: Vec<f64>,
        u: Vec<f64>,
        final_time: f64,
        reference_steps: usize,
    ) -> Self {
        let dt = final_time / reference_steps as f64;
        let reference = run(&plant, &x0, &u, dt, reference_steps, Method::Rk4, |_| {});
        Self {
            plant,
            x0,
            u,
            final_time,
            reference,
        }
    }

    /// Errors at the final time of `method` with steps `dt / 2^k` (k < levels).
    fn errors(&self, method: Method, dt: f64, levels: usize) -> Vec<f64> {
        self.errors_sharing_w(method, dt, levels, 1)
    }

    /// [`Problem::errors`] with up to `w_refresh_steps` consecutive steps sharing `W`.
    fn errors_sharing_w(
        &self,
        method: Method,
        dt: f64,
        levels: usize,
        w_refresh_steps: usize,
    ) -> Vec<f64> {
        (0..levels)
            .map(|k| {
                let h = dt / f64::from(1 << k);
                let steps = (self.final_time / h).round() as usize;
                let (x0, u) = (&self.x0, &self.u);
                let x = run_sharing_w(
                    &self.plant,
                    x0,
                    u,
                    (h, steps),
                    method,
                    w_refresh_steps,
                    |_| {},
                );
                state_distance(&x, &self.reference)
            })
            .collect()
    }
}

/// Checks that each observed order lies in `[order - 0.25, order + 0.5]`.
fn check_orders(name: &str, method: Method, errors: &[f64], order: f64) {
    let observed = orders(errors);
    println!(
        "{name} {method:?}: errors {}, orders {}",
        sci(errors, 3),
        fixed(&observed, 2)
    );
    for o in &observed {
        assert!(
            (order - 0.25..=order + 0.5).contains(o),
            "{name} {method:?}: observed order {o:.2}, expected {order} (errors {})",
            sci(errors, 3)
        );
    }
}

/// A random tree, mixed actuation, soft damped springs, gravity, constant joint and motor
/// torques: a smooth, non-stiff problem over 0.2 s.
fn random_tree_problem(seed: u64) -> Problem {
    let model = random_tree(seed);
    let actuation = mixed(&model, sea(30.0, 0.5, 2e-4, 0.1));
    let plant = Plant::new(model, actuation);
    let mut rng = Lcg::new(700 + seed);
    let q = random_q(&plant.model, 1.0, &mut rng);
    let x0 = random_state(&plant, &q, 0.5, 0.1, &mut rng);
    let u: Vec<f64> = (0..plant.model.n_joints())
        .map(|_| 0.5 * rng.next_signed())
        .collect();
    Problem::new(plant, x0, u, 0.2, 8000)
}

#[test]
fn orders_on_random_trees_without_contacts() {
    for seed in [3, 12] {
        let problem = random_tree_problem(seed);
        let name = format!("random tree {seed}");
        for (method, dt, order) in [
            (Method::Ros2, 2e-3, 2.0),
            (Method::LinearlyImplicitEuler, 1e-3, 1.0),
            (Method::Rk4, 4e-3, 4.0),
        ] {
            check_orders(&name, method, &problem.errors(method, dt, 4), order);
        }
    }
}

/// The iCub on its left foot with the paper's SEA, the motor velocity loop, Baumgarte
/// stabilisation and the scenarios' joint inertia regularisation (which keeps the light
/// wrists slow), moving from a random nearby state with constant desired motor velocities,
/// over 0.1 s.
fn icub_on_one_foot() -> Problem {
    let model = shipped("icub25.urdf");
    let actuation = all_elastic(&model, sea(350.0, 0.25, 1e-5, 0.01));
    let mut plant = Plant::new(model, actuation);
    plant.motor_input = MotorInput::VelocityLoop { gain: 200.0 };
    plant.joint_inertia_regularization = 0.1;
    let mut rng = Lcg::new(8);
    let q = random_q(&plant.model, 0.3, &mut rng);
    plant.set_contacts(&["l_sole".to_string()], &q).unwrap();
    let x0 = random_state(&plant, &q, 0.2, 0.01, &mut rng);
    let u: Vec<f64> = plant
        .actuation
        .elastic
        .iter()
        .map(|p| 0.2 * rng.next_signed() / p.ratio)
        .collect();
    Problem::new(plant, x0, u, 0.1, 8000)
}

#[test]
fn orders_on_the_icub_in_contact_with_the_motor_velocity_loop() {
    let problem = icub_on_one_foot();
    for (method, dt, levels, order) in [
        (Method::Ros2, 2e-3, 4, 2.0),
        (Method::LinearlyImplicitEuler, 1e-3, 4, 1.0),
        (Method::Rk4, 1e-3, 3, 4.0),
    ] {
        check_orders("icub", method, &problem.errors(method, dt, levels), order);
    }
}

/// ROS2 with up to 10 consecutive steps sharing the `W` prepared at the first one's start
/// (`IntegratorCache::set_w_refresh_steps`): still second order (a W-method), as accurate as
/// with a `W` per step to a few percent of the error, and bounded on the stiff springs where it
/// is with its own `W` per step.
#[test]
fn ros2_sharing_w_over_steps_keeps_its_order_and_stiff_stability() {
    let problem = icub_on_one_foot();
    let shared = problem.errors_sharing_w(Method::Ros2, 2e-3, 4, 10);
    check_orders("icub, W shared", Method::Ros2, &shared, 2.0);
    let own = problem.errors(Method::Ros2, 2e-3, 4);
    assert_ne!(shared, own, "the steps did not share W");
    for (s, o) in shared.iter().zip(&own) {
        assert!((s - o).abs() < 0.05 * o, "shared W {s:e}, own W {o:e}");
    }
    let (plant, x0) = stiff_icub();
    let u = vec![0.0; plant.model.n_joints()];
    let mut pd = PlantData::new(&plant);
    pd.integrator.set_w_refresh_steps(10);
    let ros2 = simulate(
        &plant,
        &mut pd,
        &x0,
        &u,
        1e-3,
        1000,
        Method::Ros2,
        10,
        |_| true,
    )
    .unwrap();
    let layout = plant.layout();
    let peak_speed = ros2
        .state
        .chunks(x0.len())
        .flat_map(|x| layout.nu(x).iter().map(|v| v.abs()))
        .fold(0.0, f64::max);
    assert_eq!(ros2.status, Status::Completed);
    assert!(
        peak_speed < 1.0,
        "ROS2, shared W: peak velocity {peak_speed}"
    );
}

/// The iCub with stiff springs (`K_S = 1e4`) on both feet, motor velocity loop, no joint
/// inertia regularisation (light wrists: fast spring modes).
fn stiff_icub() -> (Plant, Vec<f64>) {
    let model = shipped("icub25.urdf");
    let actuation = all_elastic(&model, sea(1e4, 0.25, 1e-5, 0.01));
    let mut plant = Plant::new(model, actuation);
    plant.motor_input = MotorInput::VelocityLoop { gain: 200.0 };
    let mut q = plant.model.neutral();
    for (name, s) in plant.model.joint_names.iter().zip(&mut q[7..]) {
        *s = match name.as_str() {
            "l_hip_pitch" | "r_hip_pitch" => 0.3,
            "l_knee" | "r_knee" => -0.6,
            "l_ankle_pitch" | "r_ankle_pitch" => -0.3,
            _ => 0.0,
        };
    }
    plant
        .set_contacts(&["l_sole".to_string(), "r_sole".to_string()], &q)
        .unwrap();
    let x0 = plant
        .make_state(&q, &vec![0.0; plant.model.nv()], None, None)
        .unwrap();
    (plant, x0)
}

#[test]
fn ros2_stays_bounded_on_stiff_springs_where_rk4_diverges() {
    let (plant, x0) = stiff_icub();
    let u = vec![0.0; plant.model.n_joints()];
    let dt = 1e-3;
    let mut pd = PlantData::new(&plant);
    let ros2 = simulate(&plant, &mut pd, &x0, &u, dt, 1000, Method::Ros2, 10, |_| {
        true
    })
    .unwrap();
    let rk4 = simulate(&plant, &mut pd, &x0, &u, dt, 1000, Method::Rk4, 10, |_| {
        true
    })
    .unwrap();
    let nx = x0.len();
    let layout = plant.layout();
    let peak_speed = ros2
        .state
        .chunks(nx)
        .flat_map(|x| layout.nu(x).iter().map(|v| v.abs()))
        .fold(0.0, f64::max);
    let drift = ros2.drift_position.iter().fold(0.0f64, |a, &d| a.max(d));
    println!(
        "stiff iCub, dt 1 ms: ROS2 {:?}, peak |nu| {peak_speed:.3e}, foot drift {drift:.2e} m; RK4 {:?}",
        ros2.status, rk4.status
    );
    assert_eq!(ros2.status, Status::Completed);
    assert!(peak_speed < 1.0, "ROS2: peak velocity {peak_speed}");
    assert!(drift < 1e-4, "ROS2: foot drift {drift} m");
    assert!(
        matches!(rk4.status, Status::Diverged { .. }),
        "RK4 did not diverge: {:?}",
        rk4.status
    );
}

#[test]
fn ros2_does_not_create_energy_on_stiff_undamped_springs() {
    // Free floating, no gravity, K_D = 0: the exact energy is constant; the L-stable ROS2 may
    // only dissipate the unresolved modes, never add energy.
    let model = shipped("icub25.urdf");
    let plant = weightless(
        model.clone(),
        all_elastic(&model, sea(1e4, 0.0, 1e-5, 0.01)),
    );
    let mut rng = Lcg::new(41);
    let q = random_q(&plant.model, 0.5, &mut rng);
    let x0 = random_state(&plant, &q, 0.5, 0.02, &mut rng);
    let u = vec![0.0; plant.model.n_joints()];
    let mut data = Data::new(&plant.model);
    let e0 = energy(&plant, &mut data, &x0).total();
    for method in [Method::Ros2, Method::LinearlyImplicitEuler] {
        let mut peak = 0.0f64;
        let mut last = 0.0;
        run(&plant, &x0, &u, 1e-3, 1000, method, |x| {
            last = energy(&plant, &mut data, x).total();
            peak = peak.max(last);
        });
        println!(
            "stiff free-floating iCub {method:?}, dt 1 ms: E(0) {e0:.4e} J, peak {peak:.4e} J, E(1 s) {last:.4e} J"
        );
        assert!(
            peak <= e0 * (1.0 + 1e-9),
            "{method:?}: energy grew to {peak} from {e0}"
        );
        assert!(last > 0.0);
    }
}
