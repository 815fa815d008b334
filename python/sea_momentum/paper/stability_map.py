"""The stability map: sweeps of the tracking scenario over the damping estimate scale and the
control rate (zero-order hold), plus the continuous column, with the eigenvalue boundary rate
at each scale."""

from __future__ import annotations

import dataclasses
import pathlib
import time as clock

import numpy as np

from ..analysis import stability_margin
from ..arrays import BoolArray, FloatArray
from ..results import Result
from ..sweep import SweepResult, sweep
from .session import Session
from .setting import ZERO_ORDER_HOLD, damping

#: Stability map axes: damping estimate scales and control rates [Hz] (log spaced).
MAP_SCALES = tuple(float(v) for v in np.geomspace(0.2, 3.0, 8))
MAP_RATES_HZ = tuple(float(v) for v in np.geomspace(100.0, 10_000.0, 7))
#: Simulated time of one stability-map run [s]: unstable settings diverge well before.
MAP_DURATION_S = 3.0


@dataclasses.dataclass(frozen=True)
class StabilityMap(Result):
    """Sweep outcomes on the (damping scale, control rate) grid plus the continuous column,
    and the eigenvalue boundary rate at each scale (None: stable over the whole rate range).
    Arrays are (scales, rates + 1), the last column continuous."""

    scales: tuple[float, ...]
    rates_hz: tuple[float, ...]
    stable: BoolArray  #: whether each run completed
    com_error_rms_m: FloatArray  #: NaN where the run diverged
    boundary_rate_hz: list[float | None]
    diverged_at_s: FloatArray  #: when the run diverged or fell; NaN where it completed
    duration_s: float
    wall_time_s: float


def _sweeps(tracking: pathlib.Path, duration: float) -> tuple[BoolArray, FloatArray, FloatArray]:
    """Stable, CoM error rms and divergence time on the map's grid, the continuous runs as the
    last column (2 workers)."""
    short = {"simulation.duration_s": duration}
    held = sweep(tracking, {"controller.damping_estimate_scale": list(MAP_SCALES), "controller.rate_hz": list(MAP_RATES_HZ)},
                 overrides={**ZERO_ORDER_HOLD, **short}, workers=2)
    continuous = sweep(tracking, {"controller.damping_estimate_scale": list(MAP_SCALES)}, overrides=short, workers=2)
    shape = (len(MAP_SCALES), len(MAP_RATES_HZ))
    stable = np.column_stack([held.stable.reshape(shape), continuous.stable])
    error = np.column_stack([held["com_error_rms_m"].reshape(shape), continuous["com_error_rms_m"]])
    diverged_at = np.column_stack([_stopped_at(held).reshape(shape), _stopped_at(continuous)])
    return stable, error, diverged_at


def _stopped_at(result: SweepResult) -> FloatArray:
    """When each unstable run of a sweep stopped: its divergence or its fall [s] (NaN when
    completed)."""
    return np.asarray(np.fmin(result["diverged_at_s"], result["fell_at_s"]), dtype=float)


def _boundary_rates(tracking: pathlib.Path) -> list[float | None]:
    """Per damping scale, the highest control rate where the eigenvalues change stability."""
    boundaries: list[float | None] = []
    for scale in MAP_SCALES:
        found = stability_margin(tracking, "controller.rate_hz", MAP_RATES_HZ[0], MAP_RATES_HZ[-1],
                                 {**ZERO_ORDER_HOLD, **damping(scale)}, grid_points=7, log_grid=True)
        boundaries.append(found[-1] if found else None)
    return boundaries


def stability_map(session: Session) -> StabilityMap:
    """The sweeps (2 workers) and, per damping scale, the eigenvalue margin over the rate."""
    started = clock.perf_counter()
    tracking = session.path("tracking")
    duration = MAP_DURATION_S if session.duration is None else min(MAP_DURATION_S, session.duration)
    session.say(f"stability map: {len(MAP_SCALES)} x {len(MAP_RATES_HZ)} sampled + {len(MAP_SCALES)} continuous runs of {duration} s")
    stable, error, diverged_at = _sweeps(tracking, duration)
    boundaries = _boundary_rates(tracking)
    session.say(f"stability map done: boundaries {[None if b is None else round(b) for b in boundaries]} Hz")
    return StabilityMap(MAP_SCALES, MAP_RATES_HZ, stable, np.where(stable, error, np.nan), boundaries,
                        diverged_at, duration, clock.perf_counter() - started)
