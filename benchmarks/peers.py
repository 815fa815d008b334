"""sea-momentum beside MuJoCo, measured in one run on the same robot.

MuJoCo compiles ``urdf/icub25.urdf`` with a free base, a floor plane and massless foot boxes of
the controller's foot rectangle (the model of ``examples/mujoco_balance.py``), standing on both
feet (4 contacts per box, 8 in all), held by the rigid momentum controller (as in the example). Its ``mj_step``
(Euler and implicitfast, 1 ms) is timed beside ``target/release/sea-sim bench --json``, which
runs as a subprocess in the same run; the two alternate ``--runs`` times and each figure is the
median of the runs (each run's figure is itself a median of batch means).

Ratios printed (below 1: ours is faster):
- one implicit SEA step (ROS2, 25 motor states, two rigid feet) / ``mj_step``;
- controller tick (two feet; model terms, QP, SEA map) / ``mj_step``;
- the same tick with Clarabel on every tick / ``mj_step``;
- the same tick with the active-set QP solver on every tick / ``mj_step``;
- one simulated second of the closed loop at 1 kHz / 1000 ``mj_step``;
- one simulated second of the multi-rate loop (QP at 100 Hz, joint loops at 1 kHz) / 1000 ``mj_step``;
- the continuous-time closed loop (controller at every integrator stage) / the 1 kHz one.

Run: ``python benchmarks/peers.py [--runs 3] [--batches 31] [--steps 500] [--json FILE]
[--sea-sim PATH ...]`` (needs ``pip install mujoco`` and ``cargo build --release -p sea_sim --bin
sea-sim``). ``--sea-sim`` given several times times each binary in turn within every run (e.g. a
build of the commit before a change beside the one after it), so the before/after ratios come
from one run on one machine. The CPU model is printed with the figures: ratios to MuJoCo differ
between CPUs (the same commit measured 0.47x and 0.72x ``mj_step`` on two machines).
"""

from __future__ import annotations

import argparse
import json
import pathlib
import platform
import statistics
import subprocess
import sys
import time

import mujoco
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))
import mujoco_balance  # noqa: E402  (the MuJoCo model of the iCub, one source of truth)

import sea_momentum as sm  # noqa: E402

URDF = ROOT / "urdf" / "icub25.urdf"
SEA_SIM = ROOT / "target" / "release" / "sea-sim"
#: Contacts expected with both foot boxes flat on the floor (4 box corners each).
EXPECTED_CONTACTS = 8
#: Steps of settling before timing, so the soft contacts have built up [steps of 1 ms].
SETTLING_STEPS = 300
INTEGRATORS = {
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
}


class StandingMujoco:
    """The iCub in MuJoCo standing on both feet, gravity compensated, and a snapshot of that
    state to restart every timed batch from."""

    def __init__(self) -> None:
        scenario = sm.Scenario.load(
            mujoco_balance.SCENARIO,
            {"robot.contacts": mujoco_balance.FEET, "robot.initial_posture": "two_feet"},
        )
        joints = scenario.model.joint_names
        self.model = mujoco_balance.mujoco_model(URDF, joints)
        self.data = mujoco.MjData(self.model)
        q0 = np.array(scenario.initial_state[: scenario.model.nq])
        self.states = mujoco_balance.StateMap.of(self.model, joints)
        self.states.set_from_ours(self.data, q0)
        self.actuators = np.array([self.model.actuator(name).id for name in joints])
        # The example's rigid momentum controller holds the robot standing (a joint PD alone
        # does not: the feet carry the weight through the floating base).
        self.controller = sm.Controller(
            scenario.model,
            mujoco_balance.FEET,
            q0,
            actuators={"kind": "rigid"},
            reference={"com_origin": "initial", "com_amplitude": 0.0},
            kind="rigid",
            contact={"foot_x": list(mujoco_balance.FOOT_X), "foot_y": list(mujoco_balance.FOOT_Y)},
        )
        for _ in range(SETTLING_STEPS):
            self.hold_posture()
            mujoco.mj_step(self.model, self.data)
        if self.data.ncon != EXPECTED_CONTACTS:
            raise RuntimeError(f"{self.data.ncon} contacts after settling, expected {EXPECTED_CONTACTS}")
        spec = mujoco.mjtState.mjSTATE_INTEGRATION
        self.snapshot = np.empty(mujoco.mj_stateSize(self.model, spec))
        mujoco.mj_getState(self.model, self.data, self.snapshot, spec)

    def hold_posture(self) -> None:
        """One controller tick at the current state; its joint torques go to the actuators."""
        out = self.controller.tick(self.data.time, self.states.to_ours(self.data))
        self.data.ctrl[self.actuators] = out.input

    def restore(self) -> None:
        """Back to the settled standing state."""
        mujoco.mj_setState(self.model, self.data, self.snapshot, mujoco.mjtState.mjSTATE_INTEGRATION)
        mujoco.mj_forward(self.model, self.data)

    def step_us(self, integrator: str, batches: int, steps: int) -> float:
        """Median over ``batches`` of the mean microseconds of one ``mj_step``, each batch
        ``steps`` steps from the standing snapshot, the posture held. Only ``mj_step`` is
        timed (the holding torques are computed between the timed calls)."""
        self.model.opt.integrator = INTEGRATORS[integrator]
        means = []
        for _ in range(batches + 1):  # the first batch warms up
            self.restore()
            elapsed = 0.0
            for _ in range(steps):
                self.hold_posture()
                start = time.perf_counter()
                mujoco.mj_step(self.model, self.data)
                elapsed += time.perf_counter() - start
            means.append(elapsed * 1e6 / steps)
            if self.data.ncon != EXPECTED_CONTACTS:
                raise RuntimeError(f"{integrator}: {self.data.ncon} contacts after a batch")
        return statistics.median(means[1:])


def cpu_model() -> str:
    """The CPU's model name as ``lscpu`` gives it (``/proc/cpuinfo``), else the platform's."""
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def sea_sim_figures(binary: pathlib.Path, batches: int) -> dict:
    """``sea-sim bench --json`` on the iCub, run by ``binary``."""
    if not binary.exists():
        raise SystemExit(f"{binary} missing: cargo build --release -p sea_sim --bin sea-sim")
    command = [str(binary), "bench", "--urdf", str(URDF), "--batches", str(batches), "--json"]
    return json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)


#: (label, our key, scale to microseconds, MuJoCo steps it is compared with).
RATIOS = [
    ("one implicit SEA step (ROS2, 1 ms) / mj_step", "sim_step_us", 1.0, 1),
    ("controller tick, two feet / mj_step", "controller_tick_us", 1.0, 1),
    ("tick with Clarabel every tick / mj_step", "controller_tick_clarabel_us", 1.0, 1),
    ("tick with the active set every tick / mj_step", "controller_tick_active_set_us", 1.0, 1),
    ("closed loop, 1 simulated s at 1 kHz / 1000 mj_step", "closed_loop_second_ms", 1e3, 1000),
    ("closed loop, 1 simulated s multi-rate 100 Hz / 1 kHz / 1000 mj_step", "closed_loop_second_multi_rate_ms", 1e3, 1000),
]


def medians(runs: list[dict]) -> dict:
    """The median over ``runs`` of every numeric figure of ``sea-sim bench --json``."""
    return {
        key: statistics.median(run[key] for run in runs)
        for key, value in runs[0].items()
        if isinstance(value, (int, float)) and key != "nv"
    }


def measure(runs: int, batches: int, steps: int, binaries: list[pathlib.Path]) -> dict:
    """Alternating runs of MuJoCo and of each binary; the median of each figure over the runs.
    ``ours`` holds the first binary's medians, ``binaries`` every binary's."""
    standing = StandingMujoco()
    mujoco_runs: dict[str, list[float]] = {name: [] for name in INTEGRATORS}
    ours_runs: dict[str, list[dict]] = {str(binary): [] for binary in binaries}
    for _ in range(runs):
        for name in INTEGRATORS:
            mujoco_runs[name].append(standing.step_us(name, batches, steps))
        for binary in binaries:
            ours_runs[str(binary)].append(sea_sim_figures(binary, batches))
    per_binary = {binary: medians(figures) for binary, figures in ours_runs.items()}
    mj = {name: statistics.median(values) for name, values in mujoco_runs.items()}
    return {
        "mujoco_step_us": mj,
        "ours": per_binary[str(binaries[0])],
        "binaries": per_binary,
        "runs": {"mujoco": mujoco_runs, "ours": ours_runs},
    }


def table(result: dict, ours: dict, title: str) -> str:
    """The side-by-side table of one binary (``ours``, its medians): our figure, MuJoCo's
    (Euler, implicitfast) and the ratios, under a header naming the CPU."""
    mj = result["mujoco_step_us"]
    lines = [
        f"{title} on {result['machine']['cpu']}",
        f"MuJoCo {mujoco.__version__} mj_step on the standing iCub, {EXPECTED_CONTACTS} contacts: "
        f"Euler {mj['euler']:.1f} us, implicitfast {mj['implicitfast']:.1f} us",
        f"{'figure':<54}{'ours [us]':>12}{'/ Euler':>10}{'/ implicitfast':>16}",
    ]
    for label, key, scale, steps in RATIOS:
        if key not in ours:
            lines.append(f"{label:<54}{'missing':>12}")
            continue
        value = ours[key] * scale
        lines.append(
            f"{label:<54}{value:12.1f}{value / (steps * mj['euler']):10.2f}"
            f"{value / (steps * mj['implicitfast']):16.2f}"
        )
    if "closed_loop_second_continuous_ms" in ours and "closed_loop_second_ms" in ours:
        ratio = ours["closed_loop_second_continuous_ms"] / ours["closed_loop_second_ms"]
        lines.append(f"continuous-time closed loop / 1 kHz zero-order hold: {ratio:.2f}")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="alternating runs of both sides")
    parser.add_argument("--batches", type=int, default=31, help="timed batches per figure")
    parser.add_argument("--steps", type=int, default=500, help="mj_step calls per batch")
    parser.add_argument("--json", type=pathlib.Path, help="also write the figures as JSON")
    parser.add_argument(
        "--sea-sim",
        type=pathlib.Path,
        action="append",
        help="a sea-sim binary to time (repeat to compare builds in one run; "
        "default target/release/sea-sim)",
    )
    args = parser.parse_args()
    binaries = args.sea_sim or [SEA_SIM]
    result = measure(args.runs, args.batches, args.steps, binaries)
    result["machine"] = {
        "platform": platform.platform(),
        "processor": platform.processor(),
        "cpu": cpu_model(),
    }
    print("\n\n".join(table(result, result["binaries"][str(b)], str(b)) for b in binaries))
    if args.json:
        args.json.write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
