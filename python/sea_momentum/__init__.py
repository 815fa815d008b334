"""sea-momentum: momentum-based balancing of humanoid robots with series elastic actuators.

Conventions (the same everywhere):

- configuration ``q = [p_B (3, world), quaternion (w, x, y, z), s (n)]``, ``nq = 7 + n``;
- velocity ``nu = [pdot_B (3, world), omega_B (3, world axes), sdot (n)]``, ``nv = 6 + n``;
- spatial vectors and wrenches: linear part first, angular second;
- ``M(q) nudot + h(q, nu) = B tau + sum_k J_k^T f_k``, gravity -9.81 m/s^2 along world z.

The library needs numpy only; plots need the extra ``plots`` (matplotlib), see the guide's
install section. ``NATIVE_MODULE`` names the compiled module in use (``_native``, or
``_native_v3`` on an x86-64-v3 CPU with the distributable wheel; :mod:`._native_choice`).
"""

from ._native_choice import NATIVE_MODULE
from ._native import (
    ICUB25_JOINTS,
    Controller,
    Model,
    ModelError,
    Plant,
    Scenario,
    ScenarioError,
    SeaError,
    SeaIOError,
    SolverError,
    __version__,
    init_scenario,
)
from .analysis import Linearization, linearize, stability_margin
from .push import PushRow, PushTable, TemplateRow, push_table, template_push_table
from .closed_loop_rhs import closed_loop_rhs
from .controller import ControlOutput
from . import robot_loop
from .results import PlantOutputs, RunSummary, SimulationResult
from .robot_loop import PeriodReadings, PlantRobot, Robot, StepReadings, run_period
from .scenario import ScenarioResult, run_scenario
from .sweep import SweepResult, sweep

__all__ = [
    "init_scenario",
    "PushRow",
    "PushTable",
    "push_table",
    "template_push_table",
    "TemplateRow",
    "ICUB25_JOINTS",
    "NATIVE_MODULE",
    "ControlOutput",
    "Controller",
    "Linearization",
    "PeriodReadings",
    "Model",
    "ModelError",
    "Plant",
    "PlantOutputs",
    "PlantRobot",
    "Robot",
    "Scenario",
    "RunSummary",
    "ScenarioError",
    "ScenarioResult",
    "SeaError",
    "SeaIOError",
    "SimulationResult",
    "SolverError",
    "StepReadings",
    "SweepResult",
    "closed_loop_rhs",
    "linearize",
    "robot_loop",
    "run_period",
    "run_scenario",
    "stability_margin",
    "sweep",
    "__version__",
]
