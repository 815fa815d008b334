"""What the examples share: the command line (``--out``, ``--quick``) and the figure writer."""

from __future__ import annotations

import argparse
import pathlib

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENARIOS = ROOT / "scenarios"


def arguments(description: str, extra=None) -> argparse.Namespace:
    """``--out DIR`` (default out/examples), ``--quick`` (a shorter run, as CI runs it) and
    what ``extra(parser)`` adds."""
    parser = argparse.ArgumentParser(description=description)
    if extra is not None:
        extra(parser)
    parser.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "examples",
                        help="folder of the figure and the logs [default: out/examples]")
    parser.add_argument("--quick", action="store_true", help="a shorter run (CI)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    return args


def save(figure, path: pathlib.Path) -> None:
    """Writes the figure and says where."""
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    print(f"figure: {path}")
