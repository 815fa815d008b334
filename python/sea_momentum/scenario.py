"""Closed-loop scenarios from Python: :func:`run_scenario` runs a TOML scenario natively (the
GIL is released) and returns a :class:`ScenarioResult` of numpy arrays."""

from __future__ import annotations

import dataclasses
import os
from typing import Any, Mapping

import numpy as np

from ._native import run_scenario_native
from .results import RunStatus, RunSummary


@dataclasses.dataclass(frozen=True)
class ScenarioResult:
    """The recorded run, one row per recorded control tick (world axes, SI units).

    Every array is ``numpy.float64``; ``m`` rows, ``n_e`` elastic joints. ``q``, ``nu``,
    ``theta`` and ``thetadot`` are views into one (m, nx) state array.
    """

    time: np.ndarray  #: (m,) float64, time [s]
    q: np.ndarray  #: (m, nq) float64, configurations
    nu: np.ndarray  #: (m, nv) float64, velocities
    theta: np.ndarray  #: (m, n_e) float64, motor angles [rad]
    thetadot: np.ndarray  #: (m, n_e) float64, motor velocities [rad/s]
    thetadot_desired: np.ndarray  #: (m, n_e) float64, desired motor velocities (0: rigid control)
    com: np.ndarray  #: (m, 3) float64, CoM, world [m]
    com_reference: np.ndarray  #: (m, 3) float64, CoM reference, world [m]
    momentum: np.ndarray  #: (m, 6) float64, centroidal momentum [m pdot_com; L_com]
    contact_wrenches: np.ndarray  #: (m, n_contacts, 6) float64, simulated wrenches, world axes
    motor_torques: np.ndarray  #: (m, n_e) float64, applied motor torques [N m]
    joint_error_norm: np.ndarray  #: (m,) float64, |s - s_d| [rad]
    qp_solved: np.ndarray  #: (m,) float64, 1 solved, 0 fallback
    joint_names: list[str]  #: joint names in coordinate order
    elastic_joints: list[str]  #: elastic joint names, the columns of the motor arrays
    contacts: list[str]  #: contact frame names, the second axis of ``contact_wrenches``
    summary: RunSummary  #: summary statistics (also answers ``summary["field"]``)

    @property
    def status(self) -> RunStatus:
        """"completed", "diverged" or "interrupted"."""
        return self.summary.status

    def motor(self, joint: str) -> int:
        """Column of an elastic joint in the motor arrays."""
        return self.elastic_joints.index(joint)


def run_scenario(
    path: str | os.PathLike[str],
    overrides: Mapping[str, Any] | None = None,
    mcap: str | os.PathLike[str] | None = None,
    progress: bool = False,
) -> ScenarioResult:
    """Runs the scenario file ``path``.

    ``overrides`` maps dotted keys to values, e.g. ``{"controller.kind": "rigid",
    "controller.damping_estimate_scale": 1.45, "simulation.duration_s": 5}``; unknown keys raise
    ``ValueError`` naming the key. ``mcap`` writes a Foxglove-ready log (finished even when the
    run diverges). A diverged run is not an error: see ``result.status`` and ``result.summary``
    (a :class:`~sea_momentum.results.RunSummary`).

    Ctrl-C stops the run within a fraction of a second (the MCAP log is finished) and raises
    ``KeyboardInterrupt``; what was computed is its ``partial`` attribute, a
    :class:`ScenarioResult` with ``status == "interrupted"``::

        try:
            result = run_scenario(path)
        except KeyboardInterrupt as interrupt:
            result = interrupt.partial
    """
    try:
        raw = run_scenario_native(
            os.fspath(path),
            dict(overrides or {}),
            None if mcap is None else os.fspath(mcap),
            progress,
        )
    except KeyboardInterrupt as interrupt:
        partial = getattr(interrupt, "partial", None)
        if isinstance(partial, dict):
            interrupt.partial = _scenario_result(partial)
        raise
    return _scenario_result(raw)


def _scenario_result(raw: Mapping[str, Any]) -> ScenarioResult:
    """The :class:`ScenarioResult` of the native run's dict."""
    nq, nv, ne = raw["nq"], raw["nv"], raw["ne"]
    x = raw["x"]
    return ScenarioResult(
        time=raw["time"],
        q=x[:, :nq],
        theta=x[:, nq : nq + ne],
        nu=x[:, nq + ne : nq + ne + nv],
        thetadot=x[:, nq + ne + nv :],
        thetadot_desired=raw["thetadot_desired"],
        com=raw["com"],
        com_reference=raw["com_reference"],
        momentum=raw["momentum"],
        contact_wrenches=raw["contact_wrenches"],
        motor_torques=raw["motor_torques"],
        joint_error_norm=raw["joint_error_norm"],
        qp_solved=raw["qp_solved"],
        joint_names=list(raw["joint_names"]),
        elastic_joints=list(raw["elastic_joints"]),
        contacts=list(raw["contacts"]),
        summary=RunSummary(**raw["summary"]),
    )
