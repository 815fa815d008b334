"""sea_momentum.sweep: grids as lists and ranges, columns and rows, results that do not depend on
the number of workers or the backend (local threads, Ray tasks), failed runs as rows, bad grids
refused with the key named, and the Ray backend's ImportError without Ray."""

from __future__ import annotations

import importlib.util
import pathlib
import sys

import numpy as np
import pytest

import sea_momentum
from sea_momentum import ScenarioError, SweepResult, sweep

TRACKING = pathlib.Path(__file__).resolve().parents[1] / "scenarios" / "paper" / "tracking.toml"
#: Short runs in the sampled-data setting (the paper's file is continuous, where
#: ``controller.rate_hz`` is not used): 1 kHz zero-order hold by default, 1 ms plant step.
SHORT = {"simulation.duration_s": 0.3, "controller.sampling": "zero_order_hold", "plant.dt": 1e-3}
#: The fields that measure the machine, not the run.
WALL_CLOCK = ("wall_time_s", "realtime_factor")
HAVE_RAY = importlib.util.find_spec("ray") is not None


def comparable(result: SweepResult) -> list[dict]:
    """The rows without the wall-clock fields, with the grid index."""
    return [
        {"index": int(k), **{n: v for n, v in row.items() if n not in WALL_CLOCK}}
        for k, row in zip(result.indices, result.rows)
    ]


@pytest.fixture(scope="module")
def local_result() -> SweepResult:
    grid = {"controller.damping_estimate_scale": [0.8, 1.25], "controller.rate_hz": "100:1000:2"}
    return sweep(TRACKING, grid, overrides=SHORT, workers=2)


def test_columns_rows_and_grid_order(local_result):
    result = local_result
    assert result.keys == ("controller.damping_estimate_scale", "controller.rate_hz")
    assert len(result) == result.total == 4 and not result.interrupted
    np.testing.assert_array_equal(result.indices, [0, 1, 2, 3])
    np.testing.assert_array_equal(result["controller.damping_estimate_scale"], [0.8, 0.8, 1.25, 1.25])
    np.testing.assert_array_equal(result["controller.rate_hz"], [100.0, 1000.0, 100.0, 1000.0])
    assert result["com_error_rms_m"].dtype == np.float64
    assert result["qp_failures"].dtype == np.int64
    # 100 Hz falls (the sampled SEA loop grows until a foot's wrench leaves its constraints),
    # 1 kHz completes: both are rows, with the fall's foot and constraint as text columns.
    assert list(result["status"]) == ["fell", "completed", "fell", "completed"]
    assert np.all(np.isnan(result["fell_at_s"][[1, 3]]))
    assert np.all(result["fell_at_s"][[0, 2]] < 0.3)
    assert list(result["fall_foot"]) == ["l_sole", "", "l_sole", ""]
    assert list(result.stable) == [False, True, False, True]
    assert result.rows[1]["status"] == "completed" and result.rows[1]["message"] == ""
    assert set(result.columns) == set(result.rows[0])


def test_the_number_of_workers_does_not_change_the_results(local_result):
    grid = {"controller.damping_estimate_scale": [0.8, 1.25], "controller.rate_hz": "100:1000:2"}
    one = sweep(TRACKING, grid, overrides=SHORT, workers=1)
    assert comparable(one) == comparable(local_result)


def test_a_failed_run_is_a_row():
    keys = ["controller.rate_hz"]
    rows = sea_momentum._native.sweep_batch(
        str(TRACKING), keys, [(0, [1000.0]), (1, [-5.0])], SHORT, 2
    )
    assert [row["status"] for row in rows] == ["completed", "failed"]
    assert "controller.rate_hz" in rows[1]["message"]
    assert rows[1]["com_error_rms_m"] is None


@pytest.mark.parametrize(
    "grid, key",
    [
        ({"controller.no_such_gain": [1.0]}, "controller.no_such_gain"),
        ({"controller.kind": [1.0]}, "controller.kind"),
        ({"controller.rate_hz": "1000:100:3"}, "controller.rate_hz"),
        ({"controller.rate_hz": "100:1000:0"}, "controller.rate_hz"),
        ({"controller.rate_hz": "100:abc:3"}, "controller.rate_hz"),
    ],
)
def test_bad_grids_name_the_key(grid, key):
    with pytest.raises(ScenarioError) as caught:
        sweep(TRACKING, grid, overrides=SHORT)
    assert caught.value.key == key
    assert key in str(caught.value)


def test_bad_arguments_are_value_errors():
    with pytest.raises(ValueError, match="controller.rate_hz"):
        sweep(TRACKING, {"controller.rate_hz": [1000.0, "fast"]})
    with pytest.raises(ValueError, match="backend") as backend:
        sweep(TRACKING, {"controller.rate_hz": [1000.0]}, backend="dask")
    assert backend.value.argument == "backend"
    for workers in (0, sea_momentum._native.MAX_SWEEP_WORKERS + 1, True, 2.0):
        with pytest.raises(ValueError, match="workers") as bad:
            sweep(TRACKING, {"controller.rate_hz": [1000.0]}, workers=workers)
        assert bad.value.argument == "workers"
    # An argument of the other backend, which it would ignore.
    with pytest.raises(ValueError, match="only with backend='ray'") as batch:
        sweep(TRACKING, {"controller.rate_hz": [1000.0]}, batch_size=3)
    assert batch.value.argument == "batch_size"
    with pytest.raises(ValueError, match="only with backend='local'") as ray_workers:
        sweep(TRACKING, {"controller.rate_hz": [1000.0]}, backend="ray", workers=2)
    assert ray_workers.value.argument == "workers"
    # The module's own check too: a bad argument, not a scenario key.
    with pytest.raises(ValueError, match="workers") as native:
        sea_momentum._native.sweep(str(TRACKING), ["controller.rate_hz=1000"], None, 0, False)
    assert native.value.argument == "workers"
    assert not isinstance(native.value, sea_momentum.ScenarioError)
    with pytest.raises(ValueError, match="grid"):
        sweep(TRACKING, {})


def test_to_pandas_or_a_clear_import_error(local_result):
    if importlib.util.find_spec("pandas") is None:
        with pytest.raises(ImportError, match="pandas"):
            local_result.to_pandas()
    else:
        frame = local_result.to_pandas()
        assert list(frame.columns) == list(local_result.columns)
        assert len(frame) == 4


def test_ray_backend_without_ray_says_how_to_install(monkeypatch):
    # A None entry in sys.modules makes `import ray` raise ImportError.
    monkeypatch.setitem(sys.modules, "ray", None)
    with pytest.raises(ImportError, match=r"sea-momentum\[cluster\]"):
        sweep(TRACKING, {"controller.rate_hz": [1000.0]}, overrides=SHORT, backend="ray")


@pytest.mark.skipif(not HAVE_RAY, reason="ray is not installed (pip install 'sea-momentum[cluster]')")
def test_ray_backend_matches_the_local_backend(local_result):
    import ray

    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        grid = {"controller.damping_estimate_scale": [0.8, 1.25], "controller.rate_hz": "100:1000:2"}
        # Batches of 3 runs: one full batch and a partial one.
        result = sweep(TRACKING, grid, overrides=SHORT, backend="ray", batch_size=3)
    finally:
        ray.shutdown()
    assert comparable(result) == comparable(local_result)
    assert result.total == 4 and not result.interrupted
