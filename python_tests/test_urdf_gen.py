"""Checks of the random URDF generator (python_tests/urdf_gen.py) with Pinocchio.

The generator feeds the comparisons of sea-momentum against Pinocchio on random trees, so it
must produce files Pinocchio loads, with the structure it promises (counts, joint types,
branching, unnormalised axes, valid inertias).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import Counter

import numpy as np
import pinocchio as pin
import pytest

from urdf_gen import random_urdf, write_random_urdf

SEEDS = list(range(12))


def _parse(seed: int, n_links: int) -> ET.Element:
    return ET.fromstring(random_urdf(seed, n_links))


def _inertia(element: ET.Element) -> np.ndarray:
    g = {k: float(element.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    return np.array([[g["ixx"], g["ixy"], g["ixz"]],
                     [g["ixy"], g["iyy"], g["iyz"]],
                     [g["ixz"], g["iyz"], g["izz"]]])  # fmt: skip


def test_deterministic_and_seed_dependent():
    assert random_urdf(3, 9) == random_urdf(3, 9)
    assert random_urdf(3, 9) != random_urdf(4, 9)
    assert random_urdf(3, 9) != random_urdf(3, 10)


@pytest.mark.parametrize("n_links", [1, 2, 3, 5])
def test_small_trees_are_valid(tmp_path, n_links):
    for seed in SEEDS:
        root = _parse(seed, n_links)
        assert len(root.findall("link")) == n_links
        assert len(root.findall("joint")) == n_links - 1
        pin.buildModelFromUrdf(str(write_random_urdf(tmp_path, seed, n_links)))


@pytest.mark.parametrize("n_links", [6, 8, 15])
@pytest.mark.parametrize("seed", SEEDS)
def test_structure(seed, n_links):
    root = _parse(seed, n_links)
    links = root.findall("link")
    joints = root.findall("joint")
    assert len(links) == n_links and len(joints) == n_links - 1
    types = Counter(j.get("type") for j in joints)
    assert set(types) == {"revolute", "continuous", "prismatic", "fixed"}

    massless = {l.get("name") for l in links if l.find("inertial") is None}
    assert massless, "expected at least one massless leaf"
    parents = [j.find("parent").get("link") for j in joints]
    for j in joints:
        if j.find("child").get("link") in massless:
            assert j.get("type") == "fixed"
    assert not massless & set(parents), "massless links must be leaves"
    assert max(Counter(parents).values()) >= 2, "expected a branching tree"

    for j in joints:
        kind = j.get("type")
        axis = j.find("axis")
        assert (axis is None) == (kind == "fixed")
        if axis is not None:
            norm = np.linalg.norm([float(x) for x in axis.get("xyz").split()])
            assert 0.3 - 1e-9 <= norm <= 3 + 1e-9
        limit = j.find("limit")
        if kind in ("revolute", "prismatic"):
            assert float(limit.get("lower")) < 0 < float(limit.get("upper"))

    for link in links:
        inertial = link.find("inertial")
        if inertial is None:
            continue
        assert 0.2 <= float(inertial.find("mass").get("value")) <= 3.0
        assert inertial.find("origin").get("rpy") is not None
        moments = np.linalg.eigvalsh(_inertia(inertial.find("inertia")))
        assert moments.min() > 0
        assert moments.sum() - 2 * moments.max() > 0  # triangle inequality


@pytest.mark.parametrize("n_links", [6, 8, 15])
@pytest.mark.parametrize("seed", SEEDS[:6])
def test_pinocchio_loads(tmp_path, seed, n_links):
    root = _parse(seed, n_links)
    types = Counter(j.get("type") for j in root.findall("joint"))
    n_movable = n_links - 1 - types["fixed"]
    total_mass = sum(float(l.find("inertial/mass").get("value"))
                     for l in root.findall("link") if l.find("inertial") is not None)  # fmt: skip

    model = pin.buildModelFromUrdf(str(write_random_urdf(tmp_path, seed, n_links)),
                                   pin.JointModelFreeFlyer())  # fmt: skip
    assert model.njoints == 2 + n_movable  # universe + free-flyer + movable joints
    assert model.nv == 6 + n_movable
    # Pinocchio stores continuous joints as (cos, sin): two coordinates, one velocity.
    assert model.nq == 7 + n_movable + types["continuous"]
    body_frames = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
    assert sorted(body_frames) == sorted(l.get("name") for l in root.findall("link"))
    assert pin.computeTotalMass(model) == pytest.approx(total_mass, rel=1e-12)

    rng = np.random.default_rng(seed)
    q = pin.neutral(model)
    q[:3] = rng.uniform(-1, 1, 3)
    data = model.createData()
    for _ in range(3):
        q = pin.integrate(model, q, rng.uniform(-1, 1, model.nv))
        mass_matrix = pin.crba(model, data, q)
        mass_matrix = np.triu(mass_matrix) + np.triu(mass_matrix, 1).T
        assert np.linalg.eigvalsh(mass_matrix).min() > 0


@pytest.mark.parametrize("seed", SEEDS[:4])
def test_pinocchio_normalises_axes(tmp_path, seed):
    """Scaling every axis to unit length must not change Pinocchio's dynamics.

    The comparisons against Pinocchio rely on it normalising axes like sea-momentum does.
    """
    root = _parse(seed, 10)
    for axis in root.iter("axis"):
        v = np.array([float(x) for x in axis.get("xyz").split()])
        axis.set("xyz", " ".join(repr(float(x)) for x in v / np.linalg.norm(v)))
    unit_path = tmp_path / "unit.urdf"
    unit_path.write_text(ET.tostring(root, encoding="unicode"))
    raw = pin.buildModelFromUrdf(str(write_random_urdf(tmp_path, seed, 10)))
    unit = pin.buildModelFromUrdf(str(unit_path))
    q = pin.integrate(raw, pin.neutral(raw), np.random.default_rng(seed).uniform(-1, 1, raw.nv))
    m_raw = pin.crba(raw, raw.createData(), q)
    m_unit = pin.crba(unit, unit.createData(), q)
    np.testing.assert_allclose(m_raw, m_unit, rtol=0, atol=1e-12)
