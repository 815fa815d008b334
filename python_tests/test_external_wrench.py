"""The external wrench in Python: ``Controller.set_external_wrench`` (a wrench the controller's
dynamics take as acting on the base, e.g. a caller's estimate of a push), its checks, and the
push scenario's observer, which the linearisation refuses naming its key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm

PUSH = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "push_two_feet.toml"
#: The shipped robot-rate scenarios run the stiffness identification; these tests were written
#: for the fixed estimates (a test that wants the identification sets it after these).
FIXED = {"controller.stiffness_identification": False}


def test_a_wrench_on_the_base_changes_the_torques_not_the_momentum_task() -> None:
    """Known, a push is not resisted by the feet: the QP's total contact force (its momentum
    task) is the same with and without it; the joint torques that produce it change."""
    scenario = sm.Scenario.load(PUSH, FIXED)
    controller, x = scenario.controller, scenario.initial_state
    free = controller.tick(0.0, x)
    assert free.external_wrench.shape == (6,) and not free.external_wrench.any()
    push = [40.0, -10.0, 0.0, 0.0, 2.0, 0.0]
    controller.set_external_wrench(np.array(push))
    pushed = controller.tick(0.0, x)
    assert pushed.external_wrench.tolist() == push
    total = lambda out: out.wrenches[:, :3].sum(axis=0)  # noqa: E731
    np.testing.assert_allclose(total(pushed), total(free), rtol=0, atol=1e-6)
    assert np.abs(pushed.joint_command - free.joint_command).max() > 0.1
    controller.set_external_wrench(np.zeros(6))
    again = controller.tick(0.0, x)
    np.testing.assert_allclose(again.joint_command, free.joint_command, rtol=0, atol=1e-9)


@pytest.mark.parametrize("wrench", [[1.0, 2.0, 3.0], [0.0, 0.0, 0.0, 0.0, 0.0, float("nan")]])
def test_a_bad_wrench_is_refused_naming_the_argument(wrench) -> None:
    controller = sm.Scenario.load(PUSH, FIXED).controller
    with pytest.raises(ValueError, match="wrench"):
        controller.set_external_wrench(wrench)


def test_the_linearisation_refuses_the_observer_naming_its_key() -> None:
    with pytest.raises(sm.ScenarioError) as info:
        sm.linearize(PUSH, overrides=FIXED)
    assert info.value.key == "controller.external_wrench", str(info.value)


MULTI_RATE = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "tracking_multi_rate.toml"


def test_a_generalized_disturbance_moves_the_joint_torques_and_the_contact_wrench() -> None:
    """A disturbance in a joint row changes that joint's torque by minus it (the contact
    wrench unchanged: the joint is not on the stance leg); one in the base rows (a downward
    force of 20 N, as from a model 2 kg light) is carried by the foot: its vertical force grows
    by 20 N."""
    scenario = sm.Scenario.load(MULTI_RATE, FIXED)
    controller, x = scenario.controller, scenario.initial_state
    nv = scenario.model.nv
    free = controller.tick(0.0, x)
    elbow = controller.joint_names.index("r_elbow")
    d = np.zeros(nv)
    d[6 + elbow] = 0.5
    controller.set_generalized_disturbance(d)
    on_elbow = controller.tick(0.0, x)
    np.testing.assert_allclose(on_elbow.wrenches, free.wrenches, rtol=0, atol=1e-6)
    change = on_elbow.joint_command - free.joint_command
    assert abs(change[elbow] + 0.5) < 1e-6, change
    d[:] = 0.0
    d[2] = -20.0
    controller.set_generalized_disturbance(d)
    heavier = controller.tick(0.0, x)
    # Up to the QP's regularization of the wrench (0.02 N here).
    assert abs(heavier.wrenches[0, 2] - free.wrenches[0, 2] - 20.0) < 0.1
    controller.set_generalized_disturbance(np.zeros(nv))
    again = controller.tick(0.0, x)
    np.testing.assert_allclose(again.joint_command, free.joint_command, rtol=0, atol=1e-9)


def test_a_generalized_disturbance_of_the_wrong_size_is_refused_naming_the_argument() -> None:
    controller = sm.Scenario.load(MULTI_RATE, FIXED).controller
    with pytest.raises(ValueError, match="disturbance"):
        controller.set_generalized_disturbance(np.zeros(5))


def test_a_non_finite_generalized_disturbance_is_refused_naming_the_argument() -> None:
    scenario = sm.Scenario.load(MULTI_RATE, FIXED)
    values = np.zeros(scenario.model.nv)
    values[-1] = float("inf")
    with pytest.raises(ValueError, match="disturbance"):
        scenario.controller.set_generalized_disturbance(values)


def test_the_linearisation_refuses_the_generalized_observer_naming_its_key() -> None:
    with pytest.raises(sm.ScenarioError) as info:
        sm.linearize(MULTI_RATE, overrides={**FIXED, "controller.external_wrench": "generalized"})
    assert info.value.key == "controller.external_wrench", str(info.value)
    assert "generalized" in str(info.value)


def test_a_com_offset_moves_the_momentum_task_by_its_integral_gain() -> None:
    """The robot's CoM taken 1 mm ahead of the model's: the CoM position error grows by it, so
    the momentum task (the integral term) asks the foot for a force back, opposite for -1 mm;
    zeros restore the tick."""
    scenario = sm.Scenario.load(MULTI_RATE, FIXED)
    controller, x = scenario.controller, scenario.initial_state
    free = controller.tick(0.0, x)
    changes = []
    for sign in (1.0, -1.0):
        controller.set_com_offset(np.array([sign * 1e-3, 0.0, 0.0]))
        changes.append(controller.tick(0.0, x).wrenches[0, :3] - free.wrenches[0, :3])
    ahead, behind = changes
    assert ahead[0] < -0.1, ahead
    np.testing.assert_allclose(ahead, -behind, rtol=1e-6, atol=1e-9)
    assert abs(ahead[1]) < 1e-3 * abs(ahead[0]) and abs(ahead[2]) < 1e-3 * abs(ahead[0]), ahead
    controller.set_com_offset(np.zeros(3))
    again = controller.tick(0.0, x)
    np.testing.assert_allclose(again.wrenches, free.wrenches, rtol=0, atol=1e-9)


@pytest.mark.parametrize("offset", [[1.0, 2.0], [0.0, float("nan"), 0.0]])
def test_a_bad_com_offset_is_refused_naming_the_argument(offset) -> None:
    controller = sm.Scenario.load(MULTI_RATE, FIXED).controller
    with pytest.raises(ValueError, match="offset"):
        controller.set_com_offset(offset)
