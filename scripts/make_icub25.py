#!/usr/bin/env python3
"""Derive ``urdf/icub25.urdf`` (iCub with 25 movable joints) from icub-models.

The source is the real-robot model ``iCubGenova04`` of robotology/icub-models, as installed
by the ``icub-models`` PyPI package. The paper reproduced by sea-momentum (and the MATLAB
study behind it) uses a 25-DoF iCub: torso (3), two arms (5 each, down to wrist_prosup) and
two legs (6 each). This script turns the 32-joint source into that model so that the Rust
loader, Foxglove and the tests can use one self-contained file:

* the 25 joints in ``MOVABLE_JOINTS`` stay revolute; every other revolute joint (neck
  pitch/roll/yaw, wrist pitch/yaw on both sides) becomes ``type="fixed"`` at zero: its
  ``<origin>`` is kept, its ``<axis>``/``<limit>``/``<dynamics>`` are dropped. Locking a
  revolute joint at 0 is exactly a fixed joint with the same origin, so the dynamics equal
  Pinocchio's ``buildReducedModel`` of the source with those joints locked at 0;
* massless links (sensor, skin, IMU and convenience frames) are dropped together with the
  fixed joints leading to them, except ``root_link``, ``l_sole``, ``r_sole`` (contact frames)
  and any massless link on the path from the root to a kept link (so the tree stays
  connected);
* ``<visual>``/``<collision>`` meshes (``package://`` files that we do not ship) are replaced
  by one primitive ``<visual>`` per link: the box with the link's mass and principal moments
  of inertia ("equivalent inertia box"), placed at the centre of mass along the principal
  axes; massless kept links get a small sphere. No ``<collision>`` is written;
* the top-level ``<gazebo>`` and ``<sensor>`` elements are dropped (simulator plugins and
  sensors that refer to removed frames);
* masses, inertias, joint origins, axes and limits are copied verbatim (same attribute
  strings), so the derived model is bit-for-bit the same physics.

Only ``xml.etree`` and numpy are used (no Pinocchio): the output must not depend on a
dynamics library. The output is deterministic: elements keep the source file order and the
few computed numbers (visual boxes) are printed with a fixed format.

Usage::

    python scripts/make_icub25.py            # writes urdf/icub25.urdf of this repository
    python scripts/make_icub25.py -o out.urdf

The licence of the output is CC BY-SA 4.0, as the source; see ``urdf/README.md``.
"""

from __future__ import annotations

import argparse
import copy
import importlib.metadata
import math
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import sea_momentum

SOURCE_ROBOT = "iCubGenova04"

#: The 25 joints that stay movable, in the order the project loads them (paper order:
#: torso, left arm, right arm, left leg, right leg). The file keeps the source order.
#: Defined once, in Rust (sea_sim's scenario presets), exposed by the native module.
MOVABLE_JOINTS: tuple[str, ...] = tuple(sea_momentum.ICUB25_JOINTS)

#: Revolute joints of the source that are locked (turned into fixed joints at 0).
LOCKED_JOINTS: tuple[str, ...] = (
    "neck_pitch", "neck_roll", "neck_yaw",
    "l_wrist_pitch", "l_wrist_yaw", "r_wrist_pitch", "r_wrist_yaw",
)  # fmt: skip

#: Links kept even when massless: the floating base and the contact frames.
ALWAYS_KEPT_LINKS: tuple[str, ...] = ("root_link", "l_sole", "r_sole", "l_foot", "r_foot")

ROOT_LINK = "root_link"

#: Radius of the sphere drawn for massless kept links (frames), metres.
FRAME_SPHERE_RADIUS = 0.01
#: Smallest box side drawn, metres (keeps very flat equivalent boxes visible).
MIN_BOX_SIDE = 0.005

#: Colours of the primitive visuals (rgba strings): bodies, feet, massless frames.
MATERIALS: dict[str, str] = {
    "icub25_body": "0.80 0.80 0.82 1",
    "icub25_foot": "0.30 0.30 0.32 1",
    "icub25_frame": "0.85 0.15 0.15 1",
}


def source_model_path() -> Path:
    """Return the path of the source URDF installed by the ``icub-models`` package."""
    import icub_models  # imported here so ``--help`` works without the package

    return Path(icub_models.get_model_file(SOURCE_ROBOT))


def source_version() -> str:
    """Return the installed ``icub-models`` package version (recorded in the header)."""
    return importlib.metadata.version("icub-models")


def _floats(text: str | None, default: str) -> list[float]:
    """Parse a URDF whitespace-separated vector attribute (absent -> ``default``)."""
    return [float(x) for x in (text if text is not None else default).split()]


def rpy_to_matrix(rpy: list[float]) -> np.ndarray:
    """URDF roll-pitch-yaw to rotation matrix: ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (math.cos(r), math.sin(r), math.cos(p), math.sin(p),
                              math.cos(y), math.sin(y))  # fmt: skip
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_to_rpy(rot: np.ndarray) -> tuple[float, float, float]:
    """Inverse of :func:`rpy_to_matrix` (pitch in [-pi/2, pi/2]; yaw = 0 at gimbal lock)."""
    sp = -rot[2, 0]
    if abs(sp) >= 1.0 - 1e-12:
        # Gimbal lock: only roll -/+ yaw is defined; with yaw = 0 the (1, 1) and (1, 2)
        # entries are cos(roll) and -sin(roll) for both signs of the pitch.
        pitch = math.copysign(math.pi / 2, sp)
        return math.atan2(-rot[1, 2], rot[1, 1]), pitch, 0.0
    pitch = math.asin(sp)
    roll = math.atan2(rot[2, 1], rot[2, 2])
    yaw = math.atan2(rot[1, 0], rot[0, 0])
    return roll, pitch, yaw


def inertia_matrix(inertia: ET.Element) -> np.ndarray:
    """Return the symmetric 3x3 matrix of a URDF ``<inertia>`` element."""
    g = {k: float(inertia.get(k, "0")) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    return np.array(
        [
            [g["ixx"], g["ixy"], g["ixz"]],
            [g["ixy"], g["iyy"], g["iyz"]],
            [g["ixz"], g["iyz"], g["izz"]],
        ]
    )


def equivalent_box(inertial: ET.Element) -> tuple[list[float], tuple[float, ...], list[float]]:
    """Box with the same mass and rotational inertia as ``inertial``.

    Returns ``(xyz, rpy, size)`` of the box in the link frame. A solid box of sides a, b, c
    has principal moments m/12 (b^2 + c^2) etc., so a^2 = 6 (I_b + I_c - I_a) / m; the
    triangle inequality of the principal moments makes every side real. The box sits at the
    centre of mass with its edges along the principal axes, which is a faithful picture of
    how the mass is spread without needing the mesh files.
    """
    origin = inertial.find("origin")
    xyz = _floats(origin.get("xyz") if origin is not None else None, "0 0 0")
    rpy = _floats(origin.get("rpy") if origin is not None else None, "0 0 0")
    mass = float(inertial.find("mass").get("value"))
    moments, axes = np.linalg.eigh(inertia_matrix(inertial.find("inertia")))
    # Canonical eigenvector signs (largest component positive) and a proper rotation, so the
    # output does not depend on the LAPACK build.
    for k in range(3):
        if axes[np.argmax(np.abs(axes[:, k])), k] < 0:
            axes[:, k] = -axes[:, k]
    if np.linalg.det(axes) < 0:
        axes[:, 2] = -axes[:, 2]
    total = moments.sum()
    size = [
        max(MIN_BOX_SIDE, math.sqrt(max(0.0, 6.0 * (total - 2.0 * moments[k]) / mass)))
        for k in range(3)
    ]
    box_rpy = matrix_to_rpy(rpy_to_matrix(rpy) @ axes)
    return xyz, box_rpy, size


def _fmt(values) -> str:
    """Fixed-format vector for computed (not copied) numbers: deterministic text."""
    out = []
    for v in values:
        s = f"{v:.4f}"
        out.append("0" if s in ("0.0000", "-0.0000") else s)
    return " ".join(out)


def make_visual(link: ET.Element) -> ET.Element:
    """Primitive ``<visual>`` for ``link``: equivalent inertia box, or a sphere if massless."""
    visual = ET.Element("visual")
    inertial = link.find("inertial")
    geometry_parent: ET.Element
    if inertial is None:
        ET.SubElement(visual, "origin", {"xyz": "0 0 0", "rpy": "0 0 0"})
        geometry_parent = ET.SubElement(visual, "geometry")
        ET.SubElement(geometry_parent, "sphere", {"radius": f"{FRAME_SPHERE_RADIUS}"})
        material = "icub25_frame"
    else:
        _, rpy, size = equivalent_box(inertial)
        # The box is centred on the centre of mass: reuse the source's xyz string verbatim.
        origin = inertial.find("origin")
        xyz = origin.get("xyz", "0 0 0") if origin is not None else "0 0 0"
        ET.SubElement(visual, "origin", {"xyz": xyz, "rpy": _fmt(rpy)})
        geometry_parent = ET.SubElement(visual, "geometry")
        ET.SubElement(geometry_parent, "box", {"size": _fmt(size)})
        material = "icub25_foot" if link.get("name", "").endswith("_foot") else "icub25_body"
    ET.SubElement(visual, "material", {"name": material})
    return visual


def select_links(source: ET.Element) -> list[str]:
    """Names of the links to keep, in source order.

    Kept: every link with an ``<inertial>``, the ``ALWAYS_KEPT_LINKS``, and every ancestor
    of a kept link (a massless intermediate link must stay or its subtree would be cut off).
    """
    links = [link.get("name") for link in source.findall("link")]
    parent_of = {j.find("child").get("link"): j.find("parent").get("link")
                 for j in source.findall("joint")}  # fmt: skip
    keep = {link.get("name") for link in source.findall("link") if link.find("inertial") is not None}
    missing = [n for n in ALWAYS_KEPT_LINKS if n not in links]
    if missing:
        raise ValueError(f"source model lacks required links {missing}")
    keep.update(ALWAYS_KEPT_LINKS)
    for name in sorted(keep):
        seen = set()
        while name in parent_of:
            if name in seen:
                raise ValueError(f"kinematic loop through link {name!r}")
            seen.add(name)
            name = parent_of[name]
            keep.add(name)
    return [n for n in links if n in keep]


def check_tree(links: list[str], joints: list[ET.Element]) -> None:
    """Raise ValueError unless ``joints`` connect ``links`` into one tree rooted at root_link."""
    children: dict[str, list[str]] = {n: [] for n in links}
    parents: dict[str, str] = {}
    for joint in joints:
        parent, child = joint.find("parent").get("link"), joint.find("child").get("link")
        if parent not in children or child not in children:
            raise ValueError(f"joint {joint.get('name')!r} refers to a dropped link")
        if child in parents:
            raise ValueError(f"link {child!r} has several parents")
        parents[child] = parent
        children[parent].append(child)
    roots = [n for n in links if n not in parents]
    if roots != [ROOT_LINK]:
        raise ValueError(f"expected the single root {ROOT_LINK!r}, found {roots}")
    reached, stack = set(), [ROOT_LINK]
    while stack:
        name = stack.pop()
        reached.add(name)
        stack.extend(children[name])
    if reached != set(links):
        raise ValueError(f"links not reachable from the root: {sorted(set(links) - reached)}")


def lock_joint(joint: ET.Element) -> ET.Element:
    """Fixed-joint copy of a revolute joint locked at 0: origin, parent, child only."""
    fixed = ET.Element("joint", {"name": joint.get("name"), "type": "fixed"})
    for tag in ("origin", "parent", "child"):
        element = joint.find(tag)
        if element is not None:
            fixed.append(copy.deepcopy(element))
    return fixed


def header_comment(version: str) -> str:
    """Licence, attribution and provenance, written before the ``<robot>`` element."""
    modifications = "\n".join(
        [
            "    - kept the 25 revolute joints torso_*, {l,r}_shoulder_*, {l,r}_elbow,",
            "      {l,r}_wrist_prosup, {l,r}_hip_*, {l,r}_knee, {l,r}_ankle_*;",
            "    - turned neck_pitch/roll/yaw and {l,r}_wrist_pitch/yaw into fixed joints",
            "      at zero (origin kept, axis/limit/dynamics removed);",
            "    - removed massless sensor, skin, IMU and helper frames and their fixed",
            "      joints (root_link, l_sole and r_sole are kept);",
            "    - replaced the mesh visuals and collisions by primitive visuals",
            "      (equivalent inertia boxes; spheres for massless frames), no collisions;",
            "    - removed the <gazebo> and <sensor> elements.",
            "    Masses, inertias, joint origins, axes and limits are copied unchanged.",
        ]
    )
    return (
        "<!--\n"
        "  icub25.urdf: the iCub humanoid (iCubGenova04) reduced to 25 movable joints.\n"
        "\n"
        "  Generated by scripts/make_icub25.py, do not edit.\n"
        "\n"
        f"  Derived from the {SOURCE_ROBOT} model of robotology/icub-models\n"
        "  (https://github.com/robotology/icub-models), as installed by the PyPI package\n"
        f"  icub-models {version}. Original work by the robotology/icub-models contributors.\n"
        "\n"
        "  Licence: Creative Commons Attribution-ShareAlike 4.0 International (CC BY-SA 4.0),\n"
        "  https://creativecommons.org/licenses/by-sa/4.0/ , the licence of the original.\n"
        "\n"
        "  Modifications (by the sea-momentum project):\n"
        f"{modifications}\n"
        "-->\n"
    )


def build_icub25(source_path: Path | None = None, version: str | None = None) -> str:
    """Return the text of ``icub25.urdf`` built from the source URDF at ``source_path``."""
    source_path = source_path or source_model_path()
    version = version or source_version()
    source = ET.parse(source_path).getroot()

    revolute = {j.get("name") for j in source.findall("joint") if j.get("type") == "revolute"}
    absent = [n for n in MOVABLE_JOINTS + LOCKED_JOINTS if n not in revolute]
    if absent:
        raise ValueError(f"source model lacks revolute joints {absent}")
    unexpected = sorted(revolute - set(MOVABLE_JOINTS) - set(LOCKED_JOINTS))
    if unexpected:
        # A new revolute joint upstream must be classified on purpose, not silently fixed.
        raise ValueError(f"unclassified revolute joints in source: {unexpected}")
    other_movable = sorted(
        j.get("name") for j in source.findall("joint") if j.get("type") not in ("revolute", "fixed")
    )
    if other_movable:
        raise ValueError(f"unexpected non-revolute movable joints in source: {other_movable}")

    kept_links = select_links(source)
    kept = set(kept_links)

    robot = ET.Element("robot", {"name": "iCub25"})
    for name, rgba in MATERIALS.items():
        ET.SubElement(ET.SubElement(robot, "material", {"name": name}), "color", {"rgba": rgba})

    kept_joints: list[ET.Element] = []
    for element in source:
        if element.tag == "link" and element.get("name") in kept:
            link = ET.SubElement(robot, "link", {"name": element.get("name")})
            inertial = element.find("inertial")
            if inertial is not None:
                link.append(copy.deepcopy(inertial))  # verbatim attribute strings
            link.append(make_visual(element))
        elif element.tag == "joint" and element.find("child").get("link") in kept:
            if element.get("name") in LOCKED_JOINTS:
                joint = lock_joint(element)
            else:
                joint = copy.deepcopy(element)
            robot.append(joint)
            kept_joints.append(joint)
        # Everything else (dropped links/joints, <gazebo>, <sensor>) is left out.
    check_tree(kept_links, kept_joints)

    # Normalise whitespace inside copied elements so indentation is uniform and stable.
    for element in robot.iter():
        element.tail = None
        if len(element):
            element.text = None
    ET.indent(robot, space="  ")
    body = ET.tostring(robot, encoding="unicode")
    return '<?xml version="1.0"?>\n' + header_comment(version) + body + "\n"


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point: write the derived URDF and print a short summary."""
    default_out = Path(__file__).resolve().parent.parent / "urdf" / "icub25.urdf"
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=default_out, help="output file")
    args = parser.parse_args(argv)

    text = build_icub25()
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(text, encoding="utf-8")
    root = ET.fromstring(text)
    joints = root.findall("joint")
    n_rev = sum(j.get("type") == "revolute" for j in joints)
    print(
        f"wrote {args.output}: {len(root.findall('link'))} links, {len(joints)} joints "
        f"({n_rev} revolute, {len(joints) - n_rev} fixed)",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
