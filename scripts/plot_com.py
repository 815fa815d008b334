"""Runs a scenario file and draws its CoM against the reference (lateral and forward, world):
``python scripts/plot_com.py SCENARIO OUT.png``. Used by scripts/run_main.sh for the robots
set up by ``sea-sim init``."""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import sea_momentum as sm  # noqa: E402


def main(scenario: str, out: str) -> None:
    result = sm.run_scenario(scenario)
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


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
