"""Pictures of the feet on the ground under unilateral contacts
(``plant.contact_model = "unilateral"``), from a :class:`~sea_momentum.scenario.ScenarioResult`'s
contact points:

- :func:`contact_points_figure`: per contact, the force of each of its points along the
  ground's normal over time (one line per point; the spans where no point of the foot touches,
  i.e. the foot is lifted, shaded), and a top view of the points (their paths over the run, so
  a slip shows, and where they are at one instant, filled while they touch) with each foot's
  centre of pressure (its path and its place at that instant);
- :func:`contact_points_picture`: the figure as a PNG.

matplotlib is imported when a figure is drawn (the caller chooses the backend).
"""

from __future__ import annotations

import os
import pathlib
from typing import TYPE_CHECKING, Any

import numpy as np

from ._errors import argument_error
from .arrays import BoolArray, FloatArray
from .extras import require_plots

if TYPE_CHECKING:
    from .scenario import ScenarioResult

#: Colour of a lifted foot's spans in the force plots.
LIFTED_RGBA = (0.85, 0.3, 0.25, 0.15)


def foot_lifted(result: ScenarioResult, contact: str) -> BoolArray:
    """(m,) bool: the rows where no point of contact ``contact`` touches the ground."""
    columns = result.contact_point_slice(contact)
    return np.asarray(~result.contact_point_active[:, columns].any(axis=1), dtype=np.bool_)


def center_of_pressure(result: ScenarioResult, contact: str) -> FloatArray:
    """(m, 3) float64: contact ``contact``'s centre of pressure, world [m]: its points'
    positions weighted by their normal forces; NaN where the foot is lifted."""
    columns = result.contact_point_slice(contact)
    normal = result.contact_point_normal_forces()[:, columns]
    total = normal.sum(axis=1)
    weighted = np.einsum("rp,rpk->rk", normal, result.contact_point_positions[:, columns])
    with np.errstate(invalid="ignore", divide="ignore"):
        cop = weighted / total[:, None]
    cop[total <= 0.0] = np.nan
    return np.asarray(cop, dtype=np.float64)


def _spans(mask: BoolArray, time: FloatArray) -> list[tuple[float, float]]:
    """The time intervals where ``mask`` holds (each from its first row to the row after its
    last, or the last time)."""
    spans = []
    edges = np.flatnonzero(np.diff(np.concatenate([[False], mask, [False]]).astype(np.int8)))
    for start, stop in zip(edges[::2], edges[1::2]):
        spans.append((float(time[start]), float(time[min(stop, len(time) - 1)])))
    return spans


def _force_axes(ax: Any, result: ScenarioResult, contact: str, colour: str) -> None:
    """The normal force of each point of ``contact`` over time, lifted spans shaded."""
    columns = result.contact_point_slice(contact)
    normal = result.contact_point_normal_forces()[:, columns]
    styles = ["-", "--", "-.", ":"]
    for k in range(normal.shape[1]):
        ax.plot(result.time, normal[:, k], styles[k % len(styles)], color=colour, label=f"point {k}")
    for start, stop in _spans(foot_lifted(result, contact), result.time):
        ax.axvspan(start, stop, color=LIFTED_RGBA, linewidth=0)
    ax.set_ylabel(f"{contact}\nnormal force [N]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper right", ncol=2)


def _top_view(ax: Any, result: ScenarioResult, row: int, colours: list[str]) -> None:
    """The points' paths and places at ``row`` and each foot's centre of pressure, x-y."""
    for contact, colour in zip(result.contacts, colours):
        columns = result.contact_point_slice(contact)
        positions = result.contact_point_positions[:, columns]
        for k in range(positions.shape[1]):
            ax.plot(positions[:, k, 0], positions[:, k, 1], color=colour, alpha=0.35, linewidth=0.8)
        active = result.contact_point_active[row, columns]
        at = positions[row]
        ax.scatter(at[active, 0], at[active, 1], color=colour, s=30, label=f"{contact} points (touching)")
        ax.scatter(at[~active, 0], at[~active, 1], facecolors="none", edgecolors=colour, s=30)
        cop = center_of_pressure(result, contact)
        ax.plot(cop[:, 0], cop[:, 1], color=colour, linewidth=1.6, label=f"{contact} CoP path")
        if np.isfinite(cop[row]).all():
            ax.scatter([cop[row, 0]], [cop[row, 1]], marker="x", color="k", s=40)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"top view at t = {result.time[row]:.2f} s (x: CoP)", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def contact_points_figure(result: ScenarioResult, instant: float | None = None) -> Any:
    """The figure of the contact points of ``result`` (see the module documentation): one
    force axes per contact (``fig.axes[:n_contacts]``, one line per point), then the top view
    at the recorded sample nearest ``instant`` (default: the last). ``ValueError`` for a run
    under bilateral contacts (it has no contact points)."""
    require_plots("contact_points_figure")
    import matplotlib.pyplot as plt

    if not result.contact_points:
        raise argument_error(
            "result",
            'expected a run under unilateral contacts (plant.contact_model = "unilateral"), '
            "got one without contact points",
        )
    time = result.time
    row = len(time) - 1 if instant is None else int(np.argmin(abs(time - instant)))
    n = len(result.contacts)
    colours = [f"C{k}" for k in range(n)]
    fig = plt.figure(figsize=(10, 2.2 + 1.8 * n))
    grid = fig.add_gridspec(n, 2, width_ratios=[2.0, 1.0])
    first: Any = None
    for k, (contact, colour) in enumerate(zip(result.contacts, colours)):
        ax = fig.add_subplot(grid[k, 0], sharex=first)
        first = first or ax
        _force_axes(ax, result, contact, colour)
    first.set_title("force of each contact point along the ground normal (shaded: foot lifted)", fontsize=9)
    fig.axes[n - 1].set_xlabel("time [s]")
    _top_view(fig.add_subplot(grid[:, 1]), result, row, colours)
    fig.tight_layout()
    return fig


def contact_points_picture(
    result: ScenarioResult, path: str | os.PathLike[str], instant: float | None = None
) -> pathlib.Path:
    """:func:`contact_points_figure` written to ``path`` (PNG, 110 dpi); returns the path."""
    require_plots("contact_points_picture")
    import matplotlib.pyplot as plt

    fig = contact_points_figure(result, instant)
    path = pathlib.Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
