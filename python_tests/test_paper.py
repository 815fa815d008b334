"""The paper's experiments as integration tests (section "Simulation results"), plus the
scenario API: overrides, errors naming the key, MCAP logs read back with the `mcap` package.

Setting. The paper's scenarios (scenarios/paper/*.toml) are in the paper's setting: the
controller evaluated continuously (at every integrator stage, as inside ode15s's right-hand
side; `controller.sampling = "continuous"`, plant step 0.25 ms). The sampled-data findings are
tested separately, at 1 kHz zero-order hold with one 1 ms plant step per tick (`SAMPLED_1KHZ`).

Outcomes, paper vs ours in the paper's setting:
- K_D estimate x1.0, x1.45: stable (agree); x0.4: stable (agrees; it diverges only when the
  controller is sampled at 1 kHz, below the sampled-data boundary);
- x1.6: the paper reports it unstable; our model is stable, and its linearisation shows why
  (the SEA modes keep Re = -K_m / 2 whatever the estimate; the least stable mode is a slow
  balancing mode). The tests pin OUR outcome and name this disagreement;
  `python -m sea_momentum reproduce` reports both with the eigenvalue evidence;
- rigid controller on the SEA robot after the step: unstable (agrees); SEA controller:
  converges (agrees);
- saturation at 0.34 Nm, springs at rest at the start: the limit binds and the loop stays
  stable (agrees).
Stability is judged twice where it is cheap: by a short run and by the linearisation.
"""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest

import sea_momentum as sm  # a failed import fails the run (no importorskip)

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAPER = ROOT / "scenarios" / "paper"
TRACKING = PAPER / "tracking.toml"
#: The sampled-data setting of the 1 kHz findings: zero-order hold at the scenario's 1 kHz
#: rate, one 1 ms plant step per tick.
SAMPLED_1KHZ = {"controller.sampling": "zero_order_hold", "plant.dt": 1e-3}


def damping(scale: float) -> dict:
    """The override of the controller's damping estimate scale."""
    return {"controller.damping_estimate_scale": scale}


def test_paper_scenarios_are_in_the_paper_setting():
    for name in ("tracking", "step_sea", "step_rigid", "saturation"):
        assert sm.Scenario.load(PAPER / f"{name}.toml").sampling == "continuous", name


@pytest.fixture(scope="module")
def tracking():
    # One period of the 0.2 Hz reference after its 1 s smooth start.
    return sm.run_scenario(TRACKING, {"simulation.duration_s": 6.0})


def test_nominal_tracking_is_stable_with_millimetre_error(tracking):
    assert tracking.status == "completed" and tracking.summary.sampling == "continuous"
    after_start = tracking.time >= 2.0
    lateral = np.abs(tracking.com[after_start, 1] - tracking.com_reference[after_start, 1])
    assert lateral.max() < 3e-3  # "a few millimetres at most"
    assert np.ptp(tracking.com_reference[:, 1]) > 0.015  # the 1 cm sinusoid is really tracked
    assert tracking.summary.qp_failures == 0
    assert tracking.qp_solved.all()


def test_qp_wrenches_satisfy_the_contact_constraints(tracking):
    # Simulated wrench of the stance sole, in the sole frame (the sole stays flat: world axes).
    wrench = tracking.contact_wrenches[:, 0, :]
    force, moment = wrench[:, :3], wrench[:, 3:]
    assert (force[:, 2] > 10.0 - 1e-3).all()  # minimum normal force
    assert (np.linalg.norm(force[:, :2], axis=1) <= force[:, 2]).all()  # friction, mu = 1
    cop_x, cop_y = -moment[:, 1] / force[:, 2], moment[:, 0] / force[:, 2]
    assert (cop_x > -0.05 - 1e-4).all() and (cop_x < 0.10 + 1e-4).all()
    assert (cop_y > -0.025 - 1e-4).all() and (cop_y < 0.025 + 1e-4).all()


def sea_mode_decay(lin) -> float:
    """The mean real part [1/s] of the SEA modes (the fast oscillatory pairs, one per joint),
    after checking that they share it."""
    sea_modes = lin.eigenvalues[np.abs(lin.eigenvalues.imag) > 200.0]
    assert len(sea_modes) >= 2
    decay = float(sea_modes.real.mean())
    assert np.all(np.abs(sea_modes.real - decay) < 0.05 * abs(decay))
    return decay


@pytest.fixture(scope="module")
def nominal_linearization():
    return sm.linearize(TRACKING)


@pytest.mark.parametrize("scale", [1.45, 1.6, 0.4])
def test_damping_mismatch_is_stable_in_the_paper_setting(scale, nominal_linearization):
    """Paper: x1.45 stable, x0.4 stable, x1.6 unstable. Ours, continuous: all three stable.

    x1.6 is a disagreement with the paper: in our model over-estimating K_D only slows the
    applied torque's convergence (time constant K_D_hat / K_S, about 1 ms); the SEA modes keep
    their real part -K_m / 2 (about -100 1/s) and the least stable mode is a slow balancing
    mode. Nothing in the model (rigid contacts, ideal motor velocity loop, QP constraints
    inactive at the equilibrium) destabilises it.
    """
    result = sm.run_scenario(TRACKING, {**damping(scale), "simulation.duration_s": 3.0})
    assert result.status == "completed"
    lin = sm.linearize(TRACKING, overrides=damping(scale))
    assert lin.sampling == "continuous" and lin.converged
    assert -2.0 < lin.growth_rate < 0.0  # a slow balancing mode, not an SEA mode
    # The SEA modes decay as fast as with the exact estimate (-K_m / 2, set by the motor
    # velocity loop), far faster than the balancing modes.
    nominal_decay = sea_mode_decay(nominal_linearization)
    assert nominal_decay < 50.0 * lin.growth_rate
    assert sea_mode_decay(lin) == pytest.approx(nominal_decay, rel=0.05)


def test_damping_underestimated_by_60_percent_diverges_sampled_at_1khz():
    """The sampled-data finding: at 1 kHz zero-order hold (1 ms plant step) x0.4 lies below
    the stability boundary (about x0.46), and the SEA mode of the stance ankle roll grows. On
    the real (unilateral) contact the robot falls first: the stance foot's wrench leaves its
    constraints before the joint error reaches its divergence bound."""
    overrides = {**SAMPLED_1KHZ, **damping(0.4)}
    fallen = sm.run_scenario(TRACKING, overrides)
    assert fallen.status == "fell" and fallen.summary.fall_foot == "l_sole"
    result = sm.run_scenario(TRACKING, {**overrides, "simulation.stop_on_fall": False})
    assert result.status == "diverged"
    assert 0.0 < fallen.summary.fell_at_s < result.summary.diverged_at_s < 5.0
    assert len(result.time) > 10 and np.isfinite(result.q).all()  # data kept until then
    lin = sm.linearize(TRACKING, overrides=overrides)
    assert lin.sampling == "zero_order_hold" and lin.growth_rate > 0.0
    assert lin.dominant_states[0][0].endswith(":l_ankle_roll")
    assert sm.linearize(TRACKING, overrides=SAMPLED_1KHZ).stable  # x1.0 is above the boundary


def test_rigid_controller_diverges_after_the_step_and_sea_converges():
    sea = sm.run_scenario(PAPER / "step_sea.toml", {"simulation.duration_s": 5.0})
    # The oscillation grows for seconds; the stance foot's centre of pressure leaves the sole
    # (about 3.3 s) long before the joint error reaches its divergence bound (7.6 s).
    rigid = sm.run_scenario(PAPER / "step_rigid.toml")
    assert sea.status == "completed"
    assert sea.joint_error_norm[-1] < 0.2
    assert rigid.status == "fell"
    assert rigid.summary.fall_foot == "l_sole" and rigid.summary.fall_constraint == "center_of_pressure"
    assert rigid.summary.fell_at_s > 0.5  # after the step
    # On bilateral contacts (no fall) the oscillation grows until the joint error bound, its
    # motor velocities far above the SEA controller's.
    bilateral = sm.run_scenario(PAPER / "step_rigid.toml", {"simulation.stop_on_fall": False})
    assert bilateral.status == "diverged" and bilateral.summary.diverged_at_s > rigid.summary.fell_at_s
    assert bilateral.summary.motor_velocity_peak_rad_s > 5 * sea.summary.motor_velocity_peak_rad_s


def test_saturation_with_springs_at_rest_binds_and_stays_stable():
    """The saturation scenario starts with the springs at rest (the original study's start):
    the stance ankle roll's motor torque reaches the 0.34 Nm limit while the springs load, and
    the loop stays stable. With preloaded springs the same limit never binds."""
    short = {"simulation.duration_s": 2.0, "simulation.record_every": 1}
    at_rest = sm.run_scenario(PAPER / "saturation.toml", short)
    preloaded = sm.run_scenario(
        PAPER / "saturation.toml", {**short, "robot.initial_springs": "preloaded"}
    )
    k = at_rest.motor("l_ankle_roll")
    limit = 0.34  # the scenario's limit, the motor's datasheet value
    torque = np.abs(at_rest.motor_torques[:, k])
    assert at_rest.status == "completed"
    assert torque.max() <= limit + 1e-12
    assert (torque >= limit - 1e-9).any()  # the limit was active
    assert preloaded.status == "completed"
    assert np.abs(preloaded.motor_torques[:, k]).max() < 0.5 * limit
    # Loading the springs drives a motor velocity peak several times the preloaded start's.
    assert np.abs(at_rest.thetadot[:, k]).max() > 2.0 * np.abs(preloaded.thetadot[:, k]).max()


def test_run_summary_and_arrays_are_typed():
    result = sm.run_scenario(TRACKING, {"simulation.duration_s": 0.2})
    summary = result.summary
    assert isinstance(summary, sm.RunSummary)
    assert summary.status == result.status == summary["status"] == "completed"
    assert summary.diverged_at_s is None and summary.reason == ""
    assert 0.19 < summary.duration_s < 0.21
    assert isinstance(summary.qp_failures, int) and isinstance(summary.qp_clarabel_solves, int)
    assert json.loads(json.dumps(summary.to_dict())) == summary.to_dict()  # summary.json as before
    m, n_e, n_contacts = len(result.time), len(result.elastic_joints), len(result.contacts)
    shapes = {
        "q": (m, 7 + len(result.joint_names)),
        "nu": (m, 6 + len(result.joint_names)),
        "theta": (m, n_e),
        "thetadot_desired": (m, n_e),
        "com": (m, 3),
        "momentum": (m, 6),
        "contact_wrenches": (m, n_contacts, 6),
        "planned_wrenches": (m, n_contacts, 6),
        "qp_solved": (m,),
        "disturbance_wrench": (m, 6),
    }
    for name, shape in shapes.items():
        array = getattr(result, name)
        assert array.dtype == np.float64 and array.shape == shape, name


def test_mcap_log_reads_back(tmp_path):
    import mcap.reader as reader
    from mcap_protobuf.decoder import DecoderFactory

    path = tmp_path / "run.mcap"
    result = sm.run_scenario(TRACKING, {"simulation.duration_s": 0.5}, mcap=path)
    with open(path, "rb") as stream:
        mcap = reader.make_reader(stream)
        summary = mcap.get_summary()
        schemas = {s.name for s in summary.schemas.values()}
        topics = {c.topic for c in summary.channels.values()}
        counts = summary.statistics.channel_message_counts
        times = {}
        for schema, channel, message in mcap.iter_messages():
            times.setdefault(channel.topic, []).append(message.log_time)
            if channel.topic == "/tf":  # the Foxglove SDK's protobuf message
                tf = DecoderFactory().decoder_for(channel.message_encoding, schema)(message.data)
    assert "foxglove.FrameTransforms" in schemas
    assert {"/tf", "/com", "/momentum", "/joints", "/motors", "/contact_wrenches", "/qp"} <= topics
    # Every channel has one message per sample, except the robot's bodies, written once.
    assert counts[next(i for i, c in summary.channels.items() if c.topic == "/robot")] == 1
    assert all(
        count == len(result.time)
        for channel, count in counts.items()
        if summary.channels[channel].topic != "/robot"
    )
    assert all(np.all(np.diff(t) > 0) for t in times.values())
    assert len(tf.transforms) == len(sm.Model.from_urdf(ROOT / "urdf" / "icub25.urdf").frame_names)


def test_mcap_log_is_finished_when_the_run_diverges(tmp_path):
    import mcap.reader as reader

    path = tmp_path / "diverged.mcap"
    # diverges within 5 s (on bilateral contacts: it would fall before)
    overrides = {**SAMPLED_1KHZ, **damping(0.4), "simulation.stop_on_fall": False}
    result = sm.run_scenario(TRACKING, overrides, mcap=path)
    assert result.status == "diverged"
    with open(path, "rb") as stream:
        summary = reader.make_reader(stream).get_summary()
    assert summary is not None and summary.statistics.message_count > 0


@pytest.mark.parametrize(
    "overrides, key",
    [
        ({"controller.dampnig_estimate_scale": 1.0}, "dampnig_estimate_scale"),
        ({"controller.kind": "pid"}, "controller.kind"),
        ({"plant.dt": -1.0}, "plant.dt"),
        ({"controller.damping_estimate_scale": 0.0}, "damping_estimate_scale"),
        ({"robot.contacts": ["no_such_sole"]}, "no_such_sole"),
        ({"reference.posture_step_joints": ["neck"]}, "neck"),
        ({"actuators.overrides.knee.stiffness": 10.0}, "knee"),
    ],
)
def test_bad_scenarios_name_the_key(overrides, key):
    with pytest.raises(ValueError, match=key):
        sm.run_scenario(TRACKING, overrides)


def test_malformed_toml_and_missing_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[robot\nurdf = 'x'\n")
    with pytest.raises(ValueError, match="malformed TOML"):
        sm.run_scenario(bad)
    with pytest.raises(OSError):
        sm.run_scenario(tmp_path / "missing.toml")
