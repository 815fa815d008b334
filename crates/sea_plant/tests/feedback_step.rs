//! `integrator::step_with_feedback`: a feedback law evaluated at every stage.
//!
//! - A law that ignores time and state gives exactly the held-input `step`.
//! - The law is called at the method's stage times (ROS2: t, t + dt; RK4: t, t + dt/2,
//!   t + dt/2, t + dt; linearly implicit Euler: t), first at `(t, x)`.
//! - With a state- and time-dependent law (a motor velocity command that feeds back the joint
//!   angles and follows a sinusoid), the closed loop converges with the method's order: halving
//!   the step divides the error at a fixed time by about 4 (ROS2) or 16 (RK4), against a
//!   reference from RK4 at a far smaller step. A law held over each step instead (zero-order
//!   hold) would limit both to first order.

use sea_dyn::{Actuation, Actuator, ElasticParameters, LoadOptions, Model};
use sea_plant::integrator::step_with_feedback;
use sea_plant::{step, Method, MotorInput, Plant, PlantData, Workspace};
use std::collections::HashMap;
use std::path::Path;

/// The double pendulum on a free-floating base, both joints SEAs driven through the motor
/// velocity loop (the SEA controller's plant input), no contacts.
fn pendulum() -> (Plant, Vec<f64>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../urdf/pendulum2.urdf");
    let model = Model::from_urdf_file(&path, &LoadOptions::default()).unwrap();
    let sea = ElasticParameters {
        ratio: 0.01,
        motor_inertia: 1e-5,
        stiffness: 350.0,
        damping: 0.25,
        torque_limit: None,
    };
    let actuation = Actuation::new(&model, Actuator::Elastic(sea), &HashMap::new()).unwrap();
    let mut plant = Plant::new(model.clone(), actuation);
    plant.motor_input = MotorInput::VelocityLoop { gain: 200.0 };
    // As in the scenarios (docs/references.md#original-study-plant): keeps the light second
    // link from being the stiffest mode, so explicit RK4 runs at the steps below.
    plant.joint_inertia_regularization = 0.1;
    let mut q = model.neutral();
    q[7] = 0.3;
    q[8] = -0.2;
    let nu: Vec<f64> = (0..model.nv()).map(|k| 0.05 * (k as f64 - 3.0)).collect();
    let theta = [0.31 / 0.01, -0.19 / 0.01];
    let x = plant.make_state(&q, &nu, Some(&theta), None).unwrap();
    (plant, x)
}

const METHODS: [Method; 3] = [Method::Ros2, Method::LinearlyImplicitEuler, Method::Rk4];

#[test]
fn a_constant_law_is_the_held_input_step() {
    let (plant, x) = pendulum();
    let mut pd = PlantData::new(&plant);
    let held = [0.7, -1.3];
    for method in METHODS {
        let (mut x_held, mut x_law) = (x.clone(), x.clone());
        step(&plant, &mut pd, &x, &held, 1e-3, method, &mut x_held).unwrap();
        let mut law =
            |_: f64, _: &[f64], u: &mut [f64], _: &mut Workspace| -> sea_plant::Result<()> {
                u.copy_from_slice(&held);
                Ok(())
            };
        let mut u = [0.0; 2];
        step_with_feedback(
            &plant, &mut pd, &x, 2.5, 1e-3, method, &mut law, &mut u, &mut x_law,
        )
        .unwrap();
        assert_eq!(x_held, x_law, "{method:?}");
    }
}

#[test]
fn the_law_is_evaluated_at_the_stage_times() {
    let (plant, x) = pendulum();
    let mut pd = PlantData::new(&plant);
    let (t, dt) = (2.0, 0.25);
    let expected = [
        (Method::Ros2, vec![t, t + dt]),
        (Method::LinearlyImplicitEuler, vec![t]),
        (Method::Rk4, vec![t, t + 0.5 * dt, t + 0.5 * dt, t + dt]),
    ];
    for (method, times) in expected {
        let mut seen = Vec::new();
        let mut first_state = None;
        let mut law =
            |time: f64, state: &[f64], u: &mut [f64], _: &mut Workspace| -> sea_plant::Result<()> {
                if first_state.is_none() {
                    first_state = Some(state.to_vec());
                }
                seen.push(time);
                u.fill(0.0);
                Ok(())
            };
        let (mut u, mut x_out) = ([0.0; 2], x.clone());
        step_with_feedback(
            &plant, &mut pd, &x, t, dt, method, &mut law, &mut u, &mut x_out,
        )
        .unwrap();
        assert_eq!(seen, times, "{method:?}");
        assert_eq!(first_state.as_deref(), Some(&x[..]), "{method:?}");
    }
}

/// The law's error reaches the caller as itself.
#[test]
fn the_law_error_is_returned() {
    #[derive(Debug, PartialEq)]
    enum LawError {
        Law(f64),
        Plant,
    }
    impl From<sea_plant::Error> for LawError {
        fn from(_: sea_plant::Error) -> Self {
            LawError::Plant
        }
    }
    let (plant, x) = pendulum();
    let mut pd = PlantData::new(&plant);
    let mut law = |time: f64, _: &[f64], u: &mut [f64], _: &mut Workspace| {
        u.fill(0.0);
        if time > 1.0 {
            Err(LawError::Law(time))
        } else {
            Ok(())
        }
    };
    let (mut u, mut x_out) = ([0.0; 2], x.clone());
    let result = step_with_feedback(
        &plant,
        &mut pd,
        &x,
        0.5,
        1.0,
        Method::Ros2,
        &mut law,
        &mut u,
        &mut x_out,
    );
    assert_eq!(result, Err(LawError::Law(1.5)));
}

/// The state after `duration` with the feedback law below, `steps` steps of `method`.
fn closed_loop_state(plant: &Plant, x0: &[f64], method: Method, steps: usize) -> Vec<f64> {
    let duration = 0.2;
    let dt = duration / steps as f64;
    // Desired motor velocities: a sinusoid in time plus feedback of the joint angles and
    // velocities (stiff enough to matter: gain 40/s through the motor velocity loop).
    let layout = plant.layout();
    let mut law = |t: f64, x: &[f64], u: &mut [f64], _: &mut Workspace| -> sea_plant::Result<()> {
        let (s, sdot) = (layout.s(x), layout.sdot(x));
        for j in 0..2 {
            u[j] = (3.0 * (8.0 * t + j as f64).sin() - 40.0 * s[j] - 2.0 * sdot[j]) / 0.01;
        }
        Ok(())
    };
    let mut pd = PlantData::new(plant);
    let (mut x, mut x_next, mut u) = (x0.to_vec(), x0.to_vec(), [0.0; 2]);
    for k in 0..steps {
        let t = k as f64 * dt;
        step_with_feedback(
            plant,
            &mut pd,
            &x,
            t,
            dt,
            method,
            &mut law,
            &mut u,
            &mut x_next,
        )
        .unwrap();
        std::mem::swap(&mut x, &mut x_next);
    }
    x
}

fn sci(values: &[f64]) -> String {
    let parts: Vec<String> = values.iter().map(|v| format!("{v:.3e}")).collect();
    parts.join(", ")
}

/// `|a - b| / |b|`.
fn relative_distance(a: &[f64], b: &[f64]) -> f64 {
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|e| e * e).sum::<f64>().sqrt();
    norm(&mut a.iter().zip(b).map(|(p, q)| p - q)) / norm(&mut b.iter().copied())
}

#[test]
fn the_closed_loop_converges_with_the_method_order() {
    let (plant, x0) = pendulum();
    let reference = closed_loop_state(&plant, &x0, Method::Rk4, 6400);
    for (method, order, base_steps) in [(Method::Ros2, 2.0, 200), (Method::Rk4, 4.0, 200)] {
        let errors: Vec<f64> = (0..3)
            .map(|k| {
                relative_distance(
                    &closed_loop_state(&plant, &x0, method, base_steps << k),
                    &reference,
                )
            })
            .collect();
        let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!(
            "{method:?}: relative errors {}, observed orders {orders:.2?}",
            sci(&errors)
        );
        for observed in orders {
            assert!(
                (observed - order).abs() < 0.5,
                "{method:?}: observed order {observed:.2}, expected {order} (errors {})",
                sci(&errors)
            );
        }
    }
}
