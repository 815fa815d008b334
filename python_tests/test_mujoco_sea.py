"""Short runs of examples/mujoco_sea_icub.py (our robot-rate controller from Python on the iCub
with SEAs in MuJoCo) and of examples/mujoco_sea_check.py (our SEA plant against MuJoCo's under
the same commands). Bounded: about 1 s simulated each."""

from __future__ import annotations

import importlib
import pathlib
import sys

import numpy as np
import pytest

# An optional dependency (the `examples` extra): without it there is nothing to test.
mujoco = pytest.importorskip("mujoco", reason="pip install mujoco (the sea-momentum[examples] extra)")

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
sys.path.insert(0, str(EXAMPLES))


@pytest.fixture(scope="module")
def check():
    return importlib.import_module("mujoco_sea_check")


@pytest.fixture(scope="module")
def example():
    return importlib.import_module("mujoco_sea_icub")


def test_fixed_base_sea_plant_is_mujocos_to_the_integrators_error(check) -> None:
    """Base welded in the air, no contacts, both RK4 at 0.25 ms, 1 s of the same motor
    torques: the same ODE, so the same motion to 1e-6 rad (measured 2.4e-8 rad) while the
    joints move by a tenth of a radian. A sign, a ratio or an inertia off would differ by
    the motion itself."""
    d = check.compare("fixed", duration=1.0)
    assert d["excursion"] > 0.05
    assert d["joint_angle"] < 1e-6, d
    assert d["motor_angle"] < 1e-6, d
    assert d["joint_velocity"] < 1e-5, d


def test_motor_torque_limits_clip_the_motion_as_mujocos_actuator_force_range(check) -> None:
    """The fixed setting with every motor limited to its hold torque plus half the
    sinusoid's amplitude (ours: ``torque_limit``; MuJoCo: the rotor hinge's ``actfrcrange``,
    the limit through the gear): a third of the commands are over their limit and the limits
    move the joints by 0.03 rad (measured 0.029), yet the two simulators agree as without
    limits (measured 2.4e-8 rad). A limit off by the gear would differ by the limits' effect."""
    d = check.compare("fixed", duration=1.0, limit_fraction=0.5)
    assert d["saturated_share"] > 0.2, d
    assert d["limit_effect"] > 0.01, d
    assert d["joint_angle"] < 1e-6, d
    assert d["motor_angle"] < 1e-6, d


def test_a_scenarios_motor_torque_limits_reach_the_mujoco_model(example) -> None:
    """``actuators.torque_limit_from_urdf``: the plant's elastic parameters carry the URDF's
    effort limits through the ratio (urdf/icub25.urdf: the knees 37 N m, the hip pitches
    55.5), and the MuJoCo robot built from the scenario clamps the rotor hinges there; a
    scenario whose springs are not the MuJoCo model's is refused naming the joint and key."""
    import sea_momentum as sm
    from mujoco_sea import Sea, motor_torque_limits

    walk = example.ROOT / "scenarios" / "walking" / "walk_straight.toml"
    scenario = sm.Scenario.load(walk, {"actuators.torque_limit_from_urdf": True})
    limits = motor_torque_limits(scenario.plant, Sea())
    assert limits["l_knee"] == pytest.approx(0.37) and limits["r_hip_pitch"] == pytest.approx(0.555)
    robot = example.Robot(scenario, Sea(), example.MOTOR_VELOCITY_GAIN)
    hinge = robot.mj.joint("l_knee_rotor").id
    assert robot.mj.jnt_actfrclimited[hinge]
    assert robot.mj.jnt_actfrcrange[hinge] == pytest.approx([-37.0, 37.0])
    free = sm.Scenario.load(walk)
    assert motor_torque_limits(free.plant, Sea()) == {}
    soft = sm.Scenario.load(walk, {"actuators.overrides.l_knee.stiffness": 300.0})
    with pytest.raises(ValueError, match="l_knee.*stiffness"):
        motor_torque_limits(soft.plant, Sea())


def test_on_the_ground_the_motion_agrees_to_the_contact_models(check) -> None:
    """On two feet, 1 s of the same desired motor velocities through the motor velocity
    loops (the torso, arms and neck move by 0.1 rad at the motors): the joint angles agree
    to 1e-2 rad (measured 3.0e-3) and the base to 5 mm (measured 2.2 mm); MuJoCo's soft
    contacts sink about 0.5 mm under the weight, ours do not."""
    d = check.compare("ground", duration=1.0)
    assert d["excursion"] > 0.05
    assert d["joint_angle"] < 1e-2, d
    assert d["base_position"] < 5e-3, d


#: The short run: 1.5 s, a 3 N s push forward on the pelvis at 0.5 s.
SHORT = {"duration": 1.5, "push_impulse": 3.0, "push_start": 0.5}


@pytest.fixture(scope="module")
def mujoco_run(example):
    return example.run(**SHORT, simulator="mujoco")


def test_robot_rate_controller_balances_mujocos_sea_icub_and_recovers_a_push(example, mujoco_run) -> None:
    """The robot-rate design from Python (x0.7 stiffness estimate identified) on the SEA iCub
    in MuJoCo, pushed: it stands, the CoM follows the reference within a centimetre, and the
    identification moves the estimates towards the springs' stiffness."""
    summary = example.summary(mujoco_run)
    assert summary["standing"] == 1.0 and summary["base_drop_mm"] < 20.0, summary
    assert summary["com_error_rms_before_push_mm"] < 5.0, summary
    assert summary["com_error_max_after_push_mm"] < 30.0, summary
    assert summary["com_error_final_mm"] < 15.0, summary
    ratios = mujoco_run["stiffness_ratio"]
    assert np.abs(ratios[-1] - 1.0).mean() < np.abs(ratios[0] - 1.0).mean(), summary


def test_the_same_loop_on_our_plant_moves_the_com_as_on_mujoco(example, mujoco_run) -> None:
    """The same controller loop on our plant (the push through ``Plant.step``): the CoM
    trajectories stay within 2 mm of each other (measured 0.61 mm) while the push moves the
    CoM forward by 15 mm."""
    ours_run = example.run(**SHORT, simulator="ours")
    assert len(ours_run["time"]) == len(mujoco_run["time"])
    distance = np.linalg.norm(ours_run["com"] - mujoco_run["com"], axis=1)
    excursion = np.max(mujoco_run["com"][:, 0] - mujoco_run["com"][0, 0])
    assert excursion > 0.01, excursion
    assert distance.max() < 2e-3, distance.max()


def test_the_push_moves_the_robot(example) -> None:
    """The push acts: the CoM moves forward within 0.3 s of a 3 N s push, not without it."""
    pushed = example.run(duration=0.8, push_impulse=3.0, push_start=0.3)
    free = example.run(duration=0.8, push_impulse=0.0, push_start=0.3)
    forward = lambda s: np.max(s["com"][:, 0] - s["com"][0, 0])  # noqa: E731
    assert forward(pushed) > forward(free) + 2e-3


def test_a_walking_scenarios_controller_walks_mujocos_sea_icub_as_our_plant(example) -> None:
    """``--walk``: walk_straight.toml's controller (0.1 m/s; the plan, the contact phases, the
    swings, the touchdowns sensed from MuJoCo's foot wrenches) walks MuJoCo's SEA iCub for
    3 s (three steps), and our plant under the same loop: both bases go 0.22 m forward, the
    CoM within 1.4 mm of its reference (rms) and the two CoM trajectories within 1.3 mm of
    each other (measured), through lift-offs and touchdowns on two different contact models."""
    walk = example.ROOT / "scenarios" / "walking" / "walk_straight.toml"
    runs = {
        simulator: example.run(3.0, 0.0, 5.0, simulator, walk, example.WALK_OVERRIDES)
        for simulator in ("mujoco", "ours")
    }
    for simulator, series in runs.items():
        summary = example.summary(series)
        assert summary["standing"] == 1.0 and summary["simulated_s"] > 2.98, (simulator, summary)
        assert summary["base_forward_m"] > 0.18, (simulator, summary)
        assert summary["com_error_rms_mm"] < 3.0, (simulator, summary)
    distance = np.linalg.norm(runs["mujoco"]["com"] - runs["ours"]["com"], axis=1)
    assert distance.max() < 4e-3, distance.max()


def test_a_push_acts_in_its_direction_and_an_unknown_direction_is_refused(example) -> None:
    """``push_direction``: a 3 N s push to the left moves the CoM to the left (+y) within 0.5 s
    and not forward; a direction not in ``PUSH_DIRECTIONS`` is refused naming the argument."""
    pushed = example.run(duration=0.8, push_impulse=3.0, push_start=0.3, push_direction="left")
    free = example.run(duration=0.8, push_impulse=0.0, push_start=0.3)
    moved = pushed["com"][:, :2] - free["com"][:, :2]
    assert moved[:, 1].max() > 2e-3 and abs(moved[:, 0]).max() < 0.5 * moved[:, 1].max(), moved[-1]
    with pytest.raises(ValueError, match="push_direction"):
        example.run(duration=0.1, push_impulse=1.0, push_direction="up")


def test_a_plant_state_that_diverges_ends_the_run_as_a_fall(example, monkeypatch) -> None:
    """Our plant's step turns a state its dynamics cannot factorise (velocities of 1e150) into
    ``Diverged``, and the loop ends the series there, read as a fall, instead of raising (a
    walk pushed past what it recovers can drive the plant there: 9 N s forward at 50 % of
    walk_push.toml's fourth swing, measured at 3.53 s)."""
    scenario = example.sm.Scenario.load(example.SCENARIO, example.OVERRIDES)
    plant = example.OurPlant(scenario)
    plant.x = scenario.initial_state.copy()
    plant.x[-60:] = 1e150
    with pytest.raises(example.Diverged, match="our plant"):
        plant.step(np.zeros(scenario.plant.nu_input))
    step = example.OurPlant.step
    steps = {"done": 0}

    def diverging(self, u):
        steps["done"] += 1
        if steps["done"] > 2000:  # 0.3 s after the settling's 800 steps
            raise example.Diverged("our plant: the state is not finite")
        return step(self, u)

    monkeypatch.setattr(example.OurPlant, "step", diverging)
    series = example.run(duration=1.0, push_impulse=0.0, simulator="ours")
    summary = example.summary(series)
    assert summary["standing"] == 0.0 and 0.25 < summary["simulated_s"] < 0.35, summary
