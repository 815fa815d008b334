"""The iCub of sea-momentum balanced in MuJoCo by the rigid momentum controller.

A test against a simulator nobody here wrote: the same URDF (urdf/icub25.urdf) compiled by
MuJoCo, with a free base, soft frictional contacts between two foot boxes and a floor plane, and
torque actuators on the 25 joints; every millisecond the MuJoCo state is converted to our
conventions and handed to ``sea_momentum.Controller.tick`` (rigid controller, two feet), whose
joint torques drive the actuators.

The model, the conversion of MuJoCo's state to our conventions and the feet's measured wrenches
are in ``examples/mujoco_icub.py`` (shared with ``benchmarks/mujoco_push.py`` and
``benchmarks/peers.py``).

Run: ``python examples/mujoco_balance.py [--duration 10] [--amplitude 0.02]`` (needs
``pip install mujoco``, the ``examples`` extra). Prints the CoM error and the contact forces
measured by MuJoCo (``mj_contactForce``) against the QP's.
"""

from __future__ import annotations

import argparse
import pathlib
import sys

import mujoco
import numpy as np

import sea_momentum as sm

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from mujoco_icub import (  # noqa: E402,F401  (the model, shared with benchmarks/)
    FEET,
    FOOT_X,
    FOOT_Y,
    GRAVITY,
    SCENARIO,
    TIMESTEP,
    URDF,
    StateMap,
    foot_wrenches,
    mujoco_model,
)


def run(duration: float, amplitude: float, frequency: float = 0.2) -> dict[str, np.ndarray]:
    """Balances for ``duration`` seconds with a lateral CoM sinusoid of ``amplitude`` [m];
    returns the time series (time, com, com_reference, qp_wrenches, mujoco_wrenches, qp_solved)
    and the robot's weight [N]."""
    overrides = {
        "robot.contacts": FEET,
        "robot.initial_posture": "two_feet",
        "actuators.kind": "rigid",
        "controller.kind": "rigid",
    }
    scenario = sm.Scenario.load(SCENARIO, overrides)
    model = scenario.model
    q0 = scenario.initial_state[: model.nq]
    mj = mujoco_model(URDF, model.joint_names)
    data = mujoco.MjData(mj)
    states = StateMap.of(mj, model.joint_names)
    states.set_from_ours(data, q0)
    controller = sm.Controller(
        model,
        FEET,
        q0,
        actuators={"kind": "rigid"},
        reference={
            "com_origin": "initial",
            "com_amplitude": amplitude,
            "com_frequency": frequency,
            "com_direction": [0.0, 1.0, 0.0],
        },
        kind="rigid",
        contact={"foot_x": list(FOOT_X), "foot_y": list(FOOT_Y)},
    )
    actuator_of_joint = np.array([mj.actuator(name).id for name in model.joint_names])
    ticks = int(round(duration / TIMESTEP))
    series: dict[str, list] = {k: [] for k in ("time", "com", "com_reference", "qp_wrenches", "mujoco_wrenches", "qp_solved")}
    for k in range(ticks + 1):
        t = k * TIMESTEP
        x = states.to_ours(data)
        out = controller.tick(t, x)
        data.ctrl[actuator_of_joint] = out.input
        # mj_step's forward pass at x (before its integration) leaves the contacts and their
        # forces of this state and this input in `data`.
        mujoco.mj_step(mj, data)
        for key, value in (
            ("time", t),
            ("com", out.com),
            ("com_reference", out.com_reference),
            ("qp_wrenches", out.wrenches),
            ("mujoco_wrenches", foot_wrenches(mj, data, FEET)),
            ("qp_solved", out.qp_status == "solved"),
        ):
            series[key].append(value)
    result = {key: np.array(values) for key, values in series.items()}
    result["weight"] = np.array(model.total_mass * np.linalg.norm(GRAVITY))
    return result


#: The first instants, where MuJoCo's soft contacts build up from zero penetration, are left
#: out of the force comparison (reported apart) [s].
CONTACT_SETTLING = 0.05


def report(series: dict[str, np.ndarray], weight: float) -> str:
    """CoM error and contact forces, MuJoCo's against the QP's; ``weight`` [N]."""
    error = np.linalg.norm(series["com"] - series["com_reference"], axis=1)
    settled = series["time"] >= CONTACT_SETTLING
    qp, measured = series["qp_wrenches"], series["mujoco_wrenches"]
    force_error = np.linalg.norm(qp[:, :, :3] - measured[:, :, :3], axis=2)
    torque_error = np.linalg.norm(qp[:, :, 3:] - measured[:, :, 3:], axis=2)
    rms = lambda v: float(np.sqrt(np.mean(v**2)))  # noqa: E731
    lines = [
        f"duration {series['time'][-1]:.2f} s, QP solved at {series['qp_solved'].mean() * 100:.1f} % of the ticks",
        f"CoM error: rms {rms(error) * 1e3:.2f} mm, max {error.max() * 1e3:.2f} mm, final {error[-1] * 1e3:.2f} mm; "
        f"CoM height {series['com'][0, 2]:.3f} -> {series['com'][-1, 2]:.3f} m",
        f"total normal force after {CONTACT_SETTLING} s (mean): QP {qp[settled, :, 2].sum(axis=1).mean():.1f} N, "
        f"MuJoCo {measured[settled, :, 2].sum(axis=1).mean():.1f} N (weight {weight:.1f} N)",
    ]
    for i, foot in enumerate(FEET):
        lines.append(
            f"{foot}: normal force QP {qp[settled, i, 2].mean():.1f} N, MuJoCo {measured[settled, i, 2].mean():.1f} N; "
            f"|f_QP - f_MuJoCo| rms {rms(force_error[settled, i]):.2f} N, max {force_error[settled, i].max():.2f} N; "
            f"torque difference rms {rms(torque_error[settled, i]):.3f} N m "
            f"(before {CONTACT_SETTLING} s: force difference up to {force_error[~settled, i].max():.1f} N)"
        )
    return "\n".join(lines)


def main() -> None:
    """Runs the balance from the command line and prints the report."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--amplitude", type=float, default=0.02, help="lateral CoM sinusoid [m]")
    args = parser.parse_args()
    series = run(args.duration, args.amplitude)
    print(report(series, weight=series["weight"]))


if __name__ == "__main__":
    main()
