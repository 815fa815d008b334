"""``sea_momentum.robot_loop``: one whole-body period's steps, joint ticks and readings for any
robot, and ``Plant.contact_point_counts``. That the loop on our plant is the native run is
checked in test_controller_object.py (multi-rate, the estimators, walking) and
test_plant_push.py (pushes); here the zero-order hold, and the period's bookkeeping against a
robot whose readings are known."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm

ROOT = Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
WALK = ROOT / "scenarios" / "walking" / "walk_straight.toml"


class CountingController:
    """Stands in for ``Controller``: ``inner_tick`` returns the number of its calls as the
    input, so each step's input tells which joint tick set it."""

    def __init__(self) -> None:
        self.inner_ticks: list[np.ndarray] = []

    def inner_tick(self, x: np.ndarray) -> np.ndarray:
        self.inner_ticks.append(np.array(x))
        return np.full(2, float(len(self.inner_ticks)))


class ScriptedRobot:
    """A robot whose state is the number of steps taken and whose sensors read that number
    (wrenches) and the input (torques)."""

    def __init__(self) -> None:
        self.steps = 0
        self.inputs: list[np.ndarray] = []

    def state(self) -> np.ndarray:
        return np.array([float(self.steps)])

    def step(self, u: np.ndarray) -> sm.StepReadings:
        self.inputs.append(np.array(u))
        self.steps += 1
        return sm.StepReadings(np.full((2, 6), float(self.steps)), np.array(u))


def test_a_period_ticks_the_joint_loops_and_reads_first_last_and_mean() -> None:
    controller, robot = CountingController(), ScriptedRobot()
    readings = sm.run_period(controller, robot, np.zeros(2), 40, 10)  # type: ignore[arg-type]
    # Joint ticks before steps 10, 20 and 30, at the state those steps start from.
    assert [x[0] for x in controller.inner_ticks] == [10.0, 20.0, 30.0]
    assert [u[0] for u in robot.inputs] == [0.0] * 10 + [1.0] * 10 + [2.0] * 10 + [3.0] * 10
    assert np.all(readings.start.contact_wrenches == 1.0)
    assert np.all(readings.end.contact_wrenches == 40.0)
    assert np.all(readings.end.joint_torques == 3.0)
    np.testing.assert_allclose(readings.mean_contact_wrenches, np.full((2, 6), 20.5), rtol=1e-15)
    held = sm.run_period(CountingController(), ScriptedRobot(), np.zeros(2), 40, 40)  # type: ignore[arg-type]
    assert np.all(held.end.joint_torques == 0.0)  # zero-order hold: no joint tick
    with pytest.raises(ValueError, match="steps_per_tick"):
        sm.run_period(controller, robot, np.zeros(2), 0, 10)  # type: ignore[arg-type]


class ReusingRobot(ScriptedRobot):
    """Returns its readings in one buffer it overwrites at every step, as sensor drivers do."""

    def __init__(self) -> None:
        super().__init__()
        self.buffer = np.zeros((2, 6))

    def step(self, u: np.ndarray) -> sm.StepReadings:
        self.steps += 1
        self.buffer[:] = float(self.steps)
        return sm.StepReadings(self.buffer, np.array(u))


def test_the_readings_are_copies_of_what_the_robot_returns() -> None:
    readings = sm.run_period(CountingController(), ReusingRobot(), np.zeros(2), 4, 4)  # type: ignore[arg-type]
    assert np.all(readings.start.contact_wrenches == 1.0)
    assert np.all(readings.end.contact_wrenches == 4.0)
    np.testing.assert_allclose(readings.mean_contact_wrenches, np.full((2, 6), 2.5), rtol=1e-15)


class BadRobot(ScriptedRobot):
    """Returns ``reading(step)`` instead of its readings."""

    def __init__(self, reading) -> None:
        super().__init__()
        self.reading = reading

    def step(self, u: np.ndarray):  # type: ignore[override]
        self.steps += 1
        return self.reading(self.steps)


@pytest.mark.parametrize(
    "steps, inner, error, shown",
    [
        (40.0, 10, TypeError, "steps_per_tick: expected an integer, got 40.0"),
        (True, 10, TypeError, "steps_per_tick: expected an integer, got True"),
        (40, 2.5, TypeError, "steps_per_inner_tick: expected an integer, got 2.5"),
        (40, -1, ValueError, "steps_per_inner_tick: expected at least 1, got -1"),
    ],
)
def test_a_bad_step_count_is_refused_naming_it(steps, inner, error, shown) -> None:
    robot = ScriptedRobot()
    with pytest.raises(error) as info:
        sm.run_period(CountingController(), robot, np.zeros(2), steps, inner)  # type: ignore[arg-type]
    assert shown in str(info.value)
    assert robot.steps == 0  # refused before any step


@pytest.mark.parametrize(
    "reading, error, shown",
    [
        (lambda n: (np.zeros((2, 6)), np.zeros(2)), TypeError, "step 0 of the period): expected StepReadings, got tuple"),
        (lambda n: sm.StepReadings(np.zeros((6, 2)), np.zeros(2)), ValueError, "expected shape (n_contacts, 6), got shape [6, 2]"),
        (
            lambda n: sm.StepReadings(np.zeros((2, 6)) if n == 1 else np.zeros(6), np.zeros(2)),
            ValueError,
            "step 1 of the period): contact_wrenches: expected shape (2, 6), as the first step's, got shape [6]",
        ),
    ],
)
def test_readings_of_another_kind_or_shape_are_refused_naming_the_step(reading, error, shown) -> None:
    with pytest.raises(error) as info:
        sm.run_period(CountingController(), BadRobot(reading), np.zeros(2), 4, 4)  # type: ignore[arg-type]
    assert shown in str(info.value)


def test_the_loop_under_a_zero_order_hold_is_the_native_run() -> None:
    overrides = {
        "controller.sampling": "zero_order_hold",
        "plant.dt": 1e-3,
        "simulation.duration_s": 0.5,
        "simulation.record_every": 1,
    }
    run = sm.run_scenario(TRACKING, overrides)
    x_run = np.hstack([run.q, run.theta, run.nu, run.thetadot])
    states = sm.robot_loop.run(sm.Scenario.load(TRACKING, overrides))
    assert states.shape == x_run.shape
    scale = np.maximum(1.0, np.abs(x_run).max(axis=0))
    assert np.max(np.abs(states - x_run) / scale) < 1e-9
    with pytest.raises(ValueError, match="continuous"):
        sm.robot_loop.run(sm.Scenario.load(TRACKING, {"simulation.duration_s": 0.01}))


def test_the_plant_robot_pushes_by_the_step_start_time() -> None:
    scenario = sm.Scenario.load(WALK, {"simulation.duration_s": 0.01})
    times: list[float] = []

    def pushes(t: float) -> None:
        times.append(t)
        return None

    with pytest.raises(ValueError, match=r"x: expected shape \(113,\), got shape \[3\]"):
        sm.PlantRobot(scenario, x=np.zeros(3))
    with pytest.raises(TypeError, match="external: expected a function"):
        sm.PlantRobot(scenario, external=3)  # type: ignore[arg-type]
    robot = sm.PlantRobot(scenario, external=pushes)
    robot.state()[0] += 1.0  # a copy: the robot's state stays
    np.testing.assert_array_equal(robot.state(), scenario.initial_state)
    u = scenario.controller.tick(0.0, robot.state()).input
    readings = sm.run_period(scenario.controller, robot, u, scenario.steps_per_tick, scenario.steps_per_inner_tick)
    np.testing.assert_allclose(times, np.arange(scenario.steps_per_tick) * scenario.plant_dt, rtol=0, atol=1e-15)
    assert robot.time == pytest.approx(scenario.control_period)
    assert robot.outputs is not None
    np.testing.assert_array_equal(readings.end.contact_wrenches, robot.outputs.step_contact_wrenches)


def test_contact_point_counts_are_the_rows_of_the_point_outputs() -> None:
    plant = sm.Scenario.load(WALK, {"simulation.duration_s": 0.01}).plant
    counts = plant.contact_point_counts
    assert len(counts) == len(plant.contact_frames) == 2 and min(counts) > 0
    scenario = sm.Scenario.load(WALK, {"simulation.duration_s": 0.01})
    u = np.zeros(scenario.plant.nu_input)
    rows = scenario.plant.outputs(scenario.initial_state, u).contact_point_positions.shape[0]
    assert rows == sum(counts)
    bilateral = sm.Scenario.load(TRACKING, {"simulation.duration_s": 0.01}).plant
    assert bilateral.contact_point_counts == []


@pytest.mark.parametrize("call", [
    lambda: sm.PlantRobot(None),
    lambda: sm.robot_loop.run(None),
    lambda: sm.robot_loop.run("scenarios/walking/walk_straight.toml"),
])
def test_a_scenario_of_another_kind_is_refused_naming_it(call) -> None:
    with pytest.raises(TypeError, match="scenario: expected a sea_momentum.Scenario"):
        call()


def test_sensors_must_be_a_bool() -> None:
    scenario = sm.Scenario.load(ROOT / "scenarios" / "walking" / "walk_straight.toml")
    with pytest.raises(TypeError, match="sensors: expected True or False, got 'no'"):
        sm.robot_loop.run(scenario, sensors="no")
