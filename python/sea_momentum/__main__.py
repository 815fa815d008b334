"""Command line of the Python package: ``python -m sea_momentum COMMAND``.

Commands:

- ``reproduce [--out DIR]``: the paper application (:mod:`sea_momentum.paper`): runs the
  paper's experiments (scenarios/paper), writes the figures, MCAP logs, ``summary.json`` and
  ``outcomes.md``.
- ``check [--urdf PATH] [--out DIR]``: loads the model and checks the dynamics identities on
  random states (M symmetric positive definite, M nudot + h equal to inverse dynamics,
  H = A_G nu, frame Jacobians and the CoM Jacobian against finite differences). Writes
  ``DIR/dynamics_check.json`` and exits non-zero if an identity fails.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys

from . import checks


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sea_momentum")
    sub = parser.add_subparsers(dest="command", required=True)
    check = sub.add_parser("check", help="check the dynamics identities on random states")
    check.add_argument("--urdf", default=str(checks.default_urdf()))
    check.add_argument("--out", default="out")
    check.add_argument("--states", type=int, default=20)
    rep = sub.add_parser("reproduce", help="run the paper's experiments, write figures, logs, table")
    rep.add_argument("--out", default="out")
    rep.add_argument("--scenarios", default="scenarios/paper")
    rep.add_argument("--duration", type=float, default=None, help="override every run's duration [s]")
    args = parser.parse_args(argv)

    if args.command == "reproduce":
        from .paper import reproduce

        reproduce(pathlib.Path(args.scenarios), pathlib.Path(args.out), args.duration)
        return 0

    if args.command == "check":
        report = checks.dynamics_check(args.urdf, n_states=args.states)
        out = pathlib.Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "dynamics_check.json").write_text(json.dumps(report, indent=2))
        for name, value in report["max_relative_error"].items():
            print(f"  {name:<34} {value:.2e}")
        print(f"{report['passed']} passed, {report['failed']} failed")
        return 0 if report["failed"] == 0 else 1
    return 2


if __name__ == "__main__":
    sys.exit(main())
