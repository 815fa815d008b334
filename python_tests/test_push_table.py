"""``sm.push_table``: the push study of ``sea-sim push`` from Python. Fixed impulses report
each run; the bisection brackets the boundary between a recovered and a lost push and agrees
with the fixed runs; a push at a phase of a walk's swing starts where ``sea-sim push --phase``
starts it; bad arguments name themselves; Ctrl-C returns the rows done."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import pytest

import sea_momentum as sm

ROOT = Path(__file__).resolve().parents[1]
STANDING = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
WALK = ROOT / "scenarios" / "walking" / "walk_push.toml"
#: walk_push.toml cut after its fifth step's swing (the push must end within the run).
SHORT_WALK = {"simulation.duration_s": 2.7}


def test_fixed_impulses_report_each_run_in_the_order_given():
    # No push, and three times the forward capture-point bound (13.4 N s).
    table = sm.push_table(STANDING, ["forward"], impulses=[40.0, 0.0])
    row = table.row("forward")
    assert not table.interrupted and not row.interrupted
    assert [impulse for impulse, _ in row.pushes] == [40.0, 0.0]
    assert row.pushes[0][1] in ("diverged", "fell") and row.pushes[1][1] == "completed"
    assert row.recovered_impulse_n_s == 0.0 and row.failed_impulse_n_s == 40.0
    assert 13.0 < row.capture_point_impulse_n_s < 14.0
    with pytest.raises(KeyError, match="'left' is not in this study \\(forward\\)"):
        table.row("left")
    assert table["rows"][0]["direction"] == "forward" and table.to_dict()["interrupted"] is False


def test_the_bisection_brackets_the_boundary_and_agrees_with_single_runs():
    table = sm.push_table(STANDING, "left", tolerance_n_s=1.0)
    row = table.row("left")
    recovered, failed = row.recovered_impulse_n_s, row.failed_impulse_n_s
    assert recovered is not None and failed is not None
    assert 0.0 < recovered < failed <= recovered + 1.0
    assert len(row.pushes) >= 3 and row.ratio == pytest.approx(recovered / row.capture_point_impulse_n_s)
    # The bracket's two ends, run again one by one: the same outcomes.
    again = sm.push_table(STANDING, "left", impulses=[recovered, failed]).row("left")
    assert again.pushes[0][1] == "completed" and again.pushes[1][1] != "completed"


def _start(phase, step=None, impulses=(0.0,)):
    """The push table of left pushes of ``impulses`` at ``phase`` of step ``step``'s swing."""
    return sm.push_table(WALK, "left", impulses=list(impulses), overrides=SHORT_WALK, phase=phase, step=step)


def test_a_push_at_a_phase_of_a_swing_starts_there():
    # walk_push.toml: steps of 0.4 s, each a 0.3 s swing and a 0.1 s double support; the
    # fourth step (3, the default) from lift-off to touchdown, then the fifth's lift-off.
    lift_off, middle, touchdown = (_start(phase).start_s for phase in (0.0, 0.5, 1.0))
    assert touchdown - lift_off == pytest.approx(0.3, abs=1e-9)
    assert middle == pytest.approx(lift_off + 0.15, abs=1e-9)
    assert _start(0.0, step=4).start_s == pytest.approx(lift_off + 0.4, abs=1e-9)
    # The time sea-sim push --phase reports for this walk (the plan's, on a plant step).
    assert middle == pytest.approx(1.95, abs=1e-9)
    # The push at the phase is the push at that time.
    by_phase = _start(0.5, impulses=(3.0, 12.0))
    by_time = sm.push_table(WALK, "left", impulses=[3.0, 12.0], overrides=SHORT_WALK, start_s=middle)
    assert by_phase.row("left").pushes == by_time.row("left").pushes
    assert sm.push_table(STANDING, "left", impulses=[0.0]).start_s == 1.0


def test_a_run_that_ends_soon_after_the_push_is_warned_of():
    # 0.1 s of run after the push: a push that fells the robot may not have fallen yet.
    with pytest.warns(UserWarning, match=r"ends 0\.100 s after the push.*about 1 s"):
        sm.push_table(STANDING, "left", impulses=[0.0], overrides={"simulation.duration_s": 1.2})
    # Bad impulses are refused before that warning (and a 1e308 one named in exponent form).
    for bad, shown in ((-1.0, "-1"), (1e308, "1e308")):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ValueError, match=f"got {shown}") as refused:
                short = {"simulation.duration_s": 1.2}
                sm.push_table(STANDING, "left", impulses=[bad], overrides=short)
        assert refused.value.argument == "impulses"


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"phase": 1.5}, "phase"),
        ({"phase": 0.5, "start_s": 1.0}, "start_s"),
        ({"step": 3}, "step"),
        ({"phase": 0.5, "step": 99}, "step"),
        ({"phase": 0.5, "step": -1}, "step"),
        # The fifth step's touchdown is at 2.5 s: a push from it ends after the 2.55 s run.
        ({"phase": 1.0, "step": 4, "overrides": {"simulation.duration_s": 2.55}}, "phase"),
    ],
)
def test_a_bad_phase_or_step_names_itself(kwargs, named):
    kwargs.setdefault("overrides", SHORT_WALK)
    with pytest.raises(ValueError, match=named) as info:
        sm.push_table(WALK, "left", impulses=[0.0], **kwargs)
    assert info.value.argument == named


def test_a_phase_on_a_scenario_that_does_not_walk_names_phase():
    with pytest.raises(ValueError, match="phase") as info:
        sm.push_table(STANDING, "left", impulses=[0.0], phase=0.5)
    assert info.value.argument == "phase"


@pytest.mark.parametrize(
    ("argument", "value"),
    [("duration_s", 0.0), ("tolerance_n_s", -1.0), ("start_s", float("nan"))],
)
def test_bad_options_name_themselves(argument, value):
    with pytest.raises(ValueError, match=argument) as info:
        sm.push_table(STANDING, "forward", **{argument: value})
    assert info.value.argument == argument


@pytest.mark.parametrize(
    ("argument", "kwargs"),
    [
        ("impulses", {"impulses": [1.0, -2.0]}),
        ("impulses", {"impulses": []}),
        ("directions", {"directions": []}),
        ("directions", {"directions": ["left", "left"]}),
        # The push would come after the 3 s run's end: "recovered" at any size.
        ("start_s", {"start_s": 10.0}),
        ("link", {"link": "no_such_link"}),
    ],
)
def test_bad_arguments_name_themselves(argument, kwargs):
    kwargs.setdefault("directions", "forward")
    with pytest.raises(ValueError, match=argument) as info:
        sm.push_table(STANDING, **kwargs)
    assert info.value.argument == argument


def test_a_bad_direction_name_or_impulses_as_text_are_refused():
    with pytest.raises(sm.ScenarioError, match="up"):
        sm.push_table(STANDING, ["forward", "up"])
    with pytest.raises(TypeError, match="impulses"):
        sm.push_table(STANDING, "forward", impulses="12")


INTERRUPTED = """
import json, sys, time, warnings
import sea_momentum as sm
print(json.dumps({"event": "started"}), flush=True)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    table = sm.push_table(sys.argv[1], "forward", impulses=[40.0, 0.0],
                          overrides={"simulation.duration_s": 600.0})
row = table.row("forward")
print(json.dumps({"event": "returned", "caught": time.monotonic(), "interrupted": table.interrupted,
                  "pushes": row.pushes, "warned": [str(w.message) for w in caught]}), flush=True)
"""


def test_ctrl_c_returns_the_rows_done():
    child = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(INTERRUPTED), str(STANDING)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
    )
    try:
        assert json.loads(child.stdout.readline() or "{}").get("event") == "started", child.stderr.read()
        time.sleep(3.0)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == 0, err
    report = json.loads(out.splitlines()[-1])
    assert report["caught"] - sent < 2.0
    assert report["interrupted"] is True
    # 40 N s fell within 2 s of simulated time; the 600 s run was stopped.
    assert report["pushes"][0][1] in ("diverged", "fell")
    assert report["pushes"][1][1] == "interrupted"
    assert any("interrupted" in message for message in report["warned"])
