"""Typed results, one pattern for all: every result of the package is a frozen dataclass
deriving from :class:`Result`, which answers ``result["name"]`` like the dicts the results
replace (so code written against the dict results keeps working; new code should use the
attributes), gives ``to_dict()`` and is built from the native module's fields by
``from_native``.

Defined here: :class:`SimulationResult` (``Plant.simulate``), :class:`PlantOutputs`
(``Plant.outputs``) and :class:`RunSummary` (the summary of a scenario run), which the native
module builds from numbers and numpy arrays as ``from_native`` does by default, the fields as
keyword arguments (no JSON crosses the boundary). The other results
follow the same pattern beside the function returning them:
:class:`~sea_momentum.controller.ControlOutput`, :class:`~sea_momentum.scenario.ScenarioResult`,
:class:`~sea_momentum.analysis.Linearization`, :class:`~sea_momentum.sweep.SweepResult`.

Every array is a fresh, C-contiguous ``numpy.float64`` array owned by the result
(:data:`~sea_momentum.arrays.FloatArray`). Sizes: ``m`` recorded rows,
``nx = nq + nv + 2 n_e`` the state size, ``n`` joints, ``n_e`` elastic joints, ``n_contacts``
contact frames. Wrenches are ``[force (3); moment about the frame origin (3)]`` in world axes,
SI units.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Literal, Mapping, Optional, TypeVar

from .arrays import BoolArray, FloatArray

#: How a plant simulation ended: every step done, or stopped at the first non-finite or
#: unsolvable step.
Status = Literal["completed", "diverged"]

#: How a scenario run ended: as :data:`Status`, stopped by Ctrl-C ("interrupted"), or a foot's
#: contact wrench left what a unilateral contact with friction transmits ("fell").
RunStatus = Literal["completed", "diverged", "interrupted", "fell"]

_R = TypeVar("_R", bound="Result")


class Result:
    """Base of every typed result (subclasses are frozen dataclasses).

    - ``result.field``: the typed attribute (preferred);
    - ``result["field"]``: the same, the interface of the dict results (``KeyError`` for an
      unknown name);
    - ``result.to_dict()``: the fields as a dict (arrays not copied), e.g. for JSON;
    - ``Cls.from_native(fields)``: the result built from the native module's fields (by default
      the fields are the keyword arguments; a subclass converts what needs converting).
    """

    def __getitem__(self, key: str) -> Any:
        """The field ``key`` (``KeyError`` naming it when the result has no such field)."""
        if key not in {field.name for field in dataclasses.fields(self)}:  # type: ignore[arg-type]
            raise KeyError(key)
        return getattr(self, key)

    def to_dict(self) -> dict[str, Any]:
        """The fields as a dict (arrays are not copied)."""
        return {field.name: getattr(self, field.name) for field in dataclasses.fields(self)}  # type: ignore[arg-type]

    @classmethod
    def from_native(cls: type[_R], fields: Mapping[str, Any]) -> _R:
        """The result of the native module's ``fields`` (the keyword arguments)."""
        return cls(**fields)


@dataclasses.dataclass(frozen=True)
class SimulationResult(Result):
    """``Plant.simulate``: one row per recorded step (the initial state, every
    ``record_every``-th step and the last one), outputs evaluated at the row's state and the held
    input. Rows up to a divergence are kept."""

    time: FloatArray
    """(m,) float64, time of each row [s]."""
    x: FloatArray
    """(m, nx) float64, the state ``[q, theta, nu, thetadot]`` of each row."""
    contact_wrenches: FloatArray
    """(m, n_contacts, 6) float64, contact wrenches ``[force; moment]``, world axes [N, N m]."""
    motor_torques: FloatArray
    """(m, n_e) float64, applied motor torques (after saturation) [N m]."""
    drift_position: FloatArray
    """(m,) float64, largest contact position drift from the held pose [m]."""
    drift_rotation: FloatArray
    """(m,) float64, largest contact rotation drift from the held pose [rad]."""
    status: RunStatus
    """"completed", "diverged" or "interrupted" (Ctrl-C: the result is the
    ``KeyboardInterrupt``'s ``partial`` attribute, its last row the state reached)."""
    diverged_at: Optional[float]
    """Time of the divergence [s], None when completed or interrupted."""
    message: str
    """Why it diverged or when it was interrupted ("" when completed)."""


@dataclasses.dataclass(frozen=True)
class PlantOutputs(Result):
    """``Plant.outputs``: the plant's outputs at one state and input."""

    contact_wrenches: FloatArray
    """(n_contacts, 6) float64, contact wrenches ``[force; moment]``, world axes [N, N m]."""
    joint_torques: FloatArray
    """(n,) float64, torque applied to each joint: the spring-damper torque of an elastic joint,
    the input of a rigid one [N m]."""
    motor_torques: FloatArray
    """(n_e,) float64, applied motor torques (after saturation) [N m]."""
    drift_position: float
    """Largest contact position drift from the held pose [m]."""
    drift_rotation: float
    """Largest contact rotation drift from the held pose [rad]."""
    normal_force: FloatArray
    """(n_contacts,) float64, normal force in the sole frame [N]; negative pulls the ground."""
    friction_margin: FloatArray
    """(n_contacts,) float64, ``mu f_z - |f_xy|`` in the sole frame [N]; negative outside the
    friction cone."""
    cop_margin: FloatArray
    """(n_contacts,) float64, distance of the centre of pressure inside the foot rectangle [m];
    negative outside."""
    step_contact_wrenches: FloatArray
    """(n_contacts, 6) float64, after :meth:`Plant.step_outputs`: the wrenches the step
    delivered (its effective average; under unilateral contacts what the feet's sensors read
    over the step); otherwise equal to ``contact_wrenches``."""
    contact_point_positions: FloatArray
    """(n_points, 3) float64, unilateral contacts: each contact point, world [m] (contacts in
    order; empty under bilateral contacts)."""
    contact_point_forces: FloatArray
    """(n_points, 3) float64, unilateral contacts: each point's force on its foot, world axes
    [N]."""
    contact_point_active: BoolArray
    """(n_points,) bool, unilateral contacts: whether each point carries a force."""
    joint_stop_torques: FloatArray
    """(n,) float64, the torque of each joint's stop [N m] (zeros without stops or off them)."""


@dataclasses.dataclass(frozen=True)
class RunSummary(Result):
    """Summary statistics of a closed-loop scenario run (the ``--summary`` JSON of ``sea-sim``).

    Its fields are the keys of the Rust summary's one serialisation (``Summary`` in
    ``sea_sim::closed_loop``), built with :meth:`Result.from_native` from those keys: a key on
    one side only fails here, and ``crates/sea_sim/tests/summary_keys.rs`` checks the key sets
    of the Rust JSON, this class and ``sea-sim run`` agree."""

    status: RunStatus
    """"completed", "diverged", "interrupted" or "fell"."""
    diverged_at_s: Optional[float]
    """Time of the divergence [s], None otherwise."""
    fell_at_s: Optional[float]
    """Time of the fall [s] (status "fell"), None otherwise."""
    fall_foot: Optional[str]
    """The contact frame whose wrench violated a constraint (status "fell" under bilateral
    contacts), "" under unilateral contacts."""
    fall_link: Optional[str]
    """The link that reached the ground (``fall_constraint`` "link_on_ground"), else ""."""
    fall_constraint: Optional[
        Literal[
            "normal_force", "friction", "center_of_pressure", "base_height", "tilt", "link_on_ground"
        ]
    ]
    """Bilateral contacts: which constraint of the foot's wrench (normal force > 0, friction
    cone, CoP inside the sole). Unilateral contacts: how the robot reached the ground (the base
    below a fraction of its initial height, tilted past a bound, a link on the ground)."""
    fall_value: Optional[float]
    """The crossing value: normal force [N], friction ratio ``|f_t| / f_z``, CoP coordinate in
    the sole frame [m], base height [m], tilt [rad] or the link's height [m] (status "fell")."""
    fall_bound: Optional[float]
    """The bound crossed: 0 N, ``mu``, the sole edge [m], the height bound [m], the tilt bound
    [rad] or 0 m (status "fell")."""
    reason: str
    """Why it diverged (the quantity and its value), fell (the foot and constraint) or
    "interrupted"; "" when completed."""
    reason_kind: Optional[str]
    """The reason's stable machine-readable kind: "interrupted", the divergence's (e.g.
    "com_error_over_bound", "joint_error_over_bound", "joint_outside_limits") or the fall's
    constraint ("normal_force", "friction", "center_of_pressure"); None when completed."""
    sampling: str
    """Control sampling: "zero_order_hold", "continuous" or "multi_rate"."""
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
    qp_relaxed_solves: int
    """Control ticks whose momentum equality was infeasible and that the relaxed momentum task
    solved (``controller.momentum_relaxation = "when_infeasible"``)."""
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
    stiffness_estimates_nm_per_rad: dict[str, float]
    """``controller.sampling = "multi_rate"``: the joint loops' stiffness estimates at the run's
    end [Nm/rad] by elastic joint name (identified with ``controller.stiffness_identification``,
    else the controller's); empty otherwise. Not a sweep column."""
    contact_check_violations: int
    """Unilateral contacts: samples whose delivered wrenches the bilateral contacts' wrench check
    would have called a fall (a foot lifted, tipping or slipping); 0 under bilateral contacts."""
    contact_check_first_s: Optional[float]
    """Time of the first such sample [s], None without one."""
    touchdowns: int
    """Touchdowns of the feet (``plant.contact_model = "unilateral"``): a foot whose contact
    points carried no force at a plant step and carry force at the next; 0 otherwise."""
    touchdown_velocity_jump_m_s: Optional[float]
    """Largest velocity jump of a touchdown [m/s]: the foot's normal speed towards the ground
    at its touching points (those carrying force at the touchdown) over the millisecond
    before it, minus that over the millisecond ending 5 ms after it; None without a
    touchdown."""
    touchdown_peak_spring_torque_nm: Optional[float]
    """Largest spring torque ``|K_S (Gamma theta - s)|`` of an elastic joint over the 50 ms
    after a touchdown, at plant-step resolution [N m]; None without a touchdown."""
    touchdown_peak_motor_velocity_rad_s: Optional[float]
    """Largest ``|thetadot|`` over the 50 ms after a touchdown, at plant-step resolution
    [rad/s] (``motor_velocity_peak_rad_s`` is over the control samples only); None without a
    touchdown."""
    steps_taken: Optional[int]
    """``[walking]``: the planned steps whose touchdown time the run reached; None when the
    robot does not walk."""
    distance_walked_m: Optional[float]
    """``[walking]``: horizontal distance between the feet's mid-points at the start and at
    the run's end [m]; None when the robot does not walk."""
    walking_speed_m_s: Optional[float]
    """``[walking]``: ``distance_walked_m`` over the time from the first lift-off to the last
    touchdown (or the run's end) [m/s]; None when the robot does not walk."""
    turned_rad: Optional[float]
    """``[walking]``: the yaw the feet turned, start to end (the soles' mean heading at the
    end minus the walking frame's at the start), counter-clockwise positive, wrapped into
    (-pi, pi] [rad]; None when the robot does not walk."""
