"""Checks of the shipped ``urdf/icub25.urdf`` against its source, iCubGenova04.

The derived model must have exactly the physics of the source with the neck and the wrist
pitch/yaw locked at zero. Pinocchio's ``buildReducedModel`` gives that reference
independently of ``scripts/make_icub25.py``, so the comparison checks the script's
selection of links and joints, not just its self-consistency.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from load_file import load_file  # a helper beside the tests (see conftest.py)

import icub_models  # noqa: E402  (a test dependency: missing means failed, not skipped)

REPO = Path(__file__).resolve().parent.parent
DERIVED = REPO / "urdf" / "icub25.urdf"
make_icub25 = load_file("scripts/make_icub25.py")
MOVABLE = list(make_icub25.MOVABLE_JOINTS)
LOCKED = list(make_icub25.LOCKED_JOINTS)


@pytest.fixture(scope="module")
def original():
    """Full iCubGenova04 (32 revolute joints) on a free-flyer."""
    path = icub_models.get_model_file("iCubGenova04")
    return pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())


@pytest.fixture(scope="module")
def reduced(original):
    """iCubGenova04 with the 7 extra joints locked at 0 (Pinocchio's own reduction)."""
    lock_ids = [original.getJointId(name) for name in LOCKED]
    assert all(i < original.njoints for i in lock_ids)
    return pin.buildReducedModel(original, lock_ids, pin.neutral(original))


@pytest.fixture(scope="module")
def derived():
    """The shipped 25-DoF model on a free-flyer."""
    return pin.buildModelFromUrdf(str(DERIVED), pin.JointModelFreeFlyer())


def _v_index(model: pin.Model) -> np.ndarray:
    """Velocity indices of ``model`` ordered as [base (6), MOVABLE joints by name]."""
    idx = list(range(6))
    for name in MOVABLE:
        joint = model.joints[model.getJointId(name)]
        assert joint.nv == 1, name
        idx.append(joint.idx_v)
    return np.array(idx)


def _random_q(model: pin.Model, values: dict[str, float], base: np.ndarray) -> np.ndarray:
    """Configuration with the given free-flyer part and joint values (by name)."""
    q = pin.neutral(model)
    q[:7] = base
    for name, value in values.items():
        q[model.joints[model.getJointId(name)].idx_q] = value
    return q


def _random_state(seed: int) -> tuple[np.ndarray, dict[str, float]]:
    """Random free-flyer pose (x, y, z, qx, qy, qz, qw) and joint angles in [-1, 1]."""
    rng = np.random.default_rng(seed)
    quat = rng.normal(size=4)
    quat /= np.linalg.norm(quat)
    base = np.concatenate([rng.uniform(-1, 1, 3), quat])
    return base, {name: rng.uniform(-1.0, 1.0) for name in MOVABLE}


def test_dimensions_and_joint_names(derived):
    assert derived.nv == 31
    assert derived.nq == 32
    names = [derived.names[i] for i in range(2, derived.njoints)]
    assert sorted(names) == sorted(MOVABLE)


def test_total_mass_matches_original(original, derived):
    assert pin.computeTotalMass(original) == pytest.approx(33.06, abs=5e-3)
    assert pin.computeTotalMass(derived) == pytest.approx(pin.computeTotalMass(original), abs=1e-12)


def test_required_frames_exist(derived):
    for frame in ("root_link", "l_sole", "r_sole", "l_foot", "r_foot"):
        assert derived.existFrame(frame), frame


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_mass_matrix_matches_reduced_original(reduced, derived, seed):
    base, values = _random_state(seed)
    q_ref = _random_q(reduced, values, base)
    q_new = _random_q(derived, values, base)
    m_ref = pin.crba(reduced, reduced.createData(), q_ref)
    m_new = pin.crba(derived, derived.createData(), q_new)
    # crba fills the upper triangle only.
    m_ref = np.triu(m_ref) + np.triu(m_ref, 1).T
    m_new = np.triu(m_new) + np.triu(m_new, 1).T
    i_ref, i_new = _v_index(reduced), _v_index(derived)
    np.testing.assert_allclose(m_new[np.ix_(i_new, i_new)], m_ref[np.ix_(i_ref, i_ref)],
                               rtol=0, atol=1e-10)  # fmt: skip


@pytest.mark.parametrize("seed", [3, 4])
def test_gravity_matches_reduced_original(reduced, derived, seed):
    """Gravity torques also check the centres of mass, not only the inertias."""
    base, values = _random_state(seed)
    g_ref = pin.computeGeneralizedGravity(reduced, reduced.createData(), _random_q(reduced, values, base))
    g_new = pin.computeGeneralizedGravity(derived, derived.createData(), _random_q(derived, values, base))
    np.testing.assert_allclose(g_new[_v_index(derived)], g_ref[_v_index(reduced)], rtol=0, atol=1e-10)


@pytest.mark.parametrize("seed", [5, 6])
def test_sole_poses_match_original(original, derived, seed):
    base, values = _random_state(seed)
    values_full = dict(values, **{name: 0.0 for name in LOCKED})
    q_ref = _random_q(original, values_full, base)
    q_new = _random_q(derived, values, base)
    for frame in ("l_sole", "r_sole", "root_link"):
        d_ref, d_new = original.createData(), derived.createData()
        pin.framesForwardKinematics(original, d_ref, q_ref)
        pin.framesForwardKinematics(derived, d_new, q_new)
        pose_ref = d_ref.oMf[original.getFrameId(frame)].homogeneous
        pose_new = d_new.oMf[derived.getFrameId(frame)].homogeneous
        np.testing.assert_allclose(pose_new, pose_ref, rtol=0, atol=1e-12)


def test_soles_flat_at_neutral(derived):
    """With every joint at 0 the sole frames are level (z up), below the base."""
    data = derived.createData()
    pin.framesForwardKinematics(derived, data, pin.neutral(derived))
    for frame in ("l_sole", "r_sole"):
        pose = data.oMf[derived.getFrameId(frame)]
        np.testing.assert_allclose(pose.rotation[:, 2], [0, 0, 1], atol=1e-9)
        assert pose.translation[2] < -0.4


def test_file_is_self_contained_and_valid():
    """No mesh references, no collisions, and every inertia is physically valid."""
    text = DERIVED.read_text()
    assert "package://" not in text and "<mesh" not in text and "<collision" not in text
    assert "CC BY-SA 4.0" in text and "robotology/icub-models" in text
    root = ET.fromstring(text)
    for link in root.findall("link"):
        assert link.find("visual") is not None, link.get("name")
        inertial = link.find("inertial")
        if inertial is None:
            continue
        assert float(inertial.find("mass").get("value")) > 0
        moments = np.linalg.eigvalsh(make_icub25.inertia_matrix(inertial.find("inertia")))
        assert moments.min() > 0, link.get("name")
        assert moments.sum() - 2 * moments.max() >= 0, link.get("name")


def test_rpy_round_trip():
    """The visuals' rpy conversion (used for the boxes) inverts URDF's convention."""
    rng = np.random.default_rng(7)
    for rpy in list(rng.uniform(-3, 3, (20, 3))) + [[0.3, np.pi / 2, 0.2], [0.3, -np.pi / 2, 0.2]]:
        rot = make_icub25.rpy_to_matrix(list(rpy))
        again = make_icub25.rpy_to_matrix(list(make_icub25.matrix_to_rpy(rot)))
        np.testing.assert_allclose(again, rot, atol=1e-9)
    # Same convention as Pinocchio.
    rpy = [0.1, -0.7, 2.0]
    np.testing.assert_allclose(make_icub25.rpy_to_matrix(rpy), pin.rpy.rpyToMatrix(*rpy), atol=1e-14)


def test_generation_is_deterministic_and_up_to_date():
    first = make_icub25.build_icub25()
    assert first == make_icub25.build_icub25()
    shipped = DERIVED.read_text()
    if f"icub-models {make_icub25.source_version()}." not in shipped:
        pytest.skip("installed icub-models differs from the one the shipped file came from")
    assert first == shipped, "urdf/icub25.urdf is stale: run scripts/make_icub25.py"
