"""Checks of the hand-written test robots urdf/pendulum2.urdf and urdf/mini_biped.urdf.

They are loaded with Pinocchio (independent of sea-momentum) to make sure the files say what
urdf/README.md promises: joint names and types, masses, valid inertias, and the geometry
the tests rely on (level soles below the pelvis, a textbook double pendulum).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

URDF = Path(__file__).resolve().parent.parent / "urdf"
LEG = ["hip_pitch", "hip_roll", "knee", "ankle_pitch", "ankle_roll"]
BIPED_JOINTS = ["torso_pitch"] + [f"{s}_{j}" for s in ("l", "r") for j in LEG]


@pytest.mark.parametrize("name", ["pendulum2.urdf", "mini_biped.urdf"])
def test_inertias_valid(name):
    """Every inertia is positive definite and satisfies the triangle inequality."""
    for link in ET.parse(URDF / name).getroot().findall("link"):
        inertial = link.find("inertial")
        if inertial is None:
            continue
        g = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
        tensor = np.array([[g["ixx"], g["ixy"], g["ixz"]],
                           [g["ixy"], g["iyy"], g["iyz"]],
                           [g["ixz"], g["iyz"], g["izz"]]])  # fmt: skip
        moments = np.linalg.eigvalsh(tensor)
        assert moments.min() > 0, link.get("name")
        assert moments.sum() - 2 * moments.max() > 0, link.get("name")
        assert float(inertial.find("mass").get("value")) > 0


def test_pendulum2_is_a_double_pendulum():
    model = pin.buildModelFromUrdf(str(URDF / "pendulum2.urdf"))
    assert [model.names[i] for i in range(1, model.njoints)] == ["joint1", "joint2"]
    assert model.nv == 2 and model.nq == 3  # continuous joint: (cos, sin) in Pinocchio
    assert model.existFrame("tip")
    # Planar double pendulum about y: M11 = I1 + m1 c1^2 + I2 + m2 (l1^2 + c2^2 + 2 l1 c2 cos q2).
    m1, c1, i1, m2, c2, i2, l1 = 1.0, 0.15, 0.0076, 0.8, 0.15, 0.00608, 0.3
    q2 = 0.7
    q = np.array([0.3, np.cos(q2), np.sin(q2)])
    mass = pin.crba(model, model.createData(), q)
    m22 = i2 + m2 * c2**2
    m12 = m22 + m2 * l1 * c2 * np.cos(q2)
    m11 = i1 + m1 * c1**2 + i2 + m2 * (l1**2 + c2**2 + 2 * l1 * c2 * np.cos(q2))
    np.testing.assert_allclose(mass, [[m11, m12], [m12, m22]], atol=1e-12)


def test_mini_biped_structure_and_neutral_pose():
    model = pin.buildModelFromUrdf(str(URDF / "mini_biped.urdf"), pin.JointModelFreeFlyer())
    names = [model.names[i] for i in range(2, model.njoints)]
    assert sorted(names) == sorted(BIPED_JOINTS)
    assert all(model.joints[model.getJointId(n)].shortname().startswith("JointModelR") for n in names)
    assert model.nv == 6 + 11
    assert pin.computeTotalMass(model) == pytest.approx(8.5, abs=1e-12)

    data = model.createData()
    pin.framesForwardKinematics(model, data, pin.neutral(model))
    for side, y in (("l", 0.06), ("r", -0.06)):
        sole = data.oMf[model.getFrameId(f"{side}_sole")]
        np.testing.assert_allclose(sole.rotation, np.eye(3), atol=1e-15)  # level, x forward
        np.testing.assert_allclose(sole.translation, [0.0, y, -0.515], atol=1e-12)
