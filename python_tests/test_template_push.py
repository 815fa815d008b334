"""``sm.template_push_table``: pushes on a walk's template (the controller's planner and
momentum law on the linear inverted pendulum). The bisection agrees with the fixed pushes,
bad arguments name themselves. (That ``sea-sim push --phase`` reports the same figures is a
Rust test, ``push::the_cli_reports_the_template_beside_the_robot``.)"""

from __future__ import annotations

from pathlib import Path

import pytest

import sea_momentum as sm

ROOT = Path(__file__).resolve().parents[1]
WALK = ROOT / "scenarios" / "walking" / "walk_push.toml"
ADJUSTED = {"walking.step_adjustment": True}


def test_fixed_pushes_report_each_outcome_and_the_bisection_agrees():
    fixed = sm.template_push_table(WALK, 0.2, "left", impulses=[1, 6, 12], overrides=ADJUSTED)
    (row,) = fixed
    assert row.direction == "left" and row.pushes == [(1.0, True), (6.0, True), (12.0, False)]
    assert row.recovered_impulse_n_s == 6.0
    (bisected,) = sm.template_push_table(WALK, 0.2, ["left"], overrides=ADJUSTED, tolerance_n_s=0.05)
    assert bisected.pushes == [] and 6.0 <= bisected.recovered_impulse_n_s < 12.0
    just_below = bisected.recovered_impulse_n_s - 0.1
    (check,) = sm.template_push_table(WALK, 0.2, "left", impulses=[just_below, bisected.recovered_impulse_n_s + 0.1], overrides=ADJUSTED)
    assert [recovered for _, recovered in check.pushes] == [True, False]


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"phase": 1.5}, "phase"),
        ({"phase": 0.5, "step": 99}, "step"),
        ({"phase": 0.5, "step": -1}, "step"),
        ({"phase": 0.5, "step": 2**70}, "step"),
        ({"phase": 0.5, "duration_s": 100.0}, "duration_s"),
        ({"phase": 0.5, "directions": []}, "directions"),
        ({"phase": 0.5, "directions": ["left", "left"]}, "directions"),
        ({"phase": 0.5, "duration_s": 0.0}, "duration_s"),
        ({"phase": 0.5, "duration_s": 1e-300}, "duration_s"),
        ({"phase": 0.5, "tolerance_n_s": -1.0}, "tolerance_n_s"),
        ({"phase": 0.5, "impulses": [1.0, float("nan")]}, "impulses"),
    ],
)
def test_bad_arguments_name_themselves(kwargs, named):
    with pytest.raises(ValueError, match=named) as info:
        sm.template_push_table(WALK, **kwargs)
    assert info.value.argument == named


def test_a_scenario_that_does_not_walk_is_refused_naming_phase():
    standing = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
    with pytest.raises(ValueError, match="phase") as info:
        sm.template_push_table(standing, 0.5, "left")
    assert info.value.argument == "phase"
    with pytest.raises(TypeError, match="impulses"):
        sm.template_push_table(WALK, 0.5, "left", impulses="1,2")
    with pytest.raises(TypeError):
        sm.template_push_table(WALK, 0.5, "left", step=3.0)


def test_the_default_step_of_a_plan_of_three_steps_is_its_last():
    # The fourth step by default; a plan of three steps in place has none, and its last is taken.
    in_place = ROOT / "scenarios" / "walking" / "steps_in_place.toml"
    default = sm.template_push_table(in_place, 0.5, "left", impulses=[1.0])
    last = sm.template_push_table(in_place, 0.5, "left", impulses=[1.0], step=2)
    assert default == last
    with pytest.raises(ValueError, match="0 to 2") as beyond:
        sm.template_push_table(in_place, 0.5, "left", impulses=[1.0], step=3)
    assert beyond.value.argument == "step"
