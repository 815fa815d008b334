"""An independent check of our SEA plant against MuJoCo: the same motor torques, the same motion.

The iCub of ``urdf/icub25.urdf`` with the paper's SEA on its 25 joints, in our plant
(``sea_momentum.Plant``) and in MuJoCo (``mujoco_sea.py``: a rotor hinge with the reflected
motor inertia as armature behind a spring-damper tendon per joint), both started from the
same state and driven open loop for one second by the same motor torques, held over 1 ms:
the torques that hold the start posture against gravity plus a sinusoid per joint
(``AMPLITUDE`` joint-side, frequencies spread over 0.5-3 Hz, so that every spring and rotor
moves).

Two settings:

- ``fixed``: the base welded in the air (ours: the base frame held by a contact; MuJoCo: no
  free joint), no contacts with the ground: the two simulators integrate the same ODE, so
  they agree to their integrators' error (both RK4 at the same step) and the Baumgarte drift
  of our weld. This checks the SEA equations, the mass matrix, the armature, the signs.
- ``ground``: the free base standing on two feet (ours: the scenario's unilateral contacts;
  MuJoCo: soft contacts of foot boxes on a plane, ``implicitfast``): the contact models
  differ (MuJoCo's feet sink a fraction of a millimetre, ours do not), so the motion agrees
  to the contact model's compliance, not to round-off.

Run: ``python examples/mujoco_sea_check.py [--duration 1]``; prints the largest differences.
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time

import mujoco
import numpy as np

import sea_momentum as sm

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from mujoco_icub import FEET, SCENARIO, URDF  # noqa: E402
from mujoco_sea import MotorBoards, Sea, SeaModelOptions, SeaStateMap, sea_model  # noqa: E402

#: The torque sequence: held for HOLD s; sinusoid amplitude [N m, joint side].
HOLD = 1e-3
AMPLITUDE = 0.05
#: The ground setting's motor motion [rad, joint side] and the motor boards' velocity loop
#: gain K_m [1/s] (the iCub's plant.motor_velocity_gain).
MOTION = 0.1
MOTOR_VELOCITY_GAIN = 200.0
#: Both simulators' step [s].
STEP = 2.5e-4
#: The frame our plant holds to weld the base.
BASE = "root_link"
#: Both models' link joint armature [kg m^2]: the iCub's plant.joint_inertia_regularization.
REGULARIZATION = 0.1


def scenario(contacts: list[str]) -> sm.Scenario:
    """The iCub standing on two feet with SEAs (the initial state holds the posture)."""
    return sm.Scenario.load(
        SCENARIO,
        {
            "robot.contacts": contacts,
            "robot.initial_posture": "two_feet",
            "actuators.kind": "elastic",
            "plant.contact_model": "unilateral",
        },
    )


def torque_sequence(hold_torques: np.ndarray, sea: Sea, duration: float) -> np.ndarray:
    """Motor torques (steps, n) [N m, motor side]: ``Gamma (tau_hold + A sin(2 pi f_j t))``
    held over ``HOLD``."""
    n = hold_torques.size
    frequencies = np.linspace(0.5, 3.0, n)
    phases = np.linspace(0.0, np.pi, n)
    times = HOLD * np.arange(int(round(duration / HOLD)))
    joint_side = hold_torques + AMPLITUDE * np.sin(2 * np.pi * np.outer(times, frequencies) + phases)
    return sea.ratio * joint_side


def velocity_sequence(joints: list[str], sea: Sea, duration: float) -> np.ndarray:
    """Desired motor velocities (steps, n) [rad/s, motor side] moving the motor of each joint
    above the legs by ``MOTION`` (joint side) at 0.5-3 Hz, held over ``HOLD``; the legs' motors
    hold still (on two feet the legs close a chain: moving their joints independently would
    only press the feet against each other through the ground)."""
    n = len(joints)
    frequencies = np.linspace(0.5, 3.0, n)
    times = HOLD * np.arange(int(round(duration / HOLD)))
    omega = 2 * np.pi * frequencies
    upper = np.array([not any(leg in name for leg in ("hip", "knee", "ankle")) for name in joints])
    return upper * MOTION * omega * np.sin(np.outer(times, omega)) / sea.ratio


def ours(plant: sm.Plant, x0: np.ndarray, torques: np.ndarray, method: str) -> np.ndarray:
    """Our plant driven by ``torques``: the state after each hold (rows)."""
    steps = int(round(HOLD / STEP))
    x, states = x0, []
    for u in torques:
        for _ in range(steps):
            x = plant.step(x, u, STEP, method)
        states.append(x)
    return np.array(states)


def theirs(mj: mujoco.MjModel, states: SeaStateMap, x0: np.ndarray, torques: np.ndarray, joints: list[str], sea: Sea, base: np.ndarray | None) -> np.ndarray:
    """MuJoCo's model driven by ``torques``: our state after each hold (rows)."""
    data = mujoco.MjData(mj)
    states.set_from_ours(data, x0)
    boards = MotorBoards.of(mj, joints, sea.ratio)
    steps = int(round(HOLD / STEP))
    out = []
    for u in torques:
        for _ in range(steps):
            boards.command(mj, data, u)  # the motor boards' loop, at every MuJoCo step
            mujoco.mj_step(mj, data)
        out.append(states.to_ours(data, base))
    return np.array(out)


def split(x: np.ndarray, n: int) -> dict[str, np.ndarray]:
    """Joint angles, motor angles (joint side, Gamma theta), joint velocities of states
    (rows); the base pose too."""
    return {
        "base_position": x[:, :3],
        "s": x[:, 7 : 7 + n],
        "theta": x[:, 7 + n : 7 + 2 * n],
        "sdot": x[:, 13 + 2 * n : 13 + 3 * n],
    }


def torque_limits(joints: list[str], hold: np.ndarray, sea: Sea, fraction: float | None) -> dict[str, float]:
    """Motor torque limits [N m, motor side] that clip the peaks of ``torque_sequence``: the
    hold torque's size plus ``fraction`` of the sinusoid's amplitude, ``Gamma (|tau_hold| +
    fraction A)``, so every motor saturates near its peaks while the joints stay near the
    start posture (none: no limits)."""
    if fraction is None:
        return {}
    limits = sea.ratio * (np.abs(hold) + fraction * AMPLITUDE)
    return {name: float(limit) for name, limit in zip(joints, limits)}


def fixed_plant(model: sm.Model, q0: np.ndarray, limits: dict[str, float]) -> sm.Plant:
    """Our plant with the base welded at ``q0`` and the motors limited by ``limits``."""
    actuators = {name: {"kind": "elastic", "torque_limit": limit} for name, limit in limits.items()}
    return sm.Plant(
        model,
        actuator="elastic",
        actuators=actuators,
        contacts=[BASE],
        contact_q=q0,
        joint_inertia_regularization=REGULARIZATION,
    )


def compare(setting: str, duration: float = 1.0, limit_fraction: float | None = None) -> dict[str, float]:
    """Runs ``setting`` ("fixed" or "ground") in both simulators; the largest differences:
    joint angle [rad], motor angle (joint side) [rad], joint velocity [rad/s], base position
    [m], and the largest joint excursion [rad] for scale; wall times [s].

    With ``limit_fraction`` ("fixed" only) each motor's torque is limited to its hold torque
    plus that fraction of the sinusoid's amplitude (``torque_limits``): ours through the
    actuators' ``torque_limit``, MuJoCo's through the rotor hinges' ``actfrcrange``. Then
    also ``saturated_share``, the share of the commands over their limit, and
    ``limit_effect``, the largest joint angle difference the limits make to our run [rad]."""
    sea, sc = Sea(), scenario(FEET)
    model, x0 = sc.model, sc.initial_state
    n, q0 = model.n_joints, x0[: model.nq]
    limits: dict[str, float] = {}
    if setting == "fixed":
        hold = model.gravity_forces(q0)[6:]
        torques = torque_sequence(hold, sea, duration)
        limits = torque_limits(model.joint_names, hold, sea, limit_fraction)
        plant = fixed_plant(model, q0, limits)
        x0 = plant.make_state(q0, joint_torques=hold)
        options = SeaModelOptions(
            joint_armature=REGULARIZATION,
            fixed_base=q0[:7].copy(),
            integrator=mujoco.mjtIntegrator.mjINT_RK4,
            torque_limits=limits,
        )
        method, base = "rk4", q0[:7].copy()
    elif limit_fraction is not None:
        raise ValueError(f"limit_fraction: only the fixed setting takes one, not {setting!r}")
    else:
        plant = sc.plant  # the motor velocity loop, K_m = 200 1/s
        options = SeaModelOptions(joint_armature=REGULARIZATION, motor_velocity_gain=MOTOR_VELOCITY_GAIN)
        method, base = sc.method, None
        torques = velocity_sequence(model.joint_names, sea, duration)
    start = time.perf_counter()
    ours_x = ours(plant, x0, torques, method)
    ours_wall = time.perf_counter() - start
    mj = sea_model(URDF, model.joint_names, sea, options)
    states = SeaStateMap.of(mj, model.joint_names, sea.ratio)
    start = time.perf_counter()
    theirs_x = theirs(mj, states, x0, torques, model.joint_names, sea, base)
    theirs_wall = time.perf_counter() - start
    a, b = split(ours_x, n), split(theirs_x, n)
    d = {
        "joint_angle": float(np.abs(a["s"] - b["s"]).max()),
        "motor_angle": float(sea.ratio * np.abs(a["theta"] - b["theta"]).max()),
        "joint_velocity": float(np.abs(a["sdot"] - b["sdot"]).max()),
        "base_position": float(np.abs(a["base_position"] - b["base_position"]).max()),
        "excursion": float(np.abs(a["s"] - x0[7 : 7 + n]).max()),
        "ours_wall_s": ours_wall,
        "mujoco_wall_s": theirs_wall,
    }
    if limits:
        bounds = np.array([limits[name] for name in model.joint_names])
        free = split(ours(fixed_plant(model, q0, {}), x0, torques, method), n)
        d["saturated_share"] = float(np.mean(np.abs(torques) > bounds))
        d["limit_effect"] = float(np.abs(free["s"] - a["s"]).max())
    return d


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=1.0, help="simulated time [s]")
    args = parser.parse_args()
    for setting in ("fixed", "ground"):
        d = compare(setting, args.duration)
        print(
            f"{setting}: max |s_ours - s_mujoco| {d['joint_angle']:.3e} rad, motor angle (joint side) "
            f"{d['motor_angle']:.3e} rad, joint velocity {d['joint_velocity']:.3e} rad/s, base position "
            f"{d['base_position']:.3e} m; largest joint excursion {d['excursion']:.3e} rad; wall time ours "
            f"{d['ours_wall_s']:.1f} s, MuJoCo {d['mujoco_wall_s']:.1f} s"
        )


if __name__ == "__main__":
    main()
