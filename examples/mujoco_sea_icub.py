"""Our robot-rate controller in Python, as on a robot, driving the iCub with SEAs in MuJoCo.

The robot: ``urdf/icub25.urdf`` in MuJoCo with a series elastic actuator on each of its 25
joints, modelled the MuJoCo way (``mujoco_sea.py``: a rotor hinge with the reflected motor
inertia as armature behind a spring-damper tendon, the motor boards' velocity loop as an
implicit velocity actuator), standing on two foot boxes on a floor with MuJoCo's soft
contacts, 0.25 ms steps.

The controller: the robot-rate design of ``scenarios/robot_rate/push_two_feet.toml``
(docs/guide/robot_rate.md) as the Python ``Controller`` stack: the whole-body QP at 100 Hz
(``tick``), the joint torque loops at 1 kHz (``inner_tick``), the stiffness identification
(started from an estimate x0.7 of the springs' 350 N m/rad) and the push observer, updated
after each period (``end_period``) from the feet's force/torque sensors (the first and last
steps' and their mean over the period) and the joint torque sensors, read from MuJoCo
(``mj_contactForce``, the springs' tendons). Each period is ``sea_momentum.run_period`` (the
robot's loop, ``sea_momentum.robot_loop``) with MuJoCo's robot as its ``Robot``. It reads only
what a robot measures: the joint and motor encoders, the base's pose and velocity, the feet's
wrenches, the joint torques; it writes the motor boards' desired motor velocities.

The run: 10 s of the 1 cm lateral CoM sinusoid at 0.2 Hz, and a push on the pelvis (5 N s
forward: 50 N for 0.1 s at 5 s, as the shipped scenario's). Prints the CoM error, the push's
recovery and the identified stiffnesses; writes a figure.

``--simulator ours`` runs the same loop on our plant (the scenario's, the push through
``Plant.step(..., external=...)``); ``--compare`` runs both and compares their CoM.

``--walk SCENARIO`` runs a walking scenario's controller instead (e.g.
``scenarios/walking/walk_fast.toml``: 50 steps at 0.3 m/s; the plan, the contact phases, the
swings and the touchdowns sensed from MuJoCo's foot wrenches), with the MuJoCo foot boxes as
its CoP rectangle and no push unless asked; ``--set KEY=VALUE`` overrides a scenario key
(``--set controller.stiffness_estimate_scale=0.7 --set
controller.stiffness_identification=true``). ``--push-direction`` pushes backward, left or
right instead of forward; ``scripts/mujoco_walk_pushes.py`` runs grids of pushes while walking.
A simulator that diverges (our plant's state past what its dynamics factorise, MuJoCo's bad
accelerations) ends the run there, as a fall.

Run: ``python examples/mujoco_sea_icub.py [--duration 10] [--push-impulse 5] [--figure out.png]``,
``python examples/mujoco_sea_icub.py --walk scenarios/walking/walk_fast.toml --duration 22``.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time
from typing import Callable

import mujoco
import numpy as np

import sea_momentum as sm

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from mujoco_icub import FEET, FOOT_X, FOOT_Y, URDF, foot_wrenches  # noqa: E402
from mujoco_sea import MotorBoards, Sea, SeaModelOptions, SeaStateMap, motor_torque_limits, sea_model  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
#: The design's keys over the shipped push scenario: the stiffness estimate x0.7, the CoM
#: sinusoid, the MuJoCo foot boxes as the CoP rectangle, no scenario push (MuJoCo pushes).
OVERRIDES = {
    "controller.stiffness_estimate_scale": 0.7,
    "controller.stiffness_identification": True,
    "controller.contact.foot_x": list(FOOT_X),
    "controller.contact.foot_y": list(FOOT_Y),
    "reference.com_amplitude": 0.01,
    "reference.com_frequency": 0.2,
    "reference.com_direction": [0.0, 1.0, 0.0],
    "disturbances": [],
}
#: A walking scenario's keys in MuJoCo (``--walk``): the MuJoCo foot boxes as the CoP rectangle.
WALK_OVERRIDES = {
    "controller.contact.foot_x": list(FOOT_X),
    "controller.contact.foot_y": list(FOOT_Y),
}
#: The push: on this link's origin, world axes, for PUSH_DURATION s, in one of these
#: directions (``--push-direction``; left is the world's +y, the robot's left at the start).
PUSH_LINK = "root_link"
PUSH_DIRECTIONS = {
    "forward": (1.0, 0.0, 0.0),
    "backward": (-1.0, 0.0, 0.0),
    "left": (0.0, 1.0, 0.0),
    "right": (0.0, -1.0, 0.0),
}
PUSH_DURATION = 0.1
#: A run has fallen when the base drops this far below its start [m].
FALL_DROP = 0.1


#: A push schedule: the force [N] (3, world) on the pelvis over the step starting at ``t`` [s]
#: after the controller's start, or None.
Push = Callable[[float], "np.ndarray | None"]


def push_schedule(impulse: float, start: float, direction: str) -> Push | None:
    """A push of ``impulse`` [N s] over ``PUSH_DURATION`` from ``start`` [s] in ``direction``
    (a key of ``PUSH_DIRECTIONS``); None for no push (``impulse`` 0)."""
    if direction not in PUSH_DIRECTIONS:
        raise ValueError(f"push_direction: expected one of {sorted(PUSH_DIRECTIONS)}, got {direction!r}")
    if impulse <= 0:
        return None
    force = impulse / PUSH_DURATION * np.array(PUSH_DIRECTIONS[direction])
    return lambda t: force if start - 1e-9 <= t < start + PUSH_DURATION - 1e-9 else None


class Diverged(RuntimeError):
    """A simulator's state left the finite numbers or its dynamics failed (our plant's
    ``SolverError``), or its accelerations did (MuJoCo's ``mjWARN_BADQACC``, after which
    MuJoCo resets the state): the run ends there, as a fall."""


def push_wrench(mj: mujoco.MjModel, data: mujoco.MjData, body: int, force: np.ndarray) -> np.ndarray:
    """``xfrc_applied`` of a force at the body's origin: MuJoCo applies it at the body's CoM,
    so the moment ``(origin - com) x force`` is added."""
    arm = data.xpos[body] - data.xipos[body]
    return np.concatenate([force, np.cross(arm, force)])


class Robot:
    """MuJoCo's SEA iCub seen as a robot: sensors in, motor commands out."""

    def __init__(self, scenario: sm.Scenario, sea: Sea, gain: float, push: Push | None = None) -> None:
        self.joints = scenario.model.joint_names
        self.push, self.steps_taken = push, 0
        # MuJoCo steps at the scenario's plant step (0.25 ms: resolves the SEA modes).
        options = SeaModelOptions(
            motor_velocity_gain=gain,
            joint_armature=JOINT_ARMATURE,
            torque_limits=motor_torque_limits(scenario.plant, sea),
            timestep=scenario.plant_dt,
        )
        self.mj = sea_model(URDF, self.joints, sea, options)
        self.data = mujoco.MjData(self.mj)
        self.states = SeaStateMap.of(self.mj, self.joints, sea.ratio)
        self.boards = MotorBoards.of(self.mj, self.joints, sea.ratio)
        self.states.set_from_ours(self.data, scenario.initial_state)
        mujoco.mj_forward(self.mj, self.data)
        self.push_body = self.mj.body(PUSH_LINK).id
        self.dt = self.mj.opt.timestep  #: the MuJoCo step [s]
        self.n_inputs = len(self.joints)  #: one desired motor velocity per joint

    def restart_clock(self) -> None:
        """The push schedule's and MuJoCo's clocks back at 0 (``settle``)."""
        self.steps_taken, self.data.time = 0, 0.0

    def state(self) -> np.ndarray:
        """The encoders and the base estimate: our state ``[q, theta, nu, thetadot]``."""
        return self.states.to_ours(self.data)

    def step(self, u: np.ndarray) -> sm.StepReadings:
        """One MuJoCo step with the motor boards tracking ``u`` and the push (a force, world)
        on the pelvis; returns what the feet's and the joints' torque sensors read over it."""
        self.boards.command(self.mj, self.data, u)
        self.data.xfrc_applied[self.push_body] = 0.0
        force = self.push(self.steps_taken * self.dt) if self.push else None
        if force is not None:
            self.data.xfrc_applied[self.push_body] = push_wrench(self.mj, self.data, self.push_body, force)
        mujoco.mj_step(self.mj, self.data)
        self.steps_taken += 1
        if self.data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            raise Diverged(f"MuJoCo: bad accelerations at {self.data.time:.4f} s")
        # mj_step's forward pass leaves the contacts and the tendons of the step's start.
        return sm.StepReadings(foot_wrenches(self.mj, self.data, FEET), self.boards.joint_torques(self.mj, self.data))


class OurPlant(sm.PlantRobot):
    """Our SEA plant (the scenario's: unilateral contacts, the motor velocity loops) as the
    same kind of robot as ``Robot`` (``sm.PlantRobot``), the push through ``Plant.step(...,
    external=...)``: the same controller loop on the other simulator."""

    def __init__(self, scenario: sm.Scenario, push: Push | None = None) -> None:
        super().__init__(scenario, external=self.pushes)
        self.push = push
        self.n_inputs = self.plant.nu_input  #: the plant's input size

    def pushes(self, t: float) -> dict[str, np.ndarray] | None:
        """``Plant.step``'s ``external`` at time ``t``: the push on the pelvis, if any."""
        force = self.push(t) if self.push else None
        return None if force is None else {PUSH_LINK: force}

    def restart_clock(self) -> None:
        """The push schedule's clock back at 0 (``settle``)."""
        self.steps_taken = 0

    def step(self, u: np.ndarray) -> sm.StepReadings:
        """One plant step (``sm.PlantRobot.step``); a failed or non-finite one raises
        ``Diverged``."""
        try:
            readings = super().step(u)
        except sm.SolverError as error:  # a state so far off that the dynamics fail
            raise Diverged(f"our plant: {error}") from error
        if not np.isfinite(self.x).all():
            raise Diverged("our plant: the state is not finite")
        return readings


def settle(robot: Robot | OurPlant, duration: float) -> None:
    """The robot powered on before the controller starts: the motors held still (desired
    motor velocity 0) for ``duration`` s with the push set aside, while the contacts take the
    weight (MuJoCo's soft contacts start at zero penetration, and their first milliseconds'
    forces, up to the whole weight on one foot, would be the identification's first
    readings); then the robot's clock restarts at 0."""
    hold, push, robot.push = np.zeros(robot.n_inputs), robot.push, None
    for _ in range(int(round(duration / robot.dt))):
        robot.step(hold)
    robot.push = push
    robot.restart_clock()


#: The link joints' armature: the iCub plant's joint_inertia_regularization (the same robot
#: as our plant, examples/mujoco_sea_check.py).
JOINT_ARMATURE = 0.1
#: How long the motors hold still on the ground before the controller starts [s].
SETTLE = 0.2
#: The motor boards' velocity loop gain K_m [1/s] (the iCub's plant.motor_velocity_gain).
MOTOR_VELOCITY_GAIN = 200.0


def run(
    duration: float,
    push_impulse: float,
    push_start: float = 5.0,
    simulator: str = "mujoco",
    scenario_path: pathlib.Path = SCENARIO,
    overrides: dict | None = None,
    *,
    push_direction: str = "forward",
) -> dict[str, np.ndarray]:
    """The robot loop (module doc) for ``duration`` s with a push of ``push_impulse`` [N s]
    at ``push_start`` in ``push_direction`` (a key of ``PUSH_DIRECTIONS``), on MuJoCo's SEA
    iCub (``simulator="mujoco"``) or on our plant (``"ours"``), the controller of
    ``scenario_path`` with ``overrides`` (default: the balancing design, ``OVERRIDES``); the
    time series at every whole-body tick."""
    overrides = OVERRIDES if overrides is None else overrides
    push = push_schedule(push_impulse, push_start, push_direction)
    scenario = sm.Scenario.load(scenario_path, {**overrides, "simulation.duration_s": duration})
    controller = scenario.controller
    if simulator not in ("mujoco", "ours"):
        raise ValueError(f"simulator: expected 'mujoco' or 'ours', got {simulator!r}")
    robot = Robot(scenario, Sea(), MOTOR_VELOCITY_GAIN, push) if simulator == "mujoco" else OurPlant(scenario, push)
    settle(robot, SETTLE)
    elastic = scenario.plant.elastic_joints
    period = scenario.control_period
    steps, inner = scenario.steps_per_tick, scenario.steps_per_inner_tick  # 100 Hz, 1 kHz
    series: dict[str, list] = {k: [] for k in ("time", "com", "com_reference", "base_height", "base_x", "stiffness_ratio", "qp_solved")}
    start_wall = time.perf_counter()
    for k in range(int(round(duration / period))):
        t = k * period
        x = robot.state()
        if x[2] < series_start_height(series, x) - FALL_DROP:
            break  # fallen: the rest would be MuJoCo's robot lying on the floor
        out = controller.tick(t, x)
        try:
            readings = sm.run_period(controller, robot, out.input, steps, inner)
        except Diverged:
            break  # as a fall: the series ends before the run's duration
        readings.hand_to(controller)
        estimates = np.array([controller.stiffness_estimates[name] for name in elastic])
        for key, value in (
            ("time", t),
            ("com", out.com),
            ("com_reference", out.com_reference),
            ("base_height", x[2]),
            ("base_x", x[0]),
            ("stiffness_ratio", estimates / Sea().stiffness),
            ("qp_solved", out.qp_status == "solved"),
        ):
            series[key].append(value)
    result = {key: np.array(values) for key, values in series.items()}
    result["wall_s"] = np.array(time.perf_counter() - start_wall)
    result["push_start"] = np.array(push_start)
    result["push_impulse"] = np.array(push_impulse)
    result["duration"] = np.array(duration)
    scale = float(overrides.get("controller.stiffness_estimate_scale", 1.0))
    result["title"] = f"{scenario.name}, K_S estimate x{scale:g}"
    return result


def compare_simulators(
    duration: float,
    push_impulse: float,
    push_start: float,
    scenario_path: pathlib.Path = SCENARIO,
    overrides: dict | None = None,
    *,
    push_direction: str = "forward",
) -> dict[str, float]:
    """The same controller loop (``run``'s scenario, overrides and push) on MuJoCo's SEA iCub
    and on our plant: the largest and rms distance between the two CoM trajectories [mm],
    before the push and over the run, and each one's largest forward CoM excursion [mm]."""
    pushed = dict(push_direction=push_direction)
    mujoco_run = run(duration, push_impulse, push_start, "mujoco", scenario_path, overrides, **pushed)
    ours_run = run(duration, push_impulse, push_start, "ours", scenario_path, overrides, **pushed)
    rows = min(len(mujoco_run["time"]), len(ours_run["time"]))
    distance = np.linalg.norm(mujoco_run["com"][:rows] - ours_run["com"][:rows], axis=1)
    before = mujoco_run["time"][:rows] < push_start if push_impulse > 0 else np.full(rows, True)
    forward = lambda s: 1e3 * float(np.max(s["com"][:, 0] - s["com"][0, 0]))  # noqa: E731
    return {
        "com_distance_max_mm": 1e3 * float(distance.max()),
        "com_distance_max_before_push_mm": 1e3 * float(distance[before].max()),
        "com_distance_rms_mm": 1e3 * float(np.sqrt(np.mean(distance**2))),
        "forward_excursion_mujoco_mm": forward(mujoco_run),
        "forward_excursion_ours_mm": forward(ours_run),
    }


def series_start_height(series: dict[str, list], x: np.ndarray) -> float:
    """The base height at the first tick (``x``'s before any)."""
    return float(series["base_height"][0]) if series["base_height"] else float(x[2])


def summary(series: dict[str, np.ndarray]) -> dict[str, float]:
    """CoM error rms and max (before the push and over the run), the largest CoM excursion
    after the push and the error at the end; whether the robot stands (base drop), how far
    its base went forward. Without a push the whole run counts as before it."""
    error = np.linalg.norm(series["com"] - series["com_reference"], axis=1)
    pushed = float(series["push_impulse"]) > 0
    before = series["time"] < series["push_start"] if pushed else np.full(len(error), True)
    drop = series["base_height"][0] - series["base_height"].min()
    fallen = series["time"][-1] < float(series["duration"]) - 0.015
    return {
        "com_error_rms_mm": 1e3 * float(np.sqrt(np.mean(error**2))),
        "com_error_rms_before_push_mm": 1e3 * float(np.sqrt(np.mean(error[before] ** 2))),
        "com_error_max_after_push_mm": 1e3 * float(error[~before].max()) if (~before).any() else 0.0,
        "com_error_max_mm": 1e3 * float(error.max()),
        "com_error_final_mm": 1e3 * float(error[-1]),
        "base_drop_mm": 1e3 * float(drop),
        "standing": float(drop < FALL_DROP and not fallen),
        "simulated_s": float(series["time"][-1]),
        "base_forward_m": float(series["base_x"][-1] - series["base_x"][0]),
        "stiffness_ratio_min": float(series["stiffness_ratio"][-1].min()),
        "stiffness_ratio_max": float(series["stiffness_ratio"][-1].max()),
        "qp_solved_fraction": float(series["qp_solved"].mean()),
        "wall_s": float(series["wall_s"]),
    }


def figure(series: dict[str, np.ndarray], path: pathlib.Path, push_impulse: float) -> None:
    """The CoM against its reference (lateral and forward), the CoM error and the
    identified stiffness estimates over the run."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = series["time"]
    fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    for axis, label in ((1, "lateral y"), (0, "forward x")):
        axes[0].plot(t, 1e3 * (series["com"][:, axis] - series["com"][0, axis]), label=f"CoM {label}")
        axes[0].plot(t, 1e3 * (series["com_reference"][:, axis] - series["com"][0, axis]), "--", label=f"reference {label}")
    if push_impulse > 0:
        axes[0].axvspan(float(series["push_start"]), float(series["push_start"]) + PUSH_DURATION, color="r", alpha=0.2, label=f"push {push_impulse:g} N s")
    axes[0].set_ylabel("CoM from start [mm]")
    axes[0].legend(fontsize=7, ncol=3)
    error = np.linalg.norm(series["com"] - series["com_reference"], axis=1)
    axes[1].plot(t, 1e3 * error)
    axes[1].set_ylabel("|CoM error| [mm]")
    axes[2].plot(t, series["stiffness_ratio"], lw=0.7)
    axes[2].set_ylabel("K_S estimate / K_S")
    axes[2].set_xlabel("time [s]")
    fig.suptitle(
        "iCub with SEAs in MuJoCo, the robot-rate design from Python\n"
        f"(100 Hz / 1 kHz, {series['title']})",
        fontsize=10,
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)


def parse_override(text: str) -> tuple[str, object]:
    """``KEY=VALUE`` of ``--set``: the value as JSON (numbers, true/false, lists), else the
    text itself."""
    key, separator, value = text.partition("=")
    if not separator or not key.strip():
        raise SystemExit(f"--set: expected KEY=VALUE, got {text!r}")
    try:
        return key.strip(), json.loads(value)
    except json.JSONDecodeError:
        return key.strip(), value.strip()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="simulated time [s]")
    parser.add_argument("--push-impulse", type=float, default=None, help="push on the pelvis [N s] (default 5, walking 0)")
    parser.add_argument("--push-direction", choices=sorted(PUSH_DIRECTIONS), default="forward", help="the push's direction (world axes; left is +y)")
    parser.add_argument("--push-start", type=float, default=5.0, help="when the push starts [s]")
    parser.add_argument("--figure", type=pathlib.Path, default=pathlib.Path("out/mujoco_sea_icub.png"))
    parser.add_argument("--simulator", choices=["mujoco", "ours"], default="mujoco", help="the robot: MuJoCo's, or our plant for comparison")
    parser.add_argument("--compare", action="store_true", help="run on both simulators and compare the CoM")
    parser.add_argument("--walk", type=pathlib.Path, help="a walking scenario whose controller runs instead (no push unless --push-impulse)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override a scenario key (a JSON value, else a string; repeatable)")
    args = parser.parse_args()
    walking = args.walk is not None
    overrides = {**(WALK_OVERRIDES if walking else OVERRIDES), **dict(parse_override(text) for text in args.set)}
    push_impulse = args.push_impulse if args.push_impulse is not None else (0.0 if walking else 5.0)
    scenario_path = args.walk if walking else SCENARIO
    if args.compare:
        compared = compare_simulators(args.duration, push_impulse, args.push_start, scenario_path, overrides, push_direction=args.push_direction)
        for key, value in compared.items():
            print(f"{key}: {value:.4g}")
        return
    series = run(args.duration, push_impulse, args.push_start, args.simulator, scenario_path, overrides, push_direction=args.push_direction)
    for key, value in summary(series).items():
        print(f"{key}: {value:.4g}")
    figure(series, args.figure, push_impulse)
    print(f"figure: {args.figure}")


if __name__ == "__main__":
    main()
