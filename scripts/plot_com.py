"""Runs a scenario file and draws its CoM against the reference (lateral and forward, world):
``python scripts/plot_com.py SCENARIO OUT.png [--pictures STEM]``; with ``--pictures``, also
the robot along the run (``STEM_strip.png`` and ``STEM.gif`` beside ``OUT.png``, by
``sea_momentum.pictures.scenario_pictures``). Used by scripts/run_main.sh for the robots set
up by ``sea-sim init``."""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import sea_momentum as sm  # noqa: E402
from sea_momentum.pictures import scenario_pictures  # noqa: E402


def plot_com(scenario: str, result: sm.ScenarioResult, out: str) -> None:
    """The CoM and its reference, lateral and forward [mm], against time."""
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    for ax, axis, label in zip(axes, (1, 0), ("lateral y", "forward x")):
        ax.plot(result.time, 1e3 * result.com[:, axis], label="CoM")
        ax.plot(result.time, 1e3 * result.com_reference[:, axis], "--", label="reference")
        ax.set_ylabel(f"{label} [mm]")
        ax.legend(loc="upper right")
    axes[-1].set_xlabel("time [s]")
    summary = result.summary
    fig.suptitle(f"{scenario}: CoM error rms {1e6 * summary.com_error_rms_m:.2f} um ({summary.status})")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenario", help="the scenario file")
    parser.add_argument("out", help="the CoM plot (PNG)")
    parser.add_argument("--pictures", metavar="STEM", help="also draw the robot: STEM_strip.png and STEM.gif")
    args = parser.parse_args()
    result = sm.run_scenario(args.scenario)
    plot_com(args.scenario, result, args.out)
    if args.pictures:
        name = pathlib.Path(args.scenario).stem
        scenario_pictures(args.scenario, result, pathlib.Path(args.out).parent, args.pictures, title=name)


if __name__ == "__main__":
    main()
