"""Errors: one hierarchy (SeaError and its subclasses, also the matching built-in class), each
kind of failure raises its class with the key, element or path in the message and as an
attribute."""

import errno
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm
from sea_momentum import _native

ROOT = Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"


@pytest.mark.parametrize(
    "name, builtin",
    [
        ("ModelError", ValueError),
        ("ScenarioError", ValueError),
        ("SolverError", RuntimeError),
        ("SeaIOError", OSError),
    ],
)
def test_hierarchy(name, builtin):
    cls = getattr(sm, name)
    assert cls is getattr(_native, name), "re-exported from the native module"
    assert issubclass(cls, sm.SeaError) and issubclass(cls, builtin)
    assert name in sm.__all__
    assert cls.__module__ == "sea_momentum"
    assert cls.__doc__


def test_base_is_an_exception_only():
    assert issubclass(sm.SeaError, Exception)
    assert not issubclass(sm.SeaError, (ValueError, RuntimeError, OSError))
    assert "SeaError" in sm.__all__


def test_negative_postural_scale_names_its_key():
    with pytest.raises(sm.ScenarioError, match=r"controller\.postural_scale") as info:
        sm.run_scenario(TRACKING, {"controller.postural_scale": -1})
    assert info.value.key == "controller.postural_scale"
    assert "-1" in str(info.value)


def test_multi_rate_inner_rate_not_a_multiple_names_its_key():
    overrides = {"controller.sampling": "multi_rate", "controller.rate_hz": 100.0, "controller.inner_rate_hz": 1050.0}
    with pytest.raises(sm.ScenarioError, match="whole multiple") as info:
        sm.run_scenario(TRACKING, overrides)
    assert info.value.key == "controller.inner_rate_hz"


def test_negative_proportional_gain_names_the_proportional_gain():
    gains = [1.0, 1.0, -1.0, 1.0, 1.0, 1.0]
    with pytest.raises(sm.ScenarioError) as info:
        sm.run_scenario(TRACKING, {"controller.momentum_proportional": gains})
    assert info.value.key == "controller.momentum_proportional", str(info.value)


def test_type_error_names_the_key_not_the_value():
    with pytest.raises(sm.ScenarioError) as info:
        sm.run_scenario(TRACKING, {"controller.kind": 3})
    assert info.value.key == "controller.kind", str(info.value)
    assert "scenario key '3'" not in str(info.value)


def test_a_numpy_array_override_is_read_as_its_list():
    direction = sm.Scenario.load(TRACKING, {"reference.com_direction": np.array([0.0, 1.0, 0.0])})
    listed = sm.Scenario.load(TRACKING, {"reference.com_direction": [0.0, 1.0, 0.0]})
    assert np.allclose(direction.controller.com_reference(0.3), listed.controller.com_reference(0.3))
    with pytest.raises(sm.ScenarioError) as info:
        sm.Scenario.load(TRACKING, {"reference.com_direction": np.array([0.0, 1.0])})
    assert info.value.key == "reference.com_direction", str(info.value)


def test_a_single_folder_as_package_dirs_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match="package_dirs"):
        sm.run_scenario(TRACKING, {"simulation.duration_s": 0.002}, package_dirs="/tmp")


def test_a_package_dir_that_is_no_folder_is_a_value_error_naming_it(tmp_path):
    a_file = tmp_path / "file.txt"
    a_file.write_text("")
    for bad, why in ((tmp_path / "missing", "No such file"), (a_file, "a file")):
        with pytest.raises(ValueError, match=why) as run:
            sm.run_scenario(TRACKING, {"simulation.duration_s": 0.002}, package_dirs=[bad])
        assert run.value.argument == "package_dirs" and str(bad) in str(run.value)
        with pytest.raises(ValueError, match=why) as meshes:
            _native.link_meshes(str(ROOT / "urdf" / "icub25.urdf"), package_dirs=[bad])
        assert meshes.value.argument == "package_dirs"


def test_a_run_warns_of_the_urdf_elements_the_model_doubts(tmp_path):
    elbow = 'lower="0.2617993877991494" upper="1.8500490071139892"'
    text = (ROOT / "urdf" / "icub25.urdf").read_text()
    assert elbow in text
    urdf = tmp_path / "inverted.urdf"
    urdf.write_text(text.replace(elbow, 'lower="1.85" upper="0.26"'))
    inverted = {"simulation.duration_s": 0.002, "robot.urdf": str(urdf)}
    pattern = r"inverted\.urdf: joint 'l_elbow': .* taken as unlimited"
    with pytest.warns(UserWarning, match=pattern):
        sm.Scenario.load(TRACKING, inverted)
    with pytest.warns(UserWarning, match=pattern):
        sm.run_scenario(TRACKING, inverted)


def test_a_control_period_longer_than_the_run_names_the_rate():
    # A run of 0.05 s at 1 Hz would tick never and report the run completed.
    sampled = {"simulation.duration_s": 0.05, "controller.sampling": "zero_order_hold"}
    with pytest.raises(sm.ScenarioError) as info:
        sm.run_scenario(TRACKING, {**sampled, "controller.rate_hz": 1.0})
    assert info.value.key == "controller.rate_hz", str(info.value)


def test_an_empty_urdf_key_names_it():
    with pytest.raises(sm.ScenarioError) as info:
        _native.scenario_urdf(TRACKING, {"robot.urdf": ""})
    assert info.value.key == "robot.urdf", str(info.value)


def test_all_nan_initial_posture_names_the_key():
    with pytest.raises(sm.ScenarioError, match=r"robot\.initial_posture\[0\]"):
        sm.run_scenario(TRACKING, {"robot.initial_posture": [float("nan")] * 25})


def test_malformed_toml_names_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "x"\n[robot\nurdf = "x"\n')
    with pytest.raises(sm.ScenarioError, match="malformed TOML") as info:
        sm.run_scenario(bad)
    assert str(info.value).startswith(f"{bad}:2:"), str(info.value)


def test_a_bad_key_names_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[robot]\nurdf = "x.urdf"\n\n[simulation]\nduration_s = -1\n')
    with pytest.raises(sm.ScenarioError) as info:
        sm.run_scenario(bad)
    assert info.value.key == "simulation.duration_s"
    assert str(info.value).startswith(f"{bad}:5: scenario key"), str(info.value)


def test_missing_scenario_is_an_oserror_with_errno_and_filename(tmp_path):
    missing = tmp_path / "missing.toml"
    with pytest.raises(sm.SeaIOError) as info:
        sm.run_scenario(missing)
    assert isinstance(info.value, OSError)
    assert info.value.errno == errno.ENOENT
    assert info.value.filename == str(missing)
    assert info.value.strerror == "No such file or directory"
    with pytest.raises(sm.SeaIOError) as folder:
        sm.run_scenario(tmp_path)
    assert folder.value.errno == errno.EISDIR
    assert folder.value.filename == str(tmp_path)


def test_unparsable_urdf_names_the_file(tmp_path):
    path = tmp_path / "robot.urdf"
    path.write_text('<robot name="r">\n<link name="a">\n</robot>\n')
    with pytest.raises(sm.ModelError) as info:
        sm.Model.from_urdf(str(path))
    assert str(path) in str(info.value)


def test_bad_urdf_element_is_named(tmp_path):
    path = tmp_path / "robot.urdf"
    path.write_text(
        '<robot name="r"><link name="a"/><link name="b"/>'
        '<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        '<axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        "</robot>"
    )
    with pytest.raises(sm.ModelError) as info:
        sm.Model.from_urdf(str(path))
    assert info.value.element == "joint 'j'"
    assert info.value.filename == str(path)
    assert str(info.value).startswith(f"{path}: joint 'j': "), str(info.value)
    assert "zero axis" in str(info.value)


def test_missing_urdf_is_an_oserror(tmp_path):
    path = tmp_path / "nothing.urdf"
    with pytest.raises(sm.SeaIOError) as info:
        sm.Model.from_urdf(str(path))
    assert info.value.errno == errno.ENOENT and info.value.filename == str(path)


def test_unknown_frame_is_a_model_error():
    model = sm.Model.from_urdf(str(ROOT / "urdf" / "icub25.urdf"))
    with pytest.raises(sm.ModelError, match="no_such_frame"):
        model.frame_pose(model.neutral(), "no_such_frame")


def test_bad_arguments_are_plain_value_errors_naming_the_argument():
    model = sm.Model.from_urdf(str(ROOT / "urdf" / "icub25.urdf"))
    with pytest.raises(ValueError) as info:
        model.mass_matrix(np.zeros(3))
    assert not isinstance(info.value, sm.SeaError)
    assert info.value.argument == "q"
    assert "expected shape" in str(info.value)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_device_as_the_log_is_an_oserror_naming_it():
    """The MCAP writer seeks back over each chunk: a device is refused as the run starts."""
    overrides = {"simulation.duration_s": 0.05}
    with pytest.raises(OSError) as info:
        sm.run_scenario(TRACKING, overrides, mcap="/dev/full")
    assert isinstance(info.value, sm.SeaError)
    assert info.value.errno == errno.EINVAL, str(info.value)
    assert "must be a regular file" in info.value.strerror
    assert info.value.filename == "/dev/full"


FILE_SIZE_LIMIT = """
import errno, resource, signal, sys
import sea_momentum as sm
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (20000, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
try:
    sm.run_scenario(sys.argv[1], {"simulation.duration_s": 0.5}, mcap=sys.argv[2])
except sm.SeaIOError as e:
    print(e.errno, e.filename, e.strerror, sep="|")
"""


def test_a_write_refused_by_the_os_is_an_oserror_naming_the_file_and_the_earlier_log_stays(tmp_path):
    """A log that outgrows what the OS lets the process write (as a full disk would: the file
    size limit here, EFBIG) is a SeaIOError naming the path given, and an earlier file there
    is left as it was."""
    target = tmp_path / "run.mcap"
    target.write_bytes(b"an earlier log")
    out = subprocess.run(
        [sys.executable, "-c", FILE_SIZE_LIMIT, str(TRACKING), str(target)],
        capture_output=True, text=True, timeout=300, check=True,
    )
    code, filename, strerror = out.stdout.strip().split("|")
    assert int(code) == errno.EFBIG, out.stdout
    assert filename.startswith(str(target)), filename
    assert strerror == "File too large"
    assert target.read_bytes() == b"an earlier log"
    assert not (tmp_path / ".run.mcap.partial").exists()


# ---- sea_momentum.init_scenario (sea-sim init): bad input names the element, writes nothing ----

ICUB_SOLES = ("l_sole", "r_sole")
ONE_LEG_URDF = """<robot name="one_leg">
  <link name="base"><inertial><mass value="5"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="shin"><inertial><origin xyz="0 0 -0.2"/><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="toe_a"/><link name="toe_b"/>
  <joint name="knee" type="revolute"><parent link="base"/><child link="shin"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="2" effort="10" velocity="1"/></joint>
  <joint name="a" type="fixed"><parent link="shin"/><child link="toe_a"/>
    <origin xyz="0 0.05 -0.4"/></joint>
  <joint name="b" type="fixed"><parent link="shin"/><child link="toe_b"/>
    <origin xyz="0 -0.05 -0.4"/></joint>
</robot>"""


@pytest.mark.parametrize(
    "urdf, contacts, foot, named, argument",
    [
        ("icub", ("l_sloe", "r_sole"), None, "unknown frame 'l_sloe'", None),
        ("icub", ("nolink:0,0,0", "r_sole"), None, "unknown link 'nolink'", None),
        ("icub", ICUB_SOLES, (0.1, 0.0, -0.02, 0.02), "x0 < x1", "foot"),
        ("icub", ICUB_SOLES, (-1e300, 1e300, -1e300, 1e300), "within 1 m", "foot"),
        ("one_leg", ("toe_a", "toe_b"), (-0.05, 0.1, -0.02, 0.02), "cannot stand", None),
        ("package://no_such_robot/robots/robot.urdf", ICUB_SOLES, None, "no_such_robot", "urdf"),
        ("icub", ("l_sole", "r_ankle_2:0,0,1e"), None, "'1e' is not a finite number", None),
    ],
)
def test_init_refuses_bad_input_naming_the_element(tmp_path, urdf, contacts, foot, named, argument):
    """A bad argument (the foot, the URDF's path) is a ValueError naming it; what the robot's
    contacts cannot do is the written scenario's key's ScenarioError."""
    if urdf == "icub":
        urdf = str(ROOT / "urdf" / "icub25.urdf")
    elif urdf == "one_leg":
        (tmp_path / "one_leg.urdf").write_text(ONE_LEG_URDF)
        urdf = str(tmp_path / "one_leg.urdf")
    out = tmp_path / "out" / "scenario.toml"
    out.parent.mkdir()
    with pytest.raises(ValueError, match=named.replace("(", r"\(")) as refused:
        sm.init_scenario(urdf, contacts, out, foot=foot)
    if argument is None:
        assert isinstance(refused.value, sm.ScenarioError), refused.value
    else:
        assert not isinstance(refused.value, sm.ScenarioError), refused.value
        assert refused.value.argument == argument
    assert list(out.parent.iterdir()) == []


@pytest.mark.parametrize(
    "contacts, foot, argument",
    [
        (("l_sole", "r_sole", "root_link"), None, "contacts"),
        (("l_sole",), None, "contacts"),
        ("l_sole", None, "contacts"),
        (("l_sole", 3), None, "contacts"),
        (ICUB_SOLES, (0.1, 0.2, 0.3), "foot"),
    ],
)
def test_init_names_a_contacts_or_foot_argument_of_the_wrong_length(tmp_path, contacts, foot, argument):
    out = tmp_path / "scenario.toml"
    with pytest.raises(ValueError, match=f"^{argument}: expected ") as info:
        sm.init_scenario(str(ROOT / "urdf" / "icub25.urdf"), contacts, out, foot=foot)
    assert info.value.argument == argument, str(info.value)
    assert "got " in str(info.value)
    assert not out.exists()


PUSH = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"


@pytest.mark.parametrize(
    "field, value, key",
    [
        ("force", [1.0, float("nan"), 0.0], "disturbances[0].force"),
        ("torque", [float("inf"), 0.0, 0.0], "disturbances[0].torque"),
        ("start_s", -1.0, "disturbances[0].start_s"),
        ("start_s", float("nan"), "disturbances[0].start_s"),
        ("duration_s", -0.1, "disturbances[0].duration_s"),
        ("link", "no_such_link", "disturbances[0].link"),
        ("start_s", 1.0001, "disturbances[0].start_s"),  # not on the 0.25 ms plant step grid
    ],
)
def test_bad_disturbance_names_its_key(field, value, key):
    push = {"link": "root_link", "force": [1.0, 0.0, 0.0], "start_s": 1.0, "duration_s": 0.1, field: value}
    with pytest.raises(sm.ScenarioError) as info:
        sm.run_scenario(PUSH, {"disturbances": [push], "simulation.duration_s": 0.01})
    assert info.value.key == key, str(info.value)
