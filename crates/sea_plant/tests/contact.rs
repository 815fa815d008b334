//! Rigid contacts (paper eq:constraints_acc): the simulated contact wrenches are the Lagrange
//! multipliers of the constrained dynamics, and the Baumgarte-stabilised constraint keeps the
//! feet in place over seconds.
//!
//! Each identity is checked with quantities computed here from sea_dyn (CRBA, RNEA bias, frame
//! Jacobians, `Jdot nu`, centroidal momentum), not from the plant's internals:
//! - `M nudot + h = B tau + J^T f` (the equations of motion with the multipliers);
//! - `J nudot + Jdot nu = -(K_d J nu + K_p e)` (the stabilised constraint), `e` the pose error
//!   with the rotation part as the rotation vector `log(R R_ref^T)`;
//! - `Hdot = A_G nudot + Adot_G nu = sum_k [f_k; (p_k - p_com) x f_k + n_k] + [m g; 0]`
//!   (Newton-Euler of the whole robot: only gravity and the contact wrenches change H);
//! - per elastic joint, eq:alpha, eq:tauMotors and eq:motors.

use crate::support;

use nalgebra::{DMatrix, DVector, Vector3, Vector6};
use sea_dyn::sample::Lcg;
use sea_dyn::{Data, Model};
use sea_plant::{evaluate, step, Method, MotorInput, Plant, PlantData};
use support::common::log_so3;
use support::*;

/// Motor velocity loop gain of the scenarios (200 1/s,
/// docs/references.md#original-study-sea-parameters).
const MOTOR_GAIN: f64 = 200.0;

/// A robot standing on `soles` with all joints at `posture`, springs at rest, the paper's
/// SEA (with damping), the motor velocity loop and the joint inertia regularisation of the
/// scenarios.
fn standing(model: Model, posture: &[f64], soles: &[&str]) -> (Plant, Vec<f64>) {
    let actuation = all_elastic(&model, sea(350.0, 0.25, 1e-5, 0.01));
    let mut plant = Plant::new(model, actuation);
    plant.motor_input = MotorInput::VelocityLoop { gain: MOTOR_GAIN };
    plant.joint_inertia_regularization = 0.1;
    let mut q = plant.model.neutral();
    q[7..].copy_from_slice(posture);
    let soles: Vec<String> = soles.iter().map(|s| s.to_string()).collect();
    plant.set_contacts(&soles, &q).unwrap();
    (plant, q)
}

/// The iCub on both feet with slightly bent knees (legs straight is a singular posture).
fn icub_standing() -> (Plant, Vec<f64>) {
    let model = shipped("icub25.urdf");
    let posture: Vec<f64> = model
        .joint_names
        .iter()
        .map(|name| match name.as_str() {
            "l_hip_pitch" | "r_hip_pitch" => 0.3,
            "l_knee" | "r_knee" => -0.6,
            "l_ankle_pitch" | "r_ankle_pitch" => -0.3,
            _ => 0.0,
        })
        .collect();
    standing(model, &posture, &["l_sole", "r_sole"])
}

/// The mini biped on its left foot with bent knees (its knee flexion is positive). Not on both
/// feet: without hip yaw joints, two 6-D contacts make the constraint Jacobian (nearly)
/// rank-deficient at symmetric postures, which the plant reports as degenerate contacts.
fn biped_standing() -> (Plant, Vec<f64>) {
    let model = shipped("mini_biped.urdf");
    let posture: Vec<f64> = model
        .joint_names
        .iter()
        .map(|name| match name.as_str() {
            "l_hip_pitch" | "r_hip_pitch" => -0.3,
            "l_knee" | "r_knee" => 0.6,
            "l_ankle_pitch" | "r_ankle_pitch" => -0.3,
            _ => 0.0,
        })
        .collect();
    standing(model, &posture, &["l_sole"])
}

/// A state near `q`: base moved by a millimetre and rotated by a milliradian (so the pose
/// error `e` is not zero), random velocities, deflected springs.
fn perturbed_state(plant: &Plant, q: &[f64], rng: &mut Lcg) -> Vec<f64> {
    let mut q = q.to_vec();
    for c in q.iter_mut().take(3) {
        *c += 1e-3 * rng.next_signed();
    }
    let delta: Vec<f64> = (0..plant.model.nv())
        .map(|_| 1e-3 * rng.next_signed())
        .collect();
    let mut moved = q.clone();
    sea_dyn::integrate(&plant.model, &q, &delta, 1.0, &mut moved);
    random_state(plant, &moved, 0.3, 0.02, rng)
}

/// Stacked contact Jacobian (6 k x nv) and `Jdot nu` (6 k), computed by sea_dyn.
fn contact_kinematics(plant: &Plant, q: &[f64], nu: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
    let (model, nv, k) = (&plant.model, plant.model.nv(), plant.contacts.len());
    let mut data = Data::new(model);
    let mut jacobian = DMatrix::zeros(6 * k, nv);
    let mut bias = DVector::zeros(6 * k);
    for (c, contact) in plant.contacts.iter().enumerate() {
        jacobian
            .rows_mut(6 * c, 6)
            .copy_from(sea_dyn::frame_jacobian(model, &mut data, q, contact.frame));
        let jdot_nu = sea_dyn::frame_jacobian_dot_v(model, &mut data, q, nu, contact.frame);
        bias.rows_mut(6 * c, 6).copy_from(&jdot_nu);
    }
    (jacobian, bias)
}

/// Pose errors `[p - p_ref; log(R R_ref^T)]` of the contacts (6 k) and the contact origins.
fn pose_errors(plant: &Plant, q: &[f64]) -> (DVector<f64>, Vec<Vector3<f64>>) {
    let model = &plant.model;
    let mut data = Data::new(model);
    sea_dyn::forward_kinematics(model, &mut data, q);
    let mut error = DVector::zeros(6 * plant.contacts.len());
    let mut origins = Vec::new();
    for (c, contact) in plant.contacts.iter().enumerate() {
        let pose = sea_dyn::frame_placement(model, &data, contact.frame);
        let reference = &contact.world_h_frame_desired;
        let rotation = log_so3(&(pose.rotation * reference.rotation.transpose()));
        error
            .rows_mut(6 * c, 3)
            .copy_from(&(pose.translation - reference.translation));
        error.rows_mut(6 * c + 3, 3).copy_from(&rotation);
        origins.push(pose.translation);
    }
    (error, origins)
}

/// Checks the equations of motion, the stabilised constraint, Newton-Euler and the actuator
/// equations at `x` with input `u`; returns the residuals relative to their scales.
fn check_multipliers(name: &str, plant: &Plant, x: &[f64], u: &[f64]) {
    let (model, layout) = (&plant.model, plant.layout());
    let (q, nu) = (layout.q(x), layout.nu(x));
    let n = model.n_joints();
    let mut pd = PlantData::new(plant);
    evaluate(plant, &mut pd.workspace, x, u, &mut pd.outputs).unwrap();
    let nudot = DVector::from_column_slice(layout.tangent().dnu(pd.outputs.xdot.as_slice()));
    let f = &pd.outputs.contact_wrench;
    let mut data = Data::new(model);

    // M nudot + h = B tau + J^T f.
    let m = plant_mass_matrix(plant, &mut data, q);
    let h = sea_dyn::bias_forces(model, &mut data, q, nu).clone();
    let (jacobian, jdot_nu) = contact_kinematics(plant, q, nu);
    let mut generalized = jacobian.transpose() * f;
    for j in 0..n {
        generalized[6 + j] += pd.outputs.joint_torque[j];
    }
    let lhs = &m * &nudot + &h;
    let dynamics = (&lhs - &generalized).amax() / lhs.amax().max(generalized.amax());

    // J nudot + Jdot nu = -(K_d J nu + K_p e).
    let (error, origins) = pose_errors(plant, q);
    let velocity = &jacobian * DVector::from_column_slice(nu);
    let acceleration = &jacobian * &nudot + &jdot_nu;
    let target = -(velocity * plant.baumgarte_kd + &error * plant.baumgarte_kp);
    let constraint = (&acceleration - &target).amax() / target.amax();

    // Hdot = sum of the contact wrenches about the CoM + m g (regularisation-free: it only
    // adds to the joint rows, which do not enter H's balance).
    let a_g = sea_dyn::centroidal_momentum_matrix(model, &mut data, q).clone();
    let adot_nu = sea_dyn::centroidal_momentum_bias(model, &mut data, q, nu);
    let hdot = &a_g * &nudot + adot_nu;
    let com = sea_dyn::com(model, &mut data, q);
    let mut net_force = model.gravity * model.total_mass();
    let mut net_moment = Vector3::zeros();
    for (c, origin) in origins.iter().enumerate() {
        let force = Vector3::new(f[6 * c], f[6 * c + 1], f[6 * c + 2]);
        let moment = Vector3::new(f[6 * c + 3], f[6 * c + 4], f[6 * c + 5]);
        net_force += force;
        net_moment += (origin - com).cross(&force) + moment;
    }
    let external = Vector6::new(
        net_force.x,
        net_force.y,
        net_force.z,
        net_moment.x,
        net_moment.y,
        net_moment.z,
    );
    let newton_euler = (hdot - external).amax() / external.amax();

    let motors = motor_residual(plant, &pd, x, u);
    println!(
        "{name}: |f| {:.3e} N, |e| {:.1e}, relative residuals: dynamics {dynamics:.1e}, constraint {constraint:.1e}, Newton-Euler {newton_euler:.1e}, motors {motors:.1e}",
        f.amax(),
        error.amax()
    );
    assert!(f.amax() > 1.0, "{name}: no contact wrench");
    assert!(error.amax() > 1e-4, "{name}: the pose error is zero");
    assert!(
        dynamics < 1e-10,
        "{name}: M nudot + h - B tau - J^T f: {dynamics:e}"
    );
    assert!(
        constraint < 1e-7,
        "{name}: stabilised constraint: {constraint:e}"
    );
    assert!(
        newton_euler < 1e-10,
        "{name}: Newton-Euler: {newton_euler:e}"
    );
    assert!(motors < 1e-12, "{name}: actuator equations: {motors:e}");
}

/// Largest relative residual of eq:alpha (`tau`), eq:tauMotors (`tau_m`) and eq:motors
/// (`I_m thetaddot = tau_m - Gamma tau`) over the elastic joints.
/// A fresh workspace evaluated at `(x, u)`: the reference of the bitwise comparisons.
fn evaluated(plant: &Plant, x: &[f64], u: &[f64]) -> PlantData {
    let mut pd = PlantData::new(plant);
    evaluate(plant, &mut pd.workspace, x, u, &mut pd.outputs).unwrap();
    pd
}

fn motor_residual(plant: &Plant, pd: &PlantData, x: &[f64], u: &[f64]) -> f64 {
    let layout = plant.layout();
    let (s, sdot) = (layout.s(x), layout.sdot(x));
    let (theta, thetadot) = (layout.theta(x), layout.thetadot(x));
    let MotorInput::VelocityLoop { gain } = plant.motor_input else {
        panic!("the contact tests use the motor velocity loop");
    };
    let actuation = &plant.actuation;
    let mut worst = 0.0f64;
    for (e, (&j, p)) in actuation
        .elastic_joints
        .iter()
        .zip(&actuation.elastic)
        .enumerate()
    {
        let tau = p.stiffness * (p.ratio * theta[e] - s[j])
            + p.damping * (p.ratio * thetadot[e] - sdot[j]);
        let tau_m = -p.motor_inertia * gain * (thetadot[e] - u[j]) + p.ratio * tau;
        let thetaddot = layout.tangent().dthetadot(pd.outputs.xdot.as_slice())[e];
        worst = worst
            .max((pd.outputs.joint_torque[j] - tau).abs() / tau.abs().max(1e-3))
            .max((pd.outputs.motor_torque[e] - tau_m).abs() / tau_m.abs().max(1e-6))
            .max(
                (p.motor_inertia * thetaddot - (tau_m - p.ratio * tau)).abs()
                    / (p.ratio * tau).abs().max(1e-6),
            );
    }
    worst
}

#[test]
fn contact_wrenches_are_the_lagrange_multipliers() {
    let mut rng = Lcg::new(31);
    for (name, (plant, q)) in [("icub", icub_standing()), ("mini_biped", biped_standing())] {
        for trial in 0..3 {
            let x = perturbed_state(&plant, &q, &mut rng);
            let u: Vec<f64> = (0..plant.model.n_joints())
                .map(|_| 5.0 * rng.next_signed())
                .collect();
            check_multipliers(&format!("{name} state {trial}"), &plant, &x, &u);
        }
    }
}

/// Runs `seconds` with `u` held; returns the largest foot position [m] and rotation [rad]
/// errors (measured here from the kinematics) and the largest joint speed [rad/s].
fn drift_over(
    plant: &Plant,
    x0: &[f64],
    u: &[f64],
    dt: f64,
    seconds: f64,
    method: Method,
) -> (f64, f64, f64) {
    let layout = plant.layout();
    let steps = (seconds / dt).round() as usize;
    let (mut position, mut rotation, mut speed) = (0.0f64, 0.0f64, 0.0f64);
    run(plant, x0, u, dt, steps, method, |x| {
        let (error, _) = pose_errors(plant, layout.q(x));
        for c in 0..plant.contacts.len() {
            position = position.max(error.rows(6 * c, 3).norm());
            rotation = rotation.max(error.rows(6 * c + 3, 3).norm());
        }
        speed = speed.max(layout.sdot(x).iter().fold(0.0, |a, v| a.max(v.abs())));
    });
    (position, rotation, speed)
}

#[test]
fn feet_stay_in_place_under_constant_input() {
    for (name, (plant, q)) in [("icub", icub_standing()), ("mini_biped", biped_standing())] {
        let x0 = plant
            .make_state(&q, &vec![0.0; plant.model.nv()], None, None)
            .unwrap();
        // Constant input: desired motor velocities of a slow knee motion and a torso turn
        // (the iCub on both feet, the biped on one).
        let u: Vec<f64> = plant
            .model
            .joint_names
            .iter()
            .zip(&plant.actuation.elastic)
            .map(|(name, p)| match name.as_str() {
                n if n.ends_with("knee") => 0.05 / p.ratio,
                "torso_yaw" => 0.1 / p.ratio,
                _ => 0.0,
            })
            .collect();
        for method in [Method::Ros2, Method::LinearlyImplicitEuler] {
            let (position, rotation, speed) = drift_over(&plant, &x0, &u, 1e-3, 3.0, method);
            println!(
                "{name} {method:?}, 3 s at 1 ms: foot drift {position:.2e} m, {rotation:.2e} rad; peak joint speed {speed:.2} rad/s"
            );
            assert!(speed > 0.01, "{name}: the robot does not move");
            assert!(
                position < 2e-5,
                "{name} {method:?}: foot drift {position:e} m"
            );
            assert!(
                rotation < 2e-5,
                "{name} {method:?}: foot rotation drift {rotation:e} rad"
            );
        }
    }
}

#[test]
fn the_step_leaves_the_step_start_outputs_in_plant_data() {
    // `step` documents that `pd` holds the evaluation at the step start: the closed loop
    // records the contact wrenches from it.
    let (plant, q) = icub_standing();
    let mut rng = Lcg::new(4);
    let x = perturbed_state(&plant, &q, &mut rng);
    let u = vec![0.0; plant.model.n_joints()];
    let reference = evaluated(&plant, &x, &u);
    for method in [Method::Ros2, Method::LinearlyImplicitEuler, Method::Rk4] {
        let mut pd = PlantData::new(&plant);
        let mut next = x.clone();
        step(&plant, &mut pd, &x, &u, 1e-3, method, &mut next).unwrap();
        assert_eq!(
            pd.outputs.contact_wrench, reference.outputs.contact_wrench,
            "{method:?}"
        );
        assert_eq!(
            pd.outputs.motor_torque, reference.outputs.motor_torque,
            "{method:?}"
        );
        assert_eq!(
            pd.outputs.joint_torque, reference.outputs.joint_torque,
            "{method:?}"
        );
        // All of them, the derivative, saturation and drift included.
        assert_eq!(pd.outputs, reference.outputs, "{method:?}");
    }
}

#[test]
fn preloaded_springs_hold_the_standing_robot_at_rest() {
    // `equilibrium::static_motor_angles`: the springs transmit the static torques, so the
    // robot at rest on both feet (motor velocity loop, zero desired velocity) does not move.
    let (plant, q) = icub_standing();
    let nv = plant.model.nv();
    let u = vec![0.0; plant.model.n_joints()];
    let theta = sea_plant::equilibrium::static_motor_angles(&plant, &q).unwrap();
    let acceleration_at = |theta: Option<&[f64]>| {
        let x = plant.make_state(&q, &vec![0.0; nv], theta, None).unwrap();
        let mut pd = PlantData::new(&plant);
        evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
        pd.outputs.xdot.amax()
    };
    let preloaded = acceleration_at(Some(&theta));
    let unloaded = acceleration_at(None);
    assert!(preloaded < 1e-8, "preloaded springs: |xdot| {preloaded:e}");
    assert!(unloaded > 1.0, "springs at rest: |xdot| {unloaded:e}");
}

#[test]
fn adopted_model_terms_give_the_same_evaluation_and_only_at_their_state() {
    // `Workspace::adopt_model_terms`: the closed loop hands the controller's kinematics, bias
    // forces and M (computed at the same state with an equal model) to the plant's next
    // evaluation. The result must be bitwise the evaluation without them; at another state
    // they must not be used.
    let (plant, q) = icub_standing();
    let layout = plant.layout();
    let mut rng = Lcg::new(12);
    let x = perturbed_state(&plant, &q, &mut rng);
    let other = perturbed_state(&plant, &q, &mut rng);
    let u: Vec<f64> = (0..plant.model.n_joints())
        .map(|_| 5.0 * rng.next_signed())
        .collect();
    let terms_at = |state: &[f64]| {
        let mut data = Data::new(&plant.model);
        sea_dyn::bias_forces(&plant.model, &mut data, layout.q(state), layout.nu(state));
        sea_dyn::crba_after_rnea(&plant.model, &mut data);
        data
    };
    let reference = evaluated(&plant, &x, &u);
    let mut pd = PlantData::new(&plant);
    pd.workspace.adopt_model_terms(&terms_at(&x), &layout, &x);
    evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
    assert_eq!(pd.outputs.xdot, reference.outputs.xdot);
    assert_eq!(pd.outputs.contact_wrench, reference.outputs.contact_wrench);
    // Terms of another state offered for x: ignored (x's own terms are computed).
    let mut pd = PlantData::new(&plant);
    pd.workspace
        .adopt_model_terms(&terms_at(&other), &layout, &other);
    evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
    assert_eq!(pd.outputs.xdot, reference.outputs.xdot);
    // Used once: a second evaluation elsewhere and back computes its own.
    let mut pd = PlantData::new(&plant);
    pd.workspace.adopt_model_terms(&terms_at(&x), &layout, &x);
    evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
    evaluate(&plant, &mut pd.workspace, &other, &u, &mut pd.outputs).unwrap();
    let mut at_other = PlantData::new(&plant);
    evaluate(
        &plant,
        &mut at_other.workspace,
        &other,
        &u,
        &mut at_other.outputs,
    )
    .unwrap();
    assert_eq!(pd.outputs.xdot, at_other.outputs.xdot);

    // The contact terms too (factor of M + diag, J, Jdot nu, L^-T J^T, J M^-1 J^T), computed
    // here from sea_dyn as a controller with the plant's diagonal and contacts would.
    let data = terms_at(&x);
    let nv = plant.model.nv();
    let mut diagonal = vec![plant.joint_inertia_regularization; nv];
    diagonal[..6].fill(0.0);
    let frames: Vec<usize> = plant.contacts.iter().map(|c| c.frame).collect();
    let k = 6 * frames.len();
    let (mut jacobian, mut jdot_nu) = (DMatrix::zeros(k, nv), DVector::zeros(k));
    let mut scratch = data.clone();
    for (c, &frame) in frames.iter().enumerate() {
        sea_dyn::jacobian::frame_jacobian_from_kinematics(&plant.model, &mut scratch, frame);
        jacobian
            .rows_mut(6 * c, 6)
            .copy_from(&scratch.frame_jacobian);
        let bias = sea_dyn::jacobian::frame_bias_acceleration_after_bias_forces(
            &plant.model,
            &scratch,
            frame,
        );
        jdot_nu.fixed_rows_mut::<6>(6 * c).copy_from(&bias);
    }
    let mut factor = sea_dyn::tree_factor::TreeFactor::new(&plant.model);
    factor.factor(&data.mass_matrix, &diagonal).unwrap();
    let (mut linv_jt_t, mut schur) = (DMatrix::zeros(k, nv), DMatrix::zeros(k, k));
    factor.schur_complement(&jacobian, &mut linv_jt_t, &mut schur);
    let contacts = sea_dyn::tree_factor::FactoredContacts {
        frames: &frames,
        diagonal: &diagonal,
        factor: &factor,
        jacobian: &jacobian,
        jdot_nu: &jdot_nu,
        linv_jt_t: &linv_jt_t,
        schur: &schur,
    };
    let mut pd = PlantData::new(&plant);
    pd.workspace.adopt_model_terms(&data, &layout, &x);
    assert!(pd.workspace.adopt_contact_terms(&plant, &contacts));
    evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
    assert_eq!(pd.outputs.xdot, reference.outputs.xdot);
    assert_eq!(pd.outputs.contact_wrench, reference.outputs.contact_wrench);
    // They are really used: a different Schur complement handed over changes the result.
    let doubled = &schur * 2.0;
    let tampered = sea_dyn::tree_factor::FactoredContacts {
        schur: &doubled,
        ..contacts
    };
    let mut pd = PlantData::new(&plant);
    pd.workspace.adopt_model_terms(&data, &layout, &x);
    assert!(pd.workspace.adopt_contact_terms(&plant, &tampered));
    evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
    assert_ne!(pd.outputs.contact_wrench, reference.outputs.contact_wrench);
    // Another diagonal (a controller with the motor reflected inertia): refused.
    let mut other_diagonal = diagonal.clone();
    other_diagonal[7] += 0.01;
    let refused = sea_dyn::tree_factor::FactoredContacts {
        diagonal: &other_diagonal,
        ..contacts
    };
    let mut pd = PlantData::new(&plant);
    pd.workspace.adopt_model_terms(&data, &layout, &x);
    assert!(!pd.workspace.adopt_contact_terms(&plant, &refused));
    evaluate(&plant, &mut pd.workspace, &x, &u, &mut pd.outputs).unwrap();
    assert_eq!(pd.outputs.xdot, reference.outputs.xdot);
}
