"""The compiled modules side by side, in one process: the wheel's two modules
(``sea_momentum._native``, the x86-64 baseline, and ``sea_momentum._native_v3``, x86-64-v3) and,
with ``--native PATH``, a native build of the same sources (``_native.abi3.so`` of ``pip install
.``, loaded from its file), timed in interleaved batches so that the load of a shared machine
falls on all alike, on the iCub (``urdf/icub25.urdf``):

- ``inverse_dynamics_us``: one ``Model.inverse_dynamics`` call (RNEA, from Python);
- ``plant_step_us``: one ``Plant.step`` (ROS2, 1 ms, elastic joints, both feet);
- ``tracking_second_ms``: one simulated second of ``scenarios/paper/tracking.toml`` (the closed
  loop in Rust, the controller at every integrator stage, plant step 0.25 ms).

Each figure is the median over ``--batches`` batch means. Prints one JSON object per module
(with the CPU's model and the module's file)::

    python benchmarks/native_modules.py --native /path/to/native/_native.abi3.so
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import os
import pathlib
import platform
import statistics
import subprocess
import time
from types import ModuleType
from typing import Callable

import numpy as np

# The real baseline module under its name (not the x86-64-v3 one registered in its place).
os.environ["SEA_MOMENTUM_NATIVE"] = "baseline"
import sea_momentum  # noqa: E402,F401

ROOT = pathlib.Path(__file__).resolve().parents[1]
URDF = ROOT / "urdf" / "icub25.urdf"
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"


def cpu_model() -> str:
    """``lscpu``'s "Model name", else the platform's processor."""
    try:
        listing = subprocess.run(["lscpu"], check=True, capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return platform.processor() or "unknown CPU"
    names = [line.split(":", 1)[1].strip() for line in listing.splitlines() if line.strip().startswith("Model name:")]
    return names[0] if names else platform.processor() or "unknown CPU"


def load_native(path: pathlib.Path) -> ModuleType:
    """The extension module at ``path`` (a ``_native`` build), loaded under a name of its own."""
    spec = importlib.util.spec_from_file_location("sea_native_reference._native", path)
    if spec is None or spec.loader is None:
        raise SystemExit(f"{path}: not an extension module")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def workloads(module: ModuleType, duration_s: float) -> dict[str, tuple[Callable[[], object], int]]:
    """The three calls of the module doc on ``module``, each with its calls per batch."""
    model = module.Model.from_urdf(str(URDF), joints=list(module.ICUB25_JOINTS))
    q = model.neutral()
    rng = np.random.default_rng(0)
    nu = rng.normal(size=model.nv) * 0.1
    nudot = rng.normal(size=model.nv)
    plant = module.Plant(model, actuator="elastic", contacts=["l_sole", "r_sole"], contact_q=q)
    x = plant.make_state(q)
    u = np.zeros(model.n_joints)
    overrides = {"simulation.duration_s": duration_s}
    return {
        "inverse_dynamics_us": (lambda: model.inverse_dynamics(q, nu, nudot), 2000),
        "plant_step_us": (lambda: plant.step(x, u, 1e-3), 200),
        "tracking_second_ms": (lambda: module.run_scenario_native(str(TRACKING), overrides), 1),
    }


def measure(modules: dict[str, ModuleType], batches: int, duration_s: float) -> dict[str, dict[str, float]]:
    """Median batch means of every workload of every module, batches interleaved."""
    loads = {name: workloads(module, duration_s) for name, module in modules.items()}
    means: dict[str, dict[str, list[float]]] = {name: {key: [] for key in load} for name, load in loads.items()}
    for batch in range(batches + 1):
        for name, load in loads.items():
            for key, (call, calls) in load.items():
                start = time.perf_counter()
                for _ in range(calls):
                    call()
                if batch > 0:
                    means[name][key].append((time.perf_counter() - start) / calls * 1e6)
    scale = {"tracking_second_ms": 1e-3 / duration_s}
    return {name: {key: statistics.median(values) * scale.get(key, 1.0) for key, values in figures.items()}
            for name, figures in means.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batches", type=int, default=15, help="timed batches per figure")
    parser.add_argument("--duration", type=float, default=1.0, help="simulated seconds per tracking run")
    parser.add_argument("--native", type=pathlib.Path, help="a native build's _native.abi3.so to time beside")
    args = parser.parse_args()
    modules = {"baseline": importlib.import_module("sea_momentum._native")}
    if importlib.util.find_spec("sea_momentum._native_v3") is not None:
        modules["x86-64-v3"] = importlib.import_module("sea_momentum._native_v3")
    if args.native is not None:
        modules["native"] = load_native(args.native)
    for name, figures in measure(modules, args.batches, args.duration).items():
        print(json.dumps({"module": name, "module_file": modules[name].__file__, "cpu": cpu_model(),
                          "python": platform.python_version(), **figures}))


if __name__ == "__main__":
    main()
