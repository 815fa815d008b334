"""`python -m sea_momentum reproduce`: the figures, the table and the evidence it writes.

The whole pipeline runs once, shortened (0.5 s runs, a 2 x 2 stability map, 3 damping scales
on the growth-rate curve), so the test checks the wiring and the consistency of what is
reported, not the paper's outcomes (test_paper.py does that): every number in outcomes.md
comes from summary.json, and the stability map's simulations agree with its eigenvalue
boundary away from it.
"""

from __future__ import annotations

import json
import pathlib
from types import SimpleNamespace

import numpy as np
import pytest

import sea_momentum as sm  # a failed import fails the run (no importorskip)
from sea_momentum import paper
from sea_momentum.paper import evidence, outcomes, setting, stability_map

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAPER = ROOT / "scenarios" / "paper"
FIGURES = (
    "figure1_tracking_damping.png",
    "figure2_rigid_vs_sea.png",
    "figure3_saturation.png",
    "stability_map.png",
    "growth_rate_damping.png",
    # The robot at chosen instants of each experiment.
    *(f"{name}_strip.png" for name in ("tracking", "step_sea", "step_rigid", "saturation")),
    *(f"{name}.gif" for name in ("tracking", "step_sea", "step_rigid", "saturation")),
)


@pytest.fixture(scope="module")
def reproduced(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    with pytest.MonkeyPatch.context() as patch:
        # Rates far from both boundaries (x0.4: about 1.7 kHz, x1.0: about 0.7 kHz).
        patch.setattr(stability_map, "MAP_SCALES", (0.4, 1.0))
        patch.setattr(stability_map, "MAP_RATES_HZ", (200.0, 5000.0))
        patch.setattr(evidence, "GROWTH_SCALES", (0.4, 1.0, 1.6))
        summary = paper.reproduce(PAPER, out, duration=0.5)
    return out, summary


def test_every_output_is_written(reproduced):
    out, summary = reproduced
    for name in FIGURES + ("outcomes.md", "summary.json", "tracking.mcap", "step_sea.mcap", "saturation.mcap"):
        assert (out / name).stat().st_size > 0, name
    assert json.loads((out / "summary.json").read_text())["experiments"].keys() == setting.PAPER.keys()
    assert summary["wall_time_s"] > 0


def test_outcomes_state_both_settings_and_the_computed_evidence(reproduced):
    out, summary = reproduced
    text = (out / "outcomes.md").read_text()
    assert "Continuous" in text and "1 kHz zero-order hold" in text
    for label in setting.PAPER:
        assert f"| {label} | {setting.PAPER[label]} |" in text, label
    # The boundaries in the text are the ones computed by the run.
    at_1khz = summary["margins"]["damping scale 0.2-3, 1 kHz, dt 1 ms"]
    assert len(at_1khz) == 1 and f"{at_1khz[0]:.3g} with dt 1 ms" in text
    assert summary["margins"]["damping scale 0.2-3, continuous"] == []
    assert "mirrored" not in text
    growth = summary["linearizations"]["1 kHz x0.4"]["growth_rate_1_s"]
    assert f"{growth:+.3f} 1/s" in text


def test_linearisations_explain_the_x04_outcomes(reproduced):
    _, summary = reproduced
    continuous, held = (summary["linearizations"][k] for k in ("continuous x0.4", "1 kHz x0.4"))
    assert continuous["stable"] and not held["stable"]
    assert held["dominant_states"][0][0].endswith(":l_ankle_roll")
    # The unstable sampled mode is an SEA mode, not a balancing mode.
    assert held["least_stable_frequency_rad_s"] > evidence.SEA_MODE_MIN_FREQUENCY


def test_stability_map_simulations_agree_with_the_eigenvalue_boundary(reproduced):
    _, summary = reproduced
    grid = summary["stability_map"]
    stable = np.array(grid["stable"])
    assert stable[:, -1].all()  # continuous: every scale stable
    for row, boundary in enumerate(grid["boundary_rate_hz"]):
        assert boundary is not None
        for col, rate in enumerate(grid["rates_hz"]):
            assert stable[row, col] == (rate > boundary), (grid["scales"][row], rate, boundary)


def test_verdicts_compare_with_the_paper():
    completed = SimpleNamespace(status="completed")
    diverged = SimpleNamespace(status="diverged")
    assert outcomes.verdict("tracking x1.6", diverged) == "agrees"
    assert outcomes.verdict("tracking x1.6", completed) == "**disagrees**"
    assert outcomes.verdict("tracking x0.4", completed) == "agrees"
    assert set(setting.PAPER_STABLE) == set(setting.PAPER)


def test_sea_modes_are_one_pair_per_elastic_joint():
    lin = sm.linearize(PAPER / "tracking.toml")
    n_elastic = len(sm.Scenario.load(PAPER / "tracking.toml").plant.elastic_joints)
    modes = evidence.sea_modes(lin)
    assert len(modes) == 2 * n_elastic
    assert np.all(modes.real < 0)
