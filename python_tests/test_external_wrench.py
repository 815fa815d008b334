"""The external wrench in Python: ``Controller.set_external_wrench`` (a wrench the controller's
dynamics take as acting on the base, e.g. a caller's estimate of a push), its checks, and the
push scenario's observer, which the linearisation refuses naming its key."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm

PUSH = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "push_two_feet.toml"


def test_a_wrench_on_the_base_changes_the_torques_not_the_momentum_task() -> None:
    """Known, a push is not resisted by the feet: the QP's total contact force (its momentum
    task) is the same with and without it; the joint torques that produce it change."""
    scenario = sm.Scenario.load(PUSH)
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
    controller = sm.Scenario.load(PUSH).controller
    with pytest.raises(ValueError, match="wrench"):
        controller.set_external_wrench(wrench)


def test_the_linearisation_refuses_the_observer_naming_its_key() -> None:
    with pytest.raises(sm.ScenarioError) as info:
        sm.linearize(PUSH)
    assert info.value.key == "controller.external_wrench", str(info.value)
