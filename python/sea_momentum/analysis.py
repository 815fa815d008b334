"""Stability analysis of the closed loop: linearisation and stability margins.

``linearize`` finds the closed loop's equilibrium with the references frozen at time ``t``
(Newton's method on the state's tangent space, from the scenario's initial state, so unstable
settings can be analysed too), then the Jacobian on the tangent space by central differences:
of the vector field in continuous sampling, of the map over one control period in zero-order
hold. Tangent coordinates: ``dq`` (nv: base position, base rotation in world axes, joints),
``dtheta`` (n_e, motor side), ``dnu`` (nv), ``dthetadot`` (n_e); ``state_names`` names them.

``stability_margin`` scans ``[lower, upper]`` for a numeric scenario key and bisects every
change of stability, judged by the eigenvalues (``"eigen"``) or by whether a simulation
completes (``"simulate"``).
"""

from __future__ import annotations

import dataclasses
import math
import os
import warnings
from collections.abc import Mapping
from typing import Any, cast

from ._native import linearize_native, stability_margin_native
from .arrays import ComplexArray, FloatArray
from .results import Result

__all__ = ["Linearization", "linearize", "stability_margin"]


@dataclasses.dataclass(frozen=True)
class Linearization(Result):
    """The linearised closed loop (float64 arrays; nd = 2 nv + 2 n_e, times ``d + 1`` for a
    period map with ``sensing.delay_inner_periods = d``: its state is the history of the last
    ``d + 1`` inner-tick states, the older slots' names suffixed ``@-i``); a
    :class:`~sea_momentum.results.Result` (``lin["growth_rate"]``, ``lin.to_dict()``).

    - ``matrix`` (nd, nd): the Jacobian of the vector field [1/s] (continuous) or of the
      period map (zero-order hold, multi-rate), on the tangent space;
    - ``eigenvalues`` (nd,) complex, least stable first; ``growth_rates`` (nd,) [1/s]: the real
      part, or ``log|mu| / T`` for the period map; ``growth_rate`` the largest, ``stable``
      whether it is negative;
    - ``least_stable_rate``: the least stable eigenvalue as a continuous-time rate [1/s]
      (``log(mu) / T`` for the map), so its imaginary part is the mode's angular frequency;
    - ``least_stable_mode`` (nd,) complex eigenvector; ``dominant_states``: its largest entries
      as ``(name, weight)``, weight 1 for the largest (motor entries times the transmission
      ratio, velocities divided by the mode's rate, so all are link-side position amplitudes);
    - ``equilibrium`` (nx,), ``converged``, ``residual`` (``|f|_inf`` there),
      ``newton_iterations``, ``map_residual`` (``|Phi(x) (-) x|_inf``, zero-order hold only);
    - ``sampling`` ("continuous" | "zero_order_hold" | "multi_rate"), ``control_period`` [s]
      (multi-rate: the whole-body period, the map over it with the joint loops ticking inside)
      or None,
      ``time`` [s] at which the references were frozen;
    - ``step`` and ``check_step``: the relative finite-difference steps; ``eigenvalue_change``
      (the largest relative change of an eigenvalue between them; defective eigenvalues move
      most), ``least_stable_change`` and ``growth_rate_change`` [1/s].
    """

    matrix: FloatArray
    eigenvalues: ComplexArray
    growth_rates: FloatArray
    growth_rate: float
    stable: bool
    least_stable_rate: complex
    state_names: list[str]
    least_stable_mode: ComplexArray
    dominant_states: list[tuple[str, float]]
    equilibrium: FloatArray
    converged: bool
    residual: float
    newton_iterations: int
    map_residual: float | None
    sampling: str
    control_period: float | None
    time: float
    step: float
    check_step: float | None
    eigenvalue_change: float | None
    least_stable_change: float | None
    growth_rate_change: float | None

    @classmethod
    def from_native(cls, raw: Mapping[str, Any]) -> Linearization:
        """The result of ``linearize_native``'s dict: complex arrays and the least stable rate
        joined from their real and imaginary parts, dominant states as (str, float) pairs."""
        fields = dict(raw)
        fields["eigenvalues"] = fields.pop("eigenvalues_re") + 1j * fields.pop("eigenvalues_im")
        fields["least_stable_mode"] = fields.pop("mode_re") + 1j * fields.pop("mode_im")
        fields["least_stable_rate"] = complex(*fields["least_stable_rate"])
        fields["dominant_states"] = [(str(n), float(w)) for n, w in fields["dominant_states"]]
        return cls(**fields)


def linearize(
    scenario: str | os.PathLike[str],
    t: float | None = None,
    overrides: Mapping[str, object] | None = None,
    sampling: str | None = None,
) -> Linearization:
    """Linearises the closed loop of a scenario file about its equilibrium with the references
    frozen at ``t`` (default 0; ``ValueError`` when negative or not finite), GIL released.

    ``overrides`` are scenario keys, e.g. ``{"controller.damping_estimate_scale": 0.4}``;
    ``sampling`` is None (the scenario's ``controller.sampling``), ``"continuous"`` or
    ``"zero_order_hold"`` (at ``controller.rate_hz``) or ``"multi_rate"`` (the whole-body
    period map with the joint torque loops at ``controller.inner_rate_hz``). Raises ``ScenarioError`` naming a bad
    key.
    """
    raw = linearize_native(os.fspath(scenario), t, dict(overrides or {}), sampling)
    return Linearization.from_native(raw)


def stability_margin(
    scenario: str | os.PathLike[str],
    parameter: str,
    lower: float,
    upper: float,
    overrides: Mapping[str, object] | None = None,
    method: str = "eigen",
    sampling: str | None = None,
    grid_points: int = 9,
    log_grid: bool = False,
) -> list[float]:
    """The values of the numeric scenario key ``parameter`` in ``[lower, upper]`` where the
    closed loop's stability changes, ascending (empty when it never changes), GIL released.

    A grid of ``grid_points`` values (logarithmic with ``log_grid``) is scanned and every change
    bisected to 1e-3 of the range; a key that takes whole numbers (e.g.
    ``sensing.delay_inner_periods``) is scanned at whole numbers, each boundary halfway between
    the two neighbours it separates (8.5: one verdict at 8, the other at 9). ``method``: ``"eigen"`` (growth rate of the linearisation
    about the equilibrium at t = 0) or ``"simulate"`` (the scenario run completes). An unknown or
    non-numeric key raises ``ScenarioError`` naming it; an empty or inverted range a
    ``ValueError`` whose ``argument`` is ``"lower, upper"``, a bad ``grid_points`` one naming it.
    Ctrl-C stops the scan (a simulation under way at its next sample) and raises
    ``KeyboardInterrupt``. A ``RuntimeWarning`` names the eigen evaluations where Newton's
    method found no equilibrium (its residual above 1e-3), whose verdicts do not judge
    stability, and the boundaries next to them, which may be the edge of the equilibria (feet
    creeping on the compliant ground have none: where the scenario allows, weld them with
    ``{"plant.contact_model": "bilateral"}``, or use ``method="simulate"``); another, an eigen
    scan whose growth rate is the same at every evaluation (three or more): the parameter
    does not enter the linearisation about the standing equilibrium (a ``walking.*`` key).
    """
    report = stability_margin_native(
        os.fspath(scenario),
        parameter,
        lower,
        upper,
        dict(overrides or {}),
        method,
        sampling,
        grid_points,
        log_grid,
    )
    _warn_without_equilibrium(parameter, report)
    _warn_growth_unchanged(parameter, report)
    return list(cast("list[float]", report["boundaries"]))


def _exponent(value: float) -> str:
    """``value`` to three digits in the exponent form ``sea-sim`` prints (``4.14e3``; a NaN
    residual, which counts as no equilibrium, as ``nan``)."""
    if not math.isfinite(value):
        return f"{value}"
    mantissa, exponent = f"{value:.2e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _warn_growth_unchanged(parameter: str, report: Mapping[str, object]) -> None:
    """The ``RuntimeWarning`` of an eigen scan whose growth rate is the same at every
    evaluation: the parameter does not enter the linearisation (a ``walking.*`` key)."""
    if report["growth_unchanged"]:
        warnings.warn(
            f"{parameter}: the growth rate is the same at every evaluation: the parameter does "
            "not enter the linearisation about the standing equilibrium (use method='simulate')",
            RuntimeWarning,
            stacklevel=3,
        )


def _warn_without_equilibrium(parameter: str, report: Mapping[str, object]) -> None:
    """The ``RuntimeWarning`` of a margin scan with evaluations about no equilibrium."""
    points = cast("list[tuple[float, float]]", report["no_equilibrium"])
    if not points:
        return
    at = ", ".join(f"{value!r} (residual {_exponent(residual)})" for value, residual in points)
    beside = cast("list[float]", report["boundaries_beside_no_equilibrium"])
    edges = (
        f"; the boundaries {beside!r} lie next to them and may be the edge of the equilibria"
        if beside
        else ""
    )
    warnings.warn(
        f"{parameter}: Newton's method found no equilibrium at {at}, so the verdicts there do "
        f"not judge stability{edges} (feet creeping on the compliant ground have none: where the "
        "scenario allows, weld them with plant.contact_model = 'bilateral', or use "
        "method='simulate')",
        RuntimeWarning,
        stacklevel=3,
    )
