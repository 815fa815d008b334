#!/usr/bin/env python3
"""What the landings add to the ground's vertical force that the whole-body law did not plan.

Runs a walking scenario through the robot's loop in Python (per whole-body period: ``tick``,
the joint loops' ``inner_tick``, the plant's steps, ``end_period`` with the feet's readings,
as the native run does) and compares, period by period, the vertical force the QP planned
(``ControlOutput.wrenches``, held over the period) with the impulse the plant delivered
(``Plant.step_outputs().step_contact_wrenches`` over every plant step). Their difference is
the *unplanned* vertical force. Over a periodic walk the delivered force averages the weight,
so a mean unplanned force `F_u` makes the law plan `F_u` less than the weight on average: with
the momentum task's position gain `K_i` on the CoM height (paper eq:dotH_f, eq:IhTilde), the
CoM settles `F_u / (m K_i)` above its reference.

Per touchdown (a sole's delivered normal force above ``--threshold`` after at least 0.2 s
below it; a bounce within a step is not a new touchdown) it reports the unplanned impulse of
the periods from the one that holds the first contact to ``--window`` seconds after it (the
strike), and the sole's lowest point's descent velocity over the 10 ms before the first
contact.

    python scripts/landing_impulse.py scenarios/walking/walk_fast.toml --duration 12
    python scripts/landing_impulse.py scenarios/walking/walk_fast.toml --set actuators.kind=rigid \\
        --set controller.rate_hz=1000
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from typing import Any

import numpy as np

import sea_momentum as sm


@dataclass
class LandingImpulse:
    """The figures of one run, over the times from ``start_s`` on (SI units)."""

    com_height_error_mean_m: float  #: mean of the CoM's height less its reference [m]
    unplanned_force_mean_n: float  #: mean of the delivered less the planned vertical force [N]
    strike_impulse_median_n_s: float  #: median unplanned impulse of a touchdown's strike [N s]
    descent_velocity_median_m_s: float  #: median descent speed of the sole before contact [m/s]
    touchdowns: int  #: touchdowns counted
    status: str  #: "completed", or "diverged" (the loop stopped early, see ``_loop``)
    com: np.ndarray  #: (m, 3) CoM at each tick [m]


class _Diverged(RuntimeError):
    """The plant's step failed: the run ends there as "diverged"."""


class _WatchedPlant(sm.PlantRobot):
    """The scenario's plant, recording per step each contact's delivered normal force and its
    sole's lowest point."""

    def __init__(self, scenario: sm.Scenario) -> None:
        super().__init__(scenario)
        counts = self.plant.contact_point_counts
        if not counts:
            raise ValueError('needs plant.contact_model = "unilateral"')
        self.points = np.concatenate([[0], np.cumsum(counts)])
        self.step_fz: list[np.ndarray] = []
        self.step_low: list[list[float]] = []

    def step(self, u: np.ndarray) -> sm.StepReadings:
        try:
            readings = super().step(u)
        except (sm.SolverError, ValueError) as error:  # the state past what the plant solves
            raise _Diverged(str(error)) from error
        assert self.outputs is not None  # set by the step
        z, p = self.outputs.contact_point_positions[:, 2], self.points
        self.step_low.append([z[p[c]:p[c + 1]].min() for c in range(len(p) - 1)])
        self.step_fz.append(readings.contact_wrenches[:, 2])
        return readings


def _loop(scenario: sm.Scenario, com_error_bound: float) -> dict[str, Any]:
    """The robot's loop (``sm.robot_loop``), with per period the planned and delivered
    vertical force, and per plant step each contact's delivered normal force and its sole's
    lowest point. Stops as "diverged" when the CoM is farther than ``com_error_bound`` [m] from
    its reference or the plant's step fails."""
    controller, robot = scenario.controller, _WatchedPlant(scenario)
    status = "completed"
    planned, delivered, height_error, com = [], [], [], []
    for k in range(scenario.last_tick):
        out = controller.tick(k * scenario.control_period, robot.state())
        com.append(out.com)
        if np.linalg.norm(out.com - out.com_reference) > com_error_bound:
            status = "diverged"
            break
        try:
            readings = sm.run_period(controller, robot, out.input, scenario.steps_per_tick,
                                     scenario.steps_per_inner_tick)
        except _Diverged:
            status = "diverged"
            break
        height_error.append(out.com[2] - out.com_reference[2])
        planned.append(out.wrenches[:, 2].sum())
        delivered.append(readings.mean_contact_wrenches[:, 2].sum())
        readings.hand_to(controller)
    steps = len(delivered) * scenario.steps_per_tick
    return dict(status=status, planned=planned, delivered=delivered,
                height_error=height_error, com=com, step_fz=robot.step_fz[:steps],
                step_low=robot.step_low[:steps])


def _first_contacts(step_fz: np.ndarray, dt: float, threshold: float) -> list[tuple[int, int]]:
    """(contact, plant step) of each touchdown: the normal force above ``threshold`` after at
    least 0.2 s at or below it."""
    found, quiet_steps = [], int(round(0.2 / dt))
    for c in range(step_fz.shape[1]):
        below = 0
        for i, fz in enumerate(step_fz[:, c]):
            if fz <= threshold:
                below += 1
                continue
            if below >= quiet_steps:
                found.append((c, i))
            below = 0
    return found


def measure(path: str, overrides: dict[str, Any] | None = None, start_s: float = 3.0,
            window_s: float = 0.02, threshold_n: float = 5.0,
            com_error_bound: float = 0.1) -> LandingImpulse:
    """Runs ``path`` with ``overrides`` and measures it from ``start_s`` on (the arguments as
    the command line's options)."""
    overrides = overrides or {}
    scenario = sm.Scenario.load(path, overrides)
    if scenario.sampling == "continuous":
        raise ValueError("controller.sampling = \"continuous\" evaluates the "
                         "law at every integrator stage, which a loop of ticks does not")
    run = _loop(scenario, com_error_bound)
    period, dt = scenario.control_period, scenario.plant_dt
    steps = scenario.steps_per_tick
    unplanned = np.array(run["delivered"]) - np.array(run["planned"])
    tick_times = np.arange(len(unplanned)) * period
    used = tick_times >= start_s - 1e-9
    step_fz, step_low = np.array(run["step_fz"]), np.array(run["step_low"])
    strikes, descents = [], []
    before = int(round(0.01 / dt))
    for c, i in _first_contacts(step_fz, dt, threshold_n):
        if i * dt < start_s or i < before:
            continue
        first = i // steps
        if first >= len(unplanned):
            continue
        last = min(len(unplanned), first + int(np.ceil(window_s / period)) + 1)
        strikes.append(unplanned[first:last].sum() * period)
        descents.append((step_low[i - 1, c] - step_low[i - 1 - before, c]) / (before * dt))
    return LandingImpulse(
        com_height_error_mean_m=float(np.mean(np.array(run["height_error"])[used])),
        unplanned_force_mean_n=float(np.mean(unplanned[used])),
        strike_impulse_median_n_s=float(np.median(strikes)) if strikes else float("nan"),
        descent_velocity_median_m_s=float(np.median(descents)) if descents else float("nan"),
        touchdowns=len(strikes),
        status=run["status"],
        com=np.array(run["com"]),
    )


def _override(text: str) -> tuple[str, Any]:
    key, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"--set {text!r}: expected key=value")
    try:
        return key, json.loads(value)
    except json.JSONDecodeError:
        return key, value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario")
    parser.add_argument("--duration", type=float, default=12.0, help="simulated time [s]")
    parser.add_argument("--start", type=float, default=3.0, help="measured from [s]")
    parser.add_argument("--window", type=float, default=0.02,
                        help="a strike's periods after the first contact [s]")
    parser.add_argument("--threshold", type=float, default=5.0,
                        help="a sole's normal force that counts as contact [N]")
    parser.add_argument("--com-error-bound", type=float, default=0.1,
                        help="stop as diverged beyond this CoM error [m]")
    parser.add_argument("--set", type=_override, action="append", default=[],
                        metavar="KEY=VALUE", help="a scenario key (JSON value)")
    args = parser.parse_args()
    overrides = {"simulation.duration_s": args.duration, **dict(args.set)}
    try:
        result = measure(args.scenario, overrides, args.start, args.window, args.threshold,
                         args.com_error_bound)
    except (sm.SeaError, ValueError) as error:
        raise SystemExit(f"landing_impulse: {error}") from None
    print(f"status {result.status}, {result.touchdowns} touchdowns from {args.start} s")
    print(f"CoM height above its reference, mean: {1e3 * result.com_height_error_mean_m:.2f} mm")
    print(f"unplanned vertical force, mean: {result.unplanned_force_mean_n:.2f} N")
    print(f"a touchdown's strike, unplanned impulse, median: "
          f"{result.strike_impulse_median_n_s:.2f} N s")
    print(f"the sole's descent before contact, median: "
          f"{result.descent_velocity_median_m_s:.3f} m/s")


if __name__ == "__main__":
    main()
