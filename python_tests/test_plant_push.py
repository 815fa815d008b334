"""Pushes from Python: ``Plant.step(..., external={link: wrench})`` is a scenario's
``[[disturbances]]`` (the same code, ``sea_plant::external``), so a Python robot loop that
pushes the robot through ``Plant.step`` is the native run with the push, to round-off."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm

ROOT = Path(__file__).resolve().parents[1]
PUSH = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
#: Two pushes on the iCub on the ground at the robot's rates (identification and observer on,
#: as shipped): a force on the pelvis and a wrench (force and moment) on the chest, each on
#: the 0.25 ms plant step grid.
DISTURBANCES = [
    {"link": "root_link", "force": [40.0, -15.0, 0.0], "start_s": 0.1, "duration_s": 0.05},
    {"link": "chest", "force": [0.0, 10.0, 5.0], "torque": [0.0, 0.0, 3.0], "start_s": 0.12, "duration_s": 0.03},
]
OVERRIDES = {"simulation.duration_s": 0.3, "simulation.record_every": 1, "disturbances": DISTURBANCES}


def pushes_at(time: float, dt: float) -> dict[str, np.ndarray]:
    """The ``external`` argument of the plant step starting at ``time``: the disturbances whose
    window holds the step (as the native schedule counts whole steps)."""
    k = round(time / dt)
    acting: dict[str, np.ndarray] = {}
    for d in DISTURBANCES:
        start, end = round(d["start_s"] / dt), round((d["start_s"] + d["duration_s"]) / dt)
        if start <= k < end:
            acting[d["link"]] = np.array(d["force"] + d.get("torque", [0.0, 0.0, 0.0]))
    return acting


def robot_loop(scenario: sm.Scenario, *, push: bool) -> np.ndarray:
    """The robot's loop in Python (``sm.robot_loop.run``: ``end_period`` with the feet's
    wrenches averaged over the period, which the push observer takes), pushing through
    ``Plant.step``; the state at every tick."""
    dt = scenario.plant_dt
    robot = sm.PlantRobot(scenario, external=(lambda t: pushes_at(t, dt)) if push else None)
    return sm.robot_loop.run(scenario, robot)


def test_a_push_through_plant_step_is_the_native_disturbance() -> None:
    run = sm.run_scenario(PUSH, OVERRIDES)
    assert run.status == "completed", run.status
    x_run = np.hstack([run.q, run.theta, run.nu, run.thetadot])
    scale = np.maximum(1.0, np.abs(x_run).max(axis=0))
    pushed = robot_loop(sm.Scenario.load(PUSH, OVERRIDES), push=True)
    assert pushed.shape == x_run.shape
    assert np.max(np.abs(pushed - x_run) / scale) < 1e-9
    # The pushes moved the robot: the loop without them is another run.
    free = robot_loop(sm.Scenario.load(PUSH, OVERRIDES), push=False)
    assert np.max(np.abs(free - x_run) / scale) > 1e-4


def small_plant() -> tuple[sm.Plant, np.ndarray, np.ndarray]:
    """The iCub's SEA plant on two feet at its initial state, and a zero input."""
    scenario = sm.Scenario.load(PUSH, {"simulation.duration_s": 0.01, "disturbances": []})
    return scenario.plant, scenario.initial_state, np.zeros(scenario.model.n_joints)


def test_a_force_is_the_wrench_with_zero_moment_and_acts_one_step() -> None:
    plant, x, u = small_plant()
    dt = 2.5e-4
    by_force = plant.step(x, u, dt, external={"chest": [5.0, 0.0, 0.0]})
    by_wrench = plant.step(x, u, dt, external={"chest": np.array([5.0, 0.0, 0.0, 0.0, 0.0, 0.0])})
    assert np.array_equal(by_force, by_wrench)
    free = plant.step(x, u, dt)
    assert np.max(np.abs(by_force - free)) > 0.0
    # The push acted for its step only: a later step without it is the free step.
    assert np.array_equal(plant.step(x, u, dt), free)
    assert np.array_equal(plant.step(x, u, dt, external={}), free)


@pytest.mark.parametrize(
    "external, argument, shown",
    [
        ({"no_such_link": [1.0, 0.0, 0.0]}, "external['no_such_link']", "a link (frame) of the model"),
        ({"chest": [1.0, 0.0, 0.0, 0.0]}, "external['chest']", "length 4"),
        ({"chest": 3.0}, "external['chest']", "a force (3,) or a wrench"),
        ({"chest": [1.0, float("nan"), 0.0]}, "external['chest'][1]", "a finite number"),
        ({"chest": [0.0, 0.0, 0.0, float("inf"), 0.0, 0.0]}, "external['chest'][3]", "a finite number"),
        ({3: [1.0, 0.0, 0.0]}, "external", "link names"),
    ],
)
def test_a_bad_push_is_refused_naming_it(external, argument, shown) -> None:
    plant, x, u = small_plant()
    with pytest.raises(ValueError) as info:
        plant.step(x, u, 2.5e-4, external=external)
    assert argument in str(info.value) and shown in str(info.value), str(info.value)
    # Nothing of the refused call stays: the next step is the free one.
    fresh, x2, u2 = small_plant()
    assert np.array_equal(plant.step(x, u, 2.5e-4), fresh.step(x2, u2, 2.5e-4))
