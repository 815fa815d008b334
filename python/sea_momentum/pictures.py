"""Pictures of the robot: the URDF's visuals (boxes, cylinders, spheres, and meshes read and
decimated in Rust by :func:`~sea_momentum._native.link_meshes`) placed at the link poses of
``Model.frame_pose`` and drawn with matplotlib's 3D axes; mesh triangles are shaded by a
light from the camera's side.

- :func:`robot_strip`: a strip of the robot at chosen instants of a run (PNG);
- :func:`robot_animation`: the run as an animated GIF (matplotlib's ``PillowWriter``);
- :func:`scenario_pictures`: both for a scenario file and its :class:`ScenarioResult`.

Library code: it draws any URDF's robot along any recorded run; the paper application
(:mod:`sea_momentum.paper.figures`) chooses the runs and the instants.
"""

from __future__ import annotations

import dataclasses
import os
import pathlib
import warnings
import xml.etree.ElementTree as ET
from typing import TYPE_CHECKING, Any, Sequence, Union

import numpy as np

from ._native import PICTURE_TRIANGLE_BUDGET, Model, link_meshes, scenario_urdf
from .arrays import FloatArray
from .scenario import package_folders
from .extras import require_plots

if TYPE_CHECKING:
    from .scenario import ScenarioResult

#: Times [s]: a sequence or a float64 array.
Times = Union[Sequence[float], FloatArray]

#: Camera of every picture: a three-quarter front view (degrees); iCub faces world +x.
VIEW_ELEVATION_DEG = 12.0
VIEW_AZIMUTH_DEG = -35.0
#: Colour of links without a URDF material colour.
DEFAULT_RGBA = (0.62, 0.66, 0.72, 1.0)
#: Facets of the polygon that approximates a cylinder's circle and a sphere's meridians.
ROUND_FACETS = 12
# The default triangle budget, PICTURE_TRIANGLE_BUDGET (imported above), is defined in Rust:
# matplotlib sorts and draws every triangle in every frame, the time of a GIF grows with it.
#: Direction the light comes from (world axes, unit): front-left-above, as the camera looks.
LIGHT_DIRECTION = np.array([0.6, -0.5, 0.62]) / np.linalg.norm([0.6, -0.5, 0.62])
#: Brightness of a mesh triangle facing away from the light (1 when facing it).
AMBIENT_LIGHT = 0.45
#: Edge colour and width of the primitives' faces (mesh triangles have no edges).
PRIMITIVE_EDGE_RGBA = (0.2, 0.2, 0.2, 0.35)
PRIMITIVE_EDGE_WIDTH = 0.3


@dataclasses.dataclass(frozen=True)
class Visual:
    """One URDF visual of a link."""

    link: str  #: the link (a frame of the model)
    link_H_visual: FloatArray  #: (4, 4) placement of the visual in the link frame
    kind: str  #: "box", "cylinder", "sphere" or "mesh"
    size: tuple[float, ...]  #: box (x, y, z); cylinder (radius, length along z); sphere (radius,); mesh ()
    rgba: tuple[float, float, float, float]  #: colour
    #: mesh only: (n, 3) vertices [m] and (m, 3) vertex indices of its triangles
    mesh: tuple[FloatArray, Any] | None = None


def _rotation_rpy(roll: float, pitch: float, yaw: float) -> FloatArray:
    """URDF's fixed-axis roll-pitch-yaw: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def _floats(text: str | None, default: str) -> list[float]:
    return [float(v) for v in (text or default).split()]


def urdf_visuals(
    urdf: str | os.PathLike[str],
    package_dirs: Sequence[str | os.PathLike[str]] = (),
    triangle_budget: int = PICTURE_TRIANGLE_BUDGET,
) -> list[Visual]:
    """The visuals of a URDF file: boxes, cylinders, spheres, then meshes (decimated to about
    ``triangle_budget`` triangles for the whole robot; ``package://`` URIs looked up in
    ``package_dirs`` first). A mesh that cannot be read is left out with a ``UserWarning``
    naming the link, the URI and why."""
    return _primitive_visuals(urdf) + _mesh_visuals(urdf, package_dirs, triangle_budget)


def _mesh_visuals(
    urdf: str | os.PathLike[str], package_dirs: Sequence[str | os.PathLike[str]], triangle_budget: int
) -> list[Visual]:
    """The mesh visuals, in their link frames, read by the native module."""
    meshes, problems = link_meshes(os.fspath(urdf), package_folders(package_dirs), triangle_budget)
    for problem in problems:
        warnings.warn(f"{urdf}: {problem}", UserWarning, stacklevel=3)
    return [Visual(link, np.eye(4), "mesh", (), rgba, (vertices, triangles)) for link, vertices, triangles, rgba in meshes]


def _primitive_visuals(urdf: str | os.PathLike[str]) -> list[Visual]:
    """The box, cylinder and sphere visuals of a URDF file."""
    root = ET.parse(urdf).getroot()
    colours = {
        m.get("name"): tuple(_floats(m.find("color").get("rgba"), "1 1 1 1"))  # type: ignore[union-attr]
        for m in root.iter("material")
        if m.find("color") is not None
    }
    visuals = []
    for link in root.findall("link"):
        for visual in link.findall("visual"):
            geometry = visual.find("geometry")
            shape = None if geometry is None else next(iter(geometry), None)
            if shape is None or shape.tag not in ("box", "cylinder", "sphere"):
                continue
            origin = visual.find("origin")
            placement = np.eye(4)
            if origin is not None:
                placement[:3, :3] = _rotation_rpy(*_floats(origin.get("rpy"), "0 0 0"))
                placement[:3, 3] = _floats(origin.get("xyz"), "0 0 0")
            size = {
                "box": lambda s: tuple(_floats(s.get("size"), "0 0 0")),
                "cylinder": lambda s: (float(s.get("radius")), float(s.get("length"))),
                "sphere": lambda s: (float(s.get("radius")),),
            }[shape.tag](shape)
            material = visual.find("material")
            rgba = DEFAULT_RGBA
            if material is not None:
                inline = material.find("color")
                if inline is not None:
                    rgba = tuple(_floats(inline.get("rgba"), "1 1 1 1"))  # type: ignore[assignment]
                else:
                    rgba = colours.get(material.get("name"), DEFAULT_RGBA)  # type: ignore[assignment]
            visuals.append(Visual(link.get("name", ""), placement, shape.tag, size, rgba))  # type: ignore[arg-type]
    return visuals


def _faces(kind: str, size: tuple[float, ...]) -> list[FloatArray]:
    """The faces (each (k, 3) vertices) of a primitive centred at its origin."""
    if kind == "box":
        half = np.array(size) / 2
        corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]) * half
        quads = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
        return [corners[list(quad)] for quad in quads]
    angles = np.linspace(0, 2 * np.pi, ROUND_FACETS, endpoint=False)
    if kind == "cylinder":
        radius, length = size
        ring = np.stack([radius * np.cos(angles), radius * np.sin(angles), np.zeros_like(angles)], axis=1)
        bottom, top = ring - [0, 0, length / 2], ring + [0, 0, length / 2]
        sides = [np.array([bottom[i], bottom[i - 1], top[i - 1], top[i]]) for i in range(ROUND_FACETS)]
        return sides + [bottom, top]
    (radius,) = size
    polar = np.linspace(0, np.pi, ROUND_FACETS // 2 + 1)
    point = lambda a, p: radius * np.array([np.sin(p) * np.cos(a), np.sin(p) * np.sin(a), np.cos(p)])  # noqa: E731
    return [
        np.array([point(a0, p0), point(a1, p0), point(a1, p1), point(a0, p1)])
        for a0, a1 in zip(angles, np.roll(angles, -1))
        for p0, p1 in zip(polar[:-1], polar[1:])
    ]


def _mesh_faces(visual: Visual, world_H_link: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The world-frame triangles ((m, 3, 3)) of a mesh visual and their shaded colours ((m, 4))."""
    assert visual.mesh is not None
    vertices, triangles = visual.mesh
    world_vertices = vertices @ world_H_link[:3, :3].T + world_H_link[:3, 3]
    corners = world_vertices[triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    lengths = np.linalg.norm(normals, axis=1)
    facing = np.abs(normals @ LIGHT_DIRECTION) / np.where(lengths > 0, lengths, 1.0)
    brightness = AMBIENT_LIGHT + (1.0 - AMBIENT_LIGHT) * facing
    colours = np.empty((len(corners), 4))
    colours[:, :3] = np.clip(np.outer(brightness, visual.rgba[:3]), 0.0, 1.0)
    colours[:, 3] = visual.rgba[3]
    return corners, colours


def robot_faces(
    model: Model, q: FloatArray, visuals: Sequence[Visual]
) -> tuple[list[FloatArray], list[Any], list[float]]:
    """The world-frame faces of every visual at configuration ``q``, their colours (mesh
    triangles shaded) and their edge widths (primitives outlined, mesh triangles not: they are
    many and small)."""
    faces: list[FloatArray] = []
    colours: list[Any] = []
    edges: list[float] = []
    poses: dict[str, FloatArray] = {}
    for visual in visuals:
        if visual.link not in poses:
            poses[visual.link] = model.frame_pose(q, visual.link)
        world_H_visual = poses[visual.link] @ visual.link_H_visual
        if visual.kind == "mesh":
            corners, shaded = _mesh_faces(visual, world_H_visual)
            faces.extend(corners)
            colours.extend(shaded)
            edges.extend([0.0] * len(corners))
            continue
        for face in _faces(visual.kind, visual.size):
            faces.append(face @ world_H_visual[:3, :3].T + world_H_visual[:3, 3])
            colours.append(visual.rgba)
            edges.append(PRIMITIVE_EDGE_WIDTH)
    return faces, colours, edges


def _draw(ax: Any, model: Model, q: FloatArray, visuals: Sequence[Visual], bounds: FloatArray, title: str) -> None:
    """One picture of the robot at ``q`` on ``ax`` within ``bounds`` ((2, 3): low, high), with
    its CoM (red) and the CoM's ground projection."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ax.cla()
    # Drawn in the order added (floor, robot, CoM on top); the robot's faces are depth-sorted
    # among themselves by their collection.
    ax.computed_zorder = False
    (x0, y0, z0), (x1, y1, z1) = bounds
    # The limits are the bounds: no autoscaling on collections (faces of different vertex
    # counts, primitives' quads and mesh triangles, upset it).
    ax.set_autoscale_on(False)
    floor = np.array([[x0, y0, 0.0], [x1, y0, 0.0], [x1, y1, 0.0], [x0, y1, 0.0]])
    ax.add_collection3d(Poly3DCollection([floor], facecolors=(0.85, 0.85, 0.8, 0.5)))
    faces, colours, widths = robot_faces(model, q, visuals)
    robot = Poly3DCollection(faces, facecolors=colours, edgecolors=PRIMITIVE_EDGE_RGBA, linewidths=widths)
    ax.add_collection3d(robot)
    com = model.com(q)
    ax.plot([com[0], com[0]], [com[1], com[1]], [com[2], 0.0], color="red", lw=0.8, ls=":")
    ax.scatter(*com, color="red", s=18, depthshade=False)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_zlim(z0, z1)
    ax.set_box_aspect((x1 - x0, y1 - y0, z1 - z0))
    ax.view_init(elev=VIEW_ELEVATION_DEG, azim=VIEW_AZIMUTH_DEG)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)


def _bounds(model: Model, qs: Sequence[FloatArray], visuals: Sequence[Visual], margin: float = 0.05) -> FloatArray:
    """One box holding the robot at every configuration of ``qs`` and the floor at z = 0 (a
    robot without visuals: its frames' origins)."""
    points = np.concatenate([_robot_points(model, q, visuals) for q in qs])
    low = np.minimum(points.min(axis=0), [np.inf, np.inf, 0.0]) - margin
    high = points.max(axis=0) + margin
    return np.array([low, high])


def _robot_points(model: Model, q: FloatArray, visuals: Sequence[Visual]) -> FloatArray:
    """The corners of every face at ``q``, or the frames' origins when there is no face."""
    faces = robot_faces(model, q, visuals)[0]
    if faces:
        return np.concatenate(faces)
    return np.array([model.frame_pose(q, frame)[:3, 3] for frame in model.frame_names])


def robot_strip(
    model: Model,
    urdf: str | os.PathLike[str],
    qs: Sequence[FloatArray],
    times: Times,
    path: str | os.PathLike[str],
    title: str | None = None,
    package_dirs: Sequence[str | os.PathLike[str]] = (),
) -> pathlib.Path:
    """A PNG strip of the robot at configurations ``qs`` (each nq) labelled with ``times``
    (``package_dirs``: see :func:`urdf_visuals`)."""
    require_plots("robot_strip")
    import matplotlib.pyplot as plt

    visuals = urdf_visuals(urdf, package_dirs)
    bounds = _bounds(model, qs, visuals)
    fig = plt.figure(figsize=(2.6 * len(qs), 3.6))
    for k, (q, t) in enumerate(zip(qs, times)):
        ax = fig.add_subplot(1, len(qs), k + 1, projection="3d")
        _draw(ax, model, q, visuals, bounds, f"t = {t:.2f} s")
    if title:
        fig.suptitle(title, fontsize=10)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.92, wspace=0.0)
    path = pathlib.Path(path)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def robot_animation(
    model: Model,
    urdf: str | os.PathLike[str],
    qs: Sequence[FloatArray],
    times: Times,
    path: str | os.PathLike[str],
    fps: int = 10,
    title: str | None = None,
    package_dirs: Sequence[str | os.PathLike[str]] = (),
) -> pathlib.Path | None:
    """An animated GIF of the robot through ``qs``; None when Pillow is missing (then nothing
    is written). ``package_dirs``: see :func:`urdf_visuals`."""
    require_plots("robot_animation")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    if not PillowWriter.isAvailable():
        return None
    visuals = urdf_visuals(urdf, package_dirs)
    bounds = _bounds(model, qs, visuals)
    fig = plt.figure(figsize=(4.0, 4.6))
    ax = fig.add_subplot(projection="3d")
    prefix = f"{title}: " if title else ""

    def frame(k: int) -> list[Any]:
        _draw(ax, model, qs[k], visuals, bounds, f"{prefix}t = {times[k]:.2f} s")
        return []

    animation = FuncAnimation(fig, frame, frames=len(qs))
    path = pathlib.Path(path)
    animation.save(path, writer=PillowWriter(fps=fps), dpi=80)
    plt.close(fig)
    return path


def scenario_pictures(
    scenario: str | os.PathLike[str],
    result: ScenarioResult,
    out: str | os.PathLike[str],
    stem: str,
    instants: Times | None = None,
    title: str | None = None,
    animation_frames: int = 40,
    package_dirs: Sequence[str | os.PathLike[str]] = (),
) -> list[pathlib.Path]:
    """Writes ``out/{stem}_strip.png`` (the robot at ``instants``, default five evenly spaced
    over the run, each at the nearest recorded sample) and ``out/{stem}.gif`` (about
    ``animation_frames`` frames) for a run of the scenario file ``scenario``; ``package_dirs``:
    see :func:`urdf_visuals`. Returns the paths."""
    scenario = pathlib.Path(scenario)
    urdf = scenario_urdf(scenario)
    model = Model.from_urdf(urdf, joints=result.joint_names)
    time = result.time
    chosen = np.linspace(time[0], time[-1], 5) if instants is None else np.asarray(instants)
    rows = [int(np.argmin(abs(time - t))) for t in chosen]
    out = pathlib.Path(out)
    strip = out / f"{stem}_strip.png"
    written = [robot_strip(model, urdf, [result.q[r] for r in rows], time[rows], strip, title, package_dirs)]
    frames = np.unique(np.linspace(0, len(time) - 1, animation_frames).round().astype(int))
    qs = [result.q[r] for r in frames]
    gif = robot_animation(model, urdf, qs, time[frames], out / f"{stem}.gif", title=title, package_dirs=package_dirs)
    if gif is not None:
        written.append(gif)
    return written

