"""The SEA plant and its fixed-step integrators (issue 3).

Checks, against physics and against scipy's stiff integrator (the open analogue of the
paper's ode15s) on the same right-hand side:

- energy and momentum conservation without gravity, damping or contacts;
- convergence at the method's order against ``solve_ivp(method="Radau")`` at rtol 1e-10;
- stability where RK4 diverges (stiff springs and motor velocity loop at dt = 1 ms);
- contact drift over 10 s; clear errors for bad input; data kept on divergence.
"""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
import pytest

import sea_momentum as sm  # a failed import fails the run (no importorskip)

ROOT = pathlib.Path(__file__).resolve().parents[1]
ICUB = ROOT / "urdf" / "icub25.urdf"
BIPED = ROOT / "urdf" / "mini_biped.urdf"
ETA = 0.01  # the paper's transmission ratio


def standing_icub(**plant_options):
    """The 25-DoF iCub on both soles at the neutral posture, springs preloaded against gravity.

    Returns (model, plant, x0, gravity joint torques)."""
    model = sm.Model.from_urdf(ICUB)
    q = model.neutral()
    q[2] = -model.frame_pose(q, "l_sole")[2, 3]
    plant_options.setdefault("actuator", "elastic")
    plant = sm.Plant(model, contacts=["l_sole", "r_sole"], contact_q=q, **plant_options)
    gravity = model.gravity_forces(q)[6:]
    x0 = plant.make_state(q, joint_torques=gravity)
    return model, plant, x0, gravity


def free_biped(stiffness: float, seed: int = 1):
    """The small biped floating without gravity, with undamped springs and random motion."""
    model = sm.Model.from_urdf(BIPED)
    rng = np.random.default_rng(seed)
    q = model.neutral()
    q[7:] = rng.uniform(-0.3, 0.3, model.n_joints)
    nu = rng.normal(size=model.nv) * 0.5
    actuator = dict(stiffness=stiffness, damping=0.0, motor_inertia=1e-4, ratio=ETA)
    plant = sm.Plant(model, actuator=actuator, gravity=(0.0, 0.0, 0.0))
    theta = (q[7:] + rng.uniform(-0.05, 0.05, model.n_joints)) / ETA
    x0 = plant.make_state(q, nu, theta=theta, thetadot=rng.normal(size=model.n_joints) * 5)
    return model, plant, x0


def total_energy(model, plant, x, stiffness: float, motor_inertia: float = 1e-4) -> float:
    """Kinetic energy of links and motors plus spring energy (no gravity)."""
    d = plant.split_state(x)
    links = 0.5 * d["nu"] @ model.mass_matrix(d["q"]) @ d["nu"]
    motors = 0.5 * motor_inertia * np.sum(d["thetadot"] ** 2)
    springs = 0.5 * stiffness * np.sum((ETA * d["theta"] - d["q"][7:]) ** 2)
    return float(links + motors + springs)


def momentum(model, plant, x) -> np.ndarray:
    d = plant.split_state(x)
    return model.centroidal_momentum(d["q"], d["nu"])


def joint_side(plant, x) -> np.ndarray:
    """State with motor quantities on the joint side (Gamma theta, Gamma thetadot), so errors of
    different components are comparable."""
    d = plant.split_state(x)
    return np.concatenate([d["q"], d["nu"], ETA * d["theta"], ETA * d["thetadot"]])


# --- conservation --------------------------------------------------------------------------


def test_rk4_conserves_energy_at_small_steps():
    model, plant, x0 = free_biped(stiffness=50.0)
    e0 = total_energy(model, plant, x0, 50.0)
    drifts = []
    for dt in (5e-4, 2.5e-4):
        run = plant.simulate(x0, np.zeros(model.n_joints), dt, int(round(0.5 / dt)), method="rk4")
        assert run.status == "completed"
        drifts.append(max(abs(total_energy(model, plant, x, 50.0) - e0) for x in run.x) / e0)
    print(f"RK4 relative energy drift over 0.5 s: dt 0.5 ms {drifts[0]:.2e}, 0.25 ms {drifts[1]:.2e}")
    assert drifts[1] < 1e-6
    assert drifts[0] / drifts[1] > 16.0  # fourth order (or better)


@pytest.mark.parametrize("method, order", [("ros2", 2), ("implicit_euler", 1)])
def test_implicit_energy_drift_follows_the_order(method, order):
    # Soft springs so every mode is resolved at these steps: the drift then follows the order.
    model, plant, x0 = free_biped(stiffness=2.0)
    e0 = total_energy(model, plant, x0, 2.0)
    drifts = []
    for dt in (1e-3, 5e-4, 2.5e-4):
        run = plant.simulate(x0, np.zeros(model.n_joints), dt, int(round(0.5 / dt)), method=method)
        drifts.append(abs(total_energy(model, plant, run.x[-1], 2.0) - e0) / e0)
    ratios = [drifts[i] / drifts[i + 1] for i in range(2)]
    print(f"{method}: energy drift {['%.2e' % d for d in drifts]}, ratios {['%.2f' % r for r in ratios]}")
    assert ratios[-1] > 0.75 * 2**order


def test_free_floating_momentum_is_conserved_with_springs_acting():
    model, plant, x0 = free_biped(stiffness=50.0)
    h0 = momentum(model, plant, x0)
    assert np.linalg.norm(h0) > 1.0  # a real motion, not a trivial zero
    rk4 = plant.simulate(x0, np.zeros(model.n_joints), 2.5e-4, 2000, method="rk4", record_every=20)
    d_theta = np.ptp(rk4.x[:, model.nq : model.nq + model.n_joints], axis=0).max()
    assert d_theta > 1.0  # the springs and motors really move
    errors = [np.linalg.norm(momentum(model, plant, x) - h0) / np.linalg.norm(h0) for x in rk4.x]
    assert max(errors) < 1e-8
    # ROS2 damps the unresolved stiff modes (that costs momentum accuracy at these steps), so
    # its order is checked with soft springs, where every mode is resolved.
    model, plant, x0 = free_biped(stiffness=2.0)
    h0 = momentum(model, plant, x0)
    drifts = []
    for dt in (5e-4, 2.5e-4):
        run = plant.simulate(x0, np.zeros(model.n_joints), dt, int(round(0.5 / dt)), method="ros2")
        drifts.append(max(np.linalg.norm(momentum(model, plant, x) - h0) for x in run.x) / np.linalg.norm(h0))
    print(f"momentum drift: RK4 {max(errors):.1e}; ROS2 {drifts[0]:.1e} (0.5 ms), {drifts[1]:.1e} (0.25 ms)")
    assert drifts[1] < 1e-4 and drifts[0] / drifts[1] > 3.0


# --- against scipy --------------------------------------------------------------------------


def test_ros2_converges_to_scipy_radau_at_second_order():
    import scipy.integrate as scipy_integrate

    model, plant, x0, gravity = standing_icub()
    u = ETA * gravity  # constant motor torques, balancing gravity at the start
    horizon = 1.0
    reference = scipy_integrate.solve_ivp(
        lambda t, x: plant.dynamics(x, u), (0.0, horizon), x0, method="Radau", rtol=1e-10, atol=1e-10
    )
    assert reference.success, reference.message
    x_ref = joint_side(plant, reference.y[:, -1])
    scale = np.abs(x_ref).max()
    rows = []
    for dt in (1e-3, 5e-4, 2.5e-4, 1.25e-4):
        run = plant.simulate(x0, u, dt, int(round(horizon / dt)), method="ros2", record_every=10**9)
        assert run.status == "completed"
        rows.append((dt, np.abs(joint_side(plant, run.x[-1]) - x_ref).max() / scale))
    print("\nROS2 against scipy Radau (rtol 1e-10), iCub on two feet, constant motor torque, 1 s")
    print("  dt [ms]   max error / max |x|   ratio")
    for i, (dt, error) in enumerate(rows):
        ratio = rows[i - 1][1] / error if i else float("nan")
        print(f"  {dt * 1e3:7.4f}   {error:18.3e}   {ratio:5.2f}")
    errors = [e for _, e in rows]
    assert all(a > b for a, b in zip(errors, errors[1:]))
    assert 3.0 < errors[-2] / errors[-1] < 5.5  # second order
    assert errors[-1] < 2e-3


# --- stiffness ------------------------------------------------------------------------------


def test_rk4_diverges_where_ros2_stays_accurate():
    # Springs of 1e4 Nm/rad and a motor velocity loop of 1e4 1/s at dt = 1 ms. The damping
    # (10 Nms/rad) makes the stiff joint modes overdamped, so the exact solution is smooth and
    # "accurate" is meaningful; lightly damped 1e4 rad/s modes cannot be followed at 1 ms by
    # any method (an L-stable one damps them).
    stiffness = 1e4
    actuator = dict(stiffness=stiffness, damping=10.0)
    model, plant, x0, _ = standing_icub(actuator=actuator, motor_velocity_gain=1e4)
    u = np.full(model.n_joints, 5.0)  # desired motor velocities: 0.05 rad/s on the joints
    horizon = 0.5
    rk4 = plant.simulate(x0, u, 1e-3, 500, method="rk4")
    assert rk4.status == "diverged" and rk4.diverged_at < 0.05
    assert len(rk4.time) >= 1 and np.isfinite(rk4.x).all()  # what came before is kept
    reference = plant.simulate(x0, u, 1e-5, int(horizon / 1e-5), method="rk4", record_every=10**9)
    assert reference.status == "completed"
    ros2 = plant.simulate(x0, u, 1e-3, 500, method="ros2")
    assert ros2.status == "completed"
    ref, ours = plant.split_state(reference.x[-1]), plant.split_state(ros2.x[-1])
    joint_motion = np.abs(ref["q"][7:] - plant.split_state(x0)["q"][7:]).max()
    q_error = np.abs(ours["q"] - ref["q"]).max()
    nu_error = np.abs(ours["nu"] - ref["nu"]).max() / np.abs(ref["nu"]).max()
    print(f"stiff: RK4 diverged at {rk4.diverged_at} s; ROS2 |q err| {q_error:.1e} rad "
          f"(joint motion {joint_motion:.3f} rad), relative nu error {nu_error:.1e}")
    assert joint_motion > 0.02
    assert q_error < 1e-4 and nu_error < 2e-2


# --- contacts -------------------------------------------------------------------------------


def test_contact_drift_stays_below_a_micrometre_over_10_s():
    model, plant, x0, _ = standing_icub(motor_velocity_gain=200.0)
    run = plant.simulate(x0, np.zeros(model.n_joints), 1e-3, 10_000, method="ros2", record_every=10)
    assert run.status == "completed"
    print(f"contact drift over 10 s: {run.drift_position.max():.2e} m, {run.drift_rotation.max():.2e} rad")
    assert run.drift_position.max() < 1e-6
    wrenches = run.contact_wrenches
    assert wrenches.shape == (len(run.time), 2, 6)
    total_weight = model.total_mass * 9.81
    assert abs(wrenches[-1, :, 2].sum() - total_weight) < 1e-3 * total_weight


def test_outputs_report_wrench_margins():
    model, plant, x0, gravity = standing_icub()
    out = plant.outputs(x0, ETA * gravity)
    assert out.contact_wrenches.shape == (2, 6)
    assert np.all(out.normal_force > 100.0)
    assert np.all(out.friction_margin > 0.0)
    assert out.cop_margin.shape == (2,)
    assert out.drift_position < 1e-12
    # Springs preloaded against gravity: joint torques equal the gravity torques.
    np.testing.assert_allclose(out.joint_torques, gravity, rtol=1e-9, atol=1e-9)


def test_dynamics_matches_the_integrators_derivative():
    model, plant, x0, gravity = standing_icub()
    u = ETA * gravity + 0.001
    xdot = plant.dynamics(x0, u)
    dt = 1e-7
    x1 = plant.step(x0, u, dt, method="rk4")
    np.testing.assert_allclose((x1 - x0) / dt, xdot, rtol=1e-4, atol=1e-4)


def test_mixed_actuation_rigid_joints_take_joint_torques():
    model = sm.Model.from_urdf(BIPED)
    plant = sm.Plant(model, actuator="elastic", actuators={"l_knee": "rigid", "r_knee": {"stiffness": 100.0}})
    assert "l_knee" not in plant.elastic_joints and "r_knee" in plant.elastic_joints
    assert plant.nx == model.nq + model.nv + 2 * (model.n_joints - 1)
    x0 = plant.make_state(model.neutral())
    u = np.zeros(model.n_joints)
    u[model.joint_names.index("l_knee")] = 1.0
    out = plant.outputs(x0, u)
    assert out.joint_torques[model.joint_names.index("l_knee")] == 1.0


# --- bad input ------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def biped_plant():
    model = sm.Model.from_urdf(BIPED)
    q = model.neutral()
    return model, sm.Plant(model, actuator="elastic", contacts=["l_sole"], contact_q=q)


def test_bad_states_and_inputs_are_rejected(biped_plant):
    model, plant = biped_plant
    x = plant.make_state(model.neutral())
    u = np.zeros(model.n_joints)
    with pytest.raises(ValueError, match=r"\bx\b.*shape"):
        plant.dynamics(x[:-1], u)
    with pytest.raises(ValueError, match=r"\bu\b.*shape"):
        plant.dynamics(x, u[:-1])
    bad = x.copy()
    bad[8] = np.nan
    with pytest.raises(ValueError, match=r"x\[8\]"):
        plant.step(bad, u, 1e-3)
    bad = x.copy()
    bad[3] = 2.0
    with pytest.raises(ValueError, match="quaternion"):
        plant.simulate(bad, u, 1e-3, 10)
    with pytest.raises(ValueError, match="dt"):
        plant.step(x, u, -1e-3)
    with pytest.raises(ValueError, match="method"):
        plant.step(x, u, 1e-3, method="euler")
    # Finite but beyond floating point once squared: said as a state that is not finite.
    huge = x.copy()
    huge[plant.nx - model.nv :] = 1e300
    with pytest.raises(sm.SolverError, match="the state is not finite"):
        plant.step(huge, u, 1e-3)
    for evaluate in (plant.dynamics, plant.outputs):
        with pytest.raises(sm.SolverError, match="too large for float64"):
            evaluate(huge, u)
        with pytest.raises(sm.SolverError, match="too large for float64"):
            evaluate(x, np.full(model.n_joints, 1e308))


def test_bad_plant_settings_are_rejected():
    model = sm.Model.from_urdf(BIPED)
    q = model.neutral()
    with pytest.raises(ValueError, match="no_such_frame"):
        sm.Plant(model, contacts=["no_such_frame"], contact_q=q)
    with pytest.raises(ValueError, match="contact_q"):
        sm.Plant(model, contacts=["l_sole"])
    with pytest.raises(ValueError, match=r"actuator\['stiffness'\]: expected a number, positive and finite"):
        sm.Plant(model, actuator={"stiffness": -1.0})
    with pytest.raises(ValueError, match=r"actuator\['stiffness'\]: expected a number, got 'x'"):
        sm.Plant(model, actuator={"stiffness": "x"})
    not_unit = q.copy()
    not_unit[3:7] = 0.0
    with pytest.raises(ValueError, match=r"contact_q\[3:7\]: expected a unit quaternion"):
        sm.Plant(model, contacts=["l_sole"], contact_q=not_unit)
    with pytest.raises(ValueError, match="motor_inertia"):
        sm.Plant(model, actuators={"l_knee": {"motor_inertia": 0.0}})
    with pytest.raises(ValueError, match="torque_limit"):
        sm.Plant(model, actuator={"torque_limit": -0.3})
    with pytest.raises(ValueError, match="unknown actuator key 'stifness'"):
        sm.Plant(model, actuator={"stifness": 3.0})
    with pytest.raises(ValueError, match="unknown joint 'knee'"):
        sm.Plant(model, actuators={"knee": "rigid"})
    with pytest.raises(ValueError, match="baumgarte_kp"):
        sm.Plant(model, baumgarte_kp=-5.0)
    with pytest.raises(ValueError, match="motor_velocity_gain"):
        sm.Plant(model, motor_velocity_gain=0.0)
    with pytest.raises(ValueError, match=r"actuators\['l_knee'\]\['damping'\]: expected no such key with kind 'rigid'"):
        sm.Plant(model, actuators={"l_knee": {"kind": "rigid", "damping": 3.0}})
    with pytest.raises(ValueError, match=r"gravity: expected three finite numbers .*, got \(0, 0\)"):
        sm.Plant(model, gravity=(0.0, 0.0))
    with pytest.raises(ValueError, match=r"gravity: expected three finite numbers"):
        sm.Plant(model, gravity="abc")
    with pytest.raises(ValueError, match=r"foot_y: expected \(min, max\) .*, got \(0.1\)"):
        sm.Plant(model, foot_y=[0.1])
    with pytest.raises(ValueError, match=r"foot_x: expected \(min, max\)"):
        sm.Plant(model, foot_x=(0.1, -0.1))
    sm.Plant(model, gravity=np.array([0.0, 0.0, -3.0]), foot_x=[-0.1, 0.1])


def test_divergence_stops_with_status_and_keeps_the_data():
    model, plant, x0, gravity = standing_icub(actuator={"stiffness": 1e4}, motor_velocity_gain=1e4)
    run = plant.simulate(x0, np.zeros(model.n_joints), 1e-3, 1000, method="rk4")
    assert run.status == "diverged"
    assert 0.0 < run.diverged_at <= 1.0
    assert run.message
    n = len(run.time)
    assert n >= 1 and run.x.shape == (n, plant.nx) and run.time[-1] < run.diverged_at
    assert np.isfinite(run.x).all()


def test_a_first_step_that_fails_keeps_the_initial_state():
    model, plant, x0, _ = standing_icub()
    run = plant.simulate(x0, np.full(model.n_joints, 1e300), 1e-3, 3)
    assert run.status == "diverged" and run.message
    assert run.x.shape == (1, plant.nx) and run.time[0] == 0.0
    assert np.array_equal(run.x[0], x0)


def test_results_are_dataclasses_with_the_documented_dtypes_and_shapes():
    model, plant, x0, gravity = standing_icub()
    n_e, n_contacts = len(plant.elastic_joints), len(plant.contact_frames)
    run = plant.simulate(x0, ETA * gravity, 1e-3, 10, record_every=4)
    assert isinstance(run, sm.SimulationResult)
    rows = 4  # steps 0, 4, 8 and the last one, 10
    shapes = {
        "time": (rows,),
        "x": (rows, plant.nx),
        "contact_wrenches": (rows, n_contacts, 6),
        "motor_torques": (rows, n_e),
        "drift_position": (rows,),
        "drift_rotation": (rows,),
    }
    for name, shape in shapes.items():
        array = getattr(run, name)
        assert array.dtype == np.float64 and array.shape == shape, name
    np.testing.assert_allclose(run.time, [0.0, 4e-3, 8e-3, 1e-2], atol=1e-15)
    assert (run.status, run.diverged_at, run.message) == ("completed", None, "")
    assert run["x"] is run.x  # the dict interface of earlier versions still answers
    with pytest.raises(KeyError):
        run["nope"]

    out = plant.outputs(x0, ETA * gravity)
    assert isinstance(out, sm.PlantOutputs)
    assert out.joint_torques.shape == (model.n_joints,) and out.motor_torques.shape == (n_e,)
    for name in ("normal_force", "friction_margin", "cop_margin"):
        assert getattr(out, name).shape == (n_contacts,) and getattr(out, name).dtype == np.float64
    assert isinstance(out.drift_position, float) and isinstance(out.drift_rotation, float)
    assert set(out.to_dict()) == {f.name for f in dataclasses.fields(out)}
