"""Random URDF trees for tests.

``random_urdf(seed, n_links)`` returns the text of a random, valid, kinematic tree that
exercises the parts of a URDF loader that the hand-written robots do not:

* every supported joint type: revolute, continuous, prismatic and fixed (with ``n_links >= 6``
  at least one of each, plus at least one massless fixed leaf);
* branching (for ``n_links >= 3`` at least one link has two or more children);
* joint origins with random ``xyz`` and ``rpy``;
* axes that are *not* unit vectors (random direction scaled by a factor in [0.3, 3]); the
  URDF convention, Pinocchio and sea-momentum all normalise them on load;
* inertial frames with random ``xyz`` *and* ``rpy``, and full inertia tensors (products of
  inertia non-zero) that are positive definite and satisfy the triangle inequality: they are
  the principal moments of a solid box, rotated by a random rotation;
* masses in [0.2, 3] kg;
* massive links attached by fixed joints (to be merged into their parent) and massless
  leaves (no ``<inertial>`` at all, fixed joint), the way sensor frames appear in real models;
* ``<limit>`` on revolute and prismatic joints (continuous joints have none).

The tree has exactly ``n_links`` links (``link0`` is the root) and ``n_links - 1`` joints;
link ``k`` is the child of joint ``k``, named ``j{k}_{type}``. Output is deterministic for a
seed: the generator uses :class:`random.Random` (a documented, version-stable stream) and
plain-Python arithmetic, and prints numbers with a fixed format.
"""

from __future__ import annotations

import math
import random
from pathlib import Path

#: Joint kinds drawn by the generator. "fixed" has a massive child, "leaf" a massless child.
_KINDS = ("revolute", "continuous", "prismatic", "fixed", "leaf")
#: Relative frequencies of the kinds beyond the guaranteed one of each.
_WEIGHTS = (0.45, 0.15, 0.15, 0.1, 0.15)

Matrix = list[list[float]]


def _num(x: float) -> str:
    """Fixed-format number: 12 significant digits is exact enough and stable as text."""
    text = f"{x:.12g}"
    return "0" if text == "-0" else text


def _vec(values) -> str:
    """Space-separated URDF vector."""
    return " ".join(_num(v) for v in values)


def _random_rotation(rng: random.Random) -> Matrix:
    """Uniformly distributed rotation matrix (from a normalised Gaussian quaternion)."""
    w, x, y, z = (rng.gauss(0.0, 1.0) for _ in range(4))
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def _random_inertia(rng: random.Random, mass: float) -> Matrix:
    """Random rotational inertia about the centre of mass, PD and triangle-valid.

    The principal moments are those of a solid box with sides in [0.03, 0.4] m
    (m (b^2 + c^2) / 12 ...), so I_a + I_b - I_c = m c'^2 / 6 > 0 with a margin; a random
    rotation then fills the products of inertia.
    """
    a, b, c = (rng.uniform(0.03, 0.4) for _ in range(3))
    moments = (mass * (b * b + c * c) / 12, mass * (a * a + c * c) / 12, mass * (a * a + b * b) / 12)
    rot = _random_rotation(rng)
    return [
        [sum(rot[i][k] * moments[k] * rot[j][k] for k in range(3)) for j in range(3)]
        for i in range(3)
    ]


def _random_axis(rng: random.Random) -> list[float]:
    """Random direction, deliberately not unit length (scaled by a factor in [0.3, 3])."""
    while True:
        v = [rng.gauss(0.0, 1.0) for _ in range(3)]
        n = math.sqrt(sum(x * x for x in v))
        if n > 1e-3:
            break
    scale = rng.uniform(0.3, 3.0)
    return [x / n * scale for x in v]


def _random_pose(rng: random.Random, reach: float) -> tuple[list[float], list[float]]:
    """Random ``(xyz, rpy)``: translation in [-reach, reach]^3, angles in [-pi, pi]."""
    xyz = [rng.uniform(-reach, reach) for _ in range(3)]
    rpy = [rng.uniform(-math.pi, math.pi) for _ in range(3)]
    return xyz, rpy


def _plan_kinds(rng: random.Random, n_joints: int) -> list[str]:
    """Kinds of the ``n_joints`` joints; one of each kind when there is room for it."""
    if n_joints >= len(_KINDS):
        kinds = list(_KINDS)
        kinds += rng.choices(_KINDS, weights=_WEIGHTS, k=n_joints - len(_KINDS))
    else:
        kinds = rng.choices(_KINDS, weights=_WEIGHTS, k=n_joints)
    rng.shuffle(kinds)
    return kinds


def _plan_parents(rng: random.Random, kinds: list[str]) -> list[int]:
    """Parent link of each link 1..n-1 (index 0 unused); a branching tree.

    Massless leaves never get children. Parents are drawn among the earlier massive links,
    favouring the most recent one to get long chains as well as branches.
    """
    parents = [-1]
    massive = [0]
    for k, kind in enumerate(kinds, start=1):
        if rng.random() < 0.5:
            parents.append(massive[-1])
        else:
            parents.append(rng.choice(massive))
        if kind != "leaf":
            massive.append(k)
    n_links = len(kinds) + 1
    children = [0] * n_links
    for p in parents[1:]:
        children[p] += 1
    if n_links >= 3 and max(children) < 2:
        # A pure chain 0-1-...-(n-1): in a chain every non-last link is massive, so hang the
        # last link (which has no children) from its grandparent to create a branch.
        parents[-1] = parents[parents[-1]]
    return parents


def random_urdf(seed: int, n_links: int = 8) -> str:
    """Return the text of a random URDF tree with ``n_links`` links (see module docstring).

    Deterministic: the same ``(seed, n_links)`` always gives the same text.
    """
    if n_links < 1:
        raise ValueError(f"n_links must be >= 1, got {n_links}")
    rng = random.Random(f"sea-momentum-urdf-gen/{seed}/{n_links}")
    kinds = _plan_kinds(rng, n_links - 1)
    parents = _plan_parents(rng, kinds)
    all_kinds = ["root"] + kinds

    lines = [
        '<?xml version="1.0"?>',
        f"<!-- random test tree generated by python_tests/urdf_gen.py: seed={seed}, "
        f"n_links={n_links} -->",
        f'<robot name="random_{seed}_{n_links}">',
    ]
    for k, kind in enumerate(all_kinds):
        if k > 0:
            lines += _joint_lines(rng, k, kind, parents[k])
        lines += _link_lines(rng, k, massless=(kind == "leaf"))
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def _link_lines(rng: random.Random, k: int, massless: bool) -> list[str]:
    """``<link>`` element of link ``k``; massless links have no ``<inertial>`` at all."""
    if massless:
        return [f'  <link name="link{k}"/>']
    mass = rng.uniform(0.2, 3.0)
    xyz, rpy = _random_pose(rng, 0.2)
    inertia = _random_inertia(rng, mass)
    names = (("ixx", 0, 0), ("ixy", 0, 1), ("ixz", 0, 2), ("iyy", 1, 1), ("iyz", 1, 2), ("izz", 2, 2))
    attrs = " ".join(f'{name}="{_num(inertia[i][j])}"' for name, i, j in names)
    return [
        f'  <link name="link{k}">',
        "    <inertial>",
        f'      <origin xyz="{_vec(xyz)}" rpy="{_vec(rpy)}"/>',
        f'      <mass value="{_num(mass)}"/>',
        f"      <inertia {attrs}/>",
        "    </inertial>",
        "  </link>",
    ]


def _joint_lines(rng: random.Random, k: int, kind: str, parent: int) -> list[str]:
    """``<joint>`` element whose child is link ``k``."""
    urdf_type = "fixed" if kind in ("fixed", "leaf") else kind
    xyz, rpy = _random_pose(rng, 0.3)
    lines = [
        f'  <joint name="j{k}_{urdf_type}" type="{urdf_type}">',
        f'    <origin xyz="{_vec(xyz)}" rpy="{_vec(rpy)}"/>',
        f'    <parent link="link{parent}"/>',
        f'    <child link="link{k}"/>',
    ]
    if urdf_type != "fixed":
        lines.append(f'    <axis xyz="{_vec(_random_axis(rng))}"/>')
    if urdf_type == "revolute":
        lower, upper = rng.uniform(-3.0, -0.5), rng.uniform(0.5, 3.0)
    elif urdf_type == "prismatic":
        lower, upper = rng.uniform(-0.5, -0.05), rng.uniform(0.05, 0.5)
    else:
        lower = upper = None
    if lower is not None:
        effort, velocity = rng.uniform(5.0, 100.0), rng.uniform(1.0, 10.0)
        lines.append(
            f'    <limit lower="{_num(lower)}" upper="{_num(upper)}" '
            f'effort="{_num(effort)}" velocity="{_num(velocity)}"/>'
        )
    lines.append("  </joint>")
    return lines


def write_random_urdf(tmp_path: Path | str, seed: int, n_links: int = 8) -> Path:
    """Write ``random_urdf(seed, n_links)`` into directory ``tmp_path``; return the file path."""
    path = Path(tmp_path) / f"random_{seed}_{n_links}.urdf"
    path.write_text(random_urdf(seed, n_links), encoding="utf-8")
    return path
