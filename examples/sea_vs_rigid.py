"""The paper's step experiment: the SEA controller against the rigid one on the SEA robot.

A 1 degree step on every upper-body joint at 0.5 s, the robot on its left foot, every joint
elastic (``scenarios/paper/step_sea.toml`` and ``step_rigid.toml``). The rigid controller
ignores the springs: its oscillation grows until the run diverges; the SEA controller settles.
Draws the CoM error and the largest motor velocity of both.

Run: ``python examples/sea_vs_rigid.py`` (``--quick``: 4 s instead of the paper's 15 s).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sea_momentum as sm  # noqa: E402
from _common import SCENARIOS, arguments, save  # noqa: E402


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    overrides = {"simulation.duration_s": 4.0} if args.quick else {}
    figure, (com_axis, motor_axis) = plt.subplots(2, 1, sharex=True, figsize=(7, 5.5))
    for name in ("step_sea", "step_rigid"):
        result = sm.run_scenario(SCENARIOS / "paper" / f"{name}.toml", overrides)
        summary = result.summary
        stop = summary.fell_at_s if summary.fell_at_s is not None else summary.diverged_at_s
        ended = "" if stop is None else f" at {stop:.2f} s ({summary.reason})"
        print(f"{name}: {result.status}{ended}; peak motor velocity "
              f"{summary.motor_velocity_peak_rad_s:.2f} rad/s")
        com_error = np.linalg.norm(result.com - result.com_reference, axis=1)
        com_axis.plot(result.time, com_error * 1e3, label=name)
        motor_axis.plot(result.time, np.abs(result.thetadot).max(axis=1), label=name)
    com_axis.set_ylabel("|CoM - reference| [mm]")
    motor_axis.set_ylabel("max |motor velocity| [rad/s]")
    motor_axis.set_xlabel("time [s]")
    com_axis.legend()
    com_axis.set_title("1 degree upper-body step on the SEA iCub")
    save(figure, args.out / "sea_vs_rigid.png")


if __name__ == "__main__":
    main()
