"""Pushes and falls in Python: a `[[disturbances]]` push given as an override, and the fall
(status "fell", the foot, the constraint with its value and bound) in the run's summary."""

from pathlib import Path

import sea_momentum as sm

PUSH = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "push_two_feet.toml"
#: The shipped robot-rate scenarios run the stiffness identification; these tests were written
#: for the fixed estimates (a test that wants the identification sets it after these).
#: The proxy these tests were written for (as ``WELDED_FEET`` of the Rust tests): the feet
#: welded (bilateral contacts, a fall the wrench check's), a joint at its limit ending the run.
WELDED_FEET = {
    "plant.contact_model": "bilateral",
    "simulation.stop_at_joint_limits": True,
    "simulation.divergence_joint_error_rad": 1.0,
    "simulation.divergence_com_error_m": 0.1,
}
FIXED = {**WELDED_FEET, "controller.stiffness_identification": False}


def push(impulse_n_s: float) -> dict[str, object]:
    """A 0.1 s forward push (world +x, the soles' forward axis) on the pelvis at 1 s."""
    return {"link": "root_link", "force": [impulse_n_s / 0.1, 0.0, 0.0], "start_s": 1.0, "duration_s": 0.1}


def test_a_small_push_is_recovered_and_a_large_one_falls_on_a_named_foot():
    small = sm.run_scenario(PUSH, {**FIXED, "disturbances": [push(5.0)]})
    assert small.status == "completed" and small.summary.fall_foot is None
    large = sm.run_scenario(PUSH, {**FIXED, "disturbances": [push(20.0)]})
    s = large.summary
    assert large.status == "fell", s.reason
    assert s.fall_foot in ("l_sole", "r_sole")
    assert s.fall_constraint == "center_of_pressure"
    assert s.fall_bound == 0.1 and s.fall_value is not None and s.fall_value > 0.1
    assert s.fell_at_s is not None and 1.0 < s.fell_at_s < 3.0 and s.diverged_at_s is None
    assert large.time[-1] == s.fell_at_s  # the falling sample is the last one recorded


def test_the_push_applied_at_each_sample_is_in_the_result():
    """``disturbance_wrench`` (m, 6): the push's world wrench at the samples of its window;
    ``external_wrench`` (m, 6): the scenario's observer's estimate the controller took, zero
    before the push, then rising towards the push's force (5 Hz low pass, one period late)."""
    import numpy as np

    overrides = {**FIXED, "disturbances": [push(5.0)], "simulation.duration_s": 1.5, "simulation.record_every": 1}
    result = sm.run_scenario(PUSH, overrides)
    wrench = result.disturbance_wrench
    assert wrench.dtype == np.float64 and wrench.shape == (len(result.time), 6)
    inside = (result.time >= 1.0 - 1e-9) & (result.time < 1.1 - 1e-9)
    assert inside.sum() == 10  # the whole-body ticks (100 Hz) of the 0.1 s window
    assert (wrench[inside] == [50.0, 0.0, 0.0, 0.0, 0.0, 0.0]).all()
    assert (wrench[~inside] == 0.0).all()
    estimate = result.external_wrench
    assert estimate.dtype == np.float64 and estimate.shape == (len(result.time), 6)
    assert np.abs(estimate[result.time < 1.0 - 1e-9]).max() < 1.0
    at_end = estimate[inside][-1]
    assert 25.0 < at_end[0] < 55.0 and abs(at_end[1]) < 2.0, at_end


def test_a_fall_is_a_warning_on_events_and_the_run_metadata_of_the_log(tmp_path):
    """The MCAP of a fall: one ``foxglove.Log`` WARNING on ``/events`` at the fall's time naming
    the foot and the constraint, and the metadata record ``run`` with the fall's fields."""
    from mcap.reader import make_reader
    from mcap_protobuf.decoder import DecoderFactory

    path = tmp_path / "fall.mcap"
    result = sm.run_scenario(PUSH, {**FIXED, "disturbances": [push(20.0)]}, mcap=path)
    s = result.summary
    assert result.status == "fell"
    with open(path, "rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        events = [
            (message.log_time, decoded)
            for _, _, message, decoded in reader.iter_decoded_messages(topics=["/events"])
        ]
        metadata = {record.name: record.metadata for record in reader.iter_metadata()}
    assert len(events) == 1
    time_ns, log = events[0]
    assert time_ns == round(s.fell_at_s * 1e9)
    assert log.level == 3  # WARNING
    assert s.fall_foot in log.message and s.fall_constraint in log.message
    run = metadata["run"]
    assert run["status"] == "fell" and run["fall_foot"] == s.fall_foot
    assert float(run["fall_value"]) == s.fall_value and float(run["fall_bound"]) == s.fall_bound
