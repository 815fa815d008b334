"""sea-momentum beside MuJoCo, measured in one run on the same robot.

MuJoCo compiles ``urdf/icub25.urdf`` with a free base, a floor plane and massless foot boxes of
the controller's foot rectangle, standing on both feet (4 contacts per box, 8 in all), held by
the rigid momentum controller (as in ``examples/mujoco_balance.py``), in two forms
(``examples/mujoco_icub.py``):
- "example": the model of ``examples/mujoco_balance.py`` (``fusestatic`` false: the static
  bodies kept, 42 bodies, the foot boxes on the sole frames);
- "users": as its users would compile it: ``fusestatic`` true (MuJoCo's default for a URDF: the
  static sole frames, neck and wrist links fused into their parents, 27 bodies), the foot boxes
  on the foot links at the sole's pose, contacts active.
Their ``mj_step`` (Euler and implicitfast, 1 ms) is timed beside ``target/release/sea-sim bench
--json``, which runs as a subprocess in the same run; they alternate ``--runs`` times and each
figure is the median of the runs (each run's figure is itself a median of batch means).

Ratios printed (below 1: ours is faster):
- one implicit SEA step (ROS2, 25 motor states, two rigid feet) / ``mj_step``;
- controller tick (two feet; model terms, QP, SEA map) / ``mj_step``;
- the same tick with Clarabel on every tick / ``mj_step``;
- the same tick with the active-set QP solver on every tick / ``mj_step``;
- one simulated second of the closed loop at 1 kHz / 1000 ``mj_step``;
- one simulated second of the multi-rate loop (QP at 100 Hz, joint loops at 1 kHz) / 1000 ``mj_step``;
- one simulated second of walking (``scenarios/walking/walk_fast.toml``: 50 steps at 0.3 m/s and
  the stop, the same rates, feet on the ground, run whole by ``sea-sim run`` and its wall time
  divided by its simulated time) / 1000 ``mj_step`` (the standing model above: MuJoCo does not
  walk, its step with its 8 foot contacts is the reference), with the plant's step at 1 ms
  (1000 plant steps per second, as the closed-loop seconds above and the 1000 ``mj_step``) and
  at the scenario's 0.25 ms;
- the continuous-time closed loop (controller at every integrator stage) / the 1 kHz one.

Our own plant step with unilateral contacts will be timed beside them by
``time_our_unilateral_step`` (the hook; ``our_unilateral_step`` returns None until
``sea_momentum.Plant`` has a unilateral contact model).

Run: ``python benchmarks/peers.py [--runs 3] [--batches 31] [--steps 500] [--json FILE]
[--sea-sim PATH ...] [--mujoco-only]`` (needs ``pip install mujoco`` and ``cargo build --release -p sea_sim --bin
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
import tempfile
import time
from typing import Callable

import mujoco
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))
import mujoco_icub  # noqa: E402  (the MuJoCo model of the iCub, one source of truth)

import sea_momentum as sm  # noqa: E402

URDF = ROOT / "urdf" / "icub25.urdf"
SEA_SIM = ROOT / "target" / "release" / "sea-sim"
#: Contacts expected with both foot boxes flat on the floor (4 box corners each).
EXPECTED_CONTACTS = 8
#: Steps of settling before timing, so the soft contacts have built up [steps of 1 ms].
SETTLING_STEPS = 300
#: The MuJoCo models timed side by side: the example's, and the one its users would compile.
MODELS = {
    "example": mujoco_icub.ModelOptions(),
    "users": mujoco_icub.ModelOptions(fusestatic=True),
}
INTEGRATORS = {
    "euler": mujoco.mjtIntegrator.mjINT_EULER,
    "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST,
}


class StandingMujoco:
    """The iCub in MuJoCo standing on both feet, gravity compensated, and a snapshot of that
    state to restart every timed batch from."""

    def __init__(self, options: mujoco_icub.ModelOptions) -> None:
        scenario = sm.Scenario.load(
            mujoco_icub.SCENARIO,
            {"robot.contacts": mujoco_icub.FEET, "robot.initial_posture": "two_feet"},
        )
        joints = scenario.model.joint_names
        self.model = mujoco_icub.mujoco_model(URDF, joints, options)
        self.data = mujoco.MjData(self.model)
        q0 = np.array(scenario.initial_state[: scenario.model.nq])
        self.states = mujoco_icub.StateMap.of(self.model, joints)
        self.states.set_from_ours(self.data, q0)
        self.actuators = np.array([self.model.actuator(name).id for name in joints])
        # The example's rigid momentum controller holds the robot standing (a joint PD alone
        # does not: the feet carry the weight through the floating base).
        self.controller = sm.Controller(
            scenario.model,
            mujoco_icub.FEET,
            q0,
            actuators={"kind": "rigid"},
            reference={"com_origin": "initial", "com_amplitude": 0.0},
            kind="rigid",
            contact={"foot_x": list(mujoco_icub.FOOT_X), "foot_y": list(mujoco_icub.FOOT_Y)},
        )
        for _ in range(SETTLING_STEPS):
            self.hold_posture()
            mujoco.mj_step(self.model, self.data)
        if self.data.ncon != EXPECTED_CONTACTS:
            raise RuntimeError(f"{self.data.ncon} contacts after settling, expected {EXPECTED_CONTACTS}")
        spec = mujoco.mjtState.mjSTATE_INTEGRATION
        self.snapshot = np.empty(mujoco.mj_stateSize(self.model, spec))
        mujoco.mj_getState(self.model, self.data, self.snapshot, spec)

    def describe(self) -> str:
        """The model's size: bodies and geoms."""
        return f"{self.model.nbody} bodies, {self.model.ngeom} geoms"

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
    """The CPU's model name: ``lscpu``'s "Model name", else ``/proc/cpuinfo``'s, else the
    platform's."""
    try:
        listing = subprocess.run(["lscpu"], check=True, capture_output=True, text=True).stdout
        for line in listing.splitlines():
            if line.strip().startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except (OSError, subprocess.CalledProcessError):
        pass
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


#: The walk timed for ``walking_second_ms`` (whole: 22 simulated seconds).
WALK = ROOT / "scenarios" / "walking" / "walk_fast.toml"
#: The plant steps the walk is timed at [s] and their figures' keys: 1 ms as the closed-loop
#: seconds of ``sea-sim bench`` (1000 plant steps a second, like 1000 ``mj_step``), and the
#: scenario's own 0.25 ms. The walk's outcome is the same at both (docs/findings/walking_impacts.md).
WALK_PLANT_STEPS = {"walking_second_ms": 0.001, "walking_second_plant_025_ms": 0.00025}

#: (label, our key, scale to microseconds, MuJoCo steps it is compared with).
RATIOS = [
    ("one implicit SEA step (ROS2, 1 ms) / mj_step", "sim_step_us", 1.0, 1),
    ("the same step, 10 steps sharing W as scenarios step / mj_step", "sim_step_shared_w_us", 1.0, 1),
    ("the same step, feet on the ground (8 points) / mj_step", "sim_step_unilateral_us", 1.0, 1),
    ("the same, 10 steps sharing W as scenarios step / mj_step", "sim_step_unilateral_shared_w_us", 1.0, 1),
    ("controller tick, two feet / mj_step", "controller_tick_us", 1.0, 1),
    ("tick with Clarabel every tick / mj_step", "controller_tick_clarabel_us", 1.0, 1),
    ("tick with the active set every tick / mj_step", "controller_tick_active_set_us", 1.0, 1),
    ("closed loop, 1 simulated s at 1 kHz / 1000 mj_step", "closed_loop_second_ms", 1e3, 1000),
    ("closed loop, 1 simulated s multi-rate 100 Hz / 1 kHz / 1000 mj_step", "closed_loop_second_multi_rate_ms", 1e3, 1000),
    ("the same, feet on the ground / 1000 mj_step", "closed_loop_second_multi_rate_unilateral_ms", 1e3, 1000),
    ("walking (walk_fast, 0.3 m/s), 1 simulated s, plant step 1 ms / 1000 mj_step", "walking_second_ms", 1e3, 1000),
    ("the same walk, plant step 0.25 ms / 1000 mj_step", "walking_second_plant_025_ms", 1e3, 1000),
]


def walking_second_ms(binary: pathlib.Path, plant_dt: float) -> float:
    """Wall milliseconds per simulated second of ``WALK`` run by ``binary`` with the plant's step
    ``plant_dt`` (``sea-sim run``, no log; the summary's ``wall_time_s`` over its
    ``duration_s``: the closed loop alone, the scenario's loading not included). A walk that
    does not complete is an error naming how it ended."""
    with tempfile.TemporaryDirectory() as folder:
        summary_path = pathlib.Path(folder) / "summary.json"
        command = [str(binary), "run", str(WALK), "--summary", str(summary_path)]
        command += ["--set", f"plant.dt={plant_dt}"]
        subprocess.run(command, check=True, capture_output=True, text=True)
        summary = json.loads(summary_path.read_text())
    if summary["status"] != "completed":
        raise RuntimeError(f"{WALK} (plant.dt {plant_dt}): the walk ended {summary['status']}: {summary.get('reason')}")
    return summary["wall_time_s"] / summary["duration_s"] * 1e3


def medians(runs: list[dict]) -> dict:
    """The median over ``runs`` of every numeric figure of ``sea-sim bench --json``."""
    return {
        key: statistics.median(run[key] for run in runs)
        for key, value in runs[0].items()
        if isinstance(value, (int, float)) and key != "nv"
    }


def our_unilateral_step() -> Callable[[], object] | None:
    """Our plant's step with unilateral contacts on the standing iCub driven from Python, as a
    callable doing one 1 ms step from a standing state, for ``time_our_unilateral_step``: the
    push scenario's plant (8 points, joint stops), its step timed with the binding's overhead.
    The native figure without it is ``sea-sim bench``'s ``sim_step_unilateral_us``
    (``RATIOS``)."""
    scenario = sm.Scenario.load(ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml")
    plant, x = scenario.plant, scenario.initial_state
    u = np.zeros(plant.nu_input)
    return lambda: plant.step(x, u, 1e-3, "ros2")


def time_our_unilateral_step(step: Callable[[], object], batches: int, steps: int) -> float:
    """The hook where our unilateral-contact plant step is timed: median over ``batches`` of
    the mean microseconds of ``step()`` over ``steps`` calls (the first batch warms up), as
    ``StandingMujoco.step_us`` times ``mj_step``. ``step`` restores its own start state if it
    needs one; only its calls are timed."""
    means = []
    for _ in range(batches + 1):
        start = time.perf_counter()
        for _ in range(steps):
            step()
        means.append((time.perf_counter() - start) * 1e6 / steps)
    return statistics.median(means[1:])


def measure(
    runs: int,
    batches: int,
    steps: int,
    binaries: list[pathlib.Path],
    unilateral_step: Callable[[], object] | None = None,
) -> dict:
    """Alternating runs of each MuJoCo model, of each binary and of ``unilateral_step`` (if
    given); the median of each figure over the runs. ``mujoco_step_us`` is the example model's
    (``mujoco_step_us_by_model`` every model's), ``ours`` the first binary's medians,
    ``binaries`` every binary's, ``unilateral_step_us`` our unilateral step's (or None)."""
    standing = {name: StandingMujoco(options) for name, options in MODELS.items()}
    mujoco_runs = {model: {name: [] for name in INTEGRATORS} for model in MODELS}
    ours_runs: dict[str, list[dict]] = {str(binary): [] for binary in binaries}
    unilateral_runs: list[float] = []
    for _ in range(runs):
        for model, held in standing.items():
            for name in INTEGRATORS:
                mujoco_runs[model][name].append(held.step_us(name, batches, steps))
        for binary in binaries:
            figures = sea_sim_figures(binary, batches)
            for key, plant_dt in WALK_PLANT_STEPS.items():
                figures[key] = walking_second_ms(binary, plant_dt)
            ours_runs[str(binary)].append(figures)
        if unilateral_step is not None:
            unilateral_runs.append(time_our_unilateral_step(unilateral_step, batches, steps))
    per_binary = {binary: medians(figures) for binary, figures in ours_runs.items()}
    by_model = {
        model: {name: statistics.median(values) for name, values in figures.items()}
        for model, figures in mujoco_runs.items()
    }
    return {
        "mujoco_step_us": by_model["example"],
        "mujoco_step_us_by_model": by_model,
        "mujoco_models": {model: held.describe() for model, held in standing.items()},
        "ours": per_binary[str(binaries[0])] if binaries else {},
        "binaries": per_binary,
        "unilateral_step_us": statistics.median(unilateral_runs) if unilateral_runs else None,
        "runs": {"mujoco": mujoco_runs, "ours": ours_runs, "unilateral_step": unilateral_runs},
    }


def mujoco_table(result: dict) -> str:
    """The MuJoCo models side by side: bodies, contacts, ``mj_step`` Euler and implicitfast
    (medians), and our unilateral-contact plant step beside them once it exists."""
    lines = [
        f"MuJoCo {mujoco.__version__} mj_step on the standing iCub, {EXPECTED_CONTACTS} contacts, "
        f"on {result['machine']['cpu']} (medians of {len(result['runs']['mujoco']['example']['euler'])} runs)",
        f"{'model':<44}{'Euler [us]':>12}{'implicitfast [us]':>19}",
    ]
    for model, figures in result["mujoco_step_us_by_model"].items():
        label = f"{model}: {result['mujoco_models'][model]}"
        lines.append(f"{label:<44}{figures['euler']:12.1f}{figures['implicitfast']:19.1f}")
    unilateral = result["unilateral_step_us"]
    ours = "not yet (our_unilateral_step returns None)" if unilateral is None else f"{unilateral:.1f} us"
    lines.append(f"our plant step with unilateral contacts: {ours}")
    return "\n".join(lines)


def table(result: dict, ours: dict, title: str) -> str:
    """The side-by-side table of one binary (``ours``, its medians): our figure and the ratios
    to each MuJoCo model's ``mj_step`` (Euler, implicitfast), under a header naming the CPU."""
    models = result["mujoco_step_us_by_model"]
    columns = [(model, integrator) for model in models for integrator in INTEGRATORS]
    lines = [
        f"{title} on {result['machine']['cpu']}",
        f"{'figure':<54}{'ours [us]':>12}" + "".join(f"{'/ ' + m + ' ' + i:>24}" for m, i in columns),
    ]
    for label, key, scale, steps in RATIOS:
        if key not in ours:
            lines.append(f"{label:<54}{'missing':>12}")
            continue
        value = ours[key] * scale
        ratios = "".join(f"{value / (steps * models[m][i]):24.2f}" for m, i in columns)
        lines.append(f"{label:<54}{value:12.1f}{ratios}")
    if "closed_loop_second_continuous_ms" in ours and "closed_loop_second_ms" in ours:
        ratio = ours["closed_loop_second_continuous_ms"] / ours["closed_loop_second_ms"]
        lines.append(f"continuous-time closed loop / 1 kHz zero-order hold: {ratio:.2f}")
    return "\n".join(lines)


def main() -> None:
    """Times both sides, prints the tables and writes the JSON."""
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
    parser.add_argument("--mujoco-only", action="store_true", help="time MuJoCo only (no sea-sim)")
    args = parser.parse_args()
    binaries = [] if args.mujoco_only else (args.sea_sim or [SEA_SIM])
    result = measure(args.runs, args.batches, args.steps, binaries, our_unilateral_step())
    result["machine"] = {
        "platform": platform.platform(),
        "processor": platform.processor(),
        "cpu": cpu_model(),
    }
    print(mujoco_table(result))
    for binary in binaries:
        print("\n" + table(result, result["binaries"][str(binary)], str(binary)))
    if args.json:
        args.json.write_text(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
