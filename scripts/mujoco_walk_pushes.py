#!/usr/bin/env python3
"""Pushes while walking, in MuJoCo and on our plant, through the same Python robot loop.

The grid of `sea-sim push --phase` (docs/findings/stepping.md, "The walking-push grid") run by
`examples/mujoco_sea_icub.py`'s loop: a walking scenario's controller stack at 100 Hz / 1 kHz
reading only what a robot measures, the touchdowns sensed from the feet's wrenches, on
MuJoCo's SEA iCub (`--simulator mujoco`, soft contacts, the foot boxes) or on our plant
(`--simulator ours`). Each push lasts 0.1 s on the pelvis and starts at a fraction of the
pushed step's swing (`sea-sim push` reports that swing's lift-off and touchdown; for
walk_push.toml's fourth step 1.80 and 2.10 s, the defaults of `--lift-off` and `--swing`:
20 / 50 / 80 % start at 1.86 / 1.95 / 2.04 s).

A push is recovered (`o`) when the robot still stands at the end (the base never dropped
0.1 m) and its CoM is within `--final-error` of the reference; `x` otherwise. Prints one row
per direction and phase, as `sea-sim push` does, and the runs as JSON lines with `--verbose`.

Run: `python scripts/mujoco_walk_pushes.py --simulator mujoco --impulses 2,4,6,8,10,12`.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))
import mujoco_sea_icub as example  # noqa: E402

def numbers(text: str) -> list[float]:
    """A comma-separated list of numbers (`--impulses`, `--phases`)."""
    try:
        return [float(item) for item in text.split(",") if item.strip()]
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got {text!r}") from error


def recovered(result: dict[str, float], final_error_mm: float) -> bool:
    """Standing at the end, the CoM within `final_error_mm` of its reference."""
    return bool(result["standing"]) and result["com_error_final_mm"] <= final_error_mm


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--simulator", choices=["mujoco", "ours"], default="mujoco")
    parser.add_argument("--walk", type=pathlib.Path, default=ROOT / "scenarios" / "walking" / "walk_push.toml")
    parser.add_argument("--impulses", type=numbers, default=numbers("2,4,6,8,10,12"), help="[N s]")
    parser.add_argument("--phases", type=numbers, default=numbers("0.2,0.5,0.8"), help="fractions of the pushed swing")
    parser.add_argument("--directions", default="forward,left,right", help="of " + ", ".join(sorted(example.PUSH_DIRECTIONS)))
    parser.add_argument("--lift-off", type=float, default=1.8, help="the pushed swing's lift-off [s] (`sea-sim push SCENARIO`'s swing; walk_push.toml's fourth step)")
    parser.add_argument("--swing", type=float, default=0.3, help="the pushed swing's duration [s]")
    parser.add_argument("--duration", type=float, default=7.0, help="simulated time [s]")
    parser.add_argument("--final-error", type=float, default=20.0, help="the largest CoM error at the end of a recovered run [mm]")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a scenario key (repeatable)")
    parser.add_argument("--verbose", action="store_true", help="print every run's summary as a JSON line")
    args = parser.parse_args()
    directions = [name.strip() for name in args.directions.split(",")]
    unknown = [name for name in directions if name not in example.PUSH_DIRECTIONS]
    if unknown:
        parser.error(f"--directions: unknown {unknown}, expected some of {sorted(example.PUSH_DIRECTIONS)}")
    overrides = {**example.WALK_OVERRIDES, **dict(example.parse_override(text) for text in args.set)}
    for direction in directions:
        for phase in args.phases:
            start = round(args.lift_off + phase * args.swing, 4)
            row = ""
            for impulse in args.impulses:
                series = example.run(args.duration, impulse, start, args.simulator, args.walk, overrides, push_direction=direction)
                result = example.summary(series)
                row += "o" if recovered(result, args.final_error) else "x"
                if args.verbose:
                    print(json.dumps({"direction": direction, "phase": phase, "impulse_n_s": impulse, **result}), flush=True)
            print(f"{args.simulator} {direction:8s} {phase:.0%} start {start:.2f} s: {row}", flush=True)


if __name__ == "__main__":
    main()
