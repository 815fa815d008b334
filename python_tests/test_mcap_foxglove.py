"""The MCAP log read back with the `mcap` package as Foxglove would: every message decodes
against its schema (protobuf with `mcap-protobuf-support`, JSON validated with `jsonschema`),
every `/robot` and `/scene` entity hangs on a frame that `/tf` defines, the robot's bodies come
from the URDF (on `/robot`, once), and the URDF is attached."""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ElementTree
from collections import Counter
from pathlib import Path

import jsonschema
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory

import sea_momentum as sm

ROOT = Path(__file__).resolve().parents[1]
TRACKING = ROOT / "scenarios" / "paper" / "tracking.toml"
URDF = ROOT / "urdf" / "icub25.urdf"
PROTOBUF_TOPICS = {"/tf": "foxglove.FrameTransforms", "/scene": "foxglove.SceneUpdate", "/robot": "foxglove.SceneUpdate"}
#: Written once, with the first sample: the robot's bodies (frame-locked, lifetime 0).
ONCE_TOPICS = {"/robot"}
JSON_TOPICS = {
    "/com", "/momentum", "/joints", "/motors", "/contact_wrenches", "/qp", "/base", "/disturbances",
    "/planned_wrenches",
}


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    """A short tracking run with its MCAP log: (result, decoded messages, attachments)."""
    path = tmp_path_factory.mktemp("foxglove") / "tracking.mcap"
    result = sm.run_scenario(TRACKING, {"simulation.duration_s": 0.3}, mcap=path)
    return (result, *_read(path))


def _read(path):
    """The MCAP log at `path` decoded, each JSON message validated against its schema:
    (messages as (topic, schema name, log time, decoded), attachments)."""
    protobuf = DecoderFactory()
    decoders = {}
    messages = []
    with open(path, "rb") as stream:
        reader = make_reader(stream)
        for schema, channel, message in reader.iter_messages():
            if channel.message_encoding == "protobuf":
                assert schema.encoding == "protobuf", channel.topic
                decode = decoders.setdefault(
                    channel.id, protobuf.decoder_for(channel.message_encoding, schema)
                )
                decoded = decode(message.data)
            else:
                assert (channel.message_encoding, schema.encoding) == ("json", "jsonschema")
                decoded = json.loads(message.data)
                validator = decoders.setdefault(
                    channel.id, jsonschema.Draft202012Validator(json.loads(schema.data))
                )
                validator.validate(decoded)
            messages.append((channel.topic, schema.name, message.log_time, decoded))
        attachments = list(reader.iter_attachments())
    return messages, attachments


def test_every_channel_decodes_once_per_recorded_sample(log):
    result, messages, _ = log
    counts = Counter(topic for topic, _, _, _ in messages)
    assert set(counts) == set(PROTOBUF_TOPICS) | JSON_TOPICS
    assert all(count == 1 for topic, count in counts.items() if topic in ONCE_TOPICS), counts
    assert all(count == len(result.time) for topic, count in counts.items() if topic not in ONCE_TOPICS), counts
    for topic, schema, _, _ in messages:
        if topic in PROTOBUF_TOPICS:
            assert schema == PROTOBUF_TOPICS[topic]
        else:
            assert schema.startswith("sea_momentum.")


def _urdf_links_with_visuals() -> dict[str, int]:
    root = ElementTree.parse(URDF).getroot()
    return {
        link.get("name"): len(link.findall("visual"))
        for link in root.findall("link")
        if link.findall("visual")
    }


def test_scene_entities_hang_on_tf_frames_and_draw_the_urdf(log):
    _, messages, _ = log
    tf_frames = {"world"}
    for topic, _, _, decoded in messages:
        if topic == "/tf":
            for transform in decoded.transforms:
                tf_frames |= {transform.parent_frame_id, transform.child_frame_id}
    scenes = [decoded for topic, _, _, decoded in messages if topic == "/scene"]
    (robot,) = [(time, decoded) for topic, _, time, decoded in messages if topic == "/robot"]
    assert scenes
    assert robot[0] == min(time for _, _, time, _ in messages), "/robot comes with the first sample"
    for scene in scenes + [robot[1]]:
        for entity in scene.entities:
            assert entity.frame_id in tf_frames, f"{entity.id}: {entity.frame_id} not in /tf"
    entities = {entity.id: entity for entity in scenes[-1].entities}
    assert not any(id_.startswith("link/") for id_ in entities)
    bodies = {e.id.removeprefix("link/"): e for e in robot[1].entities if e.id.startswith("link/")}
    visuals = _urdf_links_with_visuals()
    assert {name: len(e.cubes) + len(e.cylinders) + len(e.spheres) for name, e in bodies.items()} == visuals
    assert all(e.frame_locked and e.frame_id == name for name, e in bodies.items())
    # CoM and reference spheres, an arrow and a closed support rectangle per contact.
    assert len(entities["com"].spheres) == 1 and len(entities["com_reference"].spheres) == 1
    contacts = [id_.removeprefix("wrench/") for id_ in entities if id_.startswith("wrench/")]
    assert contacts
    for contact in contacts:
        assert len(entities[f"support/{contact}"].lines[0].points) == 4
        assert entities[f"wrench/{contact}"].arrows[0].shaft_length > 0.0


def test_com_marker_follows_the_com_channel(log):
    _, messages, _ = log
    com_by_time = {t: d["com"] for topic, _, t, d in messages if topic == "/com"}
    for topic, _, time, scene in messages:
        if topic == "/scene":
            sphere = next(e for e in scene.entities if e.id == "com").spheres[0]
            position = sphere.pose.position
            assert [position.x, position.y, position.z] == pytest.approx(com_by_time[time], abs=1e-12)


def test_urdf_is_attached(log):
    _, _, attachments = log
    urdf = [a for a in attachments if a.name == URDF.name]
    assert len(urdf) == 1
    assert urdf[0].media_type == "application/xml"
    assert urdf[0].data == URDF.read_bytes()


def _leaf(decoded, field):
    """The value at `field` (dotted keys with indices: `contacts[1].force[2]`) of the decoded
    message `decoded`, `None` when it has no such field or index."""
    value = decoded
    for part in field.split("."):
        name, *indices = re.split(r"[\[\]]+", part.rstrip("]"))
        if not isinstance(value, dict) or name not in value:
            return None
        value = value[name]
        for index in indices:
            if not isinstance(value, list) or int(index) >= len(value):
                return None
            value = value[int(index)]
    return value


def test_layout_plots_fields_the_log_has(log, tmp_path):
    """foxglove/layout.json: every plotted path names a topic of the log and a leaf value of
    its messages, in the tracking run (one foot, the paper's motor velocity loop) or in a short
    walk (two feet)."""
    _, messages, _ = log
    path = tmp_path / "two_feet.mcap"
    overrides = {"simulation.duration_s": 0.02}
    sm.run_scenario(ROOT / "scenarios" / "walking" / "walk_push.toml", overrides, mcap=path)
    two_feet, _ = _read(path)
    logs = [
        {topic: decoded for topic, _, _, decoded in run if topic in JSON_TOPICS}
        for run in (messages, two_feet)
    ]
    layout = json.loads((ROOT / "foxglove" / "layout.json").read_text())
    paths = [p["value"] for config in layout["configById"].values() for p in config.get("paths", [])]
    assert paths
    for path in paths:
        topic, _, field = path.partition(".")
        assert all(topic in last for last in logs), path
        leaves = [_leaf(last[topic], field) for last in logs]
        assert any(v is not None and not isinstance(v, (dict, list)) for v in leaves), path
    three_d = next(c for key, c in layout["configById"].items() if key.startswith("3D!"))
    assert "/scene" in three_d["topics"]
    assert three_d["topics"]["/robot"]["visible"]


def test_the_unilateral_channels_validate_against_their_schemas(tmp_path):
    """Under unilateral contacts: `/contact_points` and `/contact_check` (the contact check of
    the delivered wrenches) at every recorded sample, each message valid against its JSON
    Schema; the feet start 2 mm in the air, so the check's `/events` warn of their normal force
    and then report them satisfied."""
    path = tmp_path / "dropped.mcap"
    overrides = {
        "plant.contact_model": "unilateral",
        "ground.height_m": -0.002,
        "disturbances": [],
        "simulation.stop_at_joint_limits": False,
        "simulation.duration_s": 0.1,
    }
    result = sm.run_scenario(ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml", overrides, mcap=path)
    counts: Counter[str] = Counter()
    events = []
    protobuf = DecoderFactory()
    with open(path, "rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages():
            counts[channel.topic] += 1
            if channel.topic in ("/contact_points", "/contact_check"):
                jsonschema.Draft202012Validator(json.loads(schema.data)).validate(json.loads(message.data))
            elif channel.topic == "/events":
                events.append(protobuf.decoder_for("protobuf", schema)(message.data))
    assert counts["/contact_points"] == counts["/contact_check"] == len(result.time)
    checks = [e for e in events if e.name == "sea_sim.contact_check"]
    assert [e.level for e in checks] == [3, 3, 2, 2]  # WARNING, WARNING, INFO, INFO
    assert all("normal_force" in e.message for e in checks[:2])


def test_the_log_replaces_its_target_at_the_end_and_refuses_devices_and_inputs(tmp_path):
    """The log is written beside its path and renamed over it when the run ends (no partial
    file left); a device, the scenario file itself or its robot description's file is refused
    before the run, the inputs untouched."""
    path = tmp_path / "run.mcap"
    path.write_bytes(b"an earlier file")
    sm.run_scenario(TRACKING, {"simulation.duration_s": 0.05}, mcap=path)
    assert path.read_bytes()[:8] == b"\x89MCAP0\r\n"
    assert not (tmp_path / ".run.mcap.partial").exists()
    with pytest.raises(sm.SeaIOError, match="must be a regular file"):
        sm.run_scenario(TRACKING, {"simulation.duration_s": 0.05}, mcap="/dev/null")
    copy = tmp_path / "tracking.toml"
    text = TRACKING.read_text().replace("../../urdf/icub25.urdf", str(URDF))
    copy.write_text(text)
    with pytest.raises(sm.SeaIOError, match="would overwrite the scenario file"):
        sm.run_scenario(copy, {"simulation.duration_s": 0.05}, mcap=copy)
    assert copy.read_text() == text
    description = tmp_path / "icub.toml"
    description.write_text((ROOT / "robots" / "icub_paper.toml").read_text())
    with pytest.raises(sm.SeaIOError, match="would overwrite the robot description file"):
        sm.run_scenario(copy, {"simulation.duration_s": 0.05, "robot.description": "icub.toml"},
                        mcap=description)
    assert description.read_text() == (ROOT / "robots" / "icub_paper.toml").read_text()


def test_a_disturbance_after_the_runs_end_is_a_warning_naming_it():
    push = ROOT / "scenarios" / "robot_rate" / "push_two_feet.toml"
    with pytest.warns(UserWarning, match=r"disturbances\[0\]\.start_s .* never acts"):
        sm.run_scenario(push, {"simulation.duration_s": 0.05})
