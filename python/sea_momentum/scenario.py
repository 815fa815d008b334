"""Closed-loop scenarios from Python: :func:`run_scenario` runs a TOML scenario natively (the
GIL is released) and returns a :class:`ScenarioResult` of numpy arrays."""

from __future__ import annotations

import dataclasses
import os
from typing import Any, Mapping, Sequence

import numpy as np

from ._errors import argument_error
from ._native import run_scenario_native
from .arrays import BoolArray, FloatArray
from .results import Result, RunStatus, RunSummary


@dataclasses.dataclass(frozen=True)
class ScenarioResult(Result):
    """The recorded run, one row per recorded control tick (world axes, SI units).

    Every array is ``numpy.float64``; ``m`` rows, ``n_e`` elastic joints. ``q``, ``nu``,
    ``theta`` and ``thetadot`` are views into one (m, nx) state array. A
    :class:`~sea_momentum.results.Result`: ``result["com"]`` and ``result.to_dict()`` work too.

    The joints of ``q`` and ``nu`` are in the scenario's order (``joint_names``: its
    ``robot.joints``, by default the robot description's), which need not be the URDF's.
    For the kinematics of a recorded ``q`` use the run's model,
    ``Scenario.load(path, overrides).model`` (or
    ``Model.from_urdf(urdf, joints=result.joint_names)``), not ``Model.from_urdf(urdf)``.
    """

    time: FloatArray  #: (m,) float64, time [s]
    q: FloatArray  #: (m, nq) float64, configurations
    nu: FloatArray  #: (m, nv) float64, velocities
    theta: FloatArray  #: (m, n_e) float64, motor angles [rad]
    thetadot: FloatArray  #: (m, n_e) float64, motor velocities [rad/s]
    thetadot_desired: FloatArray  #: (m, n_e) float64, desired motor velocities (0: rigid control)
    com: FloatArray  #: (m, 3) float64, CoM, world [m]
    com_reference: FloatArray  #: (m, 3) float64, CoM reference, world [m]
    momentum: FloatArray  #: (m, 6) float64, centroidal momentum [m pdot_com; L_com]
    #: (m, n_contacts, 6) float64, simulated wrenches, world axes; under unilateral contacts
    #: those delivered over each sample's first plant step (what moves the robot, what the
    #: feet's sensors read)
    contact_wrenches: FloatArray
    #: (m, n_contacts, 6) float64, the wrenches the controller's QP planned for the contacts
    #: at each tick, as ``contact_wrenches`` (at the frame origins, world axes): what the law
    #: asked each contact to carry, to compare with ``contact_wrenches`` (a swinging foot's
    #: are zero, or hundredths of a newton while an early touchdown holds it)
    planned_wrenches: FloatArray
    motor_torques: FloatArray  #: (m, n_e) float64, applied motor torques [N m]
    joint_error_norm: FloatArray  #: (m,) float64, |s - s_d| [rad]
    qp_solved: FloatArray  #: (m,) float64, 1 solved (the relaxed momentum task included), 0 fallback
    #: (m, 6) float64, the ``[[disturbances]]`` acting from each sample on, summed:
    #: [force; torque], world axes, each torque about its link's origin (zero: no push)
    disturbance_wrench: FloatArray
    #: (m, 6) float64, the external wrench the controller's dynamics took at each tick:
    #: [force; moment about the CoM], world axes (``controller.external_wrench = "observed"``:
    #: the observer's estimate; ``"generalized"``: the disturbance estimate's base rows as a
    #: wrench about the CoM; zero otherwise)
    external_wrench: FloatArray
    joint_names: list[str]  #: joint names in coordinate order
    elastic_joints: list[str]  #: elastic joint names, the columns of the motor arrays
    contacts: list[str]  #: contact frame names, the second axis of ``contact_wrenches`` and ``planned_wrenches``
    #: Unilateral contacts (``plant.contact_model = "unilateral"``): the number of points of
    #: each contact, in the order of ``contacts``; the ``n_points`` points are the contacts'
    #: points in that order. Empty under bilateral contacts (``n_points = 0``).
    contact_points: list[int]
    #: (m, n_points, 3) float64, each contact point's position, world [m]
    contact_point_positions: FloatArray
    #: (m, n_points, 3) float64, each contact point's force on its foot, world axes [N], at
    #: the sample's state: they add up to ``contact_wrenches`` but at an impact or a
    #: stick-slip change within the sample's first plant step
    contact_point_forces: FloatArray
    #: (m, n_points) bool, whether each contact point carries a force (touches the ground)
    contact_point_active: BoolArray
    #: (3,) float64, the ground's unit normal (world axes, out of the ground); None under
    #: bilateral contacts
    ground_normal: FloatArray | None
    summary: RunSummary  #: summary statistics (also answers ``summary["field"]``)

    @property
    def status(self) -> RunStatus:
        """"completed", "diverged", "interrupted" or "fell"."""
        return self.summary.status

    def motor(self, joint: str) -> int:
        """Column of an elastic joint in the motor arrays."""
        return self.elastic_joints.index(joint)

    def contact_point_slice(self, contact: str) -> slice:
        """The columns of contact ``contact``'s points in the contact point arrays (an empty
        slice under bilateral contacts); ``ValueError`` naming it when it is not a contact."""
        if contact not in self.contacts:
            raise argument_error("contact", f"expected one of {self.contacts}, got {contact!r}")
        if not self.contact_points:
            return slice(0, 0)
        k = self.contacts.index(contact)
        start = sum(self.contact_points[:k])
        return slice(start, start + self.contact_points[k])

    def contact_point_normal_forces(self) -> FloatArray:
        """(m, n_points) float64, each contact point's force along the ground's normal [N]
        (0 when it does not touch); (m, 0) under bilateral contacts."""
        if self.ground_normal is None:
            return np.zeros((len(self.time), 0))
        return np.asarray(self.contact_point_forces @ self.ground_normal, dtype=np.float64)

    @classmethod
    def from_native(cls, fields: Mapping[str, Any]) -> ScenarioResult:
        """The result of ``run_scenario_native``'s dict: the state ``x`` split into its views,
        the summary as a :class:`~sea_momentum.results.RunSummary`."""
        nq, nv, ne = fields["nq"], fields["nv"], fields["ne"]
        x = fields["x"]
        return cls(
            time=fields["time"],
            q=x[:, :nq],
            theta=x[:, nq : nq + ne],
            nu=x[:, nq + ne : nq + ne + nv],
            thetadot=x[:, nq + ne + nv :],
            thetadot_desired=fields["thetadot_desired"],
            com=fields["com"],
            com_reference=fields["com_reference"],
            momentum=fields["momentum"],
            contact_wrenches=fields["contact_wrenches"],
            planned_wrenches=fields["planned_wrenches"],
            motor_torques=fields["motor_torques"],
            joint_error_norm=fields["joint_error_norm"],
            qp_solved=fields["qp_solved"],
            disturbance_wrench=fields["disturbance_wrench"],
            external_wrench=fields["external_wrench"],
            joint_names=list(fields["joint_names"]),
            elastic_joints=list(fields["elastic_joints"]),
            contacts=list(fields["contacts"]),
            contact_points=list(fields["contact_points"]),
            contact_point_positions=fields["contact_point_positions"],
            contact_point_forces=fields["contact_point_forces"],
            contact_point_active=fields["contact_point_active"],
            ground_normal=fields["ground_normal"],
            summary=RunSummary.from_native(fields["summary"]),
        )


def package_folders(package_dirs: Sequence[str | os.PathLike[str]]) -> list[str]:
    """The folders of a ``package_dirs`` argument as strings; a single path (a ``str`` or path
    object, not a sequence of them) raises ``TypeError`` naming ``package_dirs`` instead of
    being read as a sequence of one-letter folders."""
    if isinstance(package_dirs, (str, bytes, os.PathLike)):
        raise TypeError(
            f"package_dirs: expected a sequence of folders, got the single path {package_dirs!r} "
            f"(write [{package_dirs!r}])"
        )
    return [os.fspath(d) for d in package_dirs]

def run_scenario(
    path: str | os.PathLike[str],
    overrides: Mapping[str, Any] | None = None,
    mcap: str | os.PathLike[str] | None = None,
    progress: bool = False,
    package_dirs: Sequence[str | os.PathLike[str]] = (),
) -> ScenarioResult:
    """Runs the scenario file ``path``.

    ``overrides`` maps dotted keys to values, e.g. ``{"controller.kind": "rigid",
    "controller.damping_estimate_scale": 1.45, "simulation.duration_s": 5}``; unknown keys raise
    ``ValueError`` naming the key. ``mcap`` writes a Foxglove-ready log (finished even when the
    run diverges), written beside its path as ``.NAME.partial`` and renamed over it when the
    run ends, so that a run that fails leaves an earlier file at the path untouched; the path
    must be a regular file (not ``/dev/null``), and none of the scenario's input files (the
    scenario, its robot description's file, its URDF; a ``SeaIOError`` naming it). Each URDF
    element the model doubts (as ``Model.from_urdf`` warns of them, not point masses) is a
    ``UserWarning`` naming the URDF and the element. A disturbance that starts at or after the
    run's end is a ``UserWarning`` naming it. A diverged run is not an error: see ``result.status`` and ``result.summary``
    (a :class:`~sea_momentum.results.RunSummary`). ``package_dirs`` are searched first for the
    URDF's ``package://`` meshes drawn in the log (as ``sea-sim run --package-dir``); a mesh
    the log cannot draw is a ``UserWarning`` naming the link and the URI (the log draws a box).
    A walking command the step limits clip (``walking.command.forward_velocity`` beyond
    ``walking.max_step_length`` per step, ...) is a ``UserWarning`` naming both keys and the
    speed the walk goes at, issued before the run.

    Ctrl-C stops the run within a fraction of a second (the MCAP log is finished) and raises
    ``KeyboardInterrupt``; what was computed is its ``partial`` attribute, a
    :class:`ScenarioResult` with ``status == "interrupted"`` (``None`` when the signal came
    while the scenario was still being built, before the run began)::

        try:
            result = run_scenario(path)
        except KeyboardInterrupt as interrupt:
            result = interrupt.partial

    SIGTERM (``kill``, a batch scheduler's stop), when the program leaves it at Python's
    default, does the same during the run and raises ``SystemExit(143)`` with the same
    ``partial``; the program then exits with the status SIGTERM would have given, its log
    finished.
    """
    try:
        raw = run_scenario_native(
            os.fspath(path),
            dict(overrides or {}),
            None if mcap is None else os.fspath(mcap),
            progress,
            package_folders(package_dirs),
        )
    except (KeyboardInterrupt, SystemExit) as interrupt:
        partial = getattr(interrupt, "partial", None)
        result = ScenarioResult.from_native(partial) if isinstance(partial, dict) else None
        interrupt.partial = result  # type: ignore[attr-defined]
        raise
    return ScenarioResult.from_native(raw)

