"""``scripts/planned_vs_delivered.py``: its episodes of a mask, and on the iCub's steps in
place the touchdowns it finds (docs/findings/stepping.md, "The planned and the delivered
wrenches at each touchdown")."""
from __future__ import annotations

from pathlib import Path

import numpy as np
from load_file import load_file  # a helper beside the tests (see conftest.py)

ROOT = Path(__file__).resolve().parents[1]
STEPS = str(ROOT / "scenarios" / "walking" / "steps_in_place.toml")

script = load_file("scripts/planned_vs_delivered.py")


def test_episodes_are_the_runs_of_the_mask_per_contact_in_time_order():
    mask = np.array([[1, 0], [1, 0], [0, 1], [1, 1], [0, 0]], dtype=bool)
    force = np.arange(10.0).reshape(5, 2)
    time = 0.01 * np.arange(5)
    found = script.episodes(mask, force, time, 0.01)
    assert [(t, c) for t, c, _, _ in found] == [(0.0, 0), (0.02, 1), (0.03, 0)]
    np.testing.assert_allclose([d for _, _, d, _ in found], [20.0, 20.0, 10.0])
    assert [p for _, _, _, p in found] == [2.0, 7.0, 6.0]


def test_on_steps_in_place_the_landing_foot_is_planned_its_load_before_it_is_loaded(capsys):
    run, found = script.measure(STEPS, script.DEFAULTS)
    assert run.status == "completed"
    assert found["air"], "no touchdown planned a load on a foot in the air"
    weight = np.median(run.contact_wrenches[:, :, 2].sum(axis=1))
    period = run.time[1] - run.time[0]
    for start, contact, duration_ms, peak in found["air"]:
        assert 0.05 * weight < peak <= 1.5 * weight
        # The foot lands within 0.1 s after the episode: it was planned its load early.
        end = int(np.searchsorted(run.time, start)) + round(duration_ms * 1e-3 / period)
        landed = run.contact_wrenches[end : end + 10, contact, 2] > 0.05 * weight
        assert landed.any(), f"the {run.contacts[contact]} episode at {start:.2f} s"
    script.main([STEPS])
    out = capsys.readouterr().out
    assert "load planned on a foot in the air" in out and "completed" in out
