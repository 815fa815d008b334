//! The scenario reader's answer to a grid of bad values (every key of the schema with numbers
//! out of every bound, wrong types, and the entries of arrays and tables), compared with the
//! recorded answers in `tests/messages.txt`: a change of the reading or validation that
//! changes what a user is told shows here. `SEA_BLESS_MESSAGES=1` rewrites the file (review
//! its diff: messages are part of the scenario format's contract).

use sea_scenario::Scenario;
use std::path::Path;

const BASE: &str = "[robot]\nurdf = \"x.urdf\"\n";

/// Every key the grid tries (the schema's leaves, without paths to files and free text).
const KEYS: &[&str] = &[
    "actuators.damping",
    "actuators.kind",
    "actuators.motor_inertia",
    "actuators.overrides",
    "actuators.ratio",
    "actuators.stiffness",
    "actuators.torque_limit",
    "actuators.overrides.l_knee.damping",
    "actuators.overrides.l_knee.ratio",
    "actuators.overrides.l_knee.stiffness",
    "actuators.overrides.l_knee.torque_limit",
    "actuators.overrides.l_knee.motor_inertia",
    "actuators.overrides.l_knee.kind",
    "controller.contact.cop_margin",
    "controller.contact.facets",
    "controller.contact.foot_x",
    "controller.contact.foot_y",
    "controller.contact.friction",
    "controller.contact.min_normal_force",
    "controller.contact.torsional_friction",
    "controller.damping_estimate_scale",
    "controller.external_wrench",
    "controller.external_wrench_bandwidth_hz",
    "controller.identification_deflection_noise_rad",
    "controller.identification_excitation_hz",
    "controller.identification_excitation_nm",
    "controller.identification_excitation_nm.l_knee",
    "controller.identification_excitation_s",
    "controller.identification_filter_hz",
    "controller.identification_hold_s",
    "controller.identification_prior_deflection_rad",
    "controller.identification_range_factor",
    "controller.identification_time_s",
    "controller.identification_wrenches",
    "controller.inner_rate_hz",
    "controller.joint_inertia_regularization",
    "controller.joint_stiffness",
    "controller.kind",
    "controller.link_mass_estimate_scales",
    "controller.link_mass_estimate_scales.l_knee",
    "controller.mass_estimate_scale",
    "controller.momentum_integral",
    "controller.momentum_proportional",
    "controller.momentum_relaxation",
    "controller.pinv_damping",
    "controller.postural_scale",
    "controller.postural_stiffness",
    "controller.qp_moment_regularization",
    "controller.qp_regularization",
    "controller.qp_solver",
    "controller.qp_unconstrained_first",
    "controller.rate_hz",
    "controller.reflected_inertia",
    "controller.relaxed_angular_weight",
    "controller.sampling",
    "controller.stiffness_estimate_joint_scales",
    "controller.stiffness_estimate_joint_scales.l_knee",
    "controller.stiffness_estimate_scale",
    "controller.stiffness_identification",
    "controller.torque_bandwidth_hz",
    "controller.torque_loop_paper_law",
    "controller.unknown_key",
    "controller.contact.unknown",
    "ground.dissipation_s_per_m",
    "ground.friction",
    "ground.height_m",
    "ground.incline_heading_rad",
    "ground.incline_rad",
    "ground.points",
    "ground.static_penetration_m",
    "ground.stiction_velocity_m_s",
    "ground.stiffness_n_per_m",
    "plant.baumgarte_kd",
    "plant.baumgarte_kp",
    "plant.contact_model",
    "plant.dt",
    "plant.joint_inertia_regularization",
    "plant.joint_stop_dissipation",
    "plant.joint_stop_stiffness",
    "plant.joint_stops",
    "plant.method",
    "plant.motor_velocity_gain",
    "plant.w_refresh_steps",
    "reference.com_amplitude",
    "reference.com_direction",
    "reference.com_frequency",
    "reference.com_origin",
    "reference.com_smooth_start",
    "reference.posture_step_deg",
    "reference.posture_step_joints",
    "reference.posture_step_time",
    "robot.contacts",
    "robot.description",
    "robot.description.momentum_integral",
    "robot.initial_posture",
    "robot.initial_springs",
    "robot.joints",
    "robot.package_dirs",
    "sensing.delay_inner_periods",
    "sensing.joint_position_noise_rad",
    "sensing.joint_velocity_noise_rad_s",
    "sensing.motor_position_noise_rad",
    "sensing.motor_velocity_noise_rad_s",
    "sensing.seed",
    "simulation.divergence_com_error_m",
    "simulation.divergence_joint_error_rad",
    "simulation.duration_s",
    "simulation.fall_base_height_fraction",
    "simulation.fall_tilt_rad",
    "simulation.record_every",
    "simulation.stop_at_joint_limits",
    "simulation.stop_on_fall",
];

/// The values tried at every key.
const VALUES: &[&str] = &[
    "-1",
    "0",
    "0.05",
    "0.5",
    "2",
    "1e9",
    "nan",
    "inf",
    "-inf",
    "-1e-5",
    "1e-300",
    "\"s\"",
    "true",
    "[1.0]",
    "[0.0, 0.0, 0.0]",
    "[1, 2, 3, 4, 5, -1]",
    "[1, 2, 3, 4, 5, nan]",
    "[0.1, -0.05]",
    "[nan, 0.1]",
    "{ l_knee = -1 }",
    "{ l_knee = nan }",
    "{ nope = 1 }",
    "{ l_knee = \"s\" }",
];

/// Settings the grid is tried under as well (the keys that only count with them).
const UNDER: &[&[(&str, &str)]] = &[
    &[],
    &[
        ("controller.sampling", "multi_rate"),
        ("controller.stiffness_identification", "true"),
    ],
    &[("actuators.kind", "rigid")],
];

/// The reader's answer to `overrides`: "accepted" or the error's key and message.
fn answer(overrides: &[(String, String)]) -> String {
    match Scenario::from_toml(BASE, overrides, Path::new(".")) {
        Ok(_) => "accepted".into(),
        Err(error @ sea_scenario::Error::Scenario { .. }) => {
            let message = error.to_string();
            let sea_scenario::Error::Scenario { key, .. } = error else {
                unreachable!()
            };
            format!("[{key}] {message}")
        }
        Err(error) => format!("other: {error}"),
    }
}

/// One line per case of the grid.
fn grid() -> String {
    let mut lines = String::new();
    for under in UNDER {
        for key in KEYS {
            for value in VALUES {
                let mut overrides: Vec<(String, String)> = under
                    .iter()
                    .map(|(k, v)| (k.to_string(), v.to_string()))
                    .collect();
                overrides.push((key.to_string(), value.to_string()));
                let case: Vec<String> = overrides.iter().map(|(k, v)| format!("{k}={v}")).collect();
                lines.push_str(&format!("{} => {}\n", case.join(" "), answer(&overrides)));
            }
        }
    }
    lines
}

#[test]
fn messages_of_bad_values_are_the_recorded_ones() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/messages.txt");
    let lines = grid();
    if std::env::var_os("SEA_BLESS_MESSAGES").is_some() {
        std::fs::write(&path, &lines).unwrap();
        return;
    }
    let recorded = std::fs::read_to_string(&path).unwrap();
    let changed: Vec<String> = recorded
        .lines()
        .zip(lines.lines())
        .filter(|(a, b)| a != b)
        .map(|(a, b)| format!("was: {a}\nnow: {b}"))
        .collect();
    assert!(
        changed.is_empty(),
        "{} changed:\n{}",
        changed.len(),
        changed.join("\n")
    );
    assert_eq!(recorded.lines().count(), lines.lines().count());
}
