"""``controller.sampling = "multi_rate"`` from Python: the run and the period map of the shipped
robot-rate scenario (the whole-body QP at 100 Hz, the joint torque loops at 1 kHz)."""

from pathlib import Path

import pytest

import sea_momentum as sm

MULTI_RATE = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "tracking_multi_rate.toml"
#: The shipped robot-rate scenarios run the stiffness identification; these tests were written
#: for the fixed estimates (a test that wants the identification sets it after these).
#: The proxy these tests were written for (as ``WELDED_FEET`` of the Rust tests): the feet
#: welded (bilateral contacts, a fall the wrench check's).
WELDED_FEET = {"plant.contact_model": "bilateral"}
FIXED = {**WELDED_FEET, "controller.stiffness_identification": False}


def test_period_map_of_the_robot_rate_scenario_is_stable_and_names_its_sampling():
    lin = sm.linearize(MULTI_RATE, overrides=FIXED)
    assert lin.sampling == "multi_rate"
    assert abs(lin.control_period - 0.01) < 1e-12
    assert lin.stable and lin.growth_rate < 0.0


def test_the_paper_law_with_500_hz_joint_loops_is_unstable():
    overrides = {
        **FIXED,
        "controller.kind": "sea",
        "controller.torque_loop_paper_law": True,
        "controller.inner_rate_hz": 500.0,
    }
    lin = sm.linearize(MULTI_RATE, overrides=overrides, sampling="multi_rate")
    assert not lin.stable and lin.growth_rate > 10.0


def test_a_delay_is_in_the_period_map_and_refused_in_continuous_time():
    nominal = sm.linearize(MULTI_RATE, overrides=FIXED)
    nd = nominal.matrix.shape[0]
    lin = sm.linearize(MULTI_RATE, overrides={**FIXED, "sensing.delay_inner_periods": 9})
    assert lin.matrix.shape == (10 * nd, 10 * nd)
    assert len(lin.state_names) == 10 * nd and lin.state_names[nd].endswith("@-1")
    # Nine inner periods of delay destabilise the 20 Hz torque loop of the free leg.
    assert not lin.stable and lin.growth_rate > 0.5
    with pytest.raises(sm.ScenarioError, match="sensing.delay_inner_periods"):
        sm.linearize(MULTI_RATE, overrides={**FIXED, "sensing.delay_inner_periods": 1}, sampling="continuous")


def test_the_delay_margin_is_scanned_at_whole_numbers():
    boundaries = sm.stability_margin(MULTI_RATE, "sensing.delay_inner_periods", 7, 10, overrides=FIXED, grid_points=4)
    assert boundaries == [8.5]


def test_the_summary_reports_the_joint_loops_stiffness_estimates():
    """Multi-rate: the stiffness the joint loops ended with, by elastic joint, in the summary
    (identified from x2 on the stance leg's loaded joints); other samplings have none."""
    overrides = {
        **FIXED,
        "simulation.duration_s": 3.0,
        "controller.stiffness_identification": True,
        "controller.stiffness_estimate_scale": 2.0,
    }
    result = sm.run_scenario(MULTI_RATE, overrides)
    estimates = result.summary.stiffness_estimates_nm_per_rad
    scenario = sm.Scenario.load(MULTI_RATE, FIXED)
    assert set(estimates) == set(scenario.model.joint_names)
    assert abs(estimates["l_knee"] / 350.0 - 1.0) < 0.01, estimates
    assert all(value > 0.0 for value in estimates.values())
    short = {**FIXED, "simulation.duration_s": 0.1}
    held = sm.run_scenario(MULTI_RATE, {**short, "controller.stiffness_estimate_scale": 2.0})
    assert set(held.summary.stiffness_estimates_nm_per_rad.values()) == {700.0}
    zoh = {**short, "controller.sampling": "zero_order_hold", "controller.rate_hz": 1000.0}
    assert sm.run_scenario(MULTI_RATE, zoh).summary.stiffness_estimates_nm_per_rad == {}
