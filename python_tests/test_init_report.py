"""``sea_momentum.init_scenario``'s report is ``sea-sim init``'s: every field of the Rust
report, among them the rank of the two feet's contact constraints (12 with legs of 6 joints,
11 with the mini biped's legs of 5, whose written scenario then takes the larger pseudo-inverse
damping), the standing figures the walking settings scale with, and with ``walking=True`` the
runs of the walk ``init`` wrote."""

import pathlib
import tomllib

import pytest

import sea_momentum as sm

ROOT = pathlib.Path(__file__).resolve().parents[1]
SOLES = ("l_sole", "r_sole")
REPORT_KEYS = {
    "out",
    "robot",
    "mass",
    "joints",
    "foot_x",
    "foot_y",
    "measured",
    "lowering_m",
    "residual",
    "com_offset_m",
    "feet_rank",
    "warnings",
    "walking_figures",
    "walk_check",
}
ICUB_FOOT = (-0.05, 0.10, -0.025, 0.025)


def test_the_report_has_the_rank_of_the_feet_constraints(tmp_path):
    icub = sm.init_scenario(
        str(ROOT / "urdf" / "icub25.urdf"),
        SOLES,
        tmp_path / "icub.toml",
        foot=ICUB_FOOT,
    )
    assert set(icub) == REPORT_KEYS
    assert icub["walk_check"] is None
    assert icub["feet_rank"] == 12
    assert icub["com_offset_m"] == 0.0
    biped = sm.init_scenario(
        str(ROOT / "urdf" / "mini_biped.urdf"),
        SOLES,
        tmp_path / "biped.toml",
        foot=(-0.05, 0.08, -0.03, 0.03),
    )
    assert biped["feet_rank"] == 11
    assert pinv_damping(tmp_path / "biped.toml") > pinv_damping(tmp_path / "icub.toml")


def test_a_walk_is_written_and_checked_by_running_it(tmp_path):
    out = tmp_path / "icub_walk.toml"
    icub25 = str(ROOT / "urdf" / "icub25.urdf")
    icub = sm.init_scenario(icub25, SOLES, out, foot=ICUB_FOOT, walking=True)
    figures = icub["walking_figures"]
    assert set(figures) == {"com_height", "feet_distance", "leg_length", "reach"}
    [run] = icub["walk_check"]
    assert run["status"] == "completed" and run["reason"] == ""
    assert run["duration_s"] > 8.0
    walking = tomllib.loads(out.read_text())["walking"]
    assert walking["com_height"] == run["com_height"] == round(figures["com_height"], 3)
    summary = sm.run_scenario(out).summary
    assert summary.status == "completed" and summary.steps_taken == 9
    unchecked = sm.init_scenario(
        icub25, SOLES, tmp_path / "b.toml", foot=ICUB_FOOT, walking=True, walk_check=False
    )
    assert unchecked["walk_check"] is None
    with pytest.raises(ValueError) as refused:
        sm.init_scenario(icub25, SOLES, tmp_path / "c.toml", foot=ICUB_FOOT, walk_check=False)
    assert refused.value.argument == "walk_check"
    assert not (tmp_path / "c.toml").exists()


def pinv_damping(scenario: pathlib.Path) -> float:
    """The pseudo-inverse damping a written scenario sets (in its robot description)."""
    found = []

    def walk(table: dict) -> None:
        for key, value in table.items():
            if key == "pinv_damping":
                found.append(value)
            elif isinstance(value, dict):
                walk(value)

    walk(tomllib.loads(scenario.read_text()))
    assert len(found) == 1, found
    return found[0]
