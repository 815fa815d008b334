"""Parameter sweeps: one scenario over the cartesian product of value grids of numeric scenario
keys, run natively in parallel on this machine's cores (``backend="local"``, the GIL released)
or as Ray tasks on a cluster (``backend="ray"``, see :mod:`sea_momentum.ray_backend`).

Both backends run the same native function on the same points, so their results are identical
(apart from the wall-clock fields ``wall_time_s`` and ``realtime_factor``), whatever the number
of workers. A run that fails is a row with status ``"failed"`` and its message; Ctrl-C stops
the sweep and returns the rows done (``SweepResult.interrupted``).
"""

from __future__ import annotations

import dataclasses
import math
import os
import warnings
from typing import Any, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._errors import argument_error
from .arrays import AnyArray, BoolArray, FloatArray, IntArray
from .results import Result

#: A grid axis: a list of numbers, or ``"START:STOP:COUNT"`` / ``"START:STOP:COUNT:log"``
#: (both ends included).
GridValues = Union[Sequence[float], FloatArray, IntArray, str]

#: Columns that hold text; every other column is numeric.
_TEXT_COLUMNS = ("status", "message", "sampling", "fall_foot", "fall_link", "fall_constraint")


def grid_specs(grid: Mapping[str, GridValues]) -> list[str]:
    """The grid as ``KEY=V1,V2,...`` / ``KEY=START:STOP:COUNT[:log]`` specifications (the
    native parser checks them; numbers are written exactly, with ``repr``)."""
    if not isinstance(grid, Mapping) or not grid:
        raise argument_error(
            "grid",
            f"expected a non-empty dict of key -> values or 'START:STOP:COUNT[:log]', got {grid!r}",
        )
    specs = []
    for key, values in grid.items():
        if isinstance(values, str):
            specs.append(f"{key}={values}")
            continue
        axis = np.asarray(values, dtype=object)
        if axis.ndim > 1:
            raise argument_error(
                f"grid['{key}']", f"expected a flat list of numbers, got shape {axis.shape}"
            )
        texts = []
        for item in np.atleast_1d(axis).tolist():
            real = isinstance(item, (int, float, np.integer, np.floating))
            if isinstance(item, (bool, np.bool_)) or not real:
                raise argument_error(
                    f"grid['{key}']", f"every value must be a real number, got {item!r}"
                )
            texts.append(repr(float(item)))
        specs.append(f"{key}={','.join(texts)}")
    return specs


def _column(name: str, values: list[Any]) -> AnyArray:
    """One column: text as a str array, numbers as float64 (None as NaN) or int64 when every
    value is a whole number."""
    if name in _TEXT_COLUMNS:
        return np.array(["" if v is None else str(v) for v in values], dtype=str)
    if values and all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return np.array(values, dtype=np.int64)
    return np.array([math.nan if v is None else float(v) for v in values], dtype=np.float64)


@dataclasses.dataclass(frozen=True)
class SweepResult(Result):
    """The runs of a sweep, in grid order (the last key varies fastest).

    ``keys``: the grid keys; ``rows``: one dict per run (the grid values by key, ``status``
    "completed" | "diverged" | "fell" | "interrupted" | "failed", ``message``, then every summary field:
    ``com_error_rms_m``, ``diverged_at_s`` (None unless diverged), ...; summary fields are None
    for a failed run); ``columns``: the same as numpy arrays by name (numbers float64 with NaN
    for None, or int64 for counts; text as str arrays); ``total``: points in the grid;
    ``interrupted``: Ctrl-C stopped the sweep (``rows`` holds the runs done, fewer than
    ``total``); ``indices``: the grid index of each row.

    A :class:`~sea_momentum.results.Result` (``to_dict()``, ``from_native``), except that its
    items are its columns: ``result["com_error_rms_m"]`` is ``result.columns["com_error_rms_m"]``.
    """

    keys: tuple[str, ...]
    rows: list[dict[str, Any]]
    columns: dict[str, AnyArray]
    total: int
    interrupted: bool
    indices: IntArray

    @classmethod
    def from_native(cls, native: Mapping[str, Any]) -> SweepResult:
        """Builds the result from the dict of ``_native.sweep`` (or the Ray backend)."""
        names = list(native["columns"])
        rows = []
        for raw in native["rows"]:
            row = {name: raw[name] for name in names}
            rows.append(row)
        columns = {name: _column(name, [row[name] for row in rows]) for name in names}
        indices = np.array([raw["index"] for raw in native["rows"]], dtype=np.int64)
        return cls(
            keys=tuple(native["keys"]),
            rows=rows,
            columns=columns,
            total=int(native["total"]),
            interrupted=bool(native["interrupted"]),
            indices=indices,
        )

    def __len__(self) -> int:
        """Number of runs done (``total`` unless interrupted)."""
        return len(self.rows)

    def __getitem__(self, key: str) -> AnyArray:
        """The column ``key`` (``KeyError`` for an unknown column)."""
        return self.columns[key]

    @property
    def stable(self) -> BoolArray:
        """Whether each run completed (bool array)."""
        return self.columns["status"] == "completed"

    def to_pandas(self) -> Any:
        """The columns as a ``pandas.DataFrame`` (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as error:
            raise ImportError("SweepResult.to_pandas() needs pandas: pip install pandas") from error
        return pd.DataFrame({name: column for name, column in self.columns.items()})


def sweep(
    scenario: Union[str, os.PathLike],
    grid: Mapping[str, GridValues],
    overrides: Optional[Mapping[str, Any]] = None,
    workers: Optional[int] = None,
    backend: str = "local",
    progress: bool = False,
    batch_size: Optional[int] = None,
) -> SweepResult:
    """Runs the scenario file ``scenario`` at every point of ``grid`` and returns a
    :class:`SweepResult`.

    ``grid``: ``{key: [values]}`` or ``{key: "START:STOP:COUNT[:log]"}`` over numeric scenario
    keys (``controller.damping_estimate_scale``, ``controller.rate_hz``, ...); the runs are the
    cartesian product. ``overrides``: scenario values for every run (a grid key wins).
    ``workers``: threads of the local backend, an integer (numpy's too) from 1 to
    ``MAX_SWEEP_WORKERS`` (default: every core). ``backend``: ``"local"`` or
    ``"ray"`` (Ray tasks of ``batch_size`` runs each on the cluster of ``ray.init(address=...)``,
    or a local Ray when none is initialised; needs ``pip install 'sea-momentum[cluster]'``).
    ``progress``: a line on stderr per finished run (per batch with Ray).

    Raises ScenarioError naming the key and the value for bad grids (unknown or non-numeric
    keys, non-numeric values, COUNT below 1, empty or inverted ranges) before any run, and
    ValueError naming the argument for a bad backend or worker count, ``workers`` with Ray or
    ``batch_size`` without it. Runs that fail are rows, not exceptions.
    """
    specs = grid_specs(grid)
    path = os.fspath(scenario)
    if backend == "local" and batch_size is not None:
        raise argument_error(
            "batch_size", f"only with backend='ray', got {batch_size!r} with 'local'"
        )
    if backend == "ray" and workers is not None:
        raise argument_error(
            "workers", f"only with backend='local' (Ray's cluster sets its own), got {workers!r}"
        )
    if backend == "local":
        integer = isinstance(workers, (int, np.integer)) and not isinstance(workers, (bool, np.bool_))
        most = _native.MAX_SWEEP_WORKERS
        if workers is not None and (not integer or not 1 <= workers <= most):
            raise argument_error(
                "workers", f"expected an int from 1 to {most} or None, got {workers!r}"
            )
        workers = None if workers is None else int(workers)
        native = _native.sweep(path, specs, overrides, workers, progress)
    elif backend == "ray":
        from .ray_backend import run_on_ray

        native = run_on_ray(path, specs, overrides, batch_size=batch_size, progress=progress)
    else:
        raise argument_error("backend", f"expected 'local' or 'ray', got {backend!r}")
    result = SweepResult.from_native(native)
    if result.interrupted:
        warnings.warn(
            f"sweep interrupted: {len(result)} of {result.total} runs done",
            RuntimeWarning,
            stacklevel=2,
        )
    return result
