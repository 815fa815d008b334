"""The runs of the paper's experiments: Figure 1's tracking with four damping estimates, the
step with the rigid and the SEA controllers, the saturation of the stance ankle roll and its two
references, and the numbers read off the saturated joint."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..scenario import ScenarioResult
from .session import Session
from .setting import DAMPING_SCALES, SATURATED_JOINT, TORQUE_LIMIT_NM, damping

#: Motor velocity [rad/s] below which the saturated joint's start transient counts as settled
#: (the CoM motion itself needs about 1 rad/s at the motor).
SETTLED_MOTOR_VELOCITY = 5.0


def run_experiments(session: Session, setting: Mapping[str, Any], logs: bool) -> dict[str, ScenarioResult]:
    """The paper's experiments with ``setting`` on top of their files; MCAP logs if ``logs``."""
    runs: dict[str, ScenarioResult] = {}
    for scale in DAMPING_SCALES:
        mcap = "tracking.mcap" if logs and scale == 1.0 else None
        runs[f"tracking x{scale}"] = session.run("tracking", {**setting, **damping(scale)}, mcap)
    for kind, label in (("rigid", "step, rigid controller"), ("sea", "step, SEA controller")):
        runs[label] = session.run(f"step_{kind}", setting, f"step_{kind}.mcap" if logs else None)
    # Every sample, so the short time at the limit is resolved.
    every = {**setting, "simulation.record_every": 1}
    runs["saturation 0.34 Nm"] = session.run("saturation", every, "saturation.mcap" if logs else None)
    return runs


def run_saturation_references(session: Session) -> dict[str, ScenarioResult]:
    """The saturation experiment's two references: springs at rest without the limit (the
    tracking scenario), and the limit with preloaded springs (where it never binds)."""
    every = {"simulation.record_every": 1}
    return {
        "at rest, no limit": session.run("tracking", {**every, "robot.initial_springs": "at_rest"}),
        "preloaded, 0.34 Nm": session.run("saturation", {**every, "robot.initial_springs": "preloaded"}),
    }


def saturation_figures(result: ScenarioResult) -> dict[str, float | None]:
    """Peak motor velocity, peak torque and time at the limit of the saturated joint."""
    k = result.motor(SATURATED_JOINT)
    torque = np.abs(result.motor_torques[:, k])
    at_limit = torque >= TORQUE_LIMIT_NM - 1e-9
    sample = float(result.time[1] - result.time[0])
    return {
        "peak_motor_velocity_rad_s": float(np.abs(result.thetadot[:, k]).max()),
        "peak_motor_torque_nm": float(torque.max()),
        "time_at_limit_s": float(at_limit.sum() * sample),
        "last_time_at_limit_s": float(result.time[at_limit][-1]) if at_limit.any() else None,
    }


def settling_time(result: ScenarioResult) -> float:
    """Last time [s] the saturated joint's motor velocity exceeds ``SETTLED_MOTOR_VELOCITY``."""
    k = result.motor(SATURATED_JOINT)
    fast = np.abs(result.thetadot[:, k]) > SETTLED_MOTOR_VELOCITY
    return float(result.time[fast][-1]) if fast.any() else 0.0


def saturation_evidence(runs: Mapping[str, ScenarioResult]) -> dict[str, dict[str, float | None]]:
    """:func:`saturation_figures` and the settling time of each saturation run, by label."""
    return {key: {**saturation_figures(r), "settling_time_s": settling_time(r)} for key, r in runs.items()}
