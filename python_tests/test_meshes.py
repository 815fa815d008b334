"""Mesh visuals drawn: every link with a visual of real robots (Talos of ``example-robot-data``,
an iCub of ``icub-models``; STL and DAE files behind ``package://`` URIs) gets an entity on the
MCAP's ``/robot`` channel, meshes as triangle lists; a missing mesh file or an unresolvable
``package://`` URI is a warning naming the link, the URI and the directories searched (in the
log's metadata), the rest is drawn; ``package_dirs`` resolves it; the pictures draw a robot made
of meshes only."""

from __future__ import annotations

import importlib.metadata
import pathlib
import warnings
import xml.etree.ElementTree as ElementTree
from types import SimpleNamespace

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

import sea_momentum as sm
from sea_momentum import pictures
from sea_momentum._native import ModelError, link_meshes

ROOT = pathlib.Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
ICUB25 = ROOT / "urdf" / "icub25.urdf"


def package_file(package: str, suffix: str) -> pathlib.Path:
    """The file of the installed PyPI ``package`` whose path ends with ``suffix``."""
    for f in importlib.metadata.files(package) or []:
        if str(f).endswith(suffix):
            return pathlib.Path(str(f.locate())).resolve()
    raise FileNotFoundError(f"{package} has no {suffix}")


TALOS = package_file("example-robot-data", "talos_data/robots/talos_reduced.urdf")
ICUB_MODELS = package_file("icub-models", "iCubGenova04/model.urdf")


def links_with_visuals(urdf: pathlib.Path) -> dict[str, list[str]]:
    """Each link with visuals: the tags of its geometries ("mesh", "box", ...)."""
    root = ElementTree.parse(urdf).getroot()
    return {
        link.get("name", ""): [next(iter(v.find("geometry"))).tag for v in link.findall("visual")]  # type: ignore[arg-type]
        for link in root.findall("link")
        if link.findall("visual")
    }


def talos_scenario(tmp_path: pathlib.Path) -> pathlib.Path:
    """A two-feet Talos scenario (rigid; the iCub-tuned defaults do not keep it up for long,
    the log's scene is written with the first sample all the same)."""
    joints = sm.Model.from_urdf(TALOS).joint_names
    path = tmp_path / "talos.toml"
    path.write_text(
        f"""name = "talos"
[robot]
urdf = "{TALOS}"
joints = {joints!r}
contacts = ["left_sole_link", "right_sole_link"]
initial_posture = "zero"
[actuators]
kind = "rigid"
[controller]
kind = "rigid"
[simulation]
duration_s = 0.05
"""
    )
    return path


def read_log(path: pathlib.Path) -> tuple[dict[str, list], dict[str, dict[str, str]]]:
    """Decoded protobuf messages by topic, and the metadata records by name."""
    decoder = DecoderFactory()
    messages: dict[str, list] = {}
    with open(path, "rb") as stream:
        reader = make_reader(stream)
        for schema, channel, message in reader.iter_messages():
            if channel.message_encoding == "protobuf":
                decode = decoder.decoder_for(channel.message_encoding, schema)
                messages.setdefault(channel.topic, []).append(decode(message.data))
        metadata = {record.name: dict(record.metadata) for record in reader.iter_metadata()}
    return messages, metadata


def check_every_visual_drawn(log: pathlib.Path, urdf: pathlib.Path) -> None:
    messages, metadata = read_log(log)
    (robot,) = messages["/robot"]
    bodies = {e.id.removeprefix("link/"): e for e in robot.entities}
    expected = links_with_visuals(urdf)
    assert set(bodies) == set(expected)
    for link, tags in expected.items():
        body = bodies[link]
        assert body.frame_locked and body.frame_id == link
        assert len(body.triangles) == tags.count("mesh"), link
        for triangles in body.triangles:
            assert len(triangles.indices) % 3 == 0 and len(triangles.indices) >= 3
            assert max(triangles.indices) < len(triangles.points)
    assert metadata["scene"]["mesh_warnings"] == "0"
    assert int(metadata["scene"]["visuals_drawn"]) == sum(len(t) for t in expected.values())
    drawn = sum(len(t.indices) // 3 for e in robot.entities for t in e.triangles)
    assert drawn <= 62_000, "the scene's triangle budget (60k, a few over allowed)"


def test_talos_meshes_are_drawn_once_on_robot(tmp_path):
    log = tmp_path / "talos.mcap"
    sm.run_scenario(talos_scenario(tmp_path), mcap=log)
    check_every_visual_drawn(log, TALOS)
    assert sum(tags.count("mesh") for tags in links_with_visuals(TALOS).values()) == 47


def test_icub_models_meshes_are_drawn(tmp_path):
    log = tmp_path / "genova04.mcap"
    sm.run_scenario(TRACKING, {"simulation.duration_s": 0.02, "robot.urdf": str(ICUB_MODELS)}, mcap=log)
    check_every_visual_drawn(log, ICUB_MODELS)


TETRAHEDRON_STL = """solid t
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 0.05 0
  vertex 0.05 0 0
 endloop
endfacet
facet normal 0 -1 0
 outer loop
  vertex 0 0 0
  vertex 0.05 0 0
  vertex 0 0 0.05
 endloop
endfacet
endsolid t
"""


def icub_with_meshes(tmp_path: pathlib.Path, *filenames: str) -> pathlib.Path:
    """icub25.urdf with one more visual per ``filename`` on ``root_link`` (a mesh), written in
    ``tmp_path/robot/``; ``tmp_path/packages/my_pkg/meshes/part.stl`` exists (not above the
    URDF: ``package://my_pkg`` needs ``tmp_path/packages`` as a package directory)."""
    (tmp_path / "packages" / "my_pkg" / "meshes").mkdir(parents=True)
    (tmp_path / "packages" / "my_pkg" / "meshes" / "part.stl").write_text(TETRAHEDRON_STL)
    (tmp_path / "robot").mkdir()
    visuals = "".join(f'<visual><geometry><mesh filename="{f}"/></geometry></visual>' for f in filenames)
    # After root_link's own visual (urdf-rs wants a link's visuals next to each other).
    head, tail = ICUB25.read_text().split('<link name="root_link">', 1)
    root, rest = tail.split("</link>", 1)
    text = f'{head}<link name="root_link">{root}{visuals}</link>{rest}'
    path = tmp_path / "robot" / "icub_meshes.urdf"
    path.write_text(text)
    return path


def test_missing_and_unresolvable_meshes_are_warnings_naming_link_uri_and_dirs(tmp_path):
    urdf = icub_with_meshes(tmp_path, "meshes/missing.stl", "package://my_pkg/meshes/part.stl")
    meshes, problems = link_meshes(urdf)
    assert meshes == []
    assert len(problems) == 2
    missing, unresolved = problems
    assert "link 'root_link'" in missing and "meshes/missing.stl" in missing and "no such file" in missing
    assert "link 'root_link'" in unresolved and "package://my_pkg/meshes/part.stl" in unresolved
    assert "no package 'my_pkg'" in unresolved and str(urdf.parent) in unresolved
    with pytest.raises(ModelError, match="missing.stl"):
        link_meshes(urdf, strict=True)
    # The run and its log are kept: the warnings go to the metadata, the boxes are drawn.
    log = tmp_path / "run.mcap"
    with pytest.warns(UserWarning, match="package://my_pkg/meshes/part.stl"):
        sm.run_scenario(TRACKING, {"simulation.duration_s": 0.02, "robot.urdf": str(urdf)}, mcap=log)
    messages, metadata = read_log(log)
    assert metadata["scene"]["mesh_warnings"] == "2"
    assert "package://my_pkg/meshes/part.stl" in metadata["scene"]["warning_1"]
    (robot,) = messages["/robot"]
    assert {e.id.removeprefix("link/") for e in robot.entities} == set(links_with_visuals(ICUB25))


def test_package_dirs_resolve_package_uris(tmp_path):
    urdf = icub_with_meshes(tmp_path, "package://my_pkg/meshes/part.stl")
    meshes, problems = link_meshes(urdf, package_dirs=[tmp_path / "packages"])
    assert problems == []
    ((link, vertices, triangles, rgba),) = meshes
    assert link == "root_link" and vertices.shape == (4, 3) and triangles.shape == (2, 3)
    assert vertices.max() == pytest.approx(0.05)
    log = tmp_path / "run.mcap"
    sm.run_scenario(TRACKING, {"simulation.duration_s": 0.02, "robot.urdf": str(urdf)}, mcap=log, package_dirs=[tmp_path / "packages"])
    messages, metadata = read_log(log)
    assert metadata["scene"]["mesh_warnings"] == "0"
    (robot,) = messages["/robot"]
    root = next(e for e in robot.entities if e.id == "link/root_link")
    assert len(root.triangles) == 1 and len(root.triangles[0].points) == 4


def test_link_meshes_refuses_a_bad_budget():
    with pytest.raises(ValueError, match="triangle_budget"):
        link_meshes(TALOS, triangle_budget=0)


def test_pictures_draw_a_robot_made_of_meshes(tmp_path):
    model = sm.Model.from_urdf(TALOS)
    q = model.neutral()
    q[2] = 1.1
    qs = np.array([q, q + np.r_[np.zeros(7), 0.2 * np.ones(model.nq - 7)]])
    stand_in = SimpleNamespace(time=np.array([0.0, 1.0]), q=qs, joint_names=model.joint_names)
    scenario = tmp_path / "talos.toml"
    scenario.write_text(f'[robot]\nurdf = "{TALOS}"\n')
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)  # no mesh left out
        visuals = pictures.urdf_visuals(TALOS)
    kinds = {v.kind for v in visuals}
    assert "mesh" in kinds
    triangles = sum(len(v.mesh[1]) for v in visuals if v.mesh is not None)
    assert 0 < triangles <= pictures.PICTURE_TRIANGLE_BUDGET
    written = pictures.scenario_pictures(scenario, stand_in, tmp_path, "talos", animation_frames=2)  # type: ignore[arg-type]
    assert [p.name for p in written][0] == "talos_strip.png"
    assert all(p.stat().st_size > 10_000 for p in written)
