"""The distributable wheel (``scripts/build_wheel.sh``), as a user meets it: abi3 and manylinux,
the baseline module and (on x86-64) the x86-64-v3 one, installed into a fresh virtual
environment that has numpy alone; there ``import sea_momentum`` and a short run of the shipped
tracking scenario work, the x86-64-v3 module is chosen where the CPU has its features and the
baseline where ``SEA_MOMENTUM_NATIVE=baseline`` asks for it, the run the same to rounding as in
the test environment, and
the figures say which extra to install.

The wheel is ``$SEA_WHEEL``: the portable one, built by scripts/build_wheel.sh and installed into
.venv when the tests run as ``SEA_INSTALL=wheel bash scripts/run_tests.sh`` (two more full builds
of the extension, one per module: too long for CI's budget). Without it (CI), the wheel is
``maturin build --release`` of the sources, which reuses the native build of the test
environment: one module, built for this CPU, so the checks of the second module and of the
emulated older CPUs are skipped and the rest (abi3, numpy alone, the run, the extras' message,
the module choice's errors) run. The fresh environment gets numpy from the package index."""

from __future__ import annotations

import importlib.util
import json
import os
import pathlib
import platform
import re
import shutil
import subprocess
import sys
import zipfile

import pytest

import sea_momentum as sm

ROOT = pathlib.Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
#: Simulated seconds of the tracking scenario in the fresh environment (two runs).
DURATION_S = 1.0
#: The two modules' runs differ by the fused multiply-adds' rounding only.
RELATIVE_TOLERANCE = 1e-6

#: Run in the fresh environment: which module, what is installed, the run's summary, and the
#: figures' error without matplotlib.
PROBE = """
import importlib.util, json, pathlib, sys
import sea_momentum as sm
from sea_momentum.paper import reproduce
result = sm.run_scenario(sys.argv[1], {"simulation.duration_s": float(sys.argv[2])})
try:
    reproduce(pathlib.Path(sys.argv[1]).parent, pathlib.Path("out"), 0.1)
    plots_error = None
except ImportError as error:
    plots_error = str(error)
print(json.dumps({
    "native_module": sm.NATIVE_MODULE,
    "module_file": sm._native.__file__,
    "cpu_supports_x86_64_v3": sm._native.cpu_supports_x86_64_v3(),
    "matplotlib": importlib.util.find_spec("matplotlib") is not None,
    "status": result.summary.status,
    "com_error_rms_m": result.summary.com_error_rms_m,
    "com_final": result.com[-1].tolist(),
    "plots_error": plots_error,
}))
"""


#: Whether the wheel under test is the portable one of scripts/build_wheel.sh.
PORTABLE = bool(os.environ.get("SEA_WHEEL"))


def wheel_path(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """``$SEA_WHEEL``, else a wheel of the native build (``maturin build --release``)."""
    given = os.environ.get("SEA_WHEEL")
    if given:
        return pathlib.Path(given)
    out = tmp_path_factory.mktemp("dist")
    command = [sys.executable, "-m", "maturin", "build", "--release", "--quiet", "--out", str(out)]
    build = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=3600)
    assert build.returncode == 0, build.stdout[-3000:] + build.stderr[-3000:]
    (wheel,) = out.glob("sea_momentum-*.whl")
    return wheel


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    path = wheel_path(tmp_path_factory)
    assert path.is_file(), path
    return path


@pytest.fixture(scope="module")
def fresh_python(wheel, tmp_path_factory):
    """The interpreter of a new virtual environment holding the wheel and numpy alone."""
    venv = tmp_path_factory.mktemp("fresh") / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    python = venv / "bin" / "python"
    install = subprocess.run(
        [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check", str(wheel)],
        capture_output=True, text=True, timeout=900)
    assert install.returncode == 0, install.stdout + install.stderr
    return python


def probe(python: pathlib.Path, cwd: pathlib.Path, **env: str) -> dict:
    """Runs ``PROBE`` in ``python`` from ``cwd`` (not the repository: the installed package is
    imported) with the extra environment variables ``env``; returns its JSON."""
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "SEA_MOMENTUM_NATIVE")}
    environment.update(env)
    result = subprocess.run([str(python), "-c", PROBE, str(TRACKING), str(DURATION_S)], cwd=cwd,
                            env=environment, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout + result.stderr
    return json.loads(result.stdout.strip().splitlines()[-1])


def test_the_wheel_is_abi3_manylinux_with_both_modules(wheel):
    name = wheel.name
    assert name.startswith(f"sea_momentum-{sm.__version__}-cp39-abi3-"), name
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
    assert "sea_momentum/_native.abi3.so" in names or sys.platform != "linux", sorted(names)
    if platform.machine() == "x86_64":
        assert "manylinux" in name and name.endswith("_x86_64.whl"), name
        assert ("sea_momentum/_native_v3.abi3.so" in names) == PORTABLE, sorted(names)
    assert "sea_momentum/_native.pyi" in names and "sea_momentum/py.typed" in names


@pytest.mark.skipif(not PORTABLE, reason="the wheel of the native build links against this machine's glibc")
def test_the_portable_wheel_keeps_its_manylinux_promise(wheel, tmp_path):
    """Where ziglang is installed, scripts/build_wheel.sh links with zig against glibc 2.17 and
    the tag says manylinux2014; whatever the tag's glibc, no symbol of either module asks for a
    newer one (their dynamic symbols, read with ``objdump -T``)."""
    tag = re.search(r"manylinux_(\d+)_(\d+)_x86_64", wheel.name)
    assert tag, wheel.name
    promised = (int(tag.group(1)), int(tag.group(2)))
    if importlib.util.find_spec("ziglang") is not None:
        assert promised == (2, 17), wheel.name
    objdump = shutil.which("objdump")
    if objdump is None:
        pytest.skip("objdump (binutils) is not installed")
    with zipfile.ZipFile(wheel) as archive:
        modules = [n for n in archive.namelist() if n.endswith(".abi3.so")]
        archive.extractall(tmp_path, modules)
    for module in modules:
        symbols = subprocess.run([objdump, "-T", str(tmp_path / module)], capture_output=True,
                                 text=True, check=True, timeout=120).stdout
        versions = {tuple(int(part) for part in v.split(".")) for v in re.findall(r"GLIBC_(\d+(?:\.\d+)*)", symbols)}
        assert versions and max(versions) <= promised, (module, wheel.name, sorted(versions)[-3:])


def test_the_wheel_runs_a_scenario_with_numpy_alone(fresh_python, tmp_path):
    auto = probe(fresh_python, tmp_path)
    baseline = probe(fresh_python, tmp_path, SEA_MOMENTUM_NATIVE="baseline")
    assert not auto["matplotlib"]
    for run in (auto, baseline):
        assert str(tmp_path) not in run["module_file"] and "site-packages" in run["module_file"], run
        assert run["status"] == "completed", run
        assert "sea-momentum[plots]" in run["plots_error"], run
    has_v3 = PORTABLE and platform.machine() == "x86_64"
    expected = "_native_v3" if has_v3 and auto["cpu_supports_x86_64_v3"] else "_native"
    assert auto["native_module"] == expected, auto
    assert auto["module_file"].endswith(f"{expected}.abi3.so"), auto
    assert baseline["native_module"] == "_native", baseline
    # The same run here, in the test environment's module (run_tests.sh: the same wheel; else a
    # native build of the same sources).
    here = sm.run_scenario(TRACKING, {"simulation.duration_s": DURATION_S})
    for run in (auto, baseline):
        assert run["com_error_rms_m"] == pytest.approx(here.summary.com_error_rms_m, rel=RELATIVE_TOLERANCE)
        assert run["com_final"] == pytest.approx(here.com[-1].tolist(), rel=RELATIVE_TOLERANCE)


def test_an_unknown_module_choice_is_an_error_naming_the_choices(fresh_python, tmp_path):
    result = subprocess.run([str(fresh_python), "-c", "import sea_momentum"], cwd=tmp_path,
                            env={**os.environ, "SEA_MOMENTUM_NATIVE": "fast"},
                            capture_output=True, text=True, timeout=120)
    assert result.returncode != 0
    assert "SEA_MOMENTUM_NATIVE='fast' is not one of auto, baseline" in result.stderr, result.stderr


#: Emulated CPUs (QEMU's names) and the module expected on each: Nehalem (2008) has SSE4.2 but
#: no AVX, Haswell (2013) is the first x86-64-v3 CPU.
EMULATED_CPUS = [("Nehalem", "_native"), ("Haswell", "_native_v3")]


@pytest.mark.skipif(not PORTABLE, reason="needs the portable wheel (SEA_INSTALL=wheel run_tests.sh)")
@pytest.mark.skipif(platform.machine() != "x86_64" or shutil.which("qemu-x86_64") is None,
                    reason="needs qemu-x86_64 (Debian: apt-get install qemu-user) on x86-64")
@pytest.mark.parametrize(("cpu", "expected"), EMULATED_CPUS)
def test_an_older_cpu_gets_the_baseline_module(fresh_python, tmp_path, cpu, expected):
    """The wheel on an emulated CPU (QEMU user mode): the module it chooses runs a short
    scenario there; on the pre-AVX CPU the x86-64-v3 module itself stops on an illegal
    instruction, which is what the choice avoids."""
    code = ("import sys, sea_momentum as sm; r = sm.run_scenario(sys.argv[1], {'simulation.duration_s': 0.05}); "
            "print(sm.NATIVE_MODULE, r.summary.status)")
    command = ["qemu-x86_64", "-cpu", cpu, str(fresh_python), "-c", code, str(TRACKING)]
    result = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.split() == [expected, "completed"], result.stdout
    if expected == "_native":
        forced = ("import sea_momentum._native_v3 as v3; "
                  f"model = v3.Model.from_urdf({str(ROOT / 'urdf' / 'icub25.urdf')!r}); "
                  "model.mass_matrix(model.neutral())")
        crash = subprocess.run(["qemu-x86_64", "-cpu", cpu, str(fresh_python), "-c", forced],
                               cwd=tmp_path, capture_output=True, text=True, timeout=600)
        assert crash.returncode != 0 and "Illegal instruction" in crash.stderr, crash.stderr[-2000:]
