"""Continuous control sampling (``controller.sampling = "continuous"``, the paper's setting: the
controller evaluated at every integrator stage, as inside ode15s) is solved accurately.

Reference: scipy's ``solve_ivp(method="Radau", rtol=atol=1e-10)`` (the open analogue of ode15s)
on :func:`sea_momentum.closed_loop_rhs` of the paper's tracking scenario (one foot, SEA
controller, all joints elastic, the CoM reference moving), over the first 0.3 s. That window
holds the start's transient: the left ankle's motor velocity rings at about 83 Hz with peaks
of 90 rad/s, decaying to below 1 rad/s by 0.03 s. Against it, ``run_scenario`` in continuous
mode (ROS2) at plant steps of 1, 0.5, 0.25 and 0.125 ms. Errors: max-norm of the state
difference with motor quantities on the joint side (``Gamma theta``, ``Gamma thetadot``, so that
positions [rad, m] and velocities [rad/s, m/s] of links and motors are comparable), at the
final time and over the whole trajectory (every plant step, against Radau's dense output).

Measured here (2 cores shared; Radau 3.7 s and 21764 evaluations with one BLAS thread, the
native runs 0.02, 0.04, 0.08 and 0.2 s; the file about 7 s):

    dt [ms]   final error   ratio   trajectory max   ratio
    1.000     4.40e-05              3.46e-01
    0.500     5.89e-06      7.5     1.04e-01         3.3
    0.250     9.33e-07      6.3     2.92e-02         3.6
    0.125     1.95e-07      4.8     7.79e-03         3.8

Second order (ratios towards 4 over the trajectory; above 4 at the final time, where what is
left is the decayed remnant of the transient's error). Radau at 1e-9 differs from 1e-10 by
3e-13 at the final time; its dense output at 1e-10 from 1e-11 by 3e-9: the reference is exact
at this scale. The trajectory error is the transient's phase error: at 1 ms (12 steps per
83 Hz period) it is 35 rad/s on a 90 rad/s motor velocity peak, 3 rad/s at 0.25 ms.

Zero-order hold at 1 kHz (plant step 0.25 ms, so that the difference is the sampling's) differs
from the continuous loop by 1.27e-04 at the final time (136 times the continuous run's error at
0.25 ms) and 0.485 over the trajectory (17 times). With the default 1 ms plant step both
settings carry errors of the same size as that difference (continuous at 1 ms: 4.4e-05 final,
0.35 trajectory; zero-order hold at 1 kHz and 1 ms: 2.2e-05 and 0.29 from the continuous
loop): telling the settings apart needs plant steps of 0.25 ms or less.
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import pathlib
import sys
import time
from typing import Iterator

import numpy as np
import pytest

import sea_momentum as sm  # a failed import fails the run (no importorskip)

scipy_integrate = pytest.importorskip("scipy.integrate")

ROOT = pathlib.Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
ETA = 0.01  # the paper's transmission ratio (the scenario's elastic actuators)
HORIZON = 0.3  # [s]: the start's transient and the CoM reference's first motion
PLANT_STEPS = (1e-3, 5e-4, 2.5e-4, 1.25e-4)  # [s], halving
TOLERANCE = 1e-10  # Radau's rtol and atol
CONTINUOUS = {
    "controller.sampling": "continuous",
    "simulation.duration_s": HORIZON,
    "simulation.record_every": 1,
}


#: (prefix, suffix) of OpenBLAS's thread-count functions: plain builds, and the scipy-openblas
#: builds in numpy's (64-bit integers) and scipy's wheels.
OPENBLAS_THREAD_FUNCTIONS = (("openblas", ""), ("scipy_openblas", ""), ("scipy_openblas", "64_"))


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """OpenBLAS on one thread while Radau factorises its 113 x 113 matrices: with its threads
    spinning on a loaded 2-core machine one factorisation takes 27 ms instead of 0.1 ms (the
    solve 33 s instead of 4 s). Uses threadpoolctl when installed, else OpenBLAS's own setter
    in the libraries already loaded (Linux); otherwise leaves the threads as they are."""
    try:
        from threadpoolctl import threadpool_limits  # type: ignore[import-not-found]
    except ImportError:
        pass
    else:
        with threadpool_limits(limits=1, user_api="blas"):
            yield
        return
    restore = []
    for library in loaded_openblas_libraries():
        for prefix, suffix in OPENBLAS_THREAD_FUNCTIONS:
            setter = getattr(library, f"{prefix}_set_num_threads{suffix}", None)
            getter = getattr(library, f"{prefix}_get_num_threads{suffix}", None)
            if setter is not None and getter is not None:
                restore.append((setter, getter()))
                setter(1)
                break
    try:
        yield
    finally:
        for setter, threads in restore:
            setter(threads)


def loaded_openblas_libraries() -> list[ctypes.CDLL]:
    """The OpenBLAS shared libraries mapped into this process (Linux; empty elsewhere)."""
    maps = pathlib.Path("/proc/self/maps")
    if not sys.platform.startswith("linux") or not maps.exists():
        return []
    paths = {line.split()[-1] for line in maps.read_text().splitlines() if "openblas" in line}
    return [ctypes.CDLL(path) for path in sorted(paths) if path.startswith("/")]


def joint_side(x: np.ndarray, scenario: sm.Scenario) -> np.ndarray:
    """Rows of states ``[q, theta, nu, thetadot]`` with the motor blocks times Gamma."""
    nq, nv, ne = scenario.model.nq, scenario.model.nv, len(scenario.plant.elastic_joints)
    scaled = np.array(np.atleast_2d(x), dtype=np.float64)
    scaled[:, nq : nq + ne] *= ETA
    scaled[:, nq + ne + nv :] *= ETA
    return scaled


def states(result: sm.ScenarioResult) -> np.ndarray:
    """The recorded states (m, nx) in the plant's order ``[q, theta, nu, thetadot]``."""
    return np.hstack([result.q, result.theta, result.nu, result.thetadot])


@dataclasses.dataclass(frozen=True)
class Reference:
    """Radau's solution of the continuous closed loop."""

    scenario: sm.Scenario
    solution: object  # scipy's OdeResult, with the dense output ``sol``
    seconds: float  # wall time of the solve

    def errors(self, result: sm.ScenarioResult) -> tuple[float, float]:
        """(final-time error, max error over the recorded times) of a run, joint side."""
        assert result.status == "completed"
        assert result.time[-1] == pytest.approx(HORIZON, abs=1e-12)
        run = joint_side(states(result), self.scenario)
        exact = joint_side(self.solution.sol(result.time).T, self.scenario)
        difference = np.abs(run - exact).max(axis=1)
        return float(difference[-1]), float(difference.max())


@pytest.fixture(scope="module")
def radau() -> Reference:
    """The continuous closed loop solved by Radau at rtol = atol = 1e-10."""
    scenario = sm.Scenario.load(TRACKING, CONTINUOUS)
    start = time.perf_counter()
    with one_blas_thread():
        solution = scipy_integrate.solve_ivp(
            sm.closed_loop_rhs(scenario),
            (0.0, HORIZON),
            scenario.initial_state,
            method="Radau",
            rtol=TOLERANCE,
            atol=TOLERANCE,
            dense_output=True,
        )
    assert solution.success, solution.message
    return Reference(scenario, solution, time.perf_counter() - start)


def timed_run(overrides: dict[str, object]) -> tuple[sm.ScenarioResult, float]:
    """``run_scenario`` of the tracking scenario and its wall time [s]."""
    start = time.perf_counter()
    result = sm.run_scenario(TRACKING, overrides)
    return result, time.perf_counter() - start


def test_closed_loop_rhs_accepts_a_drifted_quaternion_without_touching_the_state():
    scenario = sm.Scenario.load(TRACKING, CONTINUOUS)
    rhs = sm.closed_loop_rhs(scenario)
    x_unit = scenario.initial_state.copy()
    x_unit[scenario.model.nq + 5] = 0.05  # some joint velocity, so the field is not trivial
    x_drifted = x_unit.copy()
    x_drifted[3:7] *= 1.0 + 1e-3  # the plant alone refuses a norm off by more than 1e-4
    with pytest.raises(ValueError, match="unit quaternion"):
        scenario.plant.dynamics(x_drifted, np.zeros(scenario.plant.nu_input))
    drifted_copy = x_drifted.copy()
    np.testing.assert_allclose(rhs(0.1, x_drifted), rhs(0.1, x_unit), rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(x_drifted, drifted_copy)
    # The field is the closed loop's: the controller's input at (t, x), not a held one.
    assert not np.allclose(rhs(0.1, x_unit), rhs(0.2, x_unit))


def test_continuous_sampling_converges_to_radau_at_second_order(radau):
    rows = []
    for dt in PLANT_STEPS:
        result, seconds = timed_run({**CONTINUOUS, "plant.dt": dt})
        rows.append((dt, *radau.errors(result), seconds))
    print(f"\nContinuous sampling (ROS2) against Radau (rtol {TOLERANCE:g}, {radau.seconds:.1f} s,")
    print(f"{radau.solution.nfev} evaluations), tracking scenario, {HORIZON} s, joint-side state")
    print("  dt [ms]   final error   ratio   trajectory max   ratio   run [s]")
    for i, (dt, final, worst, seconds) in enumerate(rows):
        final_ratio = rows[i - 1][1] / final if i else float("nan")
        worst_ratio = rows[i - 1][2] / worst if i else float("nan")
        print(
            f"  {dt * 1e3:7.3f}   {final:11.3e}   {final_ratio:5.1f}   {worst:14.3e}   "
            f"{worst_ratio:5.1f}   {seconds:7.2f}"
        )
    finals = [row[1] for row in rows]
    worsts = [row[2] for row in rows]
    # Second order: at least 3 per halving (4 in the limit), at the end and all along.
    assert all(a / b > 3.0 for a, b in zip(finals, finals[1:])), finals
    assert all(a / b > 3.0 for a, b in zip(worsts, worsts[1:])), worsts
    at_quarter_ms = PLANT_STEPS.index(2.5e-4)
    assert finals[at_quarter_ms] < 2e-6  # measured 9.4e-7
    assert worsts[at_quarter_ms] < 0.06  # measured 0.029 (3 rad/s on a 90 rad/s motor peak)


def test_zero_order_hold_differs_far_more_than_the_integration_error(radau):
    continuous, _ = timed_run({**CONTINUOUS, "plant.dt": 2.5e-4})
    held, _ = timed_run(
        {
            **CONTINUOUS,
            "controller.sampling": "zero_order_hold",
            "controller.rate_hz": 1000.0,
            "plant.dt": 2.5e-4,
        }
    )
    integration_final, integration_worst = radau.errors(continuous)
    sampling_final, sampling_worst = radau.errors(held)
    print("\nAgainst Radau on the continuous loop, plant step 0.25 ms: final, trajectory max")
    print(f"  continuous sampling:      {integration_final:.3e}  {integration_worst:.3e}")
    print(f"  zero-order hold at 1 kHz: {sampling_final:.3e}  {sampling_worst:.3e}")
    assert sampling_final > 30.0 * integration_final  # measured 136 times
    assert sampling_worst > 5.0 * integration_worst  # measured 17 times
