//! The gait the controller follows: feet identified by their side, the tasks of each phase,
//! the CoM reference going to the pendulum's height over the initial transfer.

use super::walking;
use crate::walking::{FootTask, Gait, ToeOff};
use nalgebra::{Matrix3, Vector3};
use sea_dyn::spatial::Pose;

/// Soles 0.14 m apart at the ground height 0.01 m, the right one first (contact 0).
fn soles() -> [Pose; 2] {
    let sole = |y: f64| Pose {
        rotation: Matrix3::identity(),
        translation: Vector3::new(0.0, y, 0.01),
    };
    [sole(-0.07), sole(0.07)]
}

#[test]
fn the_feet_are_named_by_their_side_and_follow_the_plan() {
    let settings = walking(2, 0.1, 0.0, 0.0);
    let com = Vector3::new(0.0, 0.0, 0.54);
    let gait = Gait::new(&settings, &soles(), com, 9.81, ToeOff::default()).unwrap();
    // The contact further along +y is the left foot.
    assert_eq!(gait.contact_of, [1, 0]);
    // Standing at the start: both on the ground, half the load each.
    assert_eq!(
        gait.foot_tasks(0.0),
        [
            FootTask::Contact { share: 0.5 },
            FootTask::Contact { share: 0.5 }
        ]
    );
    // Mid-swing of the first step (the left foot, contact 1): it swings, the right carries.
    let step = gait.footsteps.steps[0];
    let mid = 0.5 * (step.lift_off + step.touchdown);
    let [right, left] = gait.foot_tasks(mid);
    assert_eq!(right, FootTask::Contact { share: 1.0 });
    let FootTask::Swing(swing) = left else {
        panic!("the left foot swings: {left:?}")
    };
    assert!((swing.world_p_sole.z - (0.01 + settings.swing_height)).abs() < 1e-12);
    // The CoM reference at the pendulum's height (ground 0.01 + 0.53), the plan's
    // horizontal CoM.
    let reference = gait.com_reference(mid);
    assert_eq!(reference.position.z, 0.54);
    assert_eq!((reference.velocity.z, reference.acceleration.z), (0.0, 0.0));
    assert_eq!(
        reference.position.xy(),
        gait.dcm.sample(mid).com.position.xy()
    );
    assert_eq!(gait.steps_landed(step.touchdown), 1);
}

#[test]
fn a_gait_needs_two_feet() {
    let settings = walking(2, 0.1, 0.0, 0.0);
    let error = Gait::new(
        &settings,
        &soles()[..1],
        Vector3::zeros(),
        9.81,
        ToeOff::default(),
    )
    .unwrap_err();
    assert!(error.to_string().contains("controller.contacts"), "{error}");
}

#[test]
fn the_com_goes_to_the_pendulum_height_over_the_initial_transfer() {
    let settings = walking(2, 0.1, 0.0, 0.0);
    let com = Vector3::new(0.0, 0.0, 0.60);
    let gait = Gait::new(&settings, &soles(), com, 9.81, ToeOff::default()).unwrap();
    let transfer = settings.transfer_duration;
    let target = 0.01 + settings.com_height;
    assert_eq!(gait.world_z_com, target);
    let at = |t: f64| gait.com_reference(t);
    // From the robot's height at rest to the pendulum's at rest.
    assert_eq!(at(0.0).position.z, 0.60);
    assert_eq!((at(0.0).velocity.z, at(0.0).acceleration.z), (0.0, 0.0));
    assert!((at(transfer).position.z - target).abs() < 1e-12);
    assert!(at(transfer).velocity.z.abs() < 1e-12);
    assert!(at(transfer).acceleration.z.abs() < 1e-9);
    assert_eq!(at(transfer + 1.0).position.z, target);
    // Halfway, halfway down, at its fastest; the derivatives are the position's.
    let mid = 0.5 * transfer;
    assert!((at(mid).position.z - 0.5 * (0.60 + target)).abs() < 1e-12);
    let h = 1e-6;
    for t in [0.1, mid, 0.5] {
        let velocity = (at(t + h).position.z - at(t - h).position.z) / (2.0 * h);
        let acceleration = (at(t + h).velocity.z - at(t - h).velocity.z) / (2.0 * h);
        assert!((velocity - at(t).velocity.z).abs() < 1e-6, "{t}");
        assert!((acceleration - at(t).acceleration.z).abs() < 1e-5, "{t}");
    }
    assert!(at(mid).velocity.z < 0.0);
}
