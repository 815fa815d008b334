"""Validation of every scenario value and of the bindings' arguments (issue 10, items 3, 4, 8).

Scenario values that make no physical sense are refused before the run with a
``ScenarioError`` naming the key and the value; binding arguments are checked before anything
is allocated; a property-based test (hypothesis) feeds generated override values to
``run_scenario`` and requires a clear error or a result, never a panic or a hang.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import sea_momentum as sm

ROOT = Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
PENDULUM = ROOT / "urdf" / "pendulum2.urdf"
#: A run as short as possible: one control tick at the default rate.
TINY = {"simulation.duration_s": 0.002}

NAN, INF = float("nan"), float("inf")

# (override key, value, key named by the error). Each was accepted before issue 10 and ran to
# "completed" with every QP failing, "diverged" at t = 0 or silently lost a feature.
REFUSED = [
    ("controller.contact.friction", -0.5, "controller.contact.friction"),
    ("controller.contact.friction", NAN, "controller.contact.friction"),
    ("controller.contact.min_normal_force", INF, "controller.contact.min_normal_force"),
    ("controller.contact.min_normal_force", 1e4, "controller.contact.min_normal_force"),
    ("controller.contact.torsional_friction", NAN, "controller.contact.torsional_friction"),
    ("controller.contact.foot_x", [0.1, -0.05], "controller.contact.foot_x"),
    ("controller.contact.facets", 0, "controller.contact.facets"),
    ("controller.contact.facets", 10**8, "controller.contact.facets"),
    ("controller.pinv_damping", -1e-3, "controller.pinv_damping"),
    ("controller.momentum_proportional", [1.0, 1.0, -1.0, 1.0, 1.0, 1.0], "controller.momentum_proportional"),
    ("controller.qp_regularization", NAN, "controller.qp_regularization"),
    ("controller.qp_solver", "quadprog", "controller.qp_solver"),
    ("controller.qp_moment_regularization", -1.0, "controller.qp_moment_regularization"),
    ("controller.contact.cop_margin", 1.0, "controller.contact.cop_margin"),
    ("controller.momentum_relaxation", "always", "controller.momentum_relaxation"),
    ("controller.external_wrench", "estimated", "controller.external_wrench"),
    ("controller.external_wrench_bandwidth_hz", 0.0, "controller.external_wrench_bandwidth_hz"),
    ("controller.external_wrench_bandwidth_hz", NAN, "controller.external_wrench_bandwidth_hz"),
    ("simulation.stop_at_joint_limits", "yes", "simulation.stop_at_joint_limits"),
    ("simulation.divergence_com_error_m", NAN, "simulation.divergence_com_error_m"),
    ("simulation.divergence_joint_error_rad", 0.0, "simulation.divergence_joint_error_rad"),
    ("simulation.divergence_joint_error_rad", NAN, "simulation.divergence_joint_error_rad"),
    ("reference.com_smooth_start", INF, "reference.com_smooth_start"),
    ("reference.posture_step_time", NAN, "reference.posture_step_time"),
    ("reference.com_amplitude", NAN, "reference.com_amplitude"),
    ("reference.com_direction", [0.0, NAN, 0.0], "reference.com_direction"),
    ("actuators.damping", 0.0, "actuators.damping"),
    ("actuators.overrides.l_knee.damping", 0.0, "actuators.overrides.l_knee.damping"),
    ("plant.dt", 1e-300, "plant.dt"),
]


@pytest.mark.parametrize("key, value, named", REFUSED, ids=[f"{k}={v}" for k, v, _ in REFUSED])
def test_nonsense_values_are_refused_naming_key_and_value(key, value, named):
    start = time.monotonic()
    with pytest.raises(sm.ScenarioError) as info:
        sm.run_scenario(TRACKING, {**TINY, key: value})
    assert time.monotonic() - start < 5.0, "refused before the run"
    assert info.value.key == named, str(info.value)
    assert f"'{named}'" in str(info.value)
    if isinstance(value, float) and math.isnan(value):
        assert "NaN" in str(info.value), "the message shows the value"


def test_zero_damping_is_fine_with_the_rigid_controller():
    result = sm.run_scenario(
        TRACKING, {**TINY, "actuators.damping": 0.0, "controller.kind": "rigid"}
    )
    assert result.status == "completed"


def test_the_external_wrench_observer_needs_sampled_control():
    """The paper's tracking file samples continuously; the observer runs once per period."""
    with pytest.raises(sm.ScenarioError, match="zero_order_hold") as info:
        sm.run_scenario(TRACKING, {**TINY, "controller.external_wrench": "observed"})
    assert info.value.key == "controller.external_wrench"


def test_min_normal_force_message_gives_the_weight():
    with pytest.raises(sm.ScenarioError, match=r"weight \d+\.\d N") as info:
        sm.run_scenario(TRACKING, {**TINY, "controller.contact.min_normal_force": 1e4})
    assert "10000" in str(info.value)


# ---------------------------------------------------------------- bindings: numpy scalars


def test_numpy_scalars_are_accepted_as_overrides():
    result = sm.run_scenario(
        TRACKING,
        {
            "simulation.duration_s": np.float32(0.002),
            "simulation.record_every": np.int64(1),
            "controller.contact.facets": np.int32(8),
            "controller.qp_unconstrained_first": np.bool_(True),
        },
    )
    assert result.status == "completed"
    assert len(result.time) >= 2


@pytest.mark.parametrize("unordered", [{"l_sole", "r_sole"}, frozenset({"l_sole", "r_sole"})])
def test_a_set_is_refused_as_an_override_array(unordered):
    """An array's order matters (robot.contacts is left, right); a set has none."""
    with pytest.raises(ValueError, match="a set has no order") as refused:
        sm.run_scenario(TRACKING, {"robot.contacts": unordered, "simulation.duration_s": 0.002})
    assert refused.value.argument == "overrides['robot.contacts']"


def pendulum_plant(actuator="elastic"):
    model = sm.Model.from_urdf(PENDULUM)
    plant = sm.Plant(model, actuator=actuator)
    return model, plant, plant.make_state(model.neutral())


@pytest.mark.parametrize("n_steps", [10**9, 2**63, 2**64 - 1])
def test_huge_step_counts_raise_before_allocating(n_steps):
    model, plant, x0 = pendulum_plant()
    start = time.monotonic()
    with pytest.raises(ValueError, match="n_steps") as info:
        plant.simulate(x0, np.zeros(model.n_joints), 1e-3, n_steps)
    assert time.monotonic() - start < 1.0
    if n_steps == 10**9:
        assert "GiB" in str(info.value), "says the memory it would need"


@pytest.mark.parametrize(("argument", "value"), [("n_steps", -1), ("record_every", 0), ("record_every", -5)])
def test_negative_counts_are_named(argument, value):
    model, plant, x0 = pendulum_plant()
    counts = {"n_steps": 10, "record_every": 1, argument: value}
    with pytest.raises(ValueError, match=argument) as info:
        plant.simulate(x0, np.zeros(model.n_joints), 1e-3, **counts)
    assert info.value.argument == argument


@pytest.mark.parametrize("n_steps", [2**64, 2**200, np.int64(-3)])
def test_a_step_count_out_of_range_is_named(n_steps):
    model, plant, x0 = pendulum_plant()
    with pytest.raises(ValueError, match="n_steps: expected an integer from 0 to") as info:
        plant.simulate(x0, np.zeros(model.n_joints), 1e-3, n_steps)
    assert info.value.argument == "n_steps"


@pytest.mark.parametrize("record_every", [2**70, 2**200, np.int64(0)])
def test_a_record_interval_out_of_range_is_named(record_every):
    model, plant, x0 = pendulum_plant()
    with pytest.raises(ValueError, match="record_every: expected an integer from 1 to") as info:
        plant.simulate(x0, np.zeros(model.n_joints), 1e-3, 10, record_every=record_every)
    assert info.value.argument == "record_every"


def test_record_every_none_records_every_step_and_a_float_is_a_type_error():
    model, plant, x0 = pendulum_plant()
    result = plant.simulate(x0, np.zeros(model.n_joints), 1e-3, 5, record_every=None)
    assert len(result.time) == 6
    with pytest.raises(TypeError):
        plant.simulate(x0, np.zeros(model.n_joints), 1e-3, 5, record_every=2.0)


@pytest.mark.parametrize("n_steps", [1.5, "10", None])
def test_a_step_count_not_an_integer_is_a_type_error(n_steps):
    model, plant, x0 = pendulum_plant()
    with pytest.raises(TypeError):
        plant.simulate(x0, np.zeros(model.n_joints), 1e-3, n_steps)


def _object_array_with_a_complex_entry(x):
    bad = x.astype(object)
    bad[0] = 1 + 0j
    return bad


@pytest.mark.parametrize(
    "make",
    [lambda x: x.astype(complex), _object_array_with_a_complex_entry, lambda x: list(x) + []],
)
def test_complex_arrays_and_object_arrays_of_non_reals_are_refused(make):
    model, plant, x0 = pendulum_plant()
    bad = make(x0)
    if isinstance(bad, list):  # a list with a complex entry
        bad[0] = 1 + 0j
    with pytest.raises(ValueError, match=r"x\b|x0|dtype|real"):
        plant.simulate(bad, np.zeros(model.n_joints), 1e-3, 1)


@pytest.mark.parametrize(
    "make",
    [
        lambda x: x.astype(object),
        lambda x: np.array([float(v) for v in x], dtype=object),
        lambda x: np.array([np.float32(v) if i % 2 else v for i, v in enumerate(x)], dtype=object),
        lambda x: x.astype(np.float32).astype(np.float64).astype(object),
    ],
)
def test_object_arrays_of_real_numbers_are_accepted_as_numpy_converts_them(make):
    # numpy.asarray(x, dtype=float64) converts these; the bindings accept what it converts.
    model, plant, x0 = pendulum_plant()
    given = make(x0)
    expected = plant.simulate(np.asarray(given, dtype=np.float64), np.zeros(model.n_joints), 1e-3, 2)
    run = plant.simulate(given, np.zeros(model.n_joints).astype(object), 1e-3, 2)
    np.testing.assert_array_equal(run.x, expected.x)


def test_object_arrays_still_refuse_nan_and_wrong_shapes_with_the_same_messages():
    model, plant, x0 = pendulum_plant()
    nan = x0.astype(object)
    nan[1] = float("nan")
    with pytest.raises(ValueError, match=r"x\[1\]: expected a finite number, got NaN") as info:
        plant.simulate(nan, np.zeros(model.n_joints), 1e-3, 1)
    assert info.value.argument == "x[1]"
    with pytest.raises(ValueError, match=r"expected shape") as info:
        plant.simulate(x0[:-1].astype(object), np.zeros(model.n_joints), 1e-3, 1)
    assert info.value.argument == "x"


# (argument, value, shown): numeric Plant arguments that make no physical sense and the text
# of the value the message shows; friction, gravity and the foot rectangle were accepted
# silently before, the gains must stay refused.
BAD_PLANT_ARGUMENTS = [
    ("friction", -1.0, "-1"),
    ("friction", 0.0, "0"),
    ("friction", NAN, "NaN"),
    ("friction", INF, "inf"),
    ("gravity", (0.0, 0.0, NAN), "(0, 0, NaN)"),
    ("gravity", (INF, 0.0, -9.81), "(inf, 0, -9.81)"),
    ("foot_x", (0.1, -0.05), "(0.1, -0.05)"),
    ("foot_x", (-0.05, NAN), "(-0.05, NaN)"),
    ("foot_y", (0.02, 0.02), "(0.02, 0.02)"),
    ("foot_y", (-INF, 0.02), "(-inf, 0.02)"),
    ("baumgarte_kp", -1.0, "-1"),
    ("baumgarte_kp", NAN, "NaN"),
    ("baumgarte_kd", -1.0, "-1"),
    ("baumgarte_kd", INF, "inf"),
    ("motor_velocity_gain", 0.0, "0"),
    ("motor_velocity_gain", NAN, "NaN"),
    ("joint_inertia_regularization", -0.1, "-0.1"),
    ("joint_inertia_regularization", NAN, "NaN"),
]


@pytest.mark.parametrize(
    "argument, value, shown", BAD_PLANT_ARGUMENTS, ids=[f"{a}={v}" for a, v, _ in BAD_PLANT_ARGUMENTS]
)
def test_bad_numeric_plant_arguments_are_refused_naming_argument_and_value(argument, value, shown):
    model = sm.Model.from_urdf(PENDULUM)
    with pytest.raises(ValueError) as info:
        sm.Plant(model, actuator="elastic", **{argument: value})
    assert info.value.argument == argument, str(info.value)
    message = str(info.value)
    assert message.startswith(f"{argument}: expected "), message
    assert message.endswith(f", got {shown}"), message


def test_good_plant_arguments_are_accepted():
    model = sm.Model.from_urdf(PENDULUM)
    plant = sm.Plant(model, actuator="elastic", friction=0.5, gravity=(0.0, 0.0, -1.62),
                     foot_x=(-0.05, 0.1), foot_y=(-0.02, 0.02), baumgarte_kp=0.0,
                     motor_velocity_gain=200.0, joint_inertia_regularization=0.0)
    assert plant.nx > 0


def test_numpy_scalars_are_accepted_as_arguments():
    model, plant, x0 = pendulum_plant()
    run = plant.simulate(x0, np.zeros(model.n_joints), np.float32(1e-3), np.int64(3),
                         record_every=np.int32(1))
    assert run.x.shape == (4, plant.nx)


def test_all_rigid_joints_keep_the_sample_dimension():
    model, plant, x0 = pendulum_plant(actuator="rigid")
    run = plant.simulate(x0, np.zeros(model.n_joints), 1e-3, 5)
    assert run.motor_torques.shape == (6, 0)
    result = sm.run_scenario(
        TRACKING,
        {**TINY, "simulation.record_every": 1, "actuators.kind": "rigid", "controller.kind": "rigid"},
    )
    rows = len(result.time)
    assert rows >= 2
    assert result.motor_torques.shape == (rows, 0)
    assert result.thetadot_desired.shape == (rows, 0)
    assert result.theta.shape == (rows, 0)


# ---------------------------------------------------------------- property-based

#: Keys of numbers (and number lists) that a user types by hand.
NUMBER_KEYS = [
    "plant.dt",
    "plant.baumgarte_kp",
    "plant.baumgarte_kd",
    "plant.motor_velocity_gain",
    "plant.joint_inertia_regularization",
    "controller.rate_hz",
    "controller.damping_estimate_scale",
    "controller.stiffness_estimate_scale",
    "controller.postural_scale",
    "controller.pinv_damping",
    "controller.qp_regularization",
    "controller.qp_moment_regularization",
    "controller.identification_deflection_noise_rad",
    "controller.identification_hold_s",
    "controller.identification_prior_deflection_rad",
    "controller.identification_range_factor",
    "controller.identification_excitation_nm.l_knee",
    "controller.identification_excitation_hz",
    "controller.identification_filter_hz",
    "controller.identification_excitation_s",
    "controller.joint_inertia_regularization",
    "controller.contact.friction",
    "controller.contact.facets",
    "controller.contact.torsional_friction",
    "controller.contact.min_normal_force",
    "controller.contact.cop_margin",
    "controller.contact.foot_x",
    "controller.contact.foot_y",
    "controller.momentum_integral",
    "actuators.ratio",
    "actuators.motor_inertia",
    "actuators.stiffness",
    "actuators.damping",
    "actuators.torque_limit",
    "actuators.overrides.l_knee.stiffness",
    "reference.com_amplitude",
    "reference.com_frequency",
    "reference.com_direction",
    "reference.com_smooth_start",
    "reference.posture_step_deg",
    "reference.posture_step_time",
    "simulation.record_every",
    "simulation.divergence_com_error_m",
    "simulation.divergence_joint_error_rad",
    "controller.external_wrench_bandwidth_hz",
    "robot.initial_posture",
]

SPECIAL = [NAN, INF, -INF, 0.0, -0.0, -1.0, 1e300, -1e300, 1e-300, 2**63, 2**64, -(2**63) - 1]
scalars = st.one_of(
    st.sampled_from(SPECIAL),
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.booleans(),
    st.text(max_size=8),
    st.sampled_from([np.float32(1.5), np.int64(3), np.float64(NAN), None, b"x", 1j, {}]),
)
values = st.one_of(scalars, st.lists(scalars, max_size=7))


def _kind_of_key_in(message: str, key: str) -> bool:
    """The message names the key (or one entry of it, or the table it belongs to)."""
    table = key.rsplit(".", 1)[0]
    return key in message or f"'{table}" in message


@settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,
)
@given(key=st.sampled_from(NUMBER_KEYS), value=values)
def test_generated_overrides_never_panic_hang_or_mislead(key, value):
    start = time.monotonic()
    try:
        result = sm.run_scenario(TRACKING, {**TINY, key: value})
    except (sm.ScenarioError, sm.ModelError, ValueError, TypeError) as error:
        message = str(error)
        assert _kind_of_key_in(message, key), f"{key}={value!r}: {message}"
    except BaseException as error:  # noqa: BLE001 - a panic is a BaseException
        pytest.fail(f"{key}={value!r}: {type(error).__name__}: {error}")
    else:
        assert result.status in ("completed", "diverged", "fell"), result.summary
        if result.status == "fell":  # a fall names its foot and constraint
            assert result.summary.fall_foot and result.summary.fall_constraint, result.summary
        assert np.all(np.isfinite(result.time))
    assert time.monotonic() - start < 5.0, f"{key}={value!r} took too long"
