"""Recording any type the bridge describes (issue 40): rosapi's ``message_details`` -> a ros2msg schema.

The simulator answers ``/rosapi/message_details`` as rosapi 1.x / 2.x do; a client publishes RViz markers
through it; the recording is read back by rosbags from the file's own schema (``Stores.EMPTY``)."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from mcap.reader import make_reader
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from pmk_nb.chair.link.record.msgdefs import DEFINITIONS
from pmk_nb.chair.link.record.msgdetails import definition_from_typedefs
from pmk_nb.chair.link.record.recording import UnsupportedType
from pmk_nb.sim.msgtypes import typedefs

MARKERS = "visualization_msgs/msg/MarkerArray"


def _marker(i: int, ros: str) -> dict:
    stamp = {"secs": 100 + i, "nsecs": 5} if ros == "ros1" else {"sec": 100 + i, "nanosec": 5}
    life = {"secs": 2, "nsecs": 0} if ros == "ros1" else {"sec": 2, "nanosec": 0}
    header = {"stamp": stamp, "frame_id": "map"}
    return {
        "markers": [
            {
                "header": header,
                "ns": "rooms",
                "id": i,
                "type": 2,
                "action": 0,
                "pose": {"position": {"x": 1.5 + i, "y": -2.0, "z": 0.0}, "orientation": {"w": 1.0}},
                "scale": {"x": 0.2, "y": 0.2, "z": 0.2},
                "color": {"r": 1.0, "g": 0.5, "b": 0.0, "a": 1.0},
                "lifetime": life,
                "points": [{"x": 0.0, "y": 1.0, "z": 0.0}, {"x": 2.0, "y": 3.0, "z": 0.0}],
                "text": "kitchen",
            }
        ]
    }


@pytest.mark.parametrize("ros", ["ros1", "ros2"])
def test_typedefs_become_the_concatenated_definition_rosbags_parses(ros: str) -> None:
    """The sim's typedefs in each rosapi dialect -> ros2msg text with the ROS 2 header and stamps."""
    described = typedefs(MARKERS, ros)
    assert described is not None and described[0]["type"] == "visualization_msgs/MarkerArray"
    text = definition_from_typedefs(MARKERS, described)
    assert text is not None and text.startswith("visualization_msgs/Marker[] markers\n")
    parsed = get_types_from_msg(text, MARKERS)
    reference = get_typestore(Stores.ROS2_HUMBLE).fielddefs
    marker = [f[0] for f in parsed["visualization_msgs/msg/Marker"][1]]
    humble = [f[0] for f in reference["visualization_msgs/msg/Marker"][1]]
    noetic_only_missing = {"texture_resource", "texture", "uv_coordinates", "mesh_file"}
    assert marker == (humble if ros == "ros2" else [f for f in humble if f not in noetic_only_missing])
    assert [f[0] for f in parsed["std_msgs/msg/Header"][1]] == ["stamp", "frame_id"]  # no ROS 1 seq
    assert "MSG: builtin_interfaces/Duration" in text and "\nduration " not in text and "double" not in text


def test_rosapi_2_idl_spellings_become_msg_primitives() -> None:
    """rosapi 2.x reports IDL names, bounded sequences unwrapped as "int32, 5", bounded strings."""
    typedef = {
        "type": "pmk_test/Odd",
        "fieldnames": ["a", "b", "c", "d", "e", "f", "g"],
        "fieldtypes": [
            "double",
            "float",
            "boolean",
            "octet",
            "int32, 5",
            "string<=10",
            "sequence<geometry_msgs/Point>",
        ],
        "fieldarraylen": [-1, 3, 0, 0, 0, -1, -1],
    }
    point = {"type": "geometry_msgs/Point", "fieldnames": ["x"], "fieldtypes": ["double"], "fieldarraylen": [-1]}
    text = definition_from_typedefs("pmk_test/msg/Odd", [typedef, point])
    assert text is not None
    own = text.split("=" * 80)[0]
    assert own == ("float64 a\nfloat32[3] b\nbool[] c\nbyte[] d\nint32[] e\nstring f\ngeometry_msgs/Point g\n")
    assert get_types_from_msg(text, "pmk_test/msg/Odd")  # a definition rosbags parses


def test_a_type_described_incompletely_is_none_not_a_broken_schema() -> None:
    described = typedefs(MARKERS, "ros2")
    assert described is not None
    without_color = [t for t in described if t["type"] != "std_msgs/ColorRGBA"]
    assert definition_from_typedefs(MARKERS, without_color) is None
    assert definition_from_typedefs(MARKERS, []) is None
    bad = [dict(described[0], fieldarraylen=[0, 0])]
    assert definition_from_typedefs(MARKERS, bad) is None


@pytest.mark.parametrize("ros", ["ros1", "ros2"])
def test_marker_arrays_record_with_the_schema_the_bridge_describes(
    sim_factory, link_factory, ros_factory, tmp_path: Path, ros: str
) -> None:
    import roslibpy

    sim = sim_factory(ros=ros)
    link = link_factory(sim)
    client = ros_factory(sim)
    spelled = "visualization_msgs/MarkerArray" if ros == "ros1" else MARKERS
    pub = roslibpy.Topic(client, "/markers", spelled)
    pub.advertise()
    deadline = time.monotonic() + 30.0
    while "/markers" not in link.discovery.topics() and time.monotonic() < deadline:
        time.sleep(0.05)
    path = tmp_path / "markers.mcap"
    recording = link.start_recording(path, ["/markers", "/odom"])
    assert recording.types["/markers"] == MARKERS
    assert recording.definitions["nav_msgs/msg/Odometry"] == DEFINITIONS["nav_msgs/msg/Odometry"]
    assert recording.wait_flowing(30.0)
    i = 0
    deadline = time.monotonic() + 60.0
    while recording.stats.messages["/markers"] < 3 and time.monotonic() < deadline:
        pub.publish(roslibpy.Message(_marker(i, ros)))
        i += 1
        time.sleep(0.05)
    stats = recording.stop()
    assert stats.messages["/markers"] >= 3 and stats.invalid == 0, stats

    with path.open("rb") as fh:
        schemas = {s.name: s for s in make_reader(fh).get_summary().schemas.values()}
    assert schemas[MARKERS].encoding == "ros2msg"
    with AnyReader([path], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        conns = [c for c in reader.connections if c.topic == "/markers"]
        msgs = [reader.deserialize(raw, c.msgtype) for c, _t, raw in reader.messages(connections=conns)]
    marker = msgs[0].markers[0]
    assert (marker.ns, marker.text, marker.type) == ("rooms", "kitchen", 2)
    assert marker.pose.position.y == -2.0 and marker.color.g == pytest.approx(0.5)
    assert (marker.header.stamp.sec, marker.header.stamp.nanosec) == (100 + marker.id, 5)  # ROS 1 secs/nsecs too
    assert marker.lifetime.sec == 2 and [p.x for p in marker.points] == [0.0, 2.0]


def test_a_type_the_bridge_cannot_describe_is_typed_and_bundled_types_need_no_rosapi(
    sim_factory, link_factory, tmp_path: Path
) -> None:
    sim = sim_factory(ros="ros2")
    link = link_factory(sim)
    with pytest.raises(UnsupportedType) as unknown:
        link.start_recording(tmp_path / "a.mcap", {"/odom": "pmk_test/msg/NoSuchType"})
    assert unknown.value.type_name == "pmk_test/msg/NoSuchType" and unknown.value.rosapi
    assert sim.bridge is not None
    del sim.bridge.services["/rosapi/message_details"]  # an old rosapi: the bundled types need no round trip
    stats = link.record(tmp_path / "b.mcap", {"/odom": "nav_msgs/msg/Odometry"}, seconds=0.3)
    assert stats.messages["/odom"] > 0 and stats.finished
    with pytest.raises(UnsupportedType):
        link.start_recording(tmp_path / "c.mcap", {"/markers": MARKERS})
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".mcap") == ["b.mcap"]
