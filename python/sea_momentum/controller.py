"""The momentum controller as an object: :class:`ControlOutput`, what one
``Controller.tick(t, x)`` returns (the classes ``Controller`` and ``Scenario`` are native, see
``sea_momentum._native``, which builds this result from its fields)."""

from __future__ import annotations

import dataclasses
from typing import Literal

from .arrays import FloatArray
from .results import Result


@dataclasses.dataclass(frozen=True)
class ControlOutput(Result):
    """One controller tick (world axes, SI units; every array ``numpy.float64``).

    ``n`` joints, ``n_e`` elastic joints, ``n_contacts`` contacts (``Controller.contacts``).
    A :class:`~sea_momentum.results.Result`: ``out["input"]`` and ``out.to_dict()`` work too.
    """

    input: FloatArray  #: (n,) plant input: rigid joints torque, elastic joints desired motor velocity (SEA controller) or motor torque (rigid controller)
    joint_command: FloatArray  #: (n,) tau* (rigid controller) or beta* (SEA), joint side [N m]
    thetadot_desired: FloatArray  #: (n_e,) desired motor velocities [rad/s] (empty: rigid controller)
    wrenches: FloatArray  #: (n_contacts, 6) QP contact wrenches [force; torque], world axes, about the contact frame origins
    qp_status: Literal["solved", "momentum_relaxed", "fallback"]  #: "momentum_relaxed": the momentum equality was infeasible, the closest feasible momentum rate was used; "fallback": the QP failed, the unconstrained solution was used
    qp_message: str  #: why the QP failed ("" when solved)
    com: FloatArray  #: (3,) CoM, world [m]
    momentum: FloatArray  #: (6,) centroidal momentum [m pdot_com; L_com]
    external_wrench: FloatArray  #: (6,) the external wrench the tick's dynamics took on the base, [force; moment about the CoM], world axes (``Controller.set_external_wrench``; zeros: none)
    com_reference: FloatArray  #: (3,) the CoM reference at t, world [m]
