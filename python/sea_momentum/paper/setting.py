"""The paper's experiments (section "Simulation results"): their settings and the outcomes the
paper reports, the reference every module of :mod:`sea_momentum.paper` compares with.

The paper's setting is continuous control: its controller runs inside ode15s's right-hand side,
so the scenarios of ``scenarios/paper`` use ``controller.sampling = "continuous"``. Every
experiment is also run with the controller sampled at 1 kHz with zero-order hold
(:data:`SAMPLED_1KHZ`, the setting of the earlier results).
"""

from __future__ import annotations

#: Damping estimate scales of the paper's Figure 1, the nominal first.
DAMPING_SCALES = (1.0, 1.45, 1.6, 0.4)
#: The sampled-data setting of the earlier results: 1 kHz zero-order hold, 1 ms plant step.
SAMPLED_1KHZ = {"controller.sampling": "zero_order_hold", "controller.rate_hz": 1000.0, "plant.dt": 1e-3}
#: Zero-order hold at the scenario's own (accurate) plant step: the stability map's setting.
ZERO_ORDER_HOLD = {"controller.sampling": "zero_order_hold"}
#: The stance ankle roll and its motor torque limit of the saturation experiment [Nm].
SATURATED_JOINT = "l_ankle_roll"
TORQUE_LIMIT_NM = 0.34

#: The paper's outcomes, by experiment.
PAPER = {
    "tracking x1.0": "stable, CoM error a few mm",
    "tracking x1.45": "stable (error does not grow)",
    "tracking x1.6": "unstable",
    "tracking x0.4": "stable",
    "step, rigid controller": "unstable",
    "step, SEA controller": "converges",
    "saturation 0.34 Nm": "stable, ~50 rad/s initial motor velocity peak, slower convergence",
}

#: Whether the paper found each experiment stable (completed).
PAPER_STABLE = {
    "tracking x1.0": True,
    "tracking x1.45": True,
    "tracking x1.6": False,
    "tracking x0.4": True,
    "step, rigid controller": False,
    "step, SEA controller": True,
    "saturation 0.34 Nm": True,
}


def damping(scale: float) -> dict[str, float]:
    """The override scaling the controller's damping estimate by ``scale``."""
    return {"controller.damping_estimate_scale": scale}
