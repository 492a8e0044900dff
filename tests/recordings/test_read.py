"""Recordings as tables (issue 40): our recording of the simulated chair, Foxglove's JSON, ROS 1 and
``ros2 bag``'s IDL channels, read with the real mcap reader; DataFrames, or a typed error without pandas."""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from mcap.writer import Writer
from rosbags.typesys import Stores, get_typestore

from pmk_nb.recordings import (
    MissingPackage,
    NotARecording,
    UnsupportedEncoding,
    read_frames,
    read_recording,
)


def _write(path: Path, channels: list[tuple[str, str, str, bytes, str, list[tuple[int, bytes]]]]) -> Path:
    """An MCAP with (topic, schema name, schema encoding, schema data, message encoding, [(ns, data)])."""
    with path.open("wb") as fh:
        writer = Writer(fh)
        writer.start(profile="", library="test")
        for topic, name, schema_encoding, data, message_encoding, messages in channels:
            schema_id = writer.register_schema(name=name, encoding=schema_encoding, data=data) if name else 0
            channel = writer.register_channel(topic=topic, message_encoding=message_encoding, schema_id=schema_id)
            for ns, payload in messages:
                writer.add_message(channel_id=channel, log_time=ns, publish_time=ns, data=payload)
        writer.finish()
    return path


@pytest.mark.slow
def test_a_recording_of_the_sim_opens_as_one_table_per_topic(
    sim_factory, link_factory, ros_factory, tmp_path: Path
) -> None:
    import roslibpy

    sim = sim_factory(ros="ros1", laser_blind=(-0.2, 0.2))
    link = link_factory(sim)
    pub = roslibpy.Topic(ros_factory(sim), "/markers", "visualization_msgs/MarkerArray")
    pub.advertise()
    deadline = time.monotonic() + 30.0
    while "/markers" not in link.discovery.topics() and time.monotonic() < deadline:
        time.sleep(0.05)
    path = tmp_path / "run.mcap"
    recording = link.start_recording(path, ["/odom", "/scan", "/tf", "/markers"])
    recording.wait_flowing(30.0)
    deadline = time.monotonic() + 60.0
    counts = recording.stats.messages
    while (min(counts.values()) < 3 or counts["/odom"] < 25) and time.monotonic() < deadline:
        link.publish_cmd_vel(0.3, 0.0)
        marker = {"header": {"stamp": {"secs": 50, "nsecs": 0}}, "ns": "n", "pose": {"position": {"x": 4.0}}}
        pub.publish(roslibpy.Message({"markers": [marker]}))
        time.sleep(0.05)
    stats = recording.stop()

    tables = read_recording(path)
    assert {t: len(r) for t, r in tables.rows.items()} == stats.messages
    assert tables.types["/odom"] == "nav_msgs/msg/Odometry" and not tables.skipped and not tables.bad
    odom = tables.rows["/odom"]
    first = odom[0]
    assert list(first)[:2] == ["received", "stamp"]
    assert first["stamp"] == pytest.approx(first["header.stamp.sec"] + first["header.stamp.nanosec"] * 1e-9)
    assert 0 <= first["received"] - first["stamp"] < 30  # received here after the chair stamped it
    assert {"pose.pose.position.x", "twist.twist.linear.x", "child_frame_id"} <= set(first)
    xs = [r["pose.pose.position.x"] for r in odom]
    assert len(set(xs)) > 1  # the chair drove: the positions change
    scan = tables.rows["/scan"][-1]
    angles = scan["angle_min"] + scan["angle_increment"] * np.arange(scan["ranges"].size)
    assert np.isnan(scan["ranges"][np.abs(angles) < 0.15]).all()  # the blind sector: NaN, never 0
    assert isinstance(tables.rows["/tf"][0]["transforms"], list)
    assert not math.isnan(tables.rows["/tf"][0]["stamp"])
    markers = tables.rows["/markers"][0]
    assert markers["stamp"] == 50.0 or math.isnan(markers["stamp"])  # a MarkerArray has no header of its own
    assert markers["markers"][0]["pose.position.x"] == 4.0 and markers["markers"][0]["header.stamp.sec"] == 50

    only = read_recording(path, ["/odom", "/not_recorded"])
    assert set(only.rows) == {"/odom", "/not_recorded"} and only.rows["/not_recorded"] == []
    assert len(only.rows["/odom"]) == len(odom)


def test_foxglove_json_channels_and_ros1_and_idl_channels_read(tmp_path: Path) -> None:
    ros1 = get_typestore(Stores.ROS1_NOETIC)
    odom_type = "nav_msgs/msg/Odometry"
    odom_text, _md5 = ros1.generate_msgdef(odom_type, ros_version=1)
    o = ros1.types
    header = o["std_msgs/msg/Header"](seq=3, stamp=o["builtin_interfaces/msg/Time"](sec=20, nanosec=5), frame_id="odom")
    point, quat = o["geometry_msgs/msg/Point"](x=1.25, y=0.0, z=0.0), o["geometry_msgs/msg/Quaternion"](0, 0, 0, 1)
    pose = o["geometry_msgs/msg/PoseWithCovariance"](o["geometry_msgs/msg/Pose"](point, quat), np.zeros(36))
    vec = o["geometry_msgs/msg/Vector3"]
    twist = o["geometry_msgs/msg/TwistWithCovariance"](
        o["geometry_msgs/msg/Twist"](vec(0.3, 0, 0), vec(0, 0, 0)), np.zeros(36)
    )
    raw_odom = ros1.serialize_ros1(o[odom_type](header, "base_link", pose, twist), odom_type)

    humble = get_typestore(Stores.ROS2_HUMBLE)
    idl = "module std_msgs {\n  module msg {\n    struct String {\n      string data;\n    };\n  };\n};\n"
    idl_schema = f"{'=' * 80}\nIDL: std_msgs/msg/String\n{idl}".encode()
    raw_string = humble.serialize_cdr(humble.types["std_msgs/msg/String"](data="hello"), "std_msgs/msg/String")

    pose_json = {"timestamp": {"sec": 9, "nsec": 500_000_000}, "frame_id": "map", "position": {"x": 2.0}}
    path = _write(
        tmp_path / "mixed.mcap",
        [
            ("/odom1", "nav_msgs/Odometry", "ros1msg", odom_text.encode(), "ros1", [(1_000, raw_odom)]),
            ("/words", "std_msgs/msg/String", "ros2idl", idl_schema, "cdr", [(2_000, raw_string)]),
            ("/pose", "foxglove.PoseInFrame", "jsonschema", b"{}", "json", [(3_000, json.dumps(pose_json).encode())]),
            ("/schemaless", "", "", b"", "json", [(4_000, b'{"header": {"stamp": {"sec": 1, "nsec": 0}}}')]),
        ],
    )
    tables = read_recording(path)
    odom = tables.rows["/odom1"][0]
    assert odom["pose.pose.position.x"] == 1.25 and odom["twist.twist.linear.x"] == pytest.approx(0.3)
    assert odom["stamp"] == pytest.approx(20 + 5e-9) and odom["header.seq"] == 3 and odom["received"] == 1e-6
    assert tables.rows["/words"][0]["data"] == "hello"
    pose = tables.rows["/pose"][0]
    assert pose["position.x"] == 2.0 and pose["timestamp.nsec"] == 500_000_000 and math.isnan(pose["stamp"])
    assert tables.rows["/schemaless"][0]["stamp"] == 1.0


def test_an_encoding_it_cannot_decode_is_typed_when_asked_and_skipped_otherwise(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "proto.mcap",
        [
            ("/cam", "foxglove.CompressedImage", "protobuf", b"\x00", "protobuf", [(1, b"\x00")]),
            ("/ok", "", "", b"", "json", [(2, b'{"a": 1}'), (3, b"not json")]),
        ],
    )
    with pytest.raises(UnsupportedEncoding) as err:
        read_recording(path, ["/cam"])
    assert (err.value.topic, err.value.message_encoding, err.value.schema_encoding) == ("/cam", "protobuf", "protobuf")
    tables = read_recording(path)
    assert set(tables.skipped) == {"/cam"} and tables.skipped["/cam"].topic == "/cam"
    assert tables.rows["/ok"] == [{"received": 2e-9, "stamp": tables.rows["/ok"][0]["stamp"], "a": 1}]
    assert tables.bad == {"/ok": 1}  # the line that is not JSON: counted, not fatal


def test_a_missing_or_foreign_file_is_not_a_recording(tmp_path: Path) -> None:
    with pytest.raises(NotARecording) as missing:
        read_recording(tmp_path / "none.mcap")
    assert missing.value.path.endswith("none.mcap")
    (text := tmp_path / "notes.mcap").write_text("not an mcap file at all")
    with pytest.raises(NotARecording) as foreign:
        read_recording(text)
    assert foreign.value.path == str(text) and foreign.value.reason


def test_frames_are_dataframes_or_a_typed_error_naming_pandas(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = _write(
        tmp_path / "j.mcap",
        [("/t", "", "", b"", "json", [(1_000_000_000, b'{"header": {"stamp": {"sec": 1, "nsec": 0}}, "v": 2.5}')])],
    )
    with monkeypatch.context() as m:  # a box where pandas cannot be imported: a typed error, not a crash
        m.setitem(sys.modules, "pandas", None)
        with pytest.raises(MissingPackage) as err:
            read_frames(path)
        assert err.value.package == "pandas" and err.value.path == str(path)
        with pytest.raises(MissingPackage):
            read_recording(path).frames()
    frames = read_frames(path)  # pandas is a runtime dependency: the DataFrames themselves
    frame = frames["/t"]
    assert list(frame.columns)[:2] == ["received", "stamp"] and frame["v"].tolist() == [2.5]
    assert frame["stamp"].tolist() == [1.0] and frame["received"].tolist() == [1.0]


def test_a_ros2_bag_written_by_rosbags_opens_as_tables(tmp_path: Path) -> None:
    """A rosbag2 MCAP storage file, as ``ros2 bag record -s mcap`` writes it (here by rosbags' writer)."""
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as BagWriter

    store = get_typestore(Stores.ROS2_HUMBLE)
    t = store.types
    stamp = t["builtin_interfaces/msg/Time"](sec=42, nanosec=0)
    pose = t["geometry_msgs/msg/Pose"](
        t["geometry_msgs/msg/Point"](3.0, 4.0, 0.0), t["geometry_msgs/msg/Quaternion"](0, 0, 0, 1)
    )
    msg = t["geometry_msgs/msg/PoseStamped"](t["std_msgs/msg/Header"](stamp, "map"), pose)
    with BagWriter(tmp_path / "bag", version=9, storage_plugin=StoragePlugin.MCAP) as bag:
        conn = bag.add_connection("/goal_pose", "geometry_msgs/msg/PoseStamped", typestore=store)
        bag.write(conn, 42 * 10**9, store.serialize_cdr(msg, "geometry_msgs/msg/PoseStamped"))
    (file,) = (tmp_path / "bag").glob("*.mcap")
    tables = read_recording(file)
    assert tables.types == {"/goal_pose": "geometry_msgs/msg/PoseStamped"}
    (goal,) = tables.rows["/goal_pose"]
    assert (goal["pose.position.x"], goal["pose.position.y"], goal["header.frame_id"]) == (3.0, 4.0, "map")
    assert goal["stamp"] == 42.0 and goal["received"] == 42.0


def test_frames_are_built_with_pandas_documented_from_records(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Without pandas here, the call itself is checked against a stand-in: one
    ``DataFrame.from_records(rows, columns=...)`` per topic, time columns first, every field once."""
    import types

    calls: list[tuple[list[dict], list[str]]] = []

    class DataFrame:
        @classmethod
        def from_records(cls, data: list[dict], columns: list[str]) -> tuple[str, int]:
            calls.append((data, columns))
            return ("frame", len(data))

    stand_in = types.ModuleType("pandas")
    stand_in.DataFrame = DataFrame  # type: ignore[attr-defined]
    monkeypatch.setitem(__import__("sys").modules, "pandas", stand_in)
    path = _write(
        tmp_path / "two.mcap",
        [
            ("/a", "", "", b"", "json", [(1, b'{"x": 1}'), (2, b'{"x": 2, "y": {"z": 3}}')]),
            ("/empty", "", "", b"", "json", []),
        ],
    )
    frames = read_frames(path)
    assert frames["/a"] == ("frame", 2)
    assert calls[0][1] == ["received", "stamp", "x", "y.z"]  # a field only later messages have still gets a column
    assert any(data == [] and columns == ["received", "stamp"] for data, columns in calls)  # a registered silent topic
