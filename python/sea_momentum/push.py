"""Push recovery studies: the largest push a scenario's closed loop recovers from, per
direction, bisected on full runs (as ``sea-sim push``), or the outcome of each of given
impulses, beside the stance's capture-point bound (the linear inverted pendulum's: a push of
impulse ``I`` gives the CoM ``I / m``, and the instantaneous capture point stays in the support
polygon while ``I <= m d omega0``).

Ctrl-C stops a study as it stops a sweep: no run starts, the runs under way stop at their
next sample, and the rows done are returned with ``interrupted`` true (and a
``RuntimeWarning``).

:func:`template_push_table` pushes a walk's template instead: the controller's own planner and
momentum law on the linear inverted pendulum, the robot left out (milliseconds a run), to tell
the planner's share of a shortfall from the robot's.
"""

from __future__ import annotations

import dataclasses
import os
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, Optional, cast

from ._native import push_table_native, template_push_native
from .results import Result

__all__ = ["PushRow", "PushTable", "TemplateRow", "push_table", "template_push_table"]

#: The push directions, along the first contact's sole axes.
DIRECTIONS = ("forward", "backward", "left", "right")


@dataclasses.dataclass(frozen=True)
class PushRow(Result):
    """One direction of a push study (a :class:`~sea_momentum.results.Result`).

    - ``direction``: "forward", "backward", "left" or "right";
    - ``capture_point_impulse_n_s``: the stance's capture-point bound [N s];
    - ``recovered_impulse_n_s``: bisected, the largest impulse seen recovered (0 when none,
      also when Ctrl-C stopped the bisection before a run ended);
      with given impulses, the largest at and below which every given one was recovered, or
      None when a push not run to its end lies at or below the first one lost;
    - ``failed_impulse_n_s``: the smallest impulse seen not recovered, or None;
    - ``pushes``: every run as ``(impulse [N s], status)``: the given impulses in their order,
      or the bisection's runs in the order they ran; status "completed" (recovered),
      "diverged", "fell" or "interrupted";
    - ``interrupted``: Ctrl-C stopped this direction's study before its end.
    """

    direction: str
    capture_point_impulse_n_s: float
    recovered_impulse_n_s: Optional[float]
    failed_impulse_n_s: Optional[float]
    pushes: list[tuple[float, str]]
    interrupted: bool

    @property
    def ratio(self) -> Optional[float]:
        """``recovered_impulse_n_s`` over the capture-point bound (None when either is not known
        or the bound is 0)."""
        if self.recovered_impulse_n_s is None or self.capture_point_impulse_n_s <= 0.0:
            return None
        return self.recovered_impulse_n_s / self.capture_point_impulse_n_s


@dataclasses.dataclass(frozen=True)
class PushTable(Result):
    """The rows of a push study, one per direction in the order asked; ``interrupted``: Ctrl-C
    stopped it (the rows hold the runs done); ``start_s``: the push's start [s] (given, or
    found at a phase of a swing). A :class:`~sea_momentum.results.Result`."""

    rows: list[PushRow]
    interrupted: bool
    start_s: float

    def row(self, direction: str) -> PushRow:
        """The row of ``direction``; ``KeyError`` naming it and the study's directions when the
        study has none."""
        for row in self.rows:
            if row.direction == direction:
                return row
        studied = ", ".join(row.direction for row in self.rows)
        raise KeyError(f"direction {direction!r} is not in this study ({studied})")


def push_table(
    scenario: str | os.PathLike[str],
    directions: Sequence[str] = DIRECTIONS,
    impulses: Optional[Sequence[float]] = None,
    overrides: Optional[Mapping[str, Any]] = None,
    link: str = "root_link",
    start_s: Optional[float] = None,
    duration_s: float = 0.1,
    tolerance_n_s: float = 0.1,
    phase: Optional[float] = None,
    step: Optional[int] = None,
) -> PushTable:
    """The push study of the scenario file ``scenario`` (its own ``disturbances`` replaced by
    the push), directions in parallel, the GIL released; returns a :class:`PushTable`.

    A push of ``duration_s`` [s] on ``link`` from ``start_s`` [s] (1.0 by default), along each
    of ``directions``. On a walking scenario, ``phase`` starts it instead at that fraction of
    the swing of step ``step`` (0-based; by default the fourth, the last of a shorter plan) of
    the scenario's walk, as ``sea-sim push --phase``: 0 the swing foot's lift-off, 1 its planned touchdown, the time
    rounded to a plant step (``PushTable.start_s``). Without ``impulses``, each direction's
    largest recovered impulse is bisected to ``tolerance_n_s`` [N s] between 0 and twice the
    capture-point bound (doubled while recovered, up to 8 times); with ``impulses`` [N s], one
    run each (islands of recovery above a failure show). A run recovers when it completes (no
    fall, no divergence); a run that ends less than 1 s after the push's end warns
    (``UserWarning``): a push that fells the robot may not have fallen by then.

    Raises ScenarioError for a bad scenario, override or direction name (naming it), SeaIOError
    for a scenario file that cannot be read, ValueError naming ``directions`` (none, or one
    twice), ``duration_s``, ``tolerance_n_s``, ``start_s`` (a push that does not end within
    the run, or given with ``phase``), ``phase`` (outside [0, 1], a scenario that does not
    walk, or a push at the phase that does not end within the run), ``step`` (beyond the
    walk's steps, negative, or given without ``phase``), ``link`` (not a link of the robot) or
    ``impulses`` (none, or one not finite and non-negative), ``start_s`` or ``duration_s``
    not a whole number of the scenario's plant steps, and TypeError for ``impulses``
    given as a string or ``step`` not an integer.
    """
    if isinstance(directions, str):
        directions = [directions]
    directions = list(directions)
    if isinstance(impulses, (str, bytes)):
        raise TypeError(f"impulses: expected a sequence of numbers [N s], got {impulses!r}")
    native = push_table_native(
        os.fspath(scenario),
        directions,
        dict(overrides or {}),
        None if impulses is None else list(impulses),
        link,
        start_s,
        duration_s,
        tolerance_n_s,
        phase,
        step,
    )
    rows = [
        PushRow(
            direction=str(row["direction"]),
            capture_point_impulse_n_s=float(row["capture_point_impulse_n_s"]),
            recovered_impulse_n_s=row["recovered_impulse_n_s"],
            failed_impulse_n_s=row["failed_impulse_n_s"],
            pushes=[(float(i), str(s)) for i, s in row["pushes"]],
            interrupted=bool(row["interrupted"]),
        )
        for row in cast("list[dict[str, Any]]", native["rows"])
    ]
    table = PushTable(
        rows=rows,
        interrupted=bool(native["interrupted"]),
        start_s=float(cast(float, native["start_s"])),
    )
    if table.interrupted:
        warnings.warn("push study interrupted: the rows hold the runs done", RuntimeWarning, stacklevel=2)
    return table


@dataclasses.dataclass(frozen=True)
class TemplateRow(Result):
    """One direction of pushes on a walk's template (a :class:`~sea_momentum.results.Result`).

    - ``direction``: "forward", "backward", "left" or "right";
    - ``recovered_impulse_n_s``: bisected, the largest impulse recovered; with given impulses,
      the largest at and below which every given one was recovered (0 when the smallest was
      lost);
    - ``pushes``: with given impulses, each as ``(impulse [N s], recovered)`` in their order;
      empty when bisected.
    """

    direction: str
    recovered_impulse_n_s: float
    pushes: list[tuple[float, bool]]


def template_push_table(
    scenario: str | os.PathLike[str],
    phase: float,
    directions: Sequence[str] = DIRECTIONS,
    impulses: Optional[Sequence[float]] = None,
    overrides: Optional[Mapping[str, Any]] = None,
    step: Optional[int] = None,
    duration_s: float = 0.1,
    tolerance_n_s: float = 0.01,
) -> list[TemplateRow]:
    """Pushes on the template of the walking scenario file ``scenario``, one
    :class:`TemplateRow` per direction: the figures ``sea-sim push --phase`` reports beside
    the robot's (``template_impulse_n_s``, there bisected to ``--tolerance``, 0.1 N s by
    default).

    The template is the controller's own walking planner (with its step adjustment) and the
    momentum task's linear rows on the linear inverted pendulum, the centre of pressure held in
    the plan's support over each whole-body period; feet land where and when planned, no
    angular momentum, no joints, the push unknown to the law
    (``docs/findings/walking_template.md``). A push of ``duration_s`` [s] on the CoM starts at
    fraction ``phase`` of the swing of step ``step`` (0-based; by default the fourth, the last
    of a shorter plan) of the scenario's walk, and must
    end within the run (``simulation.duration_s``). Without ``impulses`` each direction's largest recovered
    impulse is bisected to ``tolerance_n_s`` [N s]; with ``impulses`` [N s], one run each.

    Raises ScenarioError for a bad scenario, override or direction name (naming it),
    SeaIOError for a file that cannot be read, ValueError naming ``phase`` (outside [0, 1], or
    a scenario that does not walk), ``step`` (negative or beyond the plan), ``directions``
    (none, or one twice), ``duration_s`` (not positive, or a push that ends after the run),
    ``tolerance_n_s`` or ``impulses`` (none, or one not finite and non-negative), and
    TypeError for ``impulses`` given as a string or ``step`` not an integer.
    """
    if isinstance(directions, str):
        directions = [directions]
    if isinstance(impulses, (str, bytes)):
        raise TypeError(f"impulses: expected a sequence of numbers [N s], got {impulses!r}")
    native = template_push_native(
        os.fspath(scenario),
        list(directions),
        phase,
        step,
        dict(overrides or {}),
        None if impulses is None else list(impulses),
        duration_s,
        tolerance_n_s,
    )
    return [
        TemplateRow(
            direction=str(row["direction"]),
            recovered_impulse_n_s=float(row["recovered_impulse_n_s"]),
            pushes=[(float(i), bool(o)) for i, o in row["pushes"]],
        )
        for row in cast("list[dict[str, Any]]", native["rows"])
    ]
