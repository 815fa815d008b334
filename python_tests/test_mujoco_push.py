"""Smoke test of benchmarks/mujoco_push.py: MuJoCo's iCub under our rigid controller at 100 Hz
recovers a push well below its bound and does not recover one well above it; the bisection
finds a threshold to its tolerance."""

from __future__ import annotations

import pytest
from load_file import load_file  # a helper beside the tests (see conftest.py)

# An optional dependency (the `examples` extra): without it there is nothing to test.
pytest.importorskip("mujoco", reason="pip install mujoco (the sea-momentum[examples] extra)")


def load_benchmark():
    """benchmarks/mujoco_push.py as a module."""
    return load_file("benchmarks/mujoco_push.py")


@pytest.fixture(scope="module")
def push():
    """The benchmark module, loaded once."""
    return load_benchmark()


def test_bisection_brackets_a_threshold(push) -> None:
    low, high = push.bisect(lambda impulse: impulse < 7.3, tolerance=0.1)
    assert low < 7.3 <= high and high - low <= 0.1
    low, high = push.bisect(lambda impulse: impulse < 2.0, tolerance=0.1, failing=5.0)
    assert low < 2.0 <= high and high - low <= 0.1
    assert push.bisect(lambda impulse: True, tolerance=0.1) == (push.MAX_IMPULSE, None)


def test_a_small_push_is_recovered_and_a_large_one_is_not(push) -> None:
    # A short run: 0.5 s after the push (the benchmark watches 4 s).
    rig = push.PushRig(push.PushSetup(after_s=0.5))
    # The plant's joint inertia regularisation is MuJoCo's armature, and the URDF limits are
    # joint stops.
    assert rig.armature == pytest.approx(0.1)
    assert all(rig.model.joint(name).limited[0] for name in rig.joints)
    small = rig.run("forward", 4.0)
    assert small.recovered, small.reason
    assert not small.foot_moved
    assert small.end_s == pytest.approx(1.6)
    large = rig.run("forward", 30.0)
    assert not large.recovered
    assert large.reason
    assert large.end_s < 1.6
