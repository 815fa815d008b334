//! Tests of the scenario validation.
use super::*;
use std::path::Path;

const BASE: &str = "[robot]\nurdf = \"x.urdf\"\n";

/// The error of the base scenario with `key = value`, or `None` when it is accepted.
fn error_of(overrides: &[(&str, &str)]) -> Option<Error> {
    let pairs: Vec<(String, String)> = overrides
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Scenario::from_toml(BASE, &pairs, Path::new(".")).err()
}

/// What is wrong with how `overrides` is handled, when it is not refused with an error
/// naming `named` and showing `shown` (the value).
fn refusal_problem(overrides: &[(&str, &str)], named: &str, shown: &str) -> Option<String> {
    let Some(error) = error_of(overrides) else {
        return Some(format!("{overrides:?}: accepted"));
    };
    let message = error.to_string();
    match &error {
        Error::Scenario { key, .. } if key == named && message.contains(shown) => None,
        _ => Some(format!("{overrides:?}: {message}")),
    }
}

/// Each case must be refused with an error naming `named` and showing `shown`.
fn assert_refused(overrides: &[(&str, &str)], named: &str, shown: &str) {
    if let Some(problem) = refusal_problem(overrides, named, shown) {
        panic!("{problem}");
    }
}

// Over 100 lines on purpose: one table row per value that issue 10 found accepted, so the
// whole list reads in one place (rustfmt spreads each row over six lines).
#[test]
fn accepted_nonsense_of_the_issue_is_refused() {
    let cases: &[(&str, &str, &str, &str)] = &[
        // (override key, value, key named, value text in the message)
        (
            "controller.contact.friction",
            "-0.5",
            "controller.contact.friction",
            "-0.5",
        ),
        (
            "controller.contact.friction",
            "nan",
            "controller.contact.friction",
            "NaN",
        ),
        (
            "controller.contact.min_normal_force",
            "inf",
            "controller.contact.min_normal_force",
            "inf",
        ),
        (
            "controller.contact.min_normal_force",
            "-1.0",
            "controller.contact.min_normal_force",
            "-1",
        ),
        (
            "controller.contact.torsional_friction",
            "nan",
            "controller.contact.torsional_friction",
            "NaN",
        ),
        (
            "controller.contact.foot_x",
            "[0.1, -0.05]",
            "controller.contact.foot_x",
            "[0.1, -0.05]",
        ),
        (
            "controller.contact.foot_y",
            "[0.02, 0.02]",
            "controller.contact.foot_y",
            "[0.02, 0.02]",
        ),
        (
            "controller.contact.foot_y",
            "[nan, 0.02]",
            "controller.contact.foot_y",
            "NaN",
        ),
        (
            "controller.contact.cop_margin",
            "1.0",
            "controller.contact.cop_margin",
            "1",
        ),
        (
            "controller.contact.cop_margin",
            "-0.1",
            "controller.contact.cop_margin",
            "-0.1",
        ),
        (
            "controller.qp_moment_regularization",
            "nan",
            "controller.qp_moment_regularization",
            "NaN",
        ),
        (
            "controller.identification_deflection_noise_rad",
            "-1e-4",
            "controller.identification_deflection_noise_rad",
            "-0.0001",
        ),
        (
            "controller.momentum_relaxation",
            "\"always\"",
            "controller.momentum_relaxation",
            "always",
        ),
        (
            "controller.contact.facets",
            "0",
            "controller.contact.facets",
            "0",
        ),
        (
            "controller.contact.facets",
            "2",
            "controller.contact.facets",
            "2",
        ),
        (
            "controller.contact.facets",
            "100000000",
            "controller.contact.facets",
            "100000000",
        ),
        (
            "controller.pinv_damping",
            "-1e-3",
            "controller.pinv_damping",
            "-0.001",
        ),
        (
            "controller.qp_regularization",
            "nan",
            "controller.qp_regularization",
            "NaN",
        ),
        (
            "simulation.divergence_com_error_m",
            "nan",
            "simulation.divergence_com_error_m",
            "NaN",
        ),
        (
            "simulation.divergence_joint_error_rad",
            "nan",
            "simulation.divergence_joint_error_rad",
            "NaN",
        ),
        (
            "simulation.divergence_joint_error_rad",
            "0.0",
            "simulation.divergence_joint_error_rad",
            "0",
        ),
        (
            "simulation.divergence_joint_error_rad",
            "-1.0",
            "simulation.divergence_joint_error_rad",
            "-1",
        ),
        (
            "reference.com_smooth_start",
            "inf",
            "reference.com_smooth_start",
            "inf",
        ),
        (
            "reference.posture_step_time",
            "nan",
            "reference.posture_step_time",
            "NaN",
        ),
        (
            "reference.com_amplitude",
            "nan",
            "reference.com_amplitude",
            "NaN",
        ),
        (
            "reference.com_frequency",
            "-0.2",
            "reference.com_frequency",
            "-0.2",
        ),
        (
            "reference.com_direction",
            "[0.0, nan, 0.0]",
            "reference.com_direction",
            "NaN",
        ),
        (
            "reference.com_direction",
            "[0.0, 0.0, 0.0]",
            "reference.com_direction",
            "[0.0, 0.0, 0.0]",
        ),
        (
            "reference.posture_step_deg",
            "nan",
            "reference.posture_step_deg",
            "NaN",
        ),
        ("actuators.damping", "0.0", "actuators.damping", "0"),
        (
            "actuators.overrides.l_knee.damping",
            "0.0",
            "actuators.overrides.l_knee.damping",
            "0",
        ),
        ("actuators.stiffness", "-1.0", "actuators.stiffness", "-1"),
        (
            "actuators.torque_limit",
            "nan",
            "actuators.torque_limit",
            "NaN",
        ),
        ("plant.baumgarte_kd", "nan", "plant.baumgarte_kd", "NaN"),
        (
            "plant.joint_inertia_regularization",
            "-0.1",
            "plant.joint_inertia_regularization",
            "-0.1",
        ),
        (
            "controller.postural_stiffness",
            "[1.0, nan]",
            "controller.postural_stiffness",
            "NaN",
        ),
        (
            "simulation.record_every",
            "0",
            "simulation.record_every",
            "0",
        ),
        ("plant.dt", "1e-300", "plant.dt", "1e-300"),
        ("plant.dt", "1e-9", "plant.dt", "1e-9"),
        ("controller.rate_hz", "1e300", "controller.rate_hz", "1e300"),
        (
            "simulation.duration_s",
            "1e300",
            "simulation.duration_s",
            "1e300",
        ),
    ];
    let problems: Vec<String> = cases
        .iter()
        .filter_map(|&(key, value, named, shown)| refusal_problem(&[(key, value)], named, shown))
        .collect();
    assert!(
        problems.is_empty(),
        "{} of {} cases:\n{}",
        problems.len(),
        cases.len(),
        problems.join("\n")
    );
}

#[test]
fn zero_damping_is_allowed_with_the_rigid_controller() {
    assert!(error_of(&[
        ("actuators.damping", "0.0"),
        ("controller.kind", "\"rigid\"")
    ])
    .is_none());
    assert_refused(
        &[
            ("actuators.damping", "-1.0"),
            ("controller.kind", "\"rigid\""),
        ],
        "actuators.damping",
        "-1",
    );
}

#[test]
fn type_errors_in_actuator_tables_name_the_field() {
    for (key, named) in [
        ("actuators.stiffness", "actuators.stiffness"),
        (
            "actuators.overrides.l_knee.stiffness",
            "actuators.overrides.l_knee.stiffness",
        ),
    ] {
        assert_refused(&[(key, "false")], named, "boolean `false`");
    }
}

#[test]
fn an_unknown_qp_solver_is_refused_and_both_solvers_are_accepted() {
    assert_refused(
        &[("controller.qp_solver", "\"quadprog\"")],
        "controller.qp_solver",
        "quadprog",
    );
    for solver in sea_ctrl::qp::QpSolver::ALL {
        let value = format!("{:?}", solver.name());
        assert!(error_of(&[("controller.qp_solver", &value)]).is_none());
    }
}

#[test]
fn the_external_wrench_observer_needs_sampled_control_and_a_positive_bandwidth() {
    let observed = ("controller.external_wrench", "\"observed\"");
    for name in ["observed", "generalized"] {
        let value = format!("{name:?}");
        assert_refused(
            &[
                ("controller.external_wrench", &value),
                ("controller.sampling", "\"continuous\""),
            ],
            "controller.external_wrench",
            name,
        );
    }
    assert_refused(
        &[("controller.external_wrench", "\"estimated\"")],
        "controller.external_wrench",
        "estimated",
    );
    for (bad, shown) in [("0.0", "0"), ("-5.0", "-5"), ("nan", "NaN"), ("inf", "inf")] {
        let key = "controller.external_wrench_bandwidth_hz";
        assert_refused(&[(key, bad)], key, shown);
    }
    for sampling in ["\"zero_order_hold\"", "\"multi_rate\""] {
        let sampled = [observed, ("controller.sampling", sampling)];
        assert!(error_of(&sampled).is_none(), "{sampling}");
    }
}

#[test]
fn the_identification_prior_must_be_a_positive_deflection() {
    let key = "controller.identification_prior_deflection_rad";
    for (bad, shown) in [
        ("0.0", "0"),
        ("-1e-3", "-0.001"),
        ("nan", "NaN"),
        ("1e200", "1e200"),
    ] {
        assert_refused(&[(key, bad)], key, shown);
    }
    assert!(error_of(&[(key, "5e-3")]).is_none());
    let key = "controller.identification_range_factor";
    for (bad, shown) in [("1.0", "1"), ("0.5", "0.5"), ("inf", "inf")] {
        assert_refused(&[(key, bad)], key, shown);
    }
    assert!(error_of(&[(key, "10.0")]).is_none());
}

#[test]
fn the_external_wrench_observer_refuses_a_sensing_delay() {
    for name in ["\"observed\"", "\"generalized\""] {
        let observer = ("controller.external_wrench", name);
        let key = "sensing.delay_inner_periods";
        assert_refused(&[observer, (key, "1")], key, "1");
        assert!(error_of(&[observer, (key, "0")]).is_none());
    }
}

#[test]
fn duplicate_contacts_are_refused() {
    assert_refused(
        &[("robot.contacts", "[\"l_sole\", \"l_sole\"]")],
        "robot.contacts",
        "l_sole",
    );
}

#[test]
fn boundary_values_that_mean_something_are_accepted() {
    for overrides in [
        [("controller.contact.facets", "3")],
        [("controller.contact.facets", "64")],
        [("controller.contact.min_normal_force", "0.0")],
        [("controller.contact.torsional_friction", "0.0")],
        [("controller.contact.cop_margin", "0.0")],
        [("controller.contact.cop_margin", "0.99")],
        [("controller.momentum_relaxation", "\"when_infeasible\"")],
        [("reference.com_smooth_start", "0.0")],
        [("controller.pinv_damping", "0.0")],
        [("reference.com_amplitude", "-0.01")],
    ] {
        assert!(error_of(&overrides).is_none(), "{overrides:?}");
    }
}

#[test]
fn the_minimum_normal_force_must_be_carried_by_the_weight() {
    let two_feet = [("robot.contacts", "[\"l_sole\", \"r_sole\"]")];
    let pairs: Vec<(String, String)> = two_feet
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let mut scenario = Scenario::from_toml(BASE, &pairs, Path::new(".")).unwrap();
    let (mass, g) = (33.0, 9.81);
    scenario.controller.contact.min_normal_force = mass * g / 2.0;
    assert!(against_model(&scenario, mass, g).is_ok());
    scenario.controller.contact.min_normal_force = mass * g / 2.0 + 1.0;
    let message = against_model(&scenario, mass, g).unwrap_err().to_string();
    assert!(
        message.contains("controller.contact.min_normal_force") && message.contains("323.7"),
        "{message}"
    );
}

#[test]
fn a_joint_loop_rate_whose_plant_steps_are_below_a_microsecond_is_refused_naming_it() {
    let multi_rate = ("controller.sampling", "\"multi_rate\"");
    for rate in ["1e12", "1e10", "2e6"] {
        let shown = format!("{}", rate.parse::<f64>().unwrap());
        let overrides = [multi_rate, ("controller.inner_rate_hz", rate)];
        assert_refused(&overrides, "controller.inner_rate_hz", &shown);
    }
    // A short run does not hide it (its step count is small, its steps are not).
    let short = [
        multi_rate,
        ("controller.inner_rate_hz", "1e11"),
        ("simulation.duration_s", "0.05"),
    ];
    assert_refused(&short, "controller.inner_rate_hz", "100000000000");
    assert!(error_of(&[multi_rate, ("controller.inner_rate_hz", "1e6")]).is_none());
}
