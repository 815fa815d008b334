"""Closed-loop scenarios from Python: :func:`run_scenario` runs a TOML scenario natively (the
GIL is released) and returns a :class:`ScenarioResult` of numpy arrays."""

from __future__ import annotations

import dataclasses
import json
import os
from typing import Any, Mapping

import numpy as np

from ._native import run_scenario_native


@dataclasses.dataclass(frozen=True)
class ScenarioResult:
    """The recorded run, one row per recorded control tick (world axes, SI units)."""

    time: np.ndarray  #: (m,) [s]
    q: np.ndarray  #: (m, nq) configurations
    nu: np.ndarray  #: (m, nv) velocities
    theta: np.ndarray  #: (m, n_e) motor angles
    thetadot: np.ndarray  #: (m, n_e) motor velocities
    thetadot_desired: np.ndarray  #: (m, n_e) desired motor velocities (zeros: rigid controller)
    com: np.ndarray  #: (m, 3) CoM
    com_reference: np.ndarray  #: (m, 3) CoM reference
    momentum: np.ndarray  #: (m, 6) centroidal momentum
    contact_wrenches: np.ndarray  #: (m, n_contacts, 6) simulated wrenches
    motor_torques: np.ndarray  #: (m, n_e) applied motor torques
    joint_error_norm: np.ndarray  #: (m,) |s - s_d| [rad]
    qp_solved: np.ndarray  #: (m,) 1 solved, 0 fallback
    joint_names: list[str]
    elastic_joints: list[str]
    contacts: list[str]
    summary: dict[str, Any]

    @property
    def status(self) -> str:
        """"completed" or "diverged"."""
        return self.summary["status"]

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
    run diverges). A diverged run is not an error: see ``result.status`` and ``result.summary``.
    """
    raw = run_scenario_native(
        os.fspath(path), dict(overrides or {}), None if mcap is None else os.fspath(mcap), progress
    )
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
        summary=json.loads(raw["summary_json"]),
    )
