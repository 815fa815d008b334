"""Pushes on MuJoCo's iCub held by our rigid momentum controller at the robot's rate (100 Hz).

The rigid iCub of ``examples/mujoco_icub.py`` (free base, soft frictional contacts of two foot
boxes on a floor plane, torque actuators) with:
- ``armature`` on every joint equal to our plant's ``joint_inertia_regularization`` (read from the
  push scenario and its robot description, checked against the scenario's plant: 0.1 on the
  iCub), implicitfast, 1 ms steps, pyramidal cones (``--elliptic`` for elliptic ones);
- joint stops: MuJoCo's URDF import (``autolimits``, on by default) makes every joint with a
  URDF ``<limit>`` limited to it (checked at start, printed); the URDF ``effort`` limits, which
  the import turns into joint torque clamps, are dropped as our rigid plant has none
  (``--effort-limits`` keeps them);
- the URDF's visual boxes as shapes that collide with the floor only, to see a body touch it.

The controller is the push scenario's (``scenarios/robot_rate/push_two_feet.toml``) as the
rigid reference row of ``scripts/robot_rate.py`` builds it: rigid controller, zero-order hold
at 100 Hz (a tick every 10 MuJoCo steps, its torques held in between), the push observed from
the centroidal momentum and the feet's wrenches (``end_period`` with MuJoCo's contact forces and
actuator torques at the period's first and last step), the stiffness identification off.

A push: a force on the pelvis (``root_link``, at its origin as our ``[[disturbances]]``) for
0.1 s from t = 1 s via ``data.xfrc_applied``. Recovered: over the 4 s after the push the base
height stays above 0.8 of its initial value, the base tilt below 30 degrees, and no body but
the feet (and the bodies welded to them) touches the floor. Per direction the largest recovered
impulse is bisected, and the onset, the smallest impulse where a foot's sole origin slides more
than 5 mm horizontally or rises more than 5 mm (from its pose at the push's start), or the run
is not recovered.

Run: ``python benchmarks/mujoco_push.py [--directions forward backward left right]
[--tolerance 0.1] [--json out.json] [--elliptic] [--effort-limits] [--after 4.0]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib
import sys
import time
import tomllib
import xml.etree.ElementTree as ET
from typing import Callable

import mujoco
import numpy as np

import sea_momentum as sm

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))
import mujoco_icub as icub  # noqa: E402  (the MuJoCo model of the iCub, one source of truth)

PUSH_SCENARIO = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
#: The rigid robot under the rigid controller at 100 Hz, zero-order hold (scripts/robot_rate.py's
#: reference row), the stiffness identification off (it needs the joint loops).
RIGID_100_HZ = {
    "actuators.kind": "rigid",
    "controller.kind": "rigid",
    "controller.sampling": "zero_order_hold",
    "controller.rate_hz": 100,
    "controller.stiffness_identification": False,
}
PUSHED_LINK = "root_link"
#: Push directions, world axes (+x forward, +y to the robot's left).
DIRECTIONS = {
    "forward": (1.0, 0.0, 0.0),
    "backward": (-1.0, 0.0, 0.0),
    "left": (0.0, 1.0, 0.0),
    "right": (0.0, -1.0, 0.0),
}
#: Recovery criteria.
MIN_HEIGHT_RATIO = 0.8
MAX_TILT_DEG = 30.0
#: A foot "moves" past this slide or lift of its sole origin [m].
FOOT_MOTION_M = 0.005
#: The feet's loads are watched from the push's start to this long after its end [s]: the
#: foot unloaded by the push, not the rocking after it.
LOAD_WINDOW_S = 0.2
#: First upper bracket of the bisection [N s] (doubled while recovered, up to MAX_IMPULSE).
FIRST_BRACKET = 16.0
MAX_IMPULSE = 128.0


@dataclasses.dataclass(frozen=True)
class PushSetup:
    """The push and the run's length."""

    start_s: float = 1.0  #: push start [s]
    duration_s: float = 0.1  #: push length [s]
    after_s: float = 4.0  #: simulated time after the push's end [s]
    elliptic: bool = False  #: elliptic friction cones
    effort_limits: bool = False  #: keep the URDF's effort limits as torque clamps


@dataclasses.dataclass
class RunRecord:
    """What one push did."""

    direction: str
    impulse_n_s: float
    recovered: bool
    reason: str  #: why not recovered ("" when recovered)
    end_s: float  #: simulated time reached (a run stops at its failure)
    min_height_ratio: float
    max_tilt_deg: float
    slide_mm: dict[str, float]  #: per foot, max horizontal displacement of the sole origin
    lift_mm: dict[str, float]  #: per foot, max rise of the sole origin
    min_normal_n: dict[str, float]  #: per foot, least normal force in the push's load window
    joints_at_stop: list[str]  #: joints that reached a URDF limit (a MuJoCo joint stop)
    peak_effort_ratio: float  #: max |joint torque| / URDF effort over joints and time
    solver_errors: int  #: controller ticks that raised (the last command was held)
    wall_s: float

    @property
    def foot_moved(self) -> bool:
        """A foot's sole origin slid or rose more than ``FOOT_MOTION_M``."""
        limit = FOOT_MOTION_M * 1e3
        return max(self.slide_mm.values()) > limit or max(self.lift_mm.values()) > limit


def plant_regularization(scenario: sm.Scenario, path: pathlib.Path) -> float:
    """Our plant's ``joint_inertia_regularization``: the scenario file's ``[plant]`` value, else
    its robot description's (``robots/<description>.toml``), checked by comparing the scenario
    plant's dynamics with a plant built with that value (the feet held as rigid contacts in
    both: the regularisation is compared, not the contact model)."""
    scenario = sm.Scenario.load(path, {**RIGID_100_HZ, "plant.contact_model": "bilateral"})
    table = tomllib.loads(path.read_text())
    value = table.get("plant", {}).get("joint_inertia_regularization")
    if value is None:
        description = table.get("robot", {}).get("description", "icub_paper")
        robot = tomllib.loads((ROOT / "robots" / f"{description}.toml").read_text())
        value = robot["joint_inertia_regularization"]
    x = np.array(scenario.initial_state)
    u = np.linspace(-1.0, 1.0, scenario.plant.nu_input)
    rebuilt = sm.Plant(
        scenario.model,
        contacts=scenario.plant.contact_frames,
        contact_q=x[: scenario.model.nq],
        joint_inertia_regularization=value,
    )
    if not np.allclose(rebuilt.dynamics(x, u), scenario.plant.dynamics(x, u), rtol=1e-9, atol=1e-9):
        raise RuntimeError(f"the scenario's plant does not use joint_inertia_regularization = {value}")
    return float(value)


def load_scenario() -> sm.Scenario:
    """The push scenario as the rigid 100 Hz reference row builds it (a fresh controller)."""
    return sm.Scenario.load(PUSH_SCENARIO, RIGID_100_HZ)


def urdf_efforts(urdf: pathlib.Path, joints: list[str]) -> np.ndarray:
    """The URDF's ``effort`` limit of each of ``joints`` [N m]."""
    limits = {
        joint.get("name"): float(joint.find("limit").get("effort"))
        for joint in ET.parse(urdf).getroot().findall("joint")
        if joint.find("limit") is not None
    }
    return np.array([limits[name] for name in joints])


def joint_limits_report(model: mujoco.MjModel, joints: list[str]) -> str:
    """How MuJoCo compiled the joints' limits: stops (``limited``) and torque clamps."""
    limited = [name for name in joints if model.joint(name).limited[0]]
    clamped = [name for name in joints if model.jnt_actfrclimited[model.joint(name).id]]
    return (
        f"joint stops from the URDF limits (autolimits): {len(limited)} of {len(joints)} joints "
        f"limited; effort clamps: {len(clamped)} of {len(joints)}"
    )


class Monitor:
    """Per step: the base's height and tilt, the soles' slide and lift from their pose at the
    push's start, bodies touching the floor, joint stops and torques."""

    def __init__(self, model: mujoco.MjModel, data: mujoco.MjData, joints: list[str], effort: np.ndarray) -> None:
        self.model = model
        self.soles = [model.body(foot).id for foot in icub.FEET]
        self.base = model.body(PUSHED_LINK).id
        self.allowed = icub.foot_fixed_bodies(model) | {0}
        self.floor = model.geom("floor").id
        self.joint_ids = {model.joint(name).id: name for name in joints}
        self.actuators = np.array([model.actuator(name).id for name in joints])
        self.effort = effort
        mujoco.mj_kinematics(model, data)
        self.height0 = float(data.xpos[self.base][2])
        # World "up" in the base frame at the start: the tilt is the angle it turns by.
        self.up0 = data.xmat[self.base].reshape(3, 3).T @ np.array([0.0, 0.0, 1.0])
        self.sole0 = data.xpos[self.soles].copy()
        self.min_height_ratio, self.max_tilt_deg = 1.0, 0.0
        self.slide = np.zeros(len(self.soles))
        self.lift = np.zeros(len(self.soles))
        self.min_normal = np.full(len(self.soles), np.inf)
        self.at_stop: set[str] = set()
        self.peak_effort_ratio = 0.0
        self.floor_bodies: set[str] = set()

    def start_push(self, data: mujoco.MjData) -> None:
        """The soles' reference pose: their pose at the push's start."""
        self.sole0 = data.xpos[self.soles].copy()
        self.slide[:], self.lift[:] = 0.0, 0.0

    def step(self, data: mujoco.MjData, pushed: bool) -> None:
        """After an ``mj_step`` (``data`` holds the kinematics of the step's start)."""
        self.min_height_ratio = min(self.min_height_ratio, float(data.xpos[self.base][2]) / self.height0)
        up = data.xmat[self.base].reshape(3, 3) @ self.up0
        self.max_tilt_deg = max(self.max_tilt_deg, float(np.degrees(np.arccos(np.clip(up[2], -1.0, 1.0)))))
        if pushed:
            moved = data.xpos[self.soles] - self.sole0
            self.slide = np.maximum(self.slide, np.linalg.norm(moved[:, :2], axis=1))
            self.lift = np.maximum(self.lift, moved[:, 2])
        torque = np.abs(data.actuator_force[self.actuators])
        self.peak_effort_ratio = max(self.peak_effort_ratio, float(np.max(torque / self.effort)))
        self._contacts(data)

    def _contacts(self, data: mujoco.MjData) -> None:
        """Bodies on the floor and joints at a stop, from the contacts and constraint rows."""
        for i in range(data.ncon):
            contact = data.contact[i]
            for geom in (contact.geom1, contact.geom2):
                body = int(self.model.geom_bodyid[geom])
                if body not in self.allowed:
                    self.floor_bodies.add(self.model.body(body).name)
        rows = np.flatnonzero(data.efc_type[: data.nefc] == mujoco.mjtConstraint.mjCNSTR_LIMIT_JOINT)
        for row in rows:
            self.at_stop.add(self.joint_ids.get(int(data.efc_id[row]), "?"))

    def feet_loads(self, wrenches: np.ndarray) -> None:
        """The feet's measured wrenches at a tick after the push's start."""
        self.min_normal = np.minimum(self.min_normal, wrenches[:, 2])

    def failure(self) -> str:
        """Why the robot is not recovered so far ("" if it is)."""
        if self.min_height_ratio < MIN_HEIGHT_RATIO:
            return f"base height {self.min_height_ratio:.2f} of initial"
        if self.max_tilt_deg > MAX_TILT_DEG:
            return f"base tilt {self.max_tilt_deg:.0f} deg"
        if self.floor_bodies:
            return "on the floor: " + ", ".join(sorted(self.floor_bodies))
        return ""


class PushRig:
    """MuJoCo's iCub, compiled once, and the push runs on it (each with a fresh controller)."""

    def __init__(self, setup: PushSetup) -> None:
        self.setup = setup
        scenario = load_scenario()
        self.joints = scenario.model.joint_names
        self.q0 = np.array(scenario.initial_state[: scenario.model.nq])
        self.period_steps = int(round(scenario.control_period / icub.TIMESTEP))
        self.armature = plant_regularization(scenario, PUSH_SCENARIO)
        options = icub.ModelOptions(
            armature=self.armature,
            effort_limits=setup.effort_limits,
            elliptic=setup.elliptic,
            body_shapes=True,
        )
        self.model = icub.mujoco_model(icub.URDF, self.joints, options)
        self.actuators = np.array([self.model.actuator(name).id for name in self.joints])
        self.effort = urdf_efforts(icub.URDF, self.joints)
        self.base = self.model.body(PUSHED_LINK).id
        self.states = icub.StateMap.of(self.model, self.joints)

    def describe(self) -> str:
        """The model's settings, one line each."""
        cone = "elliptic" if self.setup.elliptic else "pyramidal"
        return "\n".join(
            [
                f"MuJoCo {mujoco.__version__}, {icub.TIMESTEP * 1e3:.0f} ms steps, implicitfast, {cone} cones, "
                f"armature {self.armature} kg m^2 (our plant's joint_inertia_regularization)",
                joint_limits_report(self.model, self.joints),
                f"controller: {PUSH_SCENARIO.relative_to(ROOT)} rigid, a tick every {self.period_steps} steps "
                f"(zero-order hold), push observed from the feet's MuJoCo wrenches",
            ]
        )

    def push_wrench(self, data: mujoco.MjData, force: np.ndarray) -> np.ndarray:
        """``xfrc_applied`` (force and torque at the body's CoM) of ``force`` at the link's
        origin, as our disturbances act (kinematics of the step before: 1 ms stale)."""
        arm = data.xpos[self.base] - data.xipos[self.base]
        return np.concatenate([force, np.cross(arm, force)])

    def readings(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """The feet's wrenches and the joint torques of the step just taken (at its start)."""
        return icub.foot_wrenches(self.model, data, icub.FEET), data.actuator_force[self.actuators].copy()

    def run(self, direction: str, impulse: float) -> RunRecord:
        """One push of ``impulse`` [N s] in ``direction`` (a key of ``DIRECTIONS``)."""
        started = time.perf_counter()
        data = mujoco.MjData(self.model)
        self.states.set_from_ours(data, self.q0)
        monitor = Monitor(self.model, data, self.joints, self.effort)
        force = np.array(DIRECTIONS[direction]) * impulse / self.setup.duration_s
        end_s, errors, reason = self.simulate(load_scenario().controller, data, monitor, force)
        feet = icub.FEET
        return RunRecord(
            direction=direction,
            impulse_n_s=impulse,
            recovered=not reason,
            reason=reason,
            end_s=end_s,
            min_height_ratio=monitor.min_height_ratio,
            max_tilt_deg=monitor.max_tilt_deg,
            slide_mm={f: float(v * 1e3) for f, v in zip(feet, monitor.slide)},
            lift_mm={f: float(v * 1e3) for f, v in zip(feet, monitor.lift)},
            min_normal_n={f: float(v) for f, v in zip(feet, monitor.min_normal)},
            joints_at_stop=sorted(monitor.at_stop),
            peak_effort_ratio=monitor.peak_effort_ratio,
            solver_errors=errors,
            wall_s=time.perf_counter() - started,
        )

    def simulate(
        self, controller: sm.Controller, data: mujoco.MjData, monitor: Monitor, force: np.ndarray
    ) -> tuple[float, int, str]:
        """The closed loop until the run's end or its failure: (time reached [s], controller
        ticks that raised, why not recovered or "")."""
        dt, period, setup = icub.TIMESTEP, self.period_steps, self.setup
        push_start = int(round(setup.start_s / dt))
        push_end = push_start + int(round(setup.duration_s / dt))
        last = push_end + int(round(setup.after_s / dt))
        load_window = int(round(LOAD_WINDOW_S / dt))
        errors, start, end = 0, None, None
        for k in range(last):
            phase = k % period
            if phase == 0:
                if start is not None and end is not None:
                    controller.end_period(start[0], start[1], end[0], end[1])
                errors += self.tick(controller, k * dt, data)
                reason = monitor.failure()
                if reason:
                    return k * dt, errors, reason
            if k == push_start:
                monitor.start_push(data)
            data.xfrc_applied[self.base] = self.push_wrench(data, force) if push_start <= k < push_end else 0.0
            mujoco.mj_step(self.model, data)
            if not np.all(np.isfinite(data.qacc)):
                return k * dt, errors, "MuJoCo diverged"
            if phase == 0:
                start = self.readings(data)
            if phase == period - 1:
                end = self.readings(data)
            if push_start <= k < push_end + load_window and phase in (0, period - 1):
                monitor.feet_loads((start if phase == 0 else end)[0])
            monitor.step(data, pushed=k >= push_start)
        return last * dt, errors, monitor.failure()

    def tick(self, controller: sm.Controller, t: float, data: mujoco.MjData) -> int:
        """One controller tick; its torques go to the actuators and are held until the next.
        Returns 1 if the tick raised (the last command is held), else 0."""
        try:
            data.ctrl[self.actuators] = controller.tick(t, self.states.to_ours(data)).input
            return 0
        except sm.SolverError:
            data.ctrl[self.actuators] = controller.command
            return 1


def bisect(ok: Callable[[float], bool], tolerance: float, failing: float | None = None) -> tuple[float, float | None]:
    """The largest impulse [N s] found ``ok`` and the smallest found not, within
    ``tolerance`` (0 is taken as ok). Without a known ``failing`` impulse the bracket starts at
    ``FIRST_BRACKET`` and doubles while ok; (largest ok, None) if still ok at ``MAX_IMPULSE``."""
    low, high = 0.0, failing
    if high is None:
        high = FIRST_BRACKET
        while ok(high):
            low, high = high, 2.0 * high
            if high > MAX_IMPULSE:
                return low, None
    while high - low > tolerance:
        middle = 0.5 * (low + high)
        if ok(middle):
            low = middle
        else:
            high = middle
    return low, high


class Pushes:
    """The runs of one rig, cached by (direction, impulse), and their progress lines."""

    def __init__(self, rig: PushRig, echo: Callable[[str], None] = print) -> None:
        self.rig = rig
        self.echo = echo
        self.runs: dict[tuple[str, float], RunRecord] = {}

    def run(self, direction: str, impulse: float) -> RunRecord:
        """The run of ``impulse`` [N s] in ``direction`` (0 N s shared by every direction)."""
        key = ("none", 0.0) if impulse == 0.0 else (direction, round(impulse, 9))
        if key not in self.runs:
            record = self.rig.run(direction, impulse)
            self.runs[key] = record
            self.echo(progress_line(record))
        return self.runs[key]

    def direction(self, direction: str, tolerance: float) -> dict:
        """The largest recovered impulse and the foot-motion onset in ``direction``."""
        baseline = self.run(direction, 0.0)
        if not baseline.recovered or baseline.foot_moved:
            raise RuntimeError(f"the unpushed run already fails: {baseline.reason or 'a foot moved'}")
        recovered, failing = bisect(lambda i: self.run(direction, i).recovered, tolerance)
        still = lambda i: self.run(direction, i).recovered and not self.run(direction, i).foot_moved  # noqa: E731
        onset_low, onset = bisect(still, tolerance, failing)
        at = lambda i: None if i is None else dataclasses.asdict(self.run(direction, i))  # noqa: E731
        return {
            "recovered_n_s": recovered,
            "first_failure_n_s": failing,
            "onset_n_s": onset,
            "last_still_n_s": onset_low,
            "at_bound": at(recovered),
            "at_failure": at(failing),
            "at_onset": at(onset),
        }


def progress_line(record: RunRecord) -> str:
    """One run, one line."""
    feet = ", ".join(
        f"{foot} slide {record.slide_mm[foot]:.1f} lift {record.lift_mm[foot]:.1f} mm "
        f"min Fz {record.min_normal_n[foot]:.0f} N"
        for foot in icub.FEET
    )
    state = "recovered" if record.recovered else f"NOT recovered at {record.end_s:.2f} s ({record.reason})"
    stops = f"; stops: {', '.join(record.joints_at_stop)}" if record.joints_at_stop else ""
    return (
        f"{record.direction:>8} {record.impulse_n_s:7.3f} N s: {state}; tilt {record.max_tilt_deg:.1f} deg; "
        f"{feet}{stops}; {record.wall_s:.1f} s wall"
    )


def lightly_loaded(record: dict) -> str:
    """The foot with the least normal force in the push's load window, and both feet's least
    normal forces [N] (left / right as ``icub.FEET``)."""
    loads = record["min_normal_n"]
    both = " / ".join(f"{loads[foot]:.0f}" for foot in icub.FEET)
    return f"{min(loads, key=loads.get)} ({both})"


def table(results: dict[str, dict]) -> str:
    """The results, a Markdown table: per direction the bound, the onset and the feet."""
    header = (
        "| direction | largest recovered [N s] | first not recovered [N s] (why) | foot-motion onset [N s] "
        "| lightly loaded foot (least Fz l / r [N]) | at the bound: slide l / r [mm] | lift l / r [mm] | joints at a stop |"
    )
    lines = [header, "|" + " --- |" * 8]
    # The onset is the first impulse where a foot moves more than FOOT_MOTION_M or the run fails.
    for direction, result in results.items():
        bound, failure = result["at_bound"], result["at_failure"]
        failing = "none" if failure is None else f"{result['first_failure_n_s']:.2f} ({failure['reason']})"
        onset = "-" if result["onset_n_s"] is None else f"{result['onset_n_s']:.2f}"
        slide = " / ".join(f"{bound['slide_mm'][f]:.1f}" for f in icub.FEET)
        lift = " / ".join(f"{bound['lift_mm'][f]:.1f}" for f in icub.FEET)
        stops = ", ".join(bound["joints_at_stop"]) or "none"
        lines.append(
            f"| {direction} | {result['recovered_n_s']:.2f} | {failing} | {onset} | "
            f"{lightly_loaded(bound)} | {slide} | {lift} | {stops} |"
        )
    return "\n".join(lines)


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--directions", nargs="+", choices=list(DIRECTIONS), default=list(DIRECTIONS))
    parser.add_argument("--tolerance", type=float, default=0.1, help="bisection tolerance [N s]")
    parser.add_argument("--json", type=pathlib.Path, help="write the results and every run as JSON")
    parser.add_argument("--elliptic", action="store_true", help="elliptic friction cones")
    parser.add_argument("--effort-limits", action="store_true", help="keep the URDF's effort limits")
    parser.add_argument("--after", type=float, default=4.0, help="simulated time after the push [s]")
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> None:
    """Bisects every direction asked for, prints the table and writes the JSON."""
    args = parse_args(argv)
    setup = PushSetup(after_s=args.after, elliptic=args.elliptic, effort_limits=args.effort_limits)
    rig = PushRig(setup)
    print(rig.describe(), flush=True)
    pushes = Pushes(rig, echo=lambda line: print(line, flush=True))
    started = time.perf_counter()
    results = {d: pushes.direction(d, args.tolerance) for d in args.directions}
    wall = time.perf_counter() - started
    print(table(results))
    print(f"{len(pushes.runs)} runs, {wall:.0f} s wall")
    if args.json:
        document = {
            "setup": dataclasses.asdict(setup),
            "model": rig.describe().splitlines(),
            "tolerance_n_s": args.tolerance,
            "wall_s": wall,
            "results": results,
            "runs": [dataclasses.asdict(record) for record in pushes.runs.values()],
        }
        args.json.write_text(json.dumps(document, indent=2))


if __name__ == "__main__":
    main()
