"""Scalar arguments and other values from Python: a bool, a complex number or an int beyond the
range is refused where a number is expected, naming the argument; a 0-d array is its number;
results that overflow are errors, not NaN; long names are shortened in messages; the objects
have a repr that says what they hold."""

import errno
from pathlib import Path

import numpy as np
import pytest

import sea_momentum as sm
from sea_momentum import _native

ROOT = Path(__file__).resolve().parents[1]
ICUB = ROOT / "urdf" / "icub25.urdf"
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
#: The iCub's sole rectangle (contact frame) [m], for `init_scenario` (its URDF has no
#: collision geometry to measure).
ICUB_FOOT = (-0.05, 0.10, -0.025, 0.025)


@pytest.fixture(scope="module")
def model():
    return sm.Model.from_urdf(ICUB, joints=list(sm.ICUB25_JOINTS))


@pytest.fixture(scope="module")
def standing(model):
    q0 = model.neutral()
    plant = sm.Plant(model, actuator="elastic", contacts=["l_sole", "r_sole"], contact_q=q0)
    controller = sm.Controller(model, ["l_sole", "r_sole"], q0)
    return plant, plant.make_state(q0), controller


#: Values that are not real numbers, and the words of their TypeError.
NOT_REAL = [
    (True, "the bool"),
    (np.True_, "the bool"),
    (np.array(True), "the bool"),
    (1 + 2j, "complex number"),
    (np.complex128(1.0), "complex number"),
    (np.array(1.0 + 0j), "complex number"),
    (10**400, "int of 1329 bits"),
    (-(10**400), "negative int of 1329 bits"),
]


@pytest.mark.parametrize("value, words", NOT_REAL)
def test_a_real_argument_refuses_bools_complex_numbers_and_huge_ints(model, standing, value, words):
    plant, x, controller = standing
    u = np.zeros(plant.nu_input)
    calls = {
        "dt": lambda: plant.step(x, u, value),
        "baumgarte_kp": lambda: sm.Plant(model, baumgarte_kp=value),
        "joint_inertia_regularization": lambda: sm.Plant(model, joint_inertia_regularization=value),
        "t": lambda: controller.tick(value, np.zeros(controller.nx)),
        "tolerance_n_s": lambda: _native.push_table_native(TRACKING, ["forward"], tolerance_n_s=value),
    }
    for argument, call in calls.items():
        with pytest.raises(TypeError) as info:
            call()
        assert str(info.value).startswith(f"argument '{argument}': expected a real number"), info.value
        assert words in str(info.value)


def test_an_integer_argument_refuses_bools_and_ints_beyond_64_bits():
    with pytest.raises(TypeError, match="argument 'triangle_budget': expected an integer.*bool True"):
        _native.link_meshes(ICUB, triangle_budget=True)
    with pytest.raises(TypeError, match="argument 'triangle_budget': .*int of 71 bits, beyond"):
        _native.link_meshes(ICUB, triangle_budget=2**70)
    with pytest.raises(TypeError, match="argument 'grid_points': .*negative int of 71 bits"):
        _native.stability_margin_native(TRACKING, "controller.postural_scale", 0.1, 1.0, grid_points=-(2**70))
    with pytest.raises(TypeError, match="argument 'triangle_budget': .*int of 64 bits, beyond"):
        _native.link_meshes(ICUB, triangle_budget=np.uint64(2**64 - 1))
    # A numpy integer is an integer.
    meshes, _ = _native.link_meshes(ICUB, triangle_budget=np.int32(100))
    assert isinstance(meshes, list)


@pytest.mark.parametrize("value", [True, np.True_, 2.5])
def test_a_count_argument_names_itself_when_given_no_integer(standing, value):
    plant, x, _ = standing
    u = np.zeros(plant.nu_input)
    with pytest.raises(TypeError, match="argument 'n_steps': "):
        plant.simulate(x, u, 1e-3, value)
    with pytest.raises(TypeError, match="argument 'record_every': "):
        plant.simulate(x, u, 1e-3, 2, record_every=value)


def test_the_python_wrappers_leave_the_check_to_the_native_arguments():
    with pytest.raises(TypeError, match="argument 'lower': expected a real number, got the complex"):
        sm.stability_margin(TRACKING, "controller.postural_scale", 1 + 0j, 2.0)
    with pytest.raises(TypeError, match="argument 'tolerance_n_s': expected a real number, got the bool"):
        sm.push_table(TRACKING, "forward", tolerance_n_s=True)
    with pytest.raises(TypeError, match="argument 'impulses': expected a real number"):
        sm.push_table(TRACKING, "forward", impulses=[1.0, True])


def test_numbers_in_dicts_and_tuples_refuse_bools(model):
    joints = list(sm.ICUB25_JOINTS)
    with pytest.raises(TypeError, match="argument 'locked': expected a real number, got the bool"):
        sm.Model.from_urdf(ICUB, joints=joints[:-1], locked={joints[-1]: True})
    with pytest.raises(ValueError) as info:
        sm.Plant(model, actuator={"kind": "elastic", "stiffness": True})
    assert info.value.argument == "actuator['stiffness']"
    for gravity in ([0.0, 0.0, np.True_], np.array([0.0, 0.0, -9.81 + 0j])):
        with pytest.raises(ValueError) as info:
            sm.Plant(model, gravity=gravity)
        assert info.value.argument == "gravity"
    # Real numbers of any kind are taken.
    plant = sm.Plant(model, gravity=(0, np.float32(0.0), np.int64(-9)), baumgarte_kp=np.float64(40))
    assert plant.nx == model.nq + model.nv


class _ForeignScalar:
    """A 0-d value of another array library: a ``dtype`` without numpy's ``kind``."""

    dtype = object()

    def __float__(self) -> float:
        return 0.5


def test_a_scalar_of_another_array_library_is_taken_by_its_float(model):
    plant = sm.Plant(model, baumgarte_kp=_ForeignScalar())
    assert plant.nx == model.nq + model.nv


def test_a_0d_array_override_is_its_number():
    scenario = sm.Scenario.load(TRACKING, {"simulation.duration_s": np.array(0.5)})
    assert scenario.duration == 0.5
    scenario = sm.Scenario.load(TRACKING, {"simulation.duration_s": np.float32(0.25)})
    assert scenario.duration == 0.25


def test_a_sweep_axis_must_be_a_flat_list_of_real_numbers():
    with pytest.raises(ValueError, match=r"grid\['simulation.duration_s'\]: expected a flat list.*\(1, 1\)"):
        sm.sweep(TRACKING, {"simulation.duration_s": [[0.01]]})
    with pytest.raises(ValueError, match="every value must be a real number, got .*1j"):
        sm.sweep(TRACKING, {"simulation.duration_s": [np.complex128(0.01 + 1j)]})


@pytest.mark.parametrize(
    "method",
    ["bias_forces", "inverse_dynamics", "centroidal_momentum", "centroidal_momentum_bias", "frame_jacobian_dot_v"],
)
def test_velocities_whose_products_overflow_are_a_solver_error_not_nan(model, method):
    q = model.neutral()
    # Finite velocities; their products overflow (the momentum, linear in them, overflows too).
    nu = np.full(model.nv, 1e308)
    args = {
        "inverse_dynamics": (q, nu, np.zeros(model.nv)),
        "frame_jacobian_dot_v": (q, nu, "l_sole"),
    }.get(method, (q, nu))
    with pytest.raises(sm.SolverError, match="not finite") as info:
        getattr(model, method)(*args)
    assert info.value.operation == method
    # The same call at ordinary velocities is finite.
    ordinary = list(args)
    ordinary[1] = np.full(model.nv, 0.5)
    assert np.all(np.isfinite(getattr(model, method)(*ordinary)))


def test_a_long_frame_name_is_shortened_in_the_message(model):
    name = "x" * 1_000_000
    with pytest.raises(sm.ModelError) as info:
        model.frame_pose(model.neutral(), name)
    assert len(str(info.value)) < 300
    assert str(info.value).endswith("(1000000 characters)'")
    assert info.value.element == name, "the attribute keeps the whole name"


def test_init_scenario_takes_a_path_and_an_output_folder_is_eisdir(tmp_path):
    report = sm.init_scenario(ICUB, ("l_sole", "r_sole"), tmp_path / "icub.toml", foot=ICUB_FOOT)
    assert Path(report["out"]).is_file()
    with pytest.raises(sm.SeaIOError) as info:
        sm.init_scenario(ICUB, ("l_sole", "r_sole"), tmp_path, foot=ICUB_FOOT)
    assert info.value.errno == errno.EISDIR
    assert info.value.filename == str(tmp_path)
    with pytest.raises(ValueError) as info:
        sm.init_scenario(ICUB, ("l_sole", "r_sole"), tmp_path / "b.toml", foot=(True, 0.1, -0.02, 0.02))
    assert info.value.argument == "foot"


def test_the_objects_say_what_they_hold(model, standing):
    plant, _, controller = standing
    assert repr(plant) == f"Plant(model='iCub25', nx={plant.nx}, elastic_joints=25, contacts=['l_sole', 'r_sole'])"
    assert repr(controller) == f"Controller(kind='sea', model='iCub25', contacts=['l_sole', 'r_sole'], nx={plant.nx})"
    scenario = sm.Scenario.load(TRACKING)
    assert repr(scenario) == (
        f"Scenario(name='tracking', duration={scenario.duration!r}, "
        f"plant_dt={scenario.plant_dt!r}, control_period={scenario.control_period!r})"
    )
