#!/usr/bin/env python3
"""The largest sideways push a walking gait's timing and step limits can capture at all.

The linear inverted pendulum (LIP) of a walk, along the lateral axis y: the divergent component
of motion (DCM, capture point) `xi = y + ydot / omega` moves as

    xidot = omega (xi - p) + F / (m omega),    omega = sqrt(g / z0),

with `p` the centre of pressure (CoP) and `F` the push's lateral force. A push of impulse `I`
over `duration` starts at a fraction `phase` of a swing. From then on the best any controller
can do under the gait's timing is:

- keep the CoP on the pushed side's edge of the support (the stance sole's edge in single
  support; the outermost sole's edge in double support), within `half_width` of each sole's
  middle (the QP's sole: the sole's half-width times `1 - cop_margin`);
- land each foot on the pushed side `max_width` from the other foot, and each foot on the far
  side `min_width` from the other (the feet never cross); the landing of the swing in flight
  optionally limited to `landing_speed` times the time left after the push starts.

The DCM at the end is a decreasing function of the CoP at every instant and of every landing
on the pushed side, so these choices give the smallest excursion. The push is captured when,
after it ends, the DCM is inside the outermost sole's edge at a touchdown of the pushed side's
foot. `bound` bisects the impulse. No joint, no angular momentum (a hip strategy could do
more), no swing dynamics (the swing foot lands anywhere at the planned time): an upper bound of
what the gait can capture with its CoP and its steps, not a prediction of a controller.

The defaults are `scenarios/walking/walk_push.toml` on the paper's iCub: 33.0 kg (the model's
mass), CoM at 0.51 m, 0.3 s swings and 0.1 s double supports, the walk's feet 0.14 m apart
(`walking.nominal_width`, as they stand), step widths 0.09-0.25 m (`walking.min_step_width`,
`max_step_width`), the sole 0.05 m wide (`controller.contact.foot_y`) with `cop_margin` 0.3,
the push of 0.1 s. The pushed swing is the right foot's, the left foot stands at y = 0;
`direction` +1 pushes to the left (towards the stance foot), -1 to the right (towards the
swing foot). `sea-sim push --phase` reports the same bound from the scenario's own plan
(`gait_bound_impulse_n_s`; `sea_study::analysis::gait_bound`, written apart from this script
and checked against it).

    python3 scripts/lateral_push_bound.py            # the table of docs/findings/stepping.md
"""
from __future__ import annotations

import argparse
import math
from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Gait:
    """A straight walk's lateral figures (the defaults: walk_push.toml's iCub)."""

    mass: float = 33.0
    com_height: float = 0.51
    gravity: float = 9.81
    swing: float = 0.3
    double_support: float = 0.1
    width: float = 0.14
    min_width: float = 0.09
    max_width: float = 0.25
    half_width: float = 0.025 * (1.0 - 0.3)
    push_duration: float = 0.1
    landing_speed: float | None = None

    @property
    def omega(self) -> float:
        """The LIP's `sqrt(g / z0)` [1/s]."""
        return math.sqrt(self.gravity / self.com_height)


def dcm_after(xi: float, p0: float, p1: float, duration: float, omega: float) -> float:
    """The DCM after `duration` [s] from `xi` under a CoP moving linearly from `p0` to `p1`
    (`xidot = omega (xi - p)`, exact): `p1 + r / omega + (xi - p0 - r / omega) e^(omega T)`,
    `r` the CoP's rate."""
    if duration <= 0.0:
        return xi
    rate = (p1 - p0) / duration
    return p1 + rate / omega + (xi - p0 - rate / omega) * math.exp(omega * duration)


def nominal_dcm_at_lift_off(gait: Gait) -> float:
    """The periodic walk's DCM [m] at the right foot's lift-off, the CoP of the plan at the
    stance sole's middle in single support and moving linearly between the soles in double
    support (left sole at 0, right at `-width`): the fixed point of one period."""
    w, ss, ds = gait.omega, gait.swing, gait.double_support
    left, right = 0.0, -gait.width

    def period(xi: float) -> float:
        xi = dcm_after(xi, left, left, ss, w)
        xi = dcm_after(xi, left, right, ds, w)
        xi = dcm_after(xi, right, right, ss, w)
        return dcm_after(xi, right, left, ds, w)

    offset = period(0.0)
    slope = period(1.0) - offset
    return offset / (1.0 - slope)


def _segments(gait: Gait, steps: int):
    """The walk from the right foot's lift-off: `(start, end, phase)` per single and double
    support, `phase` naming the stance ('L' or 'R') or 'DS'."""
    t = 0.0
    stance = "L"
    for _ in range(steps):
        yield t, t + gait.swing, stance
        t += gait.swing
        yield t, t + gait.double_support, "DS"
        t += gait.double_support
        stance = "R" if stance == "L" else "L"


def captured(impulse: float, direction: int, phase: float, gait: Gait, steps: int = 6) -> bool:
    """Whether a lateral push of `impulse` [N s] along `direction` (+1 left, -1 right),
    starting at `phase` of the right foot's swing, is captured with the best CoP and landings
    (module doc) within `steps` steps."""
    s, w, half = direction, gait.omega, gait.half_width
    push_start = phase * gait.swing
    push_end = push_start + gait.push_duration
    # The push's force as a CoP offset: omega (xi - p) + F / (m omega) = omega (xi - p_eff).
    push_offset = s * impulse / gait.push_duration / (gait.mass * w * w)
    feet = {"L": 0.0, "R": -gait.width}
    outward = {"L": 1, "R": -1}
    xi = nominal_dcm_at_lift_off(gait)
    for start, end, stance in _segments(gait, steps):
        if stance == "DS":
            cop = max(feet.values()) + half if s > 0 else min(feet.values()) - half
        else:
            cop = feet[stance] + s * half
        for a, b, pushed in _split(start, end, push_start, push_end):
            p = cop - push_offset if pushed else cop
            xi = dcm_after(xi, p, p, b - a, w)
        if stance == "DS":
            continue
        swing = "R" if stance == "L" else "L"
        other = feet[stance]
        width = gait.max_width if outward[swing] == s else gait.min_width
        target = other + outward[swing] * width
        if start == 0.0 and gait.landing_speed is not None:
            room = gait.landing_speed * max(end - push_start, 0.0)
            target = min(max(target, feet[swing] - room), feet[swing] + room)
        feet[swing] = target
        outermost = max(feet, key=lambda f: s * feet[f])
        edge = feet[outermost] + s * half
        if outermost == swing and end >= push_end and s * (xi - edge) <= 0.0:
            return True
    return False


def _split(start: float, end: float, push_start: float, push_end: float):
    """`[start, end]` cut at the push's start and end: `(a, b, pushed)` pieces."""
    cuts = sorted({start, end, *(t for t in (push_start, push_end) if start < t < end)})
    for a, b in zip(cuts, cuts[1:]):
        yield a, b, push_start <= a < push_end


def bound(direction: int, phase: float, gait: Gait, high: float = 100.0) -> float:
    """The largest impulse [N s] `captured` (bisection to 1e-6 of `high`); `high` if every
    impulse up to it is."""
    low = 0.0
    if captured(high, direction, phase, gait):
        return high
    while high - low > 1e-6 * max(high, 1.0):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if captured(mid, direction, phase, gait) else (low, mid)
    return low


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--phases", default="0.2,0.5,0.8", help="fractions of the swing")
    args = parser.parse_args()
    phases = [float(p) for p in args.phases.split(",")]
    gait = Gait()
    print(f"omega {gait.omega:.3f} 1/s, the plan's DCM at the right lift-off "
          f"{nominal_dcm_at_lift_off(gait):+.4f} m")
    rows = [
        ("the QP's sole (cop_margin 0.3)", gait),
        ("the whole sole", replace(gait, half_width=0.025)),
        ("the QP's sole, the swing in flight at 0.5 m/s", replace(gait, landing_speed=0.5)),
        ("the QP's sole, the swing in flight not moved", replace(gait, landing_speed=0.0)),
    ]
    print("| CoP and landings | direction | " + " | ".join(f"{p:.0%}" for p in phases) + " |")
    print("|---|---|" + "---|" * len(phases))
    for label, variant in rows:
        for direction, name in ((1, "left"), (-1, "right")):
            figures = " | ".join(f"{bound(direction, p, variant):.2f}" for p in phases)
            print(f"| {label} | {name} | {figures} |")


if __name__ == "__main__":
    main()
