"""``sea_momentum.init_scenario``'s report is ``sea-sim init``'s: every field of the Rust
report, among them the rank of the two feet's contact constraints (12 with legs of 6 joints,
11 with the mini biped's legs of 5, whose written scenario then takes the larger pseudo-inverse
damping)."""

import pathlib
import tomllib

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
}


def test_the_report_has_the_rank_of_the_feet_constraints(tmp_path):
    icub = sm.init_scenario(
        str(ROOT / "urdf" / "icub25.urdf"),
        SOLES,
        tmp_path / "icub.toml",
        foot=(-0.05, 0.10, -0.025, 0.025),
    )
    assert set(icub) == REPORT_KEYS
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
