//! `controller.external_wrench = "generalized"`: the generalized disturbance observer
//! (sea_ctrl::generalized_disturbance) against errors of the controller's model on the
//! multi-rate tracking (docs/findings/model_errors.md): its estimate at rest is
//! the model's gravity error exactly, it holds per-link mass errors where the paper's dynamics
//! diverge, and (its joint torques sensed through the stiffness estimate) a stiffness estimate
//! off by x0.5 without identification.

use crate::support;

use nalgebra::DVector;
use sea_ctrl::generalized_disturbance::{AppliedForces, GeneralizedDisturbanceObserver};
use sea_sim::closed_loop::run;
use sea_sim::scenario::Scenario;

/// Seed 1 of the main job's per-link mass draws (scripts/robot_rate.py, uniform in [0.9,
/// 1.1]): the model's mass 1.3 kg light, its CoM 4.5 mm off the robot's sideways.
const MASS_DRAW: &str = "{root_link=0.9269,r_hip_1=1.0695,r_hip_2=1.0528,r_hip_3=0.9510,\
r_upper_leg=0.9991,r_lower_leg=0.9899,r_ankle_1=1.0303,r_ankle_2=1.0577,r_foot=0.9188,\
torso_1=0.9057,torso_2=1.0672,chest=0.9866,neck_1=1.0525,neck_2=0.9004,head=0.9891,\
r_shoulder_1=1.0443,r_shoulder_2=0.9458,r_shoulder_3=1.0891,r_upper_arm=1.0803,\
r_elbow_1=0.9061,r_forearm=0.9051,r_wrist_1=1.0083,r_hand=1.0878,l_shoulder_1=0.9762,\
l_shoulder_2=0.9433,l_shoulder_3=0.9844,l_upper_arm=0.9058,l_elbow_1=0.9443,\
l_forearm=0.9876,l_wrist_1=0.9992,l_hand=0.9466,l_hip_1=0.9462,l_hip_2=0.9438,\
l_hip_3=0.9919,l_upper_leg=0.9580,l_lower_leg=0.9043,l_ankle_1=1.0675,l_ankle_2=1.0113,\
l_foot=1.0285}";

fn load(overrides: &[(&str, &str)]) -> Scenario {
    support::tracking(overrides)
}

/// At the initial state (the plant at rest on one foot, its springs holding it), the joint
/// torques and the foot's wrench balance the robot's gravity `g(q)`; a model with the drawn
/// masses has `g^(q)`, and the observer's residual (no low pass) is `g^ - g` in every row.
#[test]
fn at_rest_the_estimate_is_the_model_s_gravity_error() {
    let draw = ("controller.link_mass_estimate_scales", MASS_DRAW);
    let scenario = load(&[draw]);
    let setup = sea_sim::scenario::build(&scenario).unwrap();
    let (plant, x0) = (&setup.plant, &setup.x0);
    let layout = plant.layout();
    let mut pd = scenario.plant.plant_data(plant);
    let mut outputs = sea_plant::PlantOutputs::new(plant);
    let u = vec![0.0; plant.model.n_joints()];
    sea_plant::evaluate(plant, &mut pd.workspace, x0, &u, &mut outputs).unwrap();
    let acceleration = outputs.xdot.rows(plant.model.nv(), plant.model.nv()).norm();
    assert!(acceleration < 1e-6, "not at rest: |nudot| = {acceleration}");

    let controller_model = setup.controller.model();
    let mut observer = GeneralizedDisturbanceObserver::new(&setup.controller, 0.01, 1e9);
    let forces = AppliedForces {
        joint_torques: &outputs.joint_torque,
        contact_wrenches: &outputs.contact_wrench,
    };
    let robot = (controller_model, setup.controller.contact_frames());
    let state = (layout.q(x0), layout.nu(x0));
    observer.update(robot, state, forces, forces);
    let estimate = observer.update(robot, state, forces, forces).clone();

    let gravity = |model: &sea_dyn::Model| {
        let mut data = sea_dyn::Data::new(model);
        sea_dyn::gravity_forces(model, &mut data, layout.q(x0)).clone()
    };
    let expected: DVector<f64> = gravity(controller_model) - gravity(&plant.model);
    let error = (&estimate - &expected).amax();
    assert!(error < 1e-6, "error {error}: {estimate} vs {expected}");
    // The draw's model is 1.3 kg light: the base rows' vertical force is its weight.
    let mass_error = plant.model.total_mass() - controller_model.total_mass();
    assert!((estimate[2] + 9.81 * mass_error).abs() < 1e-6 * (1.0 + estimate[2].abs()));
    assert!(mass_error > 1.0, "{mass_error}");
}

/// In motion, with the controller's model equal to the robot's, the observer sees nothing: at
/// the initial state with every spring deflected 0.02 rad more the joints accelerate, the period
/// from `nu = -T nudot` to `nu = 0` (same `q`, a short `T`) has the plant's acceleration as
/// its mean, and the residual (no low pass) vanishes, the joint inertia regularisation `D`
/// that the controller adds to its `M` (0.1 kg m^2 per joint on the iCub) included: without
/// it the estimate is `-D nudot`, up to several Nm here.
#[test]
fn in_motion_an_exact_model_shows_no_disturbance() {
    let scenario = load(&[]);
    let setup = sea_sim::scenario::build(&scenario).unwrap();
    let layout = setup.plant.layout();
    let (x, outputs, nudot) = support::accelerating_state(&scenario, &setup, 0.02);
    let largest_inertial = nudot[6..].iter().map(|a| 0.1 * a.abs()).fold(0.0, f64::max);
    assert!(
        largest_inertial > 1.0,
        "D nudot at most {largest_inertial} Nm"
    );

    let period = 1e-6;
    let previous_nu: Vec<f64> = nudot.iter().map(|a| -period * a).collect();
    let mut observer = GeneralizedDisturbanceObserver::new(&setup.controller, period, 1e12);
    let forces = AppliedForces {
        joint_torques: &outputs.joint_torque,
        contact_wrenches: &outputs.contact_wrench,
    };
    let robot = (setup.controller.model(), setup.controller.contact_frames());
    observer.update(robot, (layout.q(&x), &previous_nu), forces, forces);
    let estimate = observer.update(robot, (layout.q(&x), layout.nu(&x)), forces, forces);
    let largest = estimate.amax();
    assert!(
        largest < 1e-6 * largest_inertial / 0.1,
        "|d^| = {largest}: {estimate}"
    );
}

/// The drawn masses: the paper's dynamics let the stance knee bend until the joint error bound
/// ends the run (1.8 s); taking the observed generalized disturbance, the tracking completes
/// the 10 s with the joint error within 0.2 rad, where the centroidal observer (the same
/// error taken at the base only) does not.
#[test]
fn the_generalized_observer_holds_per_link_mass_errors() {
    let draw = ("controller.link_mass_estimate_scales", MASS_DRAW);
    let outcome = |observer: &str| {
        let value = format!("{observer:?}");
        let scenario = load(&[draw, ("controller.external_wrench", &value)]);
        run(&scenario, |_, _| {}).unwrap()
    };
    for observer in ["none", "observed"] {
        let (_, summary) = outcome(observer);
        assert_eq!(summary.status, "diverged", "{observer}: {summary:?}");
        assert_eq!(
            summary.reason_kind,
            Some("joint_error_over_bound"),
            "{summary:?}"
        );
    }
    let (record, summary) = outcome("generalized");
    assert_eq!(summary.status, "completed", "{summary:?}");
    // Recorded as the wrench the contacts carry: at the end the model's missing weight, the
    // draw's 1.3 kg (the plant's mass less the model's), within 2 %.
    let setup = sea_sim::scenario::build(&load(&[draw])).unwrap();
    let missing = setup.plant.model.total_mass() - setup.controller.model().total_mass();
    let last = record.external_wrench.len() - 6;
    let vertical = record.external_wrench[last + 2];
    assert!(
        (vertical + 9.81 * missing).abs() < 0.02 * 9.81 * missing,
        "{vertical} N"
    );
    assert!(summary.joint_error_norm_final_rad < 0.2, "{summary:?}");
    // The true CoM's error: the model's CoM, which the controller tracks, is 4.5 mm off it.
    assert!(summary.com_error_rms_m < 8e-3, "{summary:?}");
}

/// A stiffness estimate x0.5 without identification: the torque loop delivers twice the
/// torques it is asked for and the robot falls; the observer reads the joint torques as the
/// robot senses them (the deflection through the estimate), sees the difference as a
/// disturbance and asks for half: the tracking completes with the nominal loop's figures.
#[test]
fn the_generalized_observer_holds_a_stiffness_estimate_of_half() {
    let scale = ("controller.stiffness_estimate_scale", "0.5");
    let without = run(&load(&[scale]), |_, _| {}).unwrap().1;
    assert_ne!(without.status, "completed", "{without:?}");
    let observed = ("controller.external_wrench", "\"generalized\"");
    let with = run(&load(&[scale, observed]), |_, _| {}).unwrap().1;
    assert_eq!(with.status, "completed", "{with:?}");
    assert!(with.com_error_rms_m <= 3.48e-3, "{with:?}");
    assert!(with.joint_error_norm_final_rad < 0.24, "{with:?}");
}

/// With the controller's model not the plant's, the CoM recorded and checked is the plant's
/// (the true one), not the controller's estimate.
#[test]
fn the_recorded_com_is_the_true_one_when_the_model_is_wrong() {
    let draw = ("controller.link_mass_estimate_scales", MASS_DRAW);
    let scenario = load(&[draw, ("simulation.duration_s", "0.01")]);
    let setup = sea_sim::scenario::build(&scenario).unwrap();
    let q0 = setup.plant.layout().q(&setup.x0).to_vec();
    let com_of = |model: &sea_dyn::Model| {
        let mut data = sea_dyn::Data::new(model);
        sea_dyn::centroidal::com(model, &mut data, &q0)
    };
    let (truth, estimate) = (com_of(&setup.plant.model), com_of(setup.controller.model()));
    assert!((truth - estimate).norm() > 4e-3);
    let (record, _) = run(&scenario, |_, _| {}).unwrap();
    let recorded = nalgebra::Vector3::from_column_slice(&record.com[..3]);
    assert!((recorded - truth).norm() < 1e-12, "{recorded} vs {truth}");
}

/// The design that holds model errors (identification with a prior of 5 mrad and the
/// generalized observer) under encoder noise (1e-4 rad on every encoder, 1e-2 rad/s on every
/// velocity, seed 0, the deflection noise declared): the tracking completes with the final
/// joint error within the goal of twice the nominal (0.24 rad), also with the identification's
/// estimates allowed to x0.1 of the prior (range factor 10). Two safeguards keep a noisy update
/// out of the estimates: with the samples unfiltered (`identification_filter_hz` 1e9) the
/// default range still completes, but with range factor 10 too one noisy update takes the
/// stance ankle roll towards x0.1 and the sole tips.
#[test]
fn the_robust_design_holds_encoder_noise_within_the_joint_error_goal() {
    let noisy = [
        ("controller.stiffness_identification", "true"),
        ("controller.identification_prior_deflection_rad", "5e-3"),
        ("controller.identification_deflection_noise_rad", "1e-4"),
        ("controller.external_wrench", "\"generalized\""),
        ("sensing.joint_position_noise_rad", "1e-4"),
        ("sensing.motor_position_noise_rad", "1e-4"),
        ("sensing.joint_velocity_noise_rad_s", "1e-2"),
        ("sensing.motor_velocity_noise_rad_s", "1e-2"),
        ("sensing.seed", "0"),
    ];
    let summary = run(&load(&noisy), |_, _| {}).unwrap().1;
    assert_eq!(summary.status, "completed", "{summary:?}");
    assert!(summary.joint_error_norm_final_rad < 0.24, "{summary:?}");
    assert!(summary.com_error_rms_m <= 3.48e-3, "{summary:?}");
    let wide = ("controller.identification_range_factor", "10.0");
    let unfiltered = ("controller.identification_filter_hz", "1e9");
    for (extra, status) in [
        (vec![wide], "completed"),
        (vec![unfiltered], "completed"),
        (vec![wide, unfiltered], "fell"),
    ] {
        let overrides: Vec<_> = noisy.iter().copied().chain(extra.clone()).collect();
        let summary = run(&load(&overrides), |_, _| {}).unwrap().1;
        assert_eq!(summary.status, status, "{extra:?}: {summary:?}");
    }
}
