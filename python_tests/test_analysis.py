"""Linearisation and stability margins from Python."""

import warnings
from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm

TRACKING = Path(__file__).resolve().parents[1] / "scenarios" / "paper" / "tracking.toml"
#: The sampled-data setting of the 1 kHz findings (the paper's file is continuous): the
#: controller at 1 kHz with zero-order hold, one 1 ms plant step per tick.
SAMPLED_1KHZ = {"controller.sampling": "zero_order_hold", "plant.dt": 1e-3}


def test_nominal_linearization_is_stable_and_consistent():
    lin = sm.linearize(TRACKING, sampling="continuous")
    nd = len(lin.state_names)
    assert lin.matrix.shape == (nd, nd)
    assert lin.eigenvalues.dtype == np.complex128 and lin.eigenvalues.shape == (nd,)
    assert lin.converged and lin.residual < 1e-8
    assert lin.stable and lin.growth_rate < 0
    assert lin.growth_rate == pytest.approx(lin.growth_rates[0])
    # The reported spectrum is the matrix's (numpy's eigenvalues agree).
    numpy_rates = np.sort(np.linalg.eigvals(lin.matrix).real)[::-1]
    assert numpy_rates[0] == pytest.approx(lin.growth_rate, abs=1e-6)
    # The mode is an eigenvector of the matrix.
    v, lam = lin.least_stable_mode, lin.eigenvalues[0]
    assert np.linalg.norm(lin.matrix @ v - lam * v) < 1e-9 * np.linalg.norm(lin.matrix)
    assert lin.dominant_states[0][1] == pytest.approx(1.0)
    assert all(name in lin.state_names for name, _ in lin.dominant_states)
    assert lin.growth_rate_change is not None and lin.growth_rate_change < 1e-3


def test_damping_x04_at_1khz_is_unstable_in_the_ankle_roll_motor():
    lin = sm.linearize(
        TRACKING, overrides={**SAMPLED_1KHZ, "controller.damping_estimate_scale": 0.4}
    )
    assert lin.sampling == "zero_order_hold" and lin.control_period == pytest.approx(1e-3)
    assert not lin.stable and lin.growth_rate > 0
    assert lin.map_residual is not None and lin.map_residual < 1e-9
    # The period map's multiplier and its continuous-time rate agree.
    mu = lin.eigenvalues[0]
    assert np.log(abs(mu)) / lin.control_period == pytest.approx(lin.growth_rate)
    assert lin.least_stable_rate.real == pytest.approx(lin.growth_rate)
    names = [name for name, _ in lin.dominant_states[:2]]
    assert set(names) == {"theta:l_ankle_roll", "thetadot:l_ankle_roll"}
    # The same setting is stable in continuous time.
    continuous = sm.linearize(
        TRACKING, overrides={"controller.damping_estimate_scale": 0.4}, sampling="continuous"
    )
    assert continuous.stable


def test_margin_of_the_damping_estimate_at_1khz():
    with warnings.catch_warnings():
        # The feet welded: every equilibrium converges, no warning.
        warnings.simplefilter("error")
        boundaries = sm.stability_margin(
            TRACKING, "controller.damping_estimate_scale", 0.3, 1.0, SAMPLED_1KHZ, grid_points=5
        )
    assert len(boundaries) == 1 and 0.44 < boundaries[0] < 0.49
    stable_range = sm.stability_margin(
        TRACKING, "controller.damping_estimate_scale", 0.8, 1.5, SAMPLED_1KHZ
    )
    assert stable_range == []


def test_a_margin_on_the_ground_warns_that_newton_found_no_equilibrium():
    # A loaded sole creeps on the compliant ground: Newton's method finds no equilibrium, and
    # the growth rates about the point it stopped at do not judge stability.
    ground = {"plant.contact_model": "unilateral"}
    assert not sm.linearize(TRACKING, overrides=ground, sampling="continuous").converged
    with pytest.warns(RuntimeWarning) as caught:
        sm.stability_margin(
            TRACKING, "controller.damping_estimate_scale", 0.8, 1.0, ground, grid_points=2
        )
    [warning] = caught
    message = str(warning.message)
    assert message.startswith(
        "controller.damping_estimate_scale: Newton's method found no equilibrium at 0.8 (residual "
    ), message
    assert ", 1.0 (residual " in message and "plant.contact_model = 'bilateral'" in message
    assert warning.filename == __file__  # the caller's line


def test_a_key_outside_the_linearisation_warns_that_the_growth_rate_never_changes():
    # The noise's seed changes nothing about the noiseless standing equilibrium.
    with pytest.warns(RuntimeWarning, match="sensing.seed: the growth rate is the same") as caught:
        sm.stability_margin(TRACKING, "sensing.seed", 1.0, 5.0, grid_points=3)
    assert caught[0].filename == __file__  # the caller's line


def test_a_nan_residual_reads_as_nan_in_the_warning():
    from sea_momentum.analysis import _exponent

    readings = (_exponent(4139.93), _exponent(1.15e-8), _exponent(float("nan")))
    assert readings == ("4.14e3", "1.15e-8", "nan")


def test_a_real_equilibrium_that_newton_leaves_above_its_tolerance_is_no_warning():
    # At a damping of 1e-4 N m s/rad round-off stops Newton's line search above its tolerance
    # of 1e-8 (measured 7.8e-6), yet the point is the equilibrium: the margin does not flag it.
    lin = sm.linearize(TRACKING, overrides={"actuators.damping": 1e-4})
    assert not lin.converged and 1e-8 < lin.residual < 1e-3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sm.stability_margin(TRACKING, "actuators.damping", 1e-4, 1e-2, grid_points=3, log_grid=True)


def test_margin_errors_name_the_key_or_the_range():
    with pytest.raises(sm.ScenarioError, match="controller.no_such_key"):
        sm.stability_margin(TRACKING, "controller.no_such_key", 0.5, 1.0)
    with pytest.raises(sm.ScenarioError, match="controller.kind"):
        sm.stability_margin(TRACKING, "controller.kind", 0.5, 1.0)
    with pytest.raises(ValueError, match="inverted") as inverted:
        sm.stability_margin(TRACKING, "controller.damping_estimate_scale", 2.0, 1.0)
    assert inverted.value.argument == "lower, upper"
    assert not isinstance(inverted.value, sm.ScenarioError)
    for points in (-3, 1):
        with pytest.raises(ValueError, match="grid_points") as bad_points:
            sm.stability_margin(TRACKING, "controller.damping_estimate_scale", 0.5, 1.0, grid_points=points)
        assert bad_points.value.argument == "grid_points"
    with pytest.raises(ValueError, match="eigen") as bad_method:
        sm.stability_margin(TRACKING, "controller.damping_estimate_scale", 0.5, 1.0, method="x")
    assert bad_method.value.argument == "method"
    assert not isinstance(bad_method.value, sm.ScenarioError)
    with pytest.raises(ValueError, match="sampling"):
        sm.linearize(TRACKING, sampling="sometimes")


def test_a_time_before_the_start_is_refused_naming_t():
    # The references start at t = 0; -1e3 s used to spin on a reference that is not finite.
    for t in (-1e3, -0.1, float("nan")):
        with pytest.raises(ValueError, match="t: expected a non-negative finite number"):
            sm.linearize(TRACKING, t=t)
