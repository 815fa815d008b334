"""The Ray backend of :func:`sea_momentum.sweep`: the grid is checked and expanded here, its
points are cut into batches, and each batch is one Ray task calling the native
``_native.sweep_batch`` (the function the local backend runs), so the rows are identical to the
local backend's.

The cluster is the user's: connect with ``ray.init(address="ray://head:10001")`` (or
``"auto"`` on a cluster node) before calling ``sweep(..., backend="ray")``; when Ray is not
initialised, ``ray.init()`` starts a local one. Every node needs ``sea-momentum`` installed and
the scenario file and its URDF at the same absolute path (a shared file system), since tasks
read them where they run.
"""

from __future__ import annotations

import math
import os
import sys
from typing import Any, Mapping, Optional, Sequence, cast

from . import _native
from ._errors import argument_error

#: Batches per CPU of the cluster when no batch size is given: a few per CPU balance uneven
#: run times (diverging runs stop early) without paying the task overhead per run.
BATCHES_PER_CPU = 2


def _import_ray() -> Any:
    """Ray, or an ImportError saying how to install it."""
    try:
        import ray
    except ImportError as error:
        raise ImportError(
            "sweep(..., backend='ray') needs Ray, which is not installed: "
            "pip install 'sea-momentum[cluster]' (or pip install ray)"
        ) from error
    return ray


def run_batch(
    path: str,
    keys: Sequence[str],
    points: Sequence[tuple[int, Sequence[float]]],
    overrides: Optional[Mapping[str, Any]],
) -> list[dict[str, Any]]:
    """One task: the runs of ``points`` ((grid index, values) pairs) on one core."""
    return _native.sweep_batch(path, list(keys), list(points), overrides, 1)


def batches(
    points: Sequence[Sequence[float]], batch_size: int
) -> list[list[tuple[int, list[float]]]]:
    """The points with their grid indices, cut into consecutive batches of ``batch_size``."""
    indexed = [(k, list(values)) for k, values in enumerate(points)]
    return [indexed[k : k + batch_size] for k in range(0, len(indexed), batch_size)]


def _batch_size(ray: Any, runs: int, batch_size: Optional[int]) -> int:
    """``batch_size``, or enough batches for every CPU of the cluster to get a few."""
    if batch_size is not None:
        if not isinstance(batch_size, int) or batch_size < 1:
            raise argument_error("batch_size", f"expected an int of at least 1, got {batch_size!r}")
        return batch_size
    cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
    return max(1, math.ceil(runs / (BATCHES_PER_CPU * cpus)))


def run_on_ray(
    path: str,
    specs: Sequence[str],
    overrides: Optional[Mapping[str, Any]] = None,
    batch_size: Optional[int] = None,
    progress: bool = False,
) -> dict[str, Any]:
    """Runs the sweep of the grid ``specs`` as Ray tasks; returns the dict that
    :meth:`SweepResult.from_native` takes. Ctrl-C cancels the batches not finished and returns
    the rows done with ``interrupted = True``."""
    ray = _import_ray()
    path = os.path.abspath(path)
    grid = _native.sweep_grid(path, list(specs), overrides)
    points = cast("list[list[float]]", grid["points"])
    if not ray.is_initialized():
        ray.init()
    size = _batch_size(ray, len(points), batch_size)
    task = ray.remote(num_cpus=1)(run_batch)
    overrides_ref = ray.put(dict(overrides) if overrides else None)
    pending = [
        task.remote(path, grid["keys"], batch, overrides_ref)
        for batch in batches(points, size)
    ]
    rows: list[dict[str, Any]] = []
    interrupted = False
    try:
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for ref in done:
                rows.extend(ray.get(ref))
            if progress:
                print(f"  sweep (ray) {len(rows)}/{len(points)} runs", file=sys.stderr)
    except KeyboardInterrupt:
        interrupted = True
        for ref in pending:
            ray.cancel(ref, force=True)
    rows.sort(key=lambda row: row["index"])
    return {
        "keys": grid["keys"],
        "columns": grid["columns"],
        "rows": rows,
        "total": len(points),
        "interrupted": interrupted,
    }
