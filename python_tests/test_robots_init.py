"""`sea-sim init` from Python (``sea_momentum.init_scenario``): robots the program has never
seen, set up from their URDF and two contacts and balanced on two feet for 5 s with the CoM
sinusoid (1 cm, 0.2 Hz): the CoM error rms stays below 5 mm. Each robot is set up and run once,
in a module fixture (about a second of wall time each); the shipped Talos scenario is run as
committed. Marked ``robots``."""

import importlib.metadata
import os
import pathlib
import subprocess
import sys

import pytest

import sea_momentum as sm
from sea_momentum import pictures

ROOT = pathlib.Path(__file__).resolve().parents[1]
RMS_BOUND_M = 5e-3

pytestmark = pytest.mark.robots


def installed_file(package: str, suffix: str) -> pathlib.Path:
    """The file of the PyPI package ``package`` whose path ends with ``suffix``."""
    for f in importlib.metadata.files(package) or []:
        path = pathlib.Path(str(f.locate())).resolve()
        if path.as_posix().endswith(suffix):
            return path
    pytest.fail(f"{package} has no file {suffix}")


def example_robot_data_share() -> pathlib.Path:
    """The ``share`` folder holding the package ``example-robot-data`` (ROS layout)."""
    talos = "share/example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    return installed_file("example-robot-data", talos).parents[4]


# (name, URDF, contacts): G1 has no sole frames, its soles are four collision spheres of
# radius 5 mm, 30 mm under each ankle roll link; Romeo (the small variant, 31 joints) has sole
# frames and COLLADA foot collision meshes; the iCub of icub-models has sole frames.
ROBOTS = [
    (
        "g1",
        "package://example-robot-data/robots/g1_description/urdf/g1_29dof_rev_1_0.urdf",
        ("left_ankle_roll_link:0,0,-0.035", "right_ankle_roll_link:0,0,-0.035"),
    ),
    (
        "romeo",
        "package://example-robot-data/robots/romeo_description/urdf/romeo_small.urdf",
        ("l_sole", "r_sole"),
    ),
    ("icub_models", "iCubGazeboV2_5/model.urdf", ("l_sole", "r_sole")),
]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Each robot's init report and run summary."""
    package_dirs = [str(example_robot_data_share())]
    icub_robots = installed_file("icub-models", "iCubGazeboV2_5/model.urdf").parents[1]
    out = tmp_path_factory.mktemp("robots")
    results = {}
    for name, urdf, contacts in ROBOTS:
        urdf = urdf if urdf.startswith("package://") else str(icub_robots / urdf)
        scenario = out / f"{name}.toml"
        report = sm.init_scenario(urdf, contacts, scenario, package_dirs=package_dirs)
        results[name] = (report, sm.run_scenario(scenario).summary)
    return results


@pytest.mark.parametrize("name", [robot[0] for robot in ROBOTS])
def test_a_new_robot_balances_on_two_feet(runs, name):
    report, summary = runs[name]
    assert report["measured"] and report["residual"] < 1e-6, report
    assert summary.status == "completed", summary
    assert summary.com_error_rms_m < RMS_BOUND_M, summary


def test_the_shipped_talos_scenario_balances(monkeypatch):
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(example_robot_data_share()))
    summary = sm.run_scenario(ROOT / "scenarios" / "robots" / "talos_two_feet.toml").summary
    assert summary.status == "completed", summary
    assert summary.duration_s == 5.0
    assert summary.com_error_rms_m < RMS_BOUND_M, summary


def test_the_pictures_find_the_urdf_of_a_robot_description(monkeypatch, tmp_path):
    """The Talos scenario names its URDF in ``[robot.description]`` as a ``package://`` URI:
    the pictures find it as the run does."""
    share = example_robot_data_share()
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(share))
    scenario = ROOT / "scenarios" / "robots" / "talos_two_feet.toml"
    urdf = sm._native.scenario_urdf(scenario)
    assert urdf.resolve() == share / "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    result = sm.run_scenario(scenario, {"simulation.duration_s": 0.02})
    written = pictures.scenario_pictures(scenario, result, tmp_path, "talos", animation_frames=2)
    assert [p.name for p in written] == ["talos_strip.png", "talos.gif"]
    assert all(p.stat().st_size > 10_000 for p in written)


def test_package_uris_resolve_in_the_interpreters_cmeel_prefix_without_virtual_env(tmp_path):
    """The way IDEs, Jupyter kernels and cron start Python (no ``activate``): no VIRTUAL_ENV nor
    ROS variables; the shipped Talos scenario's ``package://example-robot-data/...`` URDF is
    found in the running interpreter's own cmeel prefix (its ``sys.path``)."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("VIRTUAL_ENV", "ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH", "CMAKE_PREFIX_PATH")}
    scenario = ROOT / "scenarios" / "robots" / "talos_two_feet.toml"
    code = f"import sea_momentum; print(sea_momentum._native.scenario_urdf({str(scenario)!r}))"
    result = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    found = pathlib.Path(result.stdout.strip()).resolve()
    expected = example_robot_data_share() / "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"
    assert found == expected.resolve()
