"""The evidence behind the outcomes, from the closed loop's linearisation about its equilibrium
(references frozen): the least stable and the SEA modes of each experiment, the eigenvalue
stability boundaries, and the growth rate against the damping estimate scale. Every function
returns JSON-ready dicts and lists (they go to ``summary.json`` as they are)."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..analysis import Linearization, linearize, stability_margin
from ..arrays import ComplexArray
from .session import Session
from .setting import DAMPING_SCALES, SAMPLED_1KHZ, ZERO_ORDER_HOLD, damping

#: A mode whose angular frequency exceeds this [rad/s] is an SEA mode (the balancing modes
#: are slower than 10 rad/s, the SEA modes faster than 280 rad/s for scales up to 3).
SEA_MODE_MIN_FREQUENCY = 200.0
#: Damping estimate scales of the growth-rate curve.
GROWTH_SCALES = tuple(sorted({*(float(v) for v in np.geomspace(0.2, 3.0, 17)), 0.4, 1.0, 1.45, 1.6}))


def sea_modes(lin: Linearization) -> ComplexArray:
    """The SEA modes of a continuous-time linearisation (one oscillatory pair per joint)."""
    rates = lin.eigenvalues if lin.sampling == "continuous" else np.log(lin.eigenvalues.astype(complex)) / lin.control_period
    return rates[np.abs(rates.imag) > SEA_MODE_MIN_FREQUENCY]


def _min_max(values: Any) -> list[float] | None:
    """``[min, max]`` of a non-empty array, else None."""
    return [float(values.min()), float(values.max())] if values.size else None


def describe(lin: Linearization) -> dict[str, Any]:
    """What outcomes.md and summary.json say about one linearisation."""
    modes = sea_modes(lin)
    rate = lin.least_stable_rate
    return {
        "sampling": lin.sampling,
        "control_period_s": lin.control_period,
        "growth_rate_1_s": lin.growth_rate,
        "stable": lin.stable,
        "least_stable_frequency_rad_s": abs(rate.imag),
        "dominant_states": [(name, round(weight, 3)) for name, weight in lin.dominant_states[:4]],
        "sea_mode_real_min_max_1_s": _min_max(modes.real),
        "sea_mode_frequency_min_max_rad_s": _min_max(np.abs(modes.imag)),
    }


def linearization_evidence(session: Session) -> dict[str, dict[str, Any]]:
    """The linearisations behind the outcomes: each Figure 1 scale in continuous time, x0.4 at
    1 kHz, and the rigid controller after the step (continuous)."""
    tracking = session.path("tracking")
    evidence = {}
    for scale in DAMPING_SCALES:
        session.say(f"linearize tracking x{scale}, continuous")
        evidence[f"continuous x{scale}"] = describe(linearize(tracking, overrides=damping(scale)))
    session.say("linearize tracking x0.4, 1 kHz zero-order hold, dt 1 ms")
    evidence["1 kHz x0.4"] = describe(linearize(tracking, overrides={**SAMPLED_1KHZ, **damping(0.4)}))
    session.say("linearize step_rigid after the step, continuous")
    evidence["rigid after the step"] = describe(linearize(session.path("step_rigid"), t=1.0))
    return evidence


def margin_evidence(session: Session) -> dict[str, list[float]]:
    """Eigenvalue stability boundaries: the damping estimate scale in continuous time and at
    1 kHz (1 ms and the scenario's 0.25 ms plant step), and the control rate at x1.0."""
    tracking = session.path("tracking")
    scale = "controller.damping_estimate_scale"
    cases: dict[str, tuple[str, float, float, Mapping[str, Any]]] = {
        "damping scale 0.2-3, continuous": (scale, 0.2, 3.0, {}),
        "damping scale 0.2-3, 1 kHz, dt 1 ms": (scale, 0.2, 3.0, SAMPLED_1KHZ),
        "damping scale 0.2-3, 1 kHz, dt 0.25 ms": (scale, 0.2, 3.0, {**ZERO_ORDER_HOLD, "controller.rate_hz": 1000.0}),
        "control rate 100 Hz-10 kHz at x1.0, dt 0.25 ms": ("controller.rate_hz", 100.0, 10_000.0, ZERO_ORDER_HOLD),
    }
    margins = {}
    for label, (key, lower, upper, overrides) in cases.items():
        session.say(f"stability margin: {label}")
        margins[label] = stability_margin(tracking, key, lower, upper, overrides, log_grid=True)
    return margins


def growth_rate_curve(session: Session) -> dict[str, list[float]]:
    """Growth rate of the least stable mode and the SEA modes' decay against the damping
    estimate scale (:data:`GROWTH_SCALES`), in continuous time and at 1 kHz (dt 0.25 ms)."""
    tracking = session.path("tracking")
    session.say(f"growth rate curve: {len(GROWTH_SCALES)} damping scales, continuous and 1 kHz")
    curve: dict[str, list[float]] = {"scale": list(GROWTH_SCALES), "continuous": [], "sea_decay": [], "1 kHz": []}
    for scale in GROWTH_SCALES:
        lin = linearize(tracking, overrides=damping(scale))
        curve["continuous"].append(lin.growth_rate)
        curve["sea_decay"].append(float(sea_modes(lin).real.max()))
        held = linearize(tracking, overrides={**ZERO_ORDER_HOLD, "controller.rate_hz": 1000.0, **damping(scale)})
        curve["1 kHz"].append(held.growth_rate)
    return curve
