"""The closed loop in continuous time as a plain right-hand side, for external ODE solvers.

``controller.sampling = "continuous"`` (the paper's setting: its controller runs inside
ode15s's right-hand side) means ``xdot = F(x, u(t, x))``: the plant's dynamics with the
controller evaluated at the same time and state. :func:`closed_loop_rhs` builds that function
from a :class:`~sea_momentum.Scenario`, so that scipy (``solve_ivp(method="Radau")``, the open
analogue of ode15s) can solve the closed loop independently of the native integrator.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

import numpy as np

from .arrays import FloatArray

if TYPE_CHECKING:
    from ._native import Scenario

#: Where the base quaternion (w, x, y, z) sits in the state ``x = [q, theta, nu, thetadot]``:
#: ``q = [p_B (3), quaternion (4), s (n)]``.
QUATERNION = slice(3, 7)


def closed_loop_rhs(scenario: Scenario) -> Callable[[float, FloatArray], FloatArray]:
    """The closed-loop vector field ``f(t, x) = plant.dynamics(x, controller.tick(t, x).input)``.

    ``scenario`` is a :class:`~sea_momentum.Scenario` (``Scenario.load(path, overrides)``); the
    function uses its ``plant`` and ``controller`` (the scenario's references included), whatever
    its ``sampling`` says. ``x`` is the plant state (``plant.nx``, as ``scenario.initial_state``);
    the result is ``dx/dt`` (nx), quaternion rate included, the way ``solve_ivp`` wants it:

        rhs = closed_loop_rhs(scenario)
        solve_ivp(rhs, (0.0, 0.3), scenario.initial_state, method="Radau", rtol=1e-10)

    The state's quaternion is normalised before the evaluation: the exact flow keeps
    ``|quaternion| = 1``, but a solver's stages and its finite-difference Jacobian move off that
    sphere slightly, and the plant refuses a quaternion whose norm is off by more than 1e-4.
    ``x`` itself is not modified.

    The function holds the scenario's (stateless) controller and plant and their buffers: like
    them it is not thread-safe. Plant or controller failures raise their ``SeaError``.
    """
    plant = scenario.plant
    controller = scenario.controller

    def rhs(t: float, x: FloatArray) -> FloatArray:
        x_unit = np.array(x, dtype=np.float64)  # a copy: the solver's array stays as it is
        x_unit[QUATERNION] /= np.linalg.norm(x_unit[QUATERNION])
        u = controller.tick(float(t), x_unit).input
        return plant.dynamics(x_unit, u)

    return rhs
