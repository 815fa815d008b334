//! The push scenario with its feet on the ground (unilateral contacts, joint stops): a push
//! the stance holds is recovered; a large one makes the robot fall as physics (its base
//! tilts), not as a wrench check; the wrench check stays a diagnostic in the summary.

use sea_sim::scenario::Scenario;
use std::path::Path;

fn pushed(impulse_n_s: f64) -> sea_sim::closed_loop::Summary {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/robot_rate/push_two_feet.toml");
    let push = format!(
        "[{{link = \"root_link\", force = [{}, 0.0, 0.0], start_s = 1.0, duration_s = 0.1}}]",
        impulse_n_s / 0.1
    );
    let pairs = [
        ("controller.stiffness_identification", "false"),
        ("disturbances", push.as_str()),
        ("simulation.duration_s", "2.5"),
        // No bound of the controller's errors: the run ends when the robot reaches the ground.
        ("simulation.divergence_joint_error_rad", "1000.0"),
        ("simulation.divergence_com_error_m", "1000.0"),
    ]
    .map(|(k, v)| (k.to_string(), v.to_string()));
    let scenario = Scenario::from_file(&path, &pairs).unwrap();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    sea_sim::closed_loop::run_with_sinks(&scenario, &mut [], &cancel, |_, _| {}).unwrap()
}

#[test]
fn a_push_the_stance_holds_is_recovered_on_the_ground() {
    let summary = pushed(5.0);
    assert_eq!(summary.status, "completed", "{}", summary.reason);
    assert_eq!(summary.contact_check_violations, 0);
    assert_eq!(summary.touchdowns, 0, "no foot left the ground");
}

#[test]
fn a_large_push_is_a_physical_fall_with_the_wrench_check_as_a_diagnostic() {
    let summary = pushed(20.0);
    assert_eq!(summary.status, "fell", "{}", summary.reason);
    let fall = summary.fall.as_ref().unwrap();
    assert!(
        ["base_height", "tilt", "link_on_ground"].contains(&fall.constraint),
        "{fall:?}"
    );
    assert!(fall.foot.is_empty());
    // The feet lifted and landed again before the fall, which the wrench check saw.
    assert!(summary.contact_check_violations > 0);
    let first = summary.contact_check_first_s.unwrap();
    assert!(first > 1.0 && first < fall.at_s, "{first} {}", fall.at_s);
    assert!(summary.touchdowns > 0);
}
