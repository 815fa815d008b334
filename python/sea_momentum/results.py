"""Typed results of the native calls: :class:`SimulationResult` (``Plant.simulate``),
:class:`PlantOutputs` (``Plant.outputs``) and :class:`RunSummary` (the summary of a scenario
run). The native module builds them from numbers and numpy arrays; no JSON crosses the boundary.

Every array is a fresh, C-contiguous ``numpy.float64`` array owned by the result. Sizes: ``m``
recorded rows, ``nx = nq + nv + 2 n_e`` the state size, ``n`` joints, ``n_e`` elastic joints,
``n_contacts`` contact frames. Wrenches are ``[force (3); moment about the frame origin (3)]``
in world axes, SI units.

The results also answer ``result["name"]`` like the dicts they replace, so code written against
the dict results keeps working; new code should use the attributes.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Literal, Optional

import numpy as np
import numpy.typing as npt

Float64Array = npt.NDArray[np.float64]

#: How a plant simulation ended: every step done, or stopped at the first non-finite or
#: unsolvable step.
Status = Literal["completed", "diverged"]

#: How a scenario run ended: as :data:`Status`, or stopped by Ctrl-C ("interrupted").
RunStatus = Literal["completed", "diverged", "interrupted"]


class _ItemAccess:
    """``result["field"]`` for the fields of a dataclass (the dict results' interface)."""

    def __getitem__(self, key: str) -> Any:
        if key not in {field.name for field in dataclasses.fields(self)}:  # type: ignore[arg-type]
            raise KeyError(key)
        return getattr(self, key)

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict (arrays are not copied)."""
        return {field.name: getattr(self, field.name) for field in dataclasses.fields(self)}  # type: ignore[arg-type]


@dataclasses.dataclass(frozen=True)
class SimulationResult(_ItemAccess):
    """``Plant.simulate``: one row per recorded step (the initial state, every
    ``record_every``-th step and the last one), outputs evaluated at the row's state and the held
    input. Rows up to a divergence are kept."""

    time: Float64Array
    """(m,) float64, time of each row [s]."""
    x: Float64Array
    """(m, nx) float64, the state ``[q, theta, nu, thetadot]`` of each row."""
    contact_wrenches: Float64Array
    """(m, n_contacts, 6) float64, contact wrenches ``[force; moment]``, world axes [N, N m]."""
    motor_torques: Float64Array
    """(m, n_e) float64, applied motor torques (after saturation) [N m]."""
    drift_position: Float64Array
    """(m,) float64, largest contact position drift from the held pose [m]."""
    drift_rotation: Float64Array
    """(m,) float64, largest contact rotation drift from the held pose [rad]."""
    status: RunStatus
    """"completed", "diverged" or "interrupted" (Ctrl-C: the result is the
    ``KeyboardInterrupt``'s ``partial`` attribute, its last row the state reached)."""
    diverged_at: Optional[float]
    """Time of the divergence [s], None when completed or interrupted."""
    message: str
    """Why it diverged or when it was interrupted ("" when completed)."""


@dataclasses.dataclass(frozen=True)
class PlantOutputs(_ItemAccess):
    """``Plant.outputs``: the plant's outputs at one state and input."""

    contact_wrenches: Float64Array
    """(n_contacts, 6) float64, contact wrenches ``[force; moment]``, world axes [N, N m]."""
    joint_torques: Float64Array
    """(n,) float64, torque applied to each joint: the spring-damper torque of an elastic joint,
    the input of a rigid one [N m]."""
    motor_torques: Float64Array
    """(n_e,) float64, applied motor torques (after saturation) [N m]."""
    drift_position: float
    """Largest contact position drift from the held pose [m]."""
    drift_rotation: float
    """Largest contact rotation drift from the held pose [rad]."""
    normal_force: Float64Array
    """(n_contacts,) float64, normal force in the sole frame [N]; negative pulls the ground."""
    friction_margin: Float64Array
    """(n_contacts,) float64, ``mu f_z - |f_xy|`` in the sole frame [N]; negative outside the
    friction cone."""
    cop_margin: Float64Array
    """(n_contacts,) float64, distance of the centre of pressure inside the foot rectangle [m];
    negative outside."""


@dataclasses.dataclass(frozen=True)
class RunSummary(_ItemAccess):
    """Summary statistics of a closed-loop scenario run (the ``--summary`` JSON of ``sea-sim``)."""

    status: RunStatus
    """"completed", "diverged" or "interrupted"."""
    diverged_at_s: Optional[float]
    """Time of the divergence [s], None otherwise."""
    reason: str
    """Why it diverged (the quantity and its value) or "interrupted"; "" when completed."""
    sampling: str
    """Control sampling: "zero_order_hold" or "continuous"."""
    duration_s: float
    """Simulated time reached [s]."""
    com_error_rms_m: float
    """RMS of the CoM error norm [m]."""
    com_error_max_m: float
    """Largest CoM error norm [m]."""
    com_error_lateral_max_m: float
    """Largest lateral (y) CoM error after the first second [m]."""
    joint_error_norm_final_rad: float
    """``|s - s_d|`` at the last evaluated sample [rad]."""
    motor_velocity_peak_rad_s: float
    """Largest ``|thetadot|`` [rad/s]."""
    qp_failures: int
    """Control ticks whose QP failed (the controller fell back)."""
    qp_active_set_solves: int
    """Control ticks whose QP the active-set solver solved."""
    qp_clarabel_solves: int
    """Control ticks whose QP Clarabel solved (``controller.qp_solver = "clarabel"``, or the
    active set's fallback; the ticks solved by neither: the minimiser without the
    inequalities was feasible, hence optimal)."""
    wall_time_s: float
    """Wall-clock time of the run [s]."""
    realtime_factor: float
    """Simulated time / wall-clock time."""
