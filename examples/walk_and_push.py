"""The iCub walking at 0.25 m/s and pushed at mid-swing, from Python.

``scenarios/walking/walk_push.toml``: the paper's iCub with a series elastic actuator on every
joint, the robot-rate design (the whole-body law at 100 Hz over 1 kHz joint torque loops),
unilateral contacts, ten 0.1 m steps of 0.4 s and the stop; the step adjustment on (a pushed
swing lands where the capture point asks). Three parts:

1. ``sm.push_table(..., phase=0.5)``: pushes of fixed impulses on the pelvis for 0.1 s from the
   middle of the fourth step's swing, forward, left and right (as ``sea-sim push --phase``),
   beside ``sm.template_push_table``: the same pushes on the walk's template (the controller's
   planner and momentum law on the linear inverted pendulum, the robot left out);
2. one walk unpushed and one pushed sideways at that time (``run_scenario`` with the push as
   a ``disturbances`` override): the summary's steps, distance and speed, and the CoM's lateral
   path;
3. the normal force the QP planned for each foot (``planned_wrenches``) against the one the
   plant delivered (``contact_wrenches``) around the push.

Run: ``python examples/walk_and_push.py`` (``--quick``: two impulses).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sea_momentum as sm  # noqa: E402
from _common import SCENARIOS, arguments, save  # noqa: E402

SCENARIO = SCENARIOS / "walking" / "walk_push.toml"
ADJUSTED = {"walking.step_adjustment": True}
DIRECTIONS = ("forward", "left", "right")
#: The push of parts 2 and 3: 5 N s to the right (world -y) for 0.1 s.
SIDE_PUSH_N = [0.0, -50.0, 0.0]


def push_tables(impulses: list[float], overrides: dict) -> tuple[sm.PushTable, list]:
    """The robot's and the template's outcomes of ``impulses`` [N s] at mid-swing."""
    robot = sm.push_table(SCENARIO, DIRECTIONS, impulses=impulses, overrides=overrides, phase=0.5)
    template = sm.template_push_table(SCENARIO, 0.5, DIRECTIONS, impulses=impulses, overrides=overrides)
    return robot, template


def walks(start_s: float, overrides: dict) -> dict[str, sm.ScenarioResult]:
    """The walk unpushed and pushed sideways from ``start_s`` [s], recorded at every
    whole-body tick."""
    push = {"link": "root_link", "force": SIDE_PUSH_N, "start_s": start_s, "duration_s": 0.1}
    every_tick = {**overrides, "simulation.record_every": 1}
    return {
        "unpushed": sm.run_scenario(SCENARIO, every_tick),
        "pushed 5 N s right": sm.run_scenario(SCENARIO, {**every_tick, "disturbances": [push]}),
    }


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    impulses = [4.0, 8.0] if args.quick else [2.0, 4.0, 6.0, 8.0, 10.0, 12.0]
    overrides = ADJUSTED
    robot, template = push_tables(impulses, overrides)
    print(f"pushes of 0.1 s at mid-swing of the fourth step (from t = {robot.start_s:.2f} s)")
    print(f"{'direction':>10} {'impulse [N s]':>14} {'robot':>10} {'template':>9}")
    for row, template_row in zip(robot.rows, template):
        for (impulse, status), (_, recovered) in zip(row.pushes, template_row.pushes):
            print(f"{row.direction:>10} {impulse:14.1f} {status:>10} {str(recovered):>9}")

    runs = walks(robot.start_s, overrides)
    for name, result in runs.items():
        s = result.summary
        print(f"{name}: {result.status}, {s.steps_taken} steps, {s.distance_walked_m:.2f} m "
              f"at {s.walking_speed_m_s:.3f} m/s, CoM error rms {1e3 * s.com_error_rms_m:.2f} mm")

    figure, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    width = 0.8 / len(DIRECTIONS)
    for k, (row, template_row) in enumerate(zip(robot.rows, template)):
        recovered = [1.0 if status == "completed" else 0.0 for _, status in row.pushes]
        offsets = np.arange(len(impulses)) + (k - 1) * width
        axes[0].bar(offsets, recovered, width, label=f"{row.direction} (robot)")
        template_ok = [offset for offset, (_, ok) in zip(offsets, template_row.pushes) if ok]
        axes[0].plot(template_ok, [1.05] * len(template_ok), "v", color=f"C{k}")
    axes[0].set_xticks(np.arange(len(impulses)), [f"{i:g}" for i in impulses])
    axes[0].set_xlabel("impulse [N s] (triangles: the template recovers it)")
    axes[0].set_ylabel("recovered")
    axes[0].set_title("pushes at mid-swing")
    axes[0].legend(fontsize=8)
    for name, result in runs.items():
        axes[1].plot(result.time, result.com[:, 1], label=name)
    axes[1].axvspan(robot.start_s, robot.start_s + 0.1, color="0.85")
    axes[1].set_xlabel("t [s]")
    axes[1].set_ylabel("CoM y [m]")
    axes[1].set_title("the CoM's lateral path")
    axes[1].legend(fontsize=8)
    pushed = runs["pushed 5 N s right"]
    window = (pushed.time > robot.start_s - 0.3) & (pushed.time < robot.start_s + 0.8)
    for c, contact in enumerate(pushed.contacts):
        t = pushed.time[window]
        axes[2].plot(t, pushed.planned_wrenches[window, c, 2], color=f"C{c}", label=f"{contact} planned")
        axes[2].plot(t, pushed.contact_wrenches[window, c, 2], "--", color=f"C{c}",
                     label=f"{contact} delivered")
    axes[2].axvspan(robot.start_s, robot.start_s + 0.1, color="0.85")
    axes[2].set_xlabel("t [s]")
    axes[2].set_ylabel("normal force [N]")
    axes[2].set_title("planned (QP) and delivered, pushed")
    axes[2].legend(fontsize=8)
    save(figure, args.out / "walk_and_push.png")


if __name__ == "__main__":
    main()
