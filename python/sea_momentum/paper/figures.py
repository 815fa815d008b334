"""The figures of the paper application: Figures 1-3 of the paper in its setting, the growth
rate of the least stable mode against the damping estimate scale, the stability map, and the
pictures of the robot during each experiment (drawn by :mod:`sea_momentum.pictures`).
matplotlib is imported when a figure is drawn (the caller chooses the backend)."""

from __future__ import annotations

import os
import pathlib
from typing import Any, Mapping

import numpy as np

from ..arrays import FloatArray
from ..extras import require_plots
from ..pictures import scenario_pictures
from ..scenario import ScenarioResult
from .session import outcome, stable
from .setting import DAMPING_SCALES, SATURATED_JOINT, TORQUE_LIMIT_NM
from .stability_map import StabilityMap


def _save(fig: Any, path: pathlib.Path) -> None:
    """Lays the figure out, writes it to ``path`` (PNG, 120 dpi) and closes it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def figure_tracking(runs: Mapping[str, ScenarioResult], path: pathlib.Path) -> None:
    """Figure 1: lateral CoM error for each damping estimate (paper's setting)."""
    require_plots("figure_tracking")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    styles = {1.0: "-", 1.45: "--", 1.6: "-.", 0.4: ":"}
    for scale in DAMPING_SCALES:
        result = runs[f"tracking x{scale}"]
        error_mm = (result.com[:, 1] - result.com_reference[:, 1]) * 1e3
        suffix = "" if stable(result) else f" ({outcome(result)})"
        ax.plot(result.time, error_mm, styles[scale], label=f"K_D estimate x{scale}{suffix}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("lateral CoM error [mm]")
    ax.set_title("Figure 1: CoM tracking on one foot, damping mismatch (continuous control)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    _save(fig, path)


def figure_step(runs: Mapping[str, ScenarioResult], path: pathlib.Path) -> None:
    """Figure 2: joint error norm after the step, rigid and SEA controllers."""
    require_plots("figure_step")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for label in ("step, SEA controller", "step, rigid controller"):
        result = runs[label]
        ax.plot(result.time, result.joint_error_norm, label=f"{label.split(', ')[1]} ({outcome(result)})")
    # The rigid controller's divergence ends far above: keep the converged level readable.
    ax.set_ylim(0.0, 3.0 * float(np.max(runs["step, SEA controller"].joint_error_norm)))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("joint position error norm [rad]")
    ax.set_title("Figure 2: 1 degree step on torso and arms, SEA robot (continuous control)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    _save(fig, path)


def figure_saturation(runs: Mapping[str, ScenarioResult], path: pathlib.Path) -> None:
    """Figure 3: the saturated joint's motor velocity, whole run and the first 0.3 s."""
    require_plots("figure_saturation")
    import matplotlib.pyplot as plt

    fig, (whole, start) = plt.subplots(2, 1, figsize=(7, 6))
    curves = (
        ("at rest, no limit", "g--", "springs at rest, no limit"),
        ("saturation 0.34 Nm", "r-", f"springs at rest, |tau_m| <= {TORQUE_LIMIT_NM} Nm"),
        ("preloaded, 0.34 Nm", "b:", f"springs preloaded, |tau_m| <= {TORQUE_LIMIT_NM} Nm"),
    )
    for key, style, label in curves:
        result = runs[key]
        k = result.motor(SATURATED_JOINT)
        for ax in (whole, start):
            ax.plot(result.time, result.thetadot[:, k], style, lw=1.0, label=label)
    limited = runs["saturation 0.34 Nm"]
    k = limited.motor(SATURATED_JOINT)
    start.plot(limited.time, limited.thetadot_desired[:, k], "k-", lw=0.6, label="reference (limited run)")
    start.set_xlim(0.0, 0.1)
    peak = max(np.abs(runs[key].thetadot[:, runs[key].motor(SATURATED_JOINT)]).max() for key, _, _ in curves)
    start.set_ylim(-1.3 * peak, 1.3 * peak)  # the reference's first swing is larger: cut
    for ax in (whole, start):
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"{SATURATED_JOINT} motor velocity [rad/s]")
        ax.grid(True, alpha=0.3)
    whole.set_title("Figure 3: torque saturation of the stance ankle roll (continuous control)")
    start.set_title("the first 0.1 s: the springs load")
    start.legend(fontsize=8)
    _save(fig, path)


def _edges(centres: FloatArray) -> FloatArray:
    """Cell edges around equally spaced centres."""
    step = centres[1] - centres[0]
    return np.concatenate([centres - step / 2, [centres[-1] + step / 2]])


def figure_stability_map(grid: StabilityMap, path: pathlib.Path) -> None:
    """Stable or not and the CoM error on (control rate, damping scale), log10 axes, the
    continuous setting as the last column, the eigenvalue boundary rate drawn over it."""
    require_plots("figure_stability_map")
    import matplotlib.pyplot as plt

    log_rates = np.log10(grid.rates_hz)
    x = np.append(log_rates, log_rates[-1] + (log_rates[1] - log_rates[0]))  # + continuous
    y = np.log10(grid.scales)
    fig, ax = plt.subplots(figsize=(8, 5))
    cmap = plt.get_cmap("viridis").with_extremes(bad="lightgrey")  # diverged runs
    error_mm = np.ma.masked_invalid(grid.com_error_rms_m * 1e3)
    mesh = ax.pcolormesh(_edges(x), _edges(y), error_mm, cmap=cmap, shading="flat")
    fig.colorbar(mesh, ax=ax, label="CoM error rms [mm] (stable runs)")
    for row, col in zip(*np.nonzero(~grid.stable)):
        ax.text(x[col], y[row], f"{grid.diverged_at_s[row, col]:.2f} s", ha="center", va="center", fontsize=7)
    found = [(np.log10(b), ys) for b, ys in zip(grid.boundary_rate_hz, y) if b is not None]
    if found:
        bx, by = zip(*found)
        ax.plot(bx, by, "-o", color="crimson", lw=2, ms=4, label="eigenvalue boundary rate (zero-order hold)")
    ax.axvline((x[-1] + x[-2]) / 2, color="k", lw=1)
    ax.set_xticks(x, [f"{r:.0f}" for r in grid.rates_hz] + ["contin-\nuous"])
    ax.set_yticks(y, [f"x{s:.2f}" for s in grid.scales])
    ax.set_xlabel("control rate [Hz] (zero-order hold, plant step <= 0.25 ms)")
    ax.set_ylabel("damping estimate scale")
    ax.set_title(f"Stability map of the SEA controller (tracking, {grid.duration_s:g} s runs;\n"
                 "grey: diverged, at the time written)")
    ax.legend(loc="lower right", fontsize=8, framealpha=0.9)
    _save(fig, path)


def matplotlib_null_formatter() -> Any:
    """No labels on minor ticks (the major ticks name the scales)."""
    from matplotlib.ticker import NullFormatter

    return NullFormatter()


def figure_growth_rate(curve: dict[str, list[float]], path: pathlib.Path) -> None:
    """Growth rate of the least stable mode against the damping scale; the paper's scales."""
    require_plots("figure_growth_rate")
    import matplotlib.pyplot as plt

    fig, (slow, fast) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    scale = np.array(curve["scale"])
    slow.plot(scale, curve["continuous"], "b-o", ms=3, label="continuous (the paper's setting)")
    slow.set_ylabel("growth rate [1/s]")
    slow.set_title("Least stable mode of the linearised closed loop (tracking)")
    fast.plot(scale, curve["sea_decay"], "g-s", ms=3, label="SEA modes' real part, continuous")
    fast.plot(scale, curve["1 kHz"], "r-^", ms=3, label="least stable mode, 1 kHz zero-order hold (dt 0.25 ms)")
    fast.set_ylabel("rate [1/s]")
    fast.set_xlabel("damping estimate scale")
    paper = {0.4: "stable", 1.45: "stable", 1.6: "unstable"}
    for ax in (slow, fast):
        ax.axhline(0.0, color="k", lw=0.8)
        for value, verdict in paper.items():
            ax.axvline(value, color="grey", ls="--", lw=0.8)
        ax.set_xscale("log")
        ax.set_xticks([0.2, 0.3, 0.4, 0.6, 1.0, 1.45, 2.0, 3.0], ["0.2", "0.3", "0.4", "0.6", "1", "1.45", "2", "3"])
        ax.xaxis.set_minor_formatter(matplotlib_null_formatter())
        ax.grid(True, alpha=0.3, which="both")
        ax.legend(fontsize=8)
    for value, verdict in paper.items():
        slow.annotate(f"x{value}: paper {verdict}", (value, 1.0), xycoords=("data", "axes fraction"),
                      rotation=90, va="top", ha="right", fontsize=8)
    _save(fig, path)


# ---- The robot during each experiment ----


def picture_instants(result: ScenarioResult, count: int = 5) -> FloatArray:
    """Instants worth a picture: the start and the turning points of the CoM reference (the
    robot leaning furthest each way) when it moves, else ``count`` instants evenly spaced."""
    time = result.time
    offset = result.com_reference - result.com_reference[0]
    lateral = offset[:, int(np.argmax(np.ptp(offset, axis=0)))]
    if np.ptp(lateral) > 1e-6:
        slope = np.sign(np.diff(lateral))
        turns = np.where(slope[1:] * slope[:-1] < 0)[0] + 1
        if len(turns):
            return np.concatenate([[time[0]], time[turns[: count - 1]]])
    return np.linspace(time[0], time[-1], count)


def experiment_pictures(
    scenario_dir: str | os.PathLike[str],
    out: str | os.PathLike[str],
    runs: Mapping[str, ScenarioResult],
) -> list[str]:
    """For each ``runs[name]`` (a run of ``scenario_dir/{name}.toml``; a name may carry a suffix
    after ``@``), the strip and the animation of
    :func:`~sea_momentum.pictures.scenario_pictures`; returns the file names written."""
    written = []
    for name, result in runs.items():
        scenario = pathlib.Path(scenario_dir) / f"{name.split('@')[0]}.toml"
        stem = name.replace("@", "_")
        title = f"{stem} ({result.status})"
        paths = scenario_pictures(scenario, result, out, stem, picture_instants(result), title)
        written += [p.name for p in paths]
    return written


def robot_pictures(scenario_dir: pathlib.Path, out: pathlib.Path, runs: Mapping[str, ScenarioResult]) -> list[str]:
    """The robot at chosen instants of each experiment (paper's setting): PNG strips and GIFs;
    returns the file names written."""
    return experiment_pictures(scenario_dir, out, {
        "tracking": runs["tracking x1.0"],
        "step_sea": runs["step, SEA controller"],
        "step_rigid": runs["step, rigid controller"],
        "saturation": runs["saturation 0.34 Nm"],
    })
