"""Smoke test of examples/mujoco_balance.py: our rigid controller keeps MuJoCo's iCub standing
for its first second, and MuJoCo's contact forces carry the weight the QP asked for."""

from __future__ import annotations

import numpy as np
import pytest
from load_file import load_file  # a helper beside the tests (see conftest.py)

# An optional dependency (the `examples` extra): without it there is nothing to test.
pytest.importorskip("mujoco", reason="pip install mujoco (the sea-momentum[examples] extra)")


def load_example():
    """examples/mujoco_balance.py as a module."""
    return load_file("examples/mujoco_balance.py")


def test_first_second_without_falling() -> None:
    example = load_example()
    series = example.run(duration=1.0, amplitude=0.02)
    com, weight = series["com"], float(series["weight"])
    # Standing: the CoM height stays within 2 cm of its start, the CoM within 1 cm of its
    # reference, and every QP solved.
    assert np.abs(com[:, 2] - com[0, 2]).max() < 0.02
    assert np.linalg.norm(com - series["com_reference"], axis=1).max() < 0.01
    assert series["qp_solved"].all()
    # Once MuJoCo's soft contacts have built up, they carry the weight on both feet, as the
    # QP's wrenches say.
    settled = series["time"] >= example.CONTACT_SETTLING
    measured = series["mujoco_wrenches"][settled]
    planned = series["qp_wrenches"][settled]
    assert measured[:, :, 2].sum(axis=1).mean() == pytest.approx(weight, rel=0.02)
    assert (measured[:, :, 2] > 0.2 * weight).all()
    force_error = np.linalg.norm(measured[:, :, :3] - planned[:, :, :3], axis=2)
    assert np.sqrt(np.mean(force_error**2)) < 0.05 * weight
    report = example.report(series, weight)
    assert "l_sole" in report and "r_sole" in report
