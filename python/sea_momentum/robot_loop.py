"""The robot's loop in Python: the controller stack driving a plant one whole-body period at a
time, as on a robot.

Per period ``T`` (``Scenario.control_period``):

1. ``Controller.tick(t, x)`` at the period's state: the whole-body law, the plant input ``u``;
2. ``Scenario.steps_per_tick`` plant steps, with ``Controller.inner_tick(x)`` (the 1 kHz joint
   torque loops) before every ``steps_per_inner_tick``-th step but the first
   (``multi_rate``; under ``zero_order_hold`` the tick's input is held);
3. ``Controller.end_period`` with what the sensors read over the period
   (:class:`PeriodReadings`: the feet's wrenches and the joint torques over its first and last
   steps, and the feet's wrenches averaged over its steps), from which the stiffness
   identification, the observers and the touchdown detection update.

:func:`run_period` is steps 2 and 3's readings for any :class:`Robot`: our plant
(:class:`PlantRobot`), another simulator (``examples/mujoco_sea_icub.py`` drives MuJoCo), a
robot. :func:`run` is the whole loop, by default on the scenario's plant, where it is
``run_scenario``'s run to round-off (``python_tests/test_controller_object.py``). A push is the robot's business, not the loop's:
:class:`PlantRobot` takes one as ``external``.
"""

from __future__ import annotations

import dataclasses
import operator
from typing import Callable, Mapping, Optional, Protocol

import numpy as np
from numpy.typing import ArrayLike

from ._errors import argument_error
from ._native import Controller, Scenario
from .arrays import FloatArray
from .controller import ControlOutput
from .results import PlantOutputs

#: A push schedule: the external wrenches acting over the plant step that starts at time ``t``
#: [s], ``{link: force (3) or wrench (6) [force; moment]}`` at the link's origin, world axes
#: (``Plant.step``'s ``external``), or None for none.
Pushes = Callable[[float], Optional[Mapping[str, ArrayLike]]]


@dataclasses.dataclass(frozen=True)
class StepReadings:
    """What the sensors read over one plant step."""

    contact_wrenches: FloatArray  #: (n_contacts, 6) the feet's force/torque sensors, world axes [N, N m]
    joint_torques: FloatArray  #: (n,) the joint torque sensors [N m]


@dataclasses.dataclass(frozen=True)
class PeriodReadings:
    """What ``Controller.end_period`` takes after one whole-body period."""

    start: StepReadings  #: over the period's first plant step
    end: StepReadings  #: over its last plant step
    mean_contact_wrenches: FloatArray  #: (n_contacts, 6) the feet's wrenches averaged over its steps

    def hand_to(self, controller: Controller) -> None:
        """``controller.end_period`` with these readings (the mean included, which the push
        observer takes: the native run hands it too)."""
        controller.end_period(
            self.start.contact_wrenches,
            self.start.joint_torques,
            self.end.contact_wrenches,
            self.end.joint_torques,
            mean_wrenches=self.mean_contact_wrenches,
        )


class Robot(Protocol):
    """What the loop needs of a plant: its state and one step under an input."""

    def state(self) -> FloatArray:
        """The state ``[q, theta, nu, thetadot]`` (the encoders and the base estimate)."""

    def step(self, u: FloatArray) -> StepReadings:
        """One plant step under the input ``u`` (n); what the sensors read over it."""


class PlantRobot:
    """Our plant (a scenario's ``Scenario.plant``) as a :class:`Robot`: steps of the
    scenario's ``plant_dt`` and ``method`` from its initial state (or ``x``), the pushes of
    ``external`` (:data:`Pushes`, by the step's start time) through ``Plant.step``. Errors of
    ``Plant.step`` (``SolverError``, ``ValueError``) propagate; the state stays the last good
    one."""

    def __init__(self, scenario: Scenario, x: ArrayLike | None = None,
                 external: Pushes | None = None) -> None:
        _check_scenario(scenario)
        self.plant = scenario.plant
        self.dt, self.method = scenario.plant_dt, scenario.method
        self.x: FloatArray = np.array(scenario.initial_state if x is None else x, dtype=float)
        if self.x.shape != (self.plant.nx,):
            shape = list(self.x.shape)
            raise argument_error("x", f"expected shape ({self.plant.nx},), got shape {shape}")
        if external is not None and not callable(external):
            raise TypeError(f"external: expected a function of the time or None, got {external!r}")
        self.external = external
        self.steps_taken = 0  #: plant steps since construction
        self.outputs: PlantOutputs | None = None  #: the last step's ``Plant.step_outputs()``

    @property
    def time(self) -> float:
        """The time since construction [s]: ``steps_taken * dt``."""
        return self.steps_taken * self.dt

    def state(self) -> FloatArray:
        """The plant's state (a copy)."""
        return self.x.copy()

    def step(self, u: FloatArray) -> StepReadings:
        """One plant step; the wrenches it delivered and the joint torques at its start
        (``Plant.step_outputs``)."""
        pushes = self.external(self.time) if self.external is not None else None
        self.x = self.plant.step(self.x, u, self.dt, self.method, external=pushes)
        self.steps_taken += 1
        self.outputs = self.plant.step_outputs()
        return StepReadings(self.outputs.step_contact_wrenches, self.outputs.joint_torques)


def _check_scenario(scenario: object) -> None:
    """Refuses an argument ``scenario`` that is not a loaded :class:`Scenario`."""
    if not isinstance(scenario, Scenario):
        raise TypeError(f"scenario: expected a sea_momentum.Scenario (Scenario.load(path)), got {scenario!r}")


def _count(value: object, name: str) -> int:
    """``value`` as a step count of at least 1; ``ValueError`` / ``TypeError`` naming ``name``."""
    if isinstance(value, bool):
        raise TypeError(f"{name}: expected an integer, got {value!r}")
    try:
        count = operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        raise TypeError(f"{name}: expected an integer, got {value!r}") from None
    if count < 1:
        raise argument_error(name, f"expected at least 1, got {count}")
    return count


def _checked(readings: object, step: int, shape: tuple[int, ...] | None) -> StepReadings:
    """A robot's readings of plant step ``step`` of the period, copied (a robot may reuse its
    buffers), their wrenches of ``shape`` (the first step's) or ``(n_contacts, 6)``."""
    if not isinstance(readings, StepReadings):
        raise TypeError(f"robot.step (step {step} of the period): expected StepReadings, "
                        f"got {type(readings).__name__}")
    wrenches = np.array(readings.contact_wrenches, dtype=float)
    if wrenches.ndim != 2 or wrenches.shape[1] != 6 or (shape is not None and wrenches.shape != shape):
        expected = f"({shape[0]}, 6), as the first step's" if shape else "(n_contacts, 6)"
        raise ValueError(f"robot.step (step {step} of the period): contact_wrenches: expected "
                         f"shape {expected}, got shape {list(wrenches.shape)}")
    return StepReadings(wrenches, np.array(readings.joint_torques, dtype=float))


def run_period(controller: Controller, robot: Robot, u: FloatArray, steps_per_tick: int,
               steps_per_inner_tick: int) -> PeriodReadings:
    """One whole-body period from the tick's input ``u``: ``steps_per_tick`` steps of
    ``robot``, with ``controller.inner_tick`` after every ``steps_per_inner_tick`` of them
    (before steps ``j = steps_per_inner_tick, 2 steps_per_inner_tick, ...``, counted from 0;
    pass ``steps_per_tick`` to hold ``u``, as ``zero_order_hold`` does); the period's readings
    (copies). A robot's error ends the period and propagates; readings that are not
    :class:`StepReadings` with ``(n_contacts, 6)`` wrenches, the same at every step, raise
    naming the step."""
    steps = _count(steps_per_tick, "steps_per_tick")
    inner = _count(steps_per_inner_tick, "steps_per_inner_tick")
    start: StepReadings | None = None
    total = np.zeros(0)
    for j in range(steps):
        if j > 0 and j % inner == 0:
            u = controller.inner_tick(robot.state())
        readings = _checked(robot.step(u), j, None if start is None else start.contact_wrenches.shape)
        if start is None:
            start, total = readings, readings.contact_wrenches.copy()
        else:
            total += readings.contact_wrenches
    assert start is not None
    return PeriodReadings(start, readings, total / steps)


def run(scenario: Scenario, robot: Robot | None = None, controller: Controller | None = None,
        *, sensors: bool = True,
        on_tick: Callable[[int, ControlOutput], None] | None = None) -> FloatArray:
    """The robot's loop over the scenario's duration: per tick ``k`` (``0..last_tick``)
    ``controller.tick(k T, x)``, then (but after the last) :func:`run_period` and, with
    ``sensors``, ``end_period`` (without, the identification, the observers and the
    touchdown detection stand still). ``robot``: by default the scenario's plant
    (:class:`PlantRobot`); ``controller``: by default the scenario's; ``on_tick(k, out)``: called
    with each tick's output, e.g. to record it. The state at every tick, (last_tick + 1, nx).
    A scenario's controller and plant are one object each that keeps its state from run to
    run: load the scenario again for a second run. Under ``sampling = "continuous"`` (the law
    at every integrator stage, not a loop of ticks) raises ``ValueError``."""
    _check_scenario(scenario)
    if not isinstance(sensors, bool):
        raise TypeError(f"sensors: expected True or False, got {sensors!r}")
    if scenario.sampling == "continuous":
        raise argument_error("scenario", 'sampling = "continuous" evaluates the law at every '
                             "integrator stage, which a loop of ticks does not; use "
                             "zero_order_hold or multi_rate")
    robot = robot if robot is not None else PlantRobot(scenario)
    controller = controller if controller is not None else scenario.controller
    steps, inner = scenario.steps_per_tick, scenario.steps_per_inner_tick
    states = []
    for k in range(scenario.last_tick + 1):
        x = robot.state()
        states.append(np.array(x))
        out = controller.tick(k * scenario.control_period, x)
        if on_tick is not None:
            on_tick(k, out)
        u = out.input
        if k == scenario.last_tick:
            break
        readings = run_period(controller, robot, u, steps, inner)
        if sensors:
            readings.hand_to(controller)
    return np.array(states)
