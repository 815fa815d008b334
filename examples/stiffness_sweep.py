"""How wrong may the stiffness estimate be? A sweep of three designs, with the paper's margin.

The paper's tracking experiment (left foot, 1 cm lateral CoM sinusoid, every joint elastic) is
run with the controller's stiffness estimate scaled by 0.4 to 2.5 under three designs:

- the paper's controller at 1 kHz (zero-order hold), also linearised: the growth rate of the
  period map's eigenvalues (``linearize``) at each scale;
- the robot-rate design (100 Hz whole body, 1 kHz joint loops) with the stiffness
  identification alone (``scenarios/robot_rate/tracking_multi_rate.toml``);
- the same with the generalized disturbance observer: the robust design.

Draws the growth rate of the paper's controller and the CoM error rms of each run (a cross
where it did not complete). The paper's controller is stable only near the true stiffness,
and not on one interval: slow modes cross zero growth back and forth there (``stability_margin``
bisects one crossing of a grid, so its answer depends on the grid).

Run: ``python examples/stiffness_sweep.py`` (``--quick``: 6 points, 3 s).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sea_momentum as sm  # noqa: E402
from _common import SCENARIOS, arguments, save  # noqa: E402

KEY = "controller.stiffness_estimate_scale"
PAPER = SCENARIOS / "paper" / "tracking.toml"
ROBOT_RATE = SCENARIOS / "robot_rate" / "tracking_multi_rate.toml"
ZERO_ORDER_HOLD = {"controller.sampling": "zero_order_hold", "plant.dt": 1e-3}
DESIGNS = {
    "paper, 1 kHz": (PAPER, ZERO_ORDER_HOLD),
    "100 Hz / 1 kHz, identification": (ROBOT_RATE, {}),
    "100 Hz / 1 kHz, identification + observer": (
        ROBOT_RATE,
        {"controller.external_wrench": "generalized",
         "controller.identification_prior_deflection_rad": 5e-3},
    ),
}


def growth_rates(axis, scales: np.ndarray) -> None:
    """Draws the growth rate of the paper's linearised closed loop at each scale."""
    rates = []
    for scale in scales:
        linear = sm.linearize(PAPER, overrides={**ZERO_ORDER_HOLD, KEY: float(scale)})
        rates.append(linear.growth_rate)
    rates = np.array(rates)
    stable = scales[rates < 0]
    print("paper's controller at 1 kHz, linearised: stable at "
          + (", ".join(f"{value:.2f}" for value in stable) or "none of the scales"))
    axis.plot(scales, rates, "o-", color="black")
    axis.axhline(0.0, color="grey", linestyle=":")
    axis.set_yscale("symlog", linthresh=0.1)
    axis.set_ylabel("growth rate [1/s]")
    axis.set_title("the paper's controller at 1 kHz, linearised (below 0: stable)")


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    points, duration = (6, 3.0) if args.quick else (12, 10.0)
    figure, (growth_axis, axis) = plt.subplots(2, 1, sharex=True, figsize=(7, 7))
    growth_rates(growth_axis, np.geomspace(0.4, 2.5, 9 if args.quick else 25))
    for label, (scenario, overrides) in DESIGNS.items():
        grid = {KEY: f"0.4:2.5:{points}:log"}
        result = sm.sweep(scenario, grid, overrides={**overrides, "simulation.duration_s": duration})
        scales, rms, completed = result[KEY], result["com_error_rms_m"] * 1e3, result.stable
        held = scales[completed]
        span = f"{held.min():.2f} to {held.max():.2f}" if held.size else "none"
        print(f"{label}: {completed.sum()} of {len(result)} completed ({span})")
        line, = axis.plot(scales[completed], rms[completed], "o-", label=label)
        axis.plot(scales[~completed], rms[~completed], "x", color=line.get_color(), markersize=9)
    axis.set_xscale("log")
    axis.set_xlabel("stiffness estimate / true stiffness")
    axis.set_ylabel("CoM error rms [mm] (x: did not complete)")
    axis.legend(fontsize=8)
    save(figure, args.out / "stiffness_sweep.png")
    if not np.isfinite(rms).any():
        raise SystemExit("no run reported a CoM error")


if __name__ == "__main__":
    main()
