"""``scripts/lateral_push_bound.py``, the LIP's bound on a sideways push a gait can capture,
against scipy: its exact DCM segments against ``solve_ivp`` (Radau), its periodic walk by
integrating one period, and one cell of its bound against a root of the same pendulum
integrated by ``solve_ivp`` with the best CoP and landings written out by hand for that case.
"""
from __future__ import annotations

import math

import pytest
from load_file import load_file  # a helper beside the tests (see conftest.py)

scipy_integrate = pytest.importorskip("scipy.integrate")
scipy_optimize = pytest.importorskip("scipy.optimize")

bound_script = load_file("scripts/lateral_push_bound.py")
TOL = dict(method="Radau", rtol=1e-11, atol=1e-13)


def _integrate(cop, xi0: float, t0: float, t1: float, omega: float, force=lambda t: 0.0,
               mass: float = 1.0) -> float:
    """The DCM at `t1` from `xi0` at `t0` under `cop(t)` and the lateral `force(t)`."""
    rhs = lambda t, xi: [omega * (xi[0] - cop(t)) + force(t) / (mass * omega)]  # noqa: E731
    return scipy_integrate.solve_ivp(rhs, (t0, t1), [xi0], **TOL).y[0, -1]


def test_a_segment_of_moving_cop_matches_radau():
    omega, p0, p1, duration, xi0 = 4.4, -0.03, 0.12, 0.37, 0.05
    cop = lambda t: p0 + (p1 - p0) * t / duration  # noqa: E731
    reference = _integrate(cop, xi0, 0.0, duration, omega)
    assert bound_script.dcm_after(xi0, p0, p1, duration, omega) == pytest.approx(reference,
                                                                                  abs=1e-10)


def test_the_plans_dcm_at_the_lift_off_comes_back_after_one_period():
    gait = bound_script.Gait()
    ss, ds, width = gait.swing, gait.double_support, gait.width

    def cop(t: float) -> float:
        if t < ss:
            return 0.0
        if t < ss + ds:
            return -width * (t - ss) / ds
        if t < 2 * ss + ds:
            return -width
        return -width + width * (t - 2 * ss - ds) / ds

    xi0 = bound_script.nominal_dcm_at_lift_off(gait)
    period = 2 * (ss + ds)
    # one period, integrated in its four pieces (the CoP has kinks)
    xi, cuts = xi0, [0.0, ss, ss + ds, 2 * ss + ds, period]
    for a, b in zip(cuts, cuts[1:]):
        xi = _integrate(cop, xi, a, b, gait.omega)
    assert xi == pytest.approx(xi0, abs=1e-9)
    # it lies between the soles, nearer the stance sole (the left, at 0) at its lift-off
    assert -width / 2 < xi < 0.0


def test_a_left_push_at_20_percent_is_bounded_where_the_far_landing_catches_the_dcm():
    """Left push at 20 % of the right swing: the CoP stays on the left sole's outer edge until
    the right foot stands (the double support's outermost edge is the left sole's), then on the
    right sole's inner edge with the right foot landed `min_width` from the left; the left foot
    lands `max_width` further out at 0.7 s, and captures when the DCM is inside its outer edge.
    """
    gait = bound_script.Gait()
    h, w = gait.half_width, gait.omega
    start, duration = 0.2 * gait.swing, gait.push_duration
    left_lands = 2 * gait.swing + gait.double_support
    right_stance = gait.swing + gait.double_support
    xi0 = bound_script.nominal_dcm_at_lift_off(gait)
    cop = lambda t: h if t < right_stance else -gait.min_width + h  # noqa: E731
    edge = -gait.min_width + gait.max_width + h

    def excess(impulse: float) -> float:
        force = lambda t: impulse / duration if start <= t < start + duration else 0.0  # noqa
        xi, cuts = xi0, [0.0, start, start + duration, right_stance, left_lands]
        for a, b in zip(cuts, cuts[1:]):
            xi = _integrate(cop, xi, a, b, w, force, gait.mass)
        return xi - edge

    reference = scipy_optimize.brentq(excess, 0.0, 50.0, xtol=1e-9)
    assert bound_script.bound(1, 0.2, gait) == pytest.approx(reference, rel=1e-5)


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("phase", [0.2, 0.5, 0.8])
def test_the_bound_separates_captured_pushes_from_lost_ones(direction, phase):
    gait = bound_script.Gait()
    limit = bound_script.bound(direction, phase, gait)
    assert 0.0 < limit < 100.0
    assert bound_script.captured(0.999 * limit, direction, phase, gait)
    assert not bound_script.captured(1.001 * limit, direction, phase, gait)


def test_a_wider_cop_or_a_wider_step_captures_more_and_a_slow_swing_less():
    gait = bound_script.Gait()
    base = bound_script.bound(-1, 0.5, gait)
    wider_sole = bound_script.replace(gait, half_width=0.025)
    wider_step = bound_script.replace(gait, max_width=0.3)
    slow_swing = bound_script.replace(gait, landing_speed=0.2)
    assert bound_script.bound(-1, 0.5, wider_sole) > base
    assert bound_script.bound(-1, 0.5, wider_step) > base
    assert bound_script.bound(-1, 0.5, slow_swing) < base
    assert math.isfinite(base)
