"""Recording to MCAP (issue 29): the converter, the bounded inbox, typed errors, and a recording of the
simulated chair read back with an independent reader (rosbags, which knows no type but the file's own
schemas: ``Stores.EMPTY``)."""

from __future__ import annotations

import errno
import io
import math
import shutil
import time
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from mcap_ros2.writer import Writer
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from pmk_nb.chair.link.record.msgdefs import DEFINITIONS
from pmk_nb.chair.link.record.record_convert import stamp_ns, to_ros2
from pmk_nb.chair.link.record.recording import Inbox, RecordDiskError, UnknownTopic, UnsupportedType

REQUIRED = [
    "nav_msgs/msg/Odometry",
    "sensor_msgs/msg/LaserScan",
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "tf2_msgs/msg/TFMessage",
    "nav_msgs/msg/OccupancyGrid",
    "nav_msgs/msg/Path",
    "geometry_msgs/msg/Twist",
]


def _typestore_of(type_name: str):
    """A type store holding only what rosbags parses from our bundled definition text."""
    store = get_typestore(Stores.EMPTY)
    store.register(get_types_from_msg(DEFINITIONS[type_name], type_name))
    return store


def _roundtrip(type_name: str, msg: dict) -> object:
    """Convert, encode with mcap_ros2 and decode with rosbags from our schema text."""
    buf = io.BytesIO()
    writer = Writer(buf)
    schema = writer.register_msgdef(type_name, DEFINITIONS[type_name])
    writer.write_message("/t", schema, to_ros2(msg, type_name), log_time=1)
    writer.finish()
    buf.seek(0)
    raw = next(iter(make_reader(buf).iter_messages()))[2].data
    return _typestore_of(type_name).deserialize_cdr(raw, type_name)


@pytest.mark.parametrize("type_name", REQUIRED)
def test_bundled_definitions_parse_with_rosbags_as_ros2_humble_defines_them(type_name: str) -> None:
    parsed = get_types_from_msg(DEFINITIONS[type_name], type_name)
    reference = get_typestore(Stores.ROS2_HUMBLE)
    for name, (_consts, fields) in parsed.items():
        assert [f[0] for f in fields] == [f[0] for f in reference.fielddefs[name][1]], name


def test_ros1_stamps_become_sec_nanosec_and_seq_is_dropped() -> None:
    ros1 = {
        "header": {"seq": 7, "stamp": {"secs": 1700000000, "nsecs": 250}, "frame_id": "odom"},
        "child_frame_id": "base_link",
        "pose": {"pose": {"position": {"x": 1.5, "y": -2.0, "z": 0.0}, "orientation": {"w": 1.0}}},
        "twist": {"twist": {"linear": {"x": 0.4}, "angular": {"z": -0.1}}},
    }
    converted = to_ros2(ros1, "nav_msgs/msg/Odometry")
    assert converted["header"] == {"stamp": {"sec": 1700000000, "nanosec": 250}, "frame_id": "odom"}
    assert stamp_ns(converted) == 1700000000 * 10**9 + 250
    msg = _roundtrip("nav_msgs/msg/Odometry", ros1)
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (1700000000, 250)
    assert (msg.pose.pose.position.x, msg.twist.twist.linear.x, msg.twist.twist.angular.z) == (1.5, 0.4, -0.1)
    assert msg.pose.covariance.shape == (36,)


def test_null_ranges_become_nan_float32_not_zero() -> None:
    scan = {
        "header": {"stamp": {"sec": 5, "nanosec": 0}, "frame_id": "laser"},
        "angle_min": -1.0,
        "angle_max": 1.0,
        "angle_increment": 1.0,
        "range_min": 0.1,
        "range_max": 10.0,
        "ranges": [1.25, None, 3.5],
        "intensities": [],
        "scan_time": None,
    }
    msg = _roundtrip("sensor_msgs/msg/LaserScan", scan)
    assert msg.ranges.dtype == np.float32
    assert msg.ranges[0] == pytest.approx(1.25) and msg.ranges[2] == pytest.approx(3.5)
    assert math.isnan(msg.ranges[1])
    assert math.isnan(msg.scan_time)


def test_tf_message_time_is_its_first_transform_stamp() -> None:
    tf = {"transforms": [{"header": {"stamp": {"secs": 3, "nsecs": 9}, "frame_id": "odom"}, "child_frame_id": "b"}]}
    converted = to_ros2(tf, "tf2_msgs/msg/TFMessage")
    assert stamp_ns(converted) == 3 * 10**9 + 9
    assert stamp_ns(to_ros2({}, "geometry_msgs/msg/Twist")) is None


def test_the_inbox_drops_and_counts_when_full_and_never_waits() -> None:
    inbox = Inbox(limit=3)
    pushed = [inbox.push("/odom", {"i": i}) for i in range(5)]  # a blocking put would hang here forever
    assert pushed == [True, True, True, False, False]
    assert inbox.dropped == 2
    got = [inbox.get(0.01) for _ in range(4)]
    assert [g[2]["i"] for g in got[:3] if g] == [0, 1, 2] and got[3] is None


def _publish_for(link, seconds: float, v: float) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        link.publish_cmd_vel(v, 0.0)
        time.sleep(0.1)


@pytest.mark.slow
@pytest.mark.parametrize("ros", ["ros1", "ros2"])
def test_a_recording_of_the_sim_reads_back_with_rosbags(sim_factory, link_factory, tmp_path: Path, ros: str) -> None:
    sim = sim_factory(ros=ros, laser_blind=(-0.2, 0.2))
    link = link_factory(sim)
    (folder := tmp_path / "recordings").mkdir()
    path = folder / "run.mcap"
    recording = link.start_recording(path)
    assert set(recording.types) >= {"/odom", "/scan", "/tf", "/map", "/cmd_vel"}
    assert not path.exists()  # written to a temporary file, renamed at stop
    _publish_for(link, 2.0, 0.3)
    stats = recording.stop()
    assert stats.finished and stats.dropped == 0 and stats.invalid == 0
    assert stats.messages["/odom"] >= 10 and stats.messages["/scan"] >= 5 and stats.messages["/cmd_vel"] >= 5
    assert [p.name for p in folder.iterdir()] == ["run.mcap"]  # no temporary file left

    counts: dict[str, int] = {}
    speeds: list[float] = []
    with AnyReader([path], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        assert types["/odom"] == "nav_msgs/msg/Odometry" and types["/scan"] == "sensor_msgs/msg/LaserScan"
        for conn, _t, raw in reader.messages():
            msg = reader.deserialize(raw, conn.msgtype)
            counts[conn.topic] = counts.get(conn.topic, 0) + 1
            if conn.topic == "/odom":
                assert msg.header.stamp.sec > 1_600_000_000  # ROS 1 secs/nsecs arrived as sec/nanosec
                speeds.append(msg.twist.twist.linear.x)
            elif conn.topic == "/scan":
                ahead = np.abs(msg.angle_min + msg.angle_increment * np.arange(msg.ranges.size)) < 0.15
                assert msg.ranges.dtype == np.float32 and np.isnan(msg.ranges[ahead]).all()  # null -> NaN
                assert np.isfinite(msg.ranges[~ahead]).any()
            elif conn.topic == "/map":
                assert (msg.info.width, msg.info.height) == (sim.grid.width, sim.grid.height)
    assert counts == {t: n for t, n in stats.messages.items() if n}
    assert max(speeds) > 0.1  # the chair drove

    with path.open("rb") as fh:  # log_time = receive time, publish_time = header stamp
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        for _schema, _channel, message, odom in reader.iter_decoded_messages(topics=["/odom"]):
            assert message.publish_time == odom.header.stamp.sec * 10**9 + odom.header.stamp.nanosec
            assert 0 <= message.log_time - message.publish_time < 30 * 10**9


def test_unknown_topic_and_unsupported_type_are_typed(sim_chair, link_factory, tmp_path: Path) -> None:
    link = link_factory(sim_chair)
    (folder := tmp_path / "recordings").mkdir()
    with pytest.raises(UnknownTopic) as unknown:
        link.start_recording(folder / "a.mcap", ["/no_such_topic"])
    assert unknown.value.topic == "/no_such_topic" and "/odom" in unknown.value.known
    with pytest.raises(UnsupportedType) as unsupported:
        link.start_recording(folder / "b.mcap", {"/odom": "pmk_test/msg/Undescribed"})  # rosapi knows it not
    assert unsupported.value.type_name == "pmk_test/msg/Undescribed"
    assert "nav_msgs/msg/Odometry" in unsupported.value.supported
    assert list(folder.iterdir()) == []


def test_a_folder_that_does_not_exist_is_a_disk_error(sim_chair, link_factory, tmp_path: Path) -> None:
    link = link_factory(sim_chair)
    with pytest.raises(RecordDiskError) as err:
        link.record(tmp_path / "missing" / "run.mcap", ["/odom"], seconds=0.5)
    assert err.value.errno == errno.ENOENT and err.value.path.endswith("run.mcap")


def test_a_folder_removed_while_recording_is_a_disk_error_at_stop(sim_chair, link_factory, tmp_path: Path) -> None:
    link = link_factory(sim_chair)
    (folder := tmp_path / "recordings").mkdir()
    recording = link.start_recording(folder / "run.mcap", ["/odom"])
    assert recording.error is None
    shutil.rmtree(folder)  # the open temporary file goes with it: the final rename cannot happen
    with pytest.raises(RecordDiskError) as err:
        recording.stop()
    assert err.value.errno == errno.ENOENT and recording.error is err.value
    assert not recording.stats.finished and not folder.exists()


@pytest.mark.slow
def test_a_silent_topic_is_never_waited_for_and_is_named(sim_factory, link_factory, tmp_path: Path) -> None:
    """Issue 40, item 1: README's `seconds=2.0` took 12 s: /cmd_vel says nothing on a parked chair."""
    sim = sim_factory(ros="ros2")
    link = link_factory(sim)
    (folder := tmp_path / "recordings").mkdir()
    started = time.monotonic()
    stats = link.record(folder / "parked.mcap", seconds=0.5, flow_timeout=120.0)
    took = time.monotonic() - started
    assert stats.silent == ["/cmd_vel"] and stats.messages["/odom"] > 0 and stats.finished
    assert took < 60.0, f"waited {took:.0f} s for a silent topic (flow_timeout 120 s)"  # the old wait: 120 s
