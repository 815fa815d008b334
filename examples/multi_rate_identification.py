"""The robot-rate design run from Python, as on a robot: the stiffnesses identified online.

The loop a robot runs: every 10 ms the whole-body controller (``Controller.tick``), every 1 ms the
joint torque loops (``Controller.inner_tick``), at the end of each period the feet's sensors and
the joint torques handed to ``Controller.end_period`` (the stiffness identification and the
observers). Here the plant is ours (``Plant.step``); on a robot the same calls read its sensors.
The controller's stiffness estimate starts at x0.5 of the true one; the robust design
(identification and the generalized disturbance observer) tracks the paper's CoM sinusoid.
Draws the identified stiffnesses of the legs' joints over time, relative to the true ones (on
the ground some end short of it: docs/findings/contacts.md says why), and the CoM error.

Run: ``python examples/multi_rate_identification.py`` (``--quick``: 3 s instead of 10 s).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sea_momentum as sm  # noqa: E402
from _common import SCENARIOS, arguments, save  # noqa: E402

ESTIMATE_SCALE = 0.5
JOINTS = ["l_hip_pitch", "l_hip_roll", "l_knee", "l_ankle_pitch", "l_ankle_roll", "torso_pitch"]


def run(duration: float) -> tuple[np.ndarray, dict[str, np.ndarray], np.ndarray]:
    """The period times, the stiffness estimates of JOINTS (the first entry: before the first
    tick), and the CoM error at each period."""
    scenario = sm.Scenario.load(SCENARIOS / "robot_rate" / "tracking_multi_rate.toml", {
        "controller.stiffness_estimate_scale": ESTIMATE_SCALE,
        "controller.external_wrench": "generalized",
        "controller.identification_prior_deflection_rad": 5e-3,
        "simulation.duration_s": duration})
    plant, controller, x = scenario.plant, scenario.controller, scenario.initial_state
    steps, inner = scenario.steps_per_tick, scenario.steps_per_inner_tick
    times, com_errors = [0.0], []
    estimates = {name: [controller.stiffness_estimates[name]] for name in JOINTS}
    for k in range(scenario.last_tick):
        out = controller.tick(k * scenario.control_period, x)
        u = out.input
        com_errors.append(np.linalg.norm(out.com - out.com_reference))
        for j in range(steps):
            if j > 0 and j % inner == 0:
                u = controller.inner_tick(x)
            x = plant.step(x, u, scenario.plant_dt, scenario.method)
            if j == 0:
                start = plant.step_outputs()
            if j == steps - 1:
                end = plant.step_outputs()
        controller.end_period(start.step_contact_wrenches, start.joint_torques,
                              end.step_contact_wrenches, end.joint_torques)
        times.append((k + 1) * scenario.control_period)
        for name in JOINTS:
            estimates[name].append(controller.stiffness_estimates[name])
    return np.array(times), {n: np.array(v) for n, v in estimates.items()}, np.array(com_errors)


def true_stiffness(initial_estimate: float) -> float:
    """The plant's stiffness of a joint whose estimate starts at ``initial_estimate``."""
    return initial_estimate / ESTIMATE_SCALE


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    times, estimates, com_errors = run(3.0 if args.quick else 10.0)
    figure, (stiffness_axis, com_axis) = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
    for name, values in estimates.items():
        ratio = values / true_stiffness(values[0])
        stiffness_axis.plot(times, ratio, label=name)
        print(f"{name}: estimate {values[-1]:.1f} Nm/rad at the end, x{ratio[-1]:.3f} of the true")
    print(f"CoM error rms {np.sqrt(np.mean(com_errors ** 2)) * 1e3:.2f} mm, "
          f"last second max {com_errors[-100:].max() * 1e3:.2f} mm")
    stiffness_axis.axhline(1.0, color="grey", linestyle=":")
    stiffness_axis.set_ylabel("estimate / true stiffness")
    stiffness_axis.legend(fontsize=8, ncol=2)
    stiffness_axis.set_title(f"stiffness estimates from x{ESTIMATE_SCALE}, identified online")
    com_axis.plot(times[1:], com_errors * 1e3)
    com_axis.set_ylabel("|CoM - reference| [mm]")
    com_axis.set_xlabel("time [s]")
    save(figure, args.out / "multi_rate_identification.png")


if __name__ == "__main__":
    main()
