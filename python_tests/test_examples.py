"""Every example of examples/ runs (its ``--quick`` form) and draws its figure.

The MuJoCo examples have their own tests (test_mujoco_example.py, test_mujoco_push.py).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
FIGURES = {
    "balance_your_urdf.py": ["balance_your_urdf.png"],
    "sea_vs_rigid.py": ["sea_vs_rigid.png"],
    "stiffness_sweep.py": ["stiffness_sweep.png"],
    "push_table.py": ["push_table.png"],
    "multi_rate_identification.py": ["multi_rate_identification.png"],
    "foxglove_log.py": ["foxglove_contacts.png", "push_two_feet.mcap"],
    "walk_and_push.py": ["walk_and_push.png"],
}


def test_every_example_without_mujoco_is_listed():
    scripts = {p.name for p in (ROOT / "examples").glob("*.py")
               if not p.name.startswith(("_", "mujoco"))}
    assert scripts == set(FIGURES)


@pytest.mark.parametrize("script", sorted(FIGURES))
def test_an_example_runs_and_draws_its_figure(script, tmp_path):
    command = [sys.executable, str(ROOT / "examples" / script), "--quick", "--out", str(tmp_path)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-3000:]
    for name in FIGURES[script]:
        assert (tmp_path / name).stat().st_size > 1000, f"{script} did not write {name}"
    assert "figure:" in done.stdout
