"""How the feet move under a push, in MuJoCo and in our plant with unilateral contacts.

The same rigid iCub and the same rigid controller at 100 Hz (the "rigid robot, rigid controller,
100 Hz" row of ``scripts/robot_rate.py``, ``benchmarks/mujoco_push.py``'s rig), pushed 0.1 s on
the pelvis at 1 s: for each impulse, whether the run recovers (MuJoCo: the criteria of
``mujoco_push.py``; ours: the run's status under its own fall check), and per foot the largest
horizontal slide and rise of the sole origin [mm] over the run.

Run: ``python benchmarks/feet_motion.py [--direction left] [--impulses 6 7 8 9 10]
[--json FILE]`` (needs ``mujoco`` and the built ``sea_momentum``).
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np

import sea_momentum as sm

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import mujoco_push  # noqa: E402

FEET = ("l_sole", "r_sole")
#: Our fall check with ``mujoco_push.py``'s recovery criteria (base above 0.8 of its height,
#: tilt below 30 degrees), and no bound of the controller's errors (MuJoCo's runs have none).
MUJOCO_CRITERIA = {
    "simulation.fall_base_height_fraction": mujoco_push.MIN_HEIGHT_RATIO,
    "simulation.fall_tilt_rad": float(np.radians(mujoco_push.MAX_TILT_DEG)),
    "simulation.divergence_joint_error_rad": 1000.0,
    "simulation.divergence_com_error_m": 1000.0,
}


def ours(direction: str, impulse: float, setup: mujoco_push.PushSetup) -> dict:
    """Our plant (the push scenario, unilateral contacts) under the push: status and the feet's
    slide and rise [mm]."""
    force = np.array(mujoco_push.DIRECTIONS[direction]) * impulse / setup.duration_s
    push = {
        "link": mujoco_push.PUSHED_LINK,
        "force": force.tolist(),
        "start_s": setup.start_s,
        "duration_s": setup.duration_s,
    }
    overrides = {
        **mujoco_push.RIGID_100_HZ,
        "disturbances": [push],
        "simulation.duration_s": setup.start_s + setup.duration_s + setup.after_s,
        "simulation.record_every": 1,
        **MUJOCO_CRITERIA,
    }
    result = sm.run_scenario(mujoco_push.PUSH_SCENARIO, overrides)
    model = sm.Scenario.load(mujoco_push.PUSH_SCENARIO, mujoco_push.RIGID_100_HZ).model
    slide, lift = {}, {}
    for foot in FEET:
        origins = np.array([model.frame_pose(q, foot)[:3, 3] for q in result.q])
        moved = origins - origins[0]
        slide[foot] = float(np.max(np.linalg.norm(moved[:, :2], axis=1)) * 1e3)
        lift[foot] = float(np.max(moved[:, 2]) * 1e3)
    return {
        "recovered": result.status == "completed",
        "status": result.status,
        "reason": result.summary.reason,
        "slide_mm": slide,
        "lift_mm": lift,
    }


def mujoco(rig: mujoco_push.PushRig, direction: str, impulse: float) -> dict:
    """MuJoCo under the push: recovered and the feet's slide and rise [mm]."""
    record = rig.run(direction, impulse)
    return {
        "recovered": record.recovered,
        "status": "completed" if record.recovered else "fell",
        "reason": record.reason,
        "slide_mm": record.slide_mm,
        "lift_mm": record.lift_mm,
    }


def row(impulse: float, name: str, outcome: dict) -> str:
    """One markdown row."""
    feet = ", ".join(
        f"{foot} {outcome['slide_mm'][foot]:.1f} / {outcome['lift_mm'][foot]:.1f}" for foot in FEET
    )
    verdict = "recovered" if outcome["recovered"] else f"not ({outcome['reason']})"
    return f"| {impulse:.2f} | {name} | {verdict} | {feet} |"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--direction", default="left", choices=list(mujoco_push.DIRECTIONS))
    parser.add_argument("--impulses", type=float, nargs="+", default=[6.0, 7.0, 8.0, 9.0, 10.0])
    parser.add_argument("--json", type=pathlib.Path)
    args = parser.parse_args()
    setup = mujoco_push.PushSetup()
    rig = mujoco_push.PushRig(setup)
    lines = [
        f"Pushed {args.direction}, 0.1 s on the pelvis; per foot slide / rise of the sole origin [mm]:",
        "",
        "| impulse [N s] | simulator | outcome | feet |",
        "| --- | --- | --- | --- |",
    ]
    report = []
    for impulse in args.impulses:
        theirs, mine = mujoco(rig, args.direction, impulse), ours(args.direction, impulse, setup)
        report.append({"impulse_n_s": impulse, "mujoco": theirs, "ours": mine})
        lines += [row(impulse, "MuJoCo", theirs), row(impulse, "ours", mine)]
        print(lines[-2] + "\n" + lines[-1], file=sys.stderr, flush=True)
    print("\n".join(lines))
    if args.json:
        args.json.write_text(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
