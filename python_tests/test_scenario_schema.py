"""The scenario file's JSON Schema (``schemas/scenario.schema.json``, derived from the Rust types
by ``sea-sim schema``; its being current is a Rust test) accepts every shipped scenario and
refuses what the reader refuses: an unknown key, a value out of its bounds, an unknown name."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import jsonschema
import pytest

ROOT = Path(__file__).resolve().parents[1]
SCHEMA = json.loads((ROOT / "schemas" / "scenario.schema.json").read_text())
SCENARIOS = sorted((ROOT / "scenarios").rglob("*.toml"))


def _validator() -> jsonschema.Draft7Validator:
    jsonschema.Draft7Validator.check_schema(SCHEMA)
    return jsonschema.Draft7Validator(SCHEMA)


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.name for p in SCENARIOS])
def test_every_shipped_scenario_is_valid(path: Path) -> None:
    _validator().validate(tomllib.loads(path.read_text()))


@pytest.mark.parametrize(
    "table, key, value",
    [
        ("controller", "dampnig", 1.0),
        ("plant", "dt", 0.0),
        ("simulation", "record_every", 0),
        ("controller", "pinv_damping", -1e-3),
        ("controller", "sampling", "zoh"),
    ],
)
def test_what_the_reader_refuses_the_schema_refuses(table: str, key: str, value: object) -> None:
    scenario = tomllib.loads((ROOT / "scenarios" / "paper" / "tracking.toml").read_text())
    scenario.setdefault(table, {})[key] = value
    assert not _validator().is_valid(scenario)
