"""Benchmark of the sweep engine (not a timed test): 8 runs of the paper's tracking scenario
(2 s simulated each, damping estimate scale 0.8 to 1.2) with 1 worker and with 2; prints the
wall times, the speed-up and the runs per second, and checks that both give the same rows.

    python benchmarks/sweep_bench.py [--setting paper|zoh1k] [--runs 8] [--duration 2]

``paper``: the scenario as shipped (continuous sampling, plant step 0.25 ms); ``zoh1k``: 1 kHz
zero-order hold with a 1 ms plant step.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import time

import sea_momentum

TRACKING = pathlib.Path(__file__).resolve().parents[1] / "scenarios" / "paper" / "tracking.toml"
SETTINGS = {
    "paper": {},
    "zoh1k": {"controller.sampling": "zero_order_hold", "plant.dt": 1e-3},
}
WALL_CLOCK = ("wall_time_s", "realtime_factor")


def timed_sweep(runs: int, duration: float, setting: str, workers: int):
    """Wall time [s] and result of one sweep."""
    overrides = {"simulation.duration_s": duration, **SETTINGS[setting]}
    grid = {"controller.damping_estimate_scale": f"0.8:1.2:{runs}"}
    start = time.perf_counter()
    result = sea_momentum.sweep(TRACKING, grid, overrides=overrides, workers=workers)
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--setting", choices=sorted(SETTINGS), default="paper")
    parser.add_argument("--runs", type=int, default=8)
    parser.add_argument("--duration", type=float, default=2.0)
    args = parser.parse_args()
    one_s, one = timed_sweep(args.runs, args.duration, args.setting, 1)
    two_s, two = timed_sweep(args.runs, args.duration, args.setting, 2)
    strip = lambda r: [{k: v for k, v in row.items() if k not in WALL_CLOCK} for row in r.rows]
    figures = {
        "setting": args.setting,
        "runs": args.runs,
        "simulated_s_per_run": args.duration,
        "statuses": sorted(set(one.columns["status"].tolist())),
        "wall_1_worker_s": round(one_s, 3),
        "wall_2_workers_s": round(two_s, 3),
        "speed_up": round(one_s / two_s, 3),
        "runs_per_s_1_worker": round(args.runs / one_s, 3),
        "runs_per_s_2_workers": round(args.runs / two_s, 3),
        "identical_rows": strip(one) == strip(two),
    }
    print(json.dumps(figures, indent=2))


if __name__ == "__main__":
    main()
