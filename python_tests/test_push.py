"""Pushes and falls in Python: a `[[disturbances]]` push given as an override, and the fall
(status "fell", the foot, the constraint with its value and bound) in the run's summary."""

from pathlib import Path

import sea_momentum as sm

PUSH = Path(__file__).resolve().parents[1] / "scenarios" / "robot_rate" / "push_two_feet.toml"


def push(impulse_n_s: float) -> dict[str, object]:
    """A 0.1 s forward push (world +x, the soles' forward axis) on the pelvis at 1 s."""
    return {"link": "root_link", "force": [impulse_n_s / 0.1, 0.0, 0.0], "start_s": 1.0, "duration_s": 0.1}


def test_a_small_push_is_recovered_and_a_large_one_falls_on_a_named_foot():
    small = sm.run_scenario(PUSH, {"disturbances": [push(5.0)]})
    assert small.status == "completed" and small.summary.fall_foot is None
    large = sm.run_scenario(PUSH, {"disturbances": [push(8.0)]})
    s = large.summary
    assert large.status == "fell", s.reason
    assert s.fall_foot in ("l_sole", "r_sole")
    assert s.fall_constraint == "center_of_pressure"
    assert s.fall_bound == 0.1 and s.fall_value is not None and s.fall_value > 0.1
    assert s.fell_at_s is not None and 1.0 < s.fell_at_s < 3.0 and s.diverged_at_s is None
    assert large.time[-1] == s.fell_at_s  # the falling sample is the last one recorded
