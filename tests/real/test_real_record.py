"""Real-stack tier (issue 29): record odometry and scans that a real rclpy node publishes, through
rosbridge-server-rs, and read the MCAP file back with rosbags (no type known but the file's own)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from pmk_nb.chair.link import ChairLink
from tests import fixtures_ros2
from tests.fixtures_ros2 import RealChair
from tests.fixtures_sim import room_grid, write_test_map

ros2_stack, real_chair = fixtures_ros2.ros2_stack, fixtures_ros2.real_chair
pytestmark = [pytest.mark.slow, pytest.mark.timeout(300)]


def test_a_recording_of_rclpy_odometry_and_scans_reads_back(real_chair: RealChair, tmp_path: Path) -> None:
    write_test_map(room_grid(8.0, 6.0), real_chair.maps, "room")
    real_chair.start_bridge()
    real_chair.start_sim_node("--map", "room", "--no-follow-map")
    link = ChairLink("127.0.0.1", real_chair.port)
    link.connect(10)
    try:
        path = tmp_path / "real.mcap"
        stats = link.record(path, ["/odom", "/scan"], seconds=3.0)
    finally:
        link.close()
    assert stats.finished and stats.invalid == 0 and stats.dropped == 0
    assert stats.messages["/odom"] >= 30 and stats.messages["/scan"] >= 10  # 50 Hz and 20 Hz for 3 s

    stamps: dict[str, list[int]] = {"/odom": [], "/scan": []}
    with AnyReader([path], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == {
            "/odom": "nav_msgs/msg/Odometry",
            "/scan": "sensor_msgs/msg/LaserScan",
        }
        for conn, _t, raw in reader.messages():
            msg = reader.deserialize(raw, conn.msgtype)
            stamps[conn.topic].append(msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec)
            if conn.topic == "/odom":
                assert msg.header.frame_id == "odom" and msg.pose.pose.orientation.w != 0.0
            else:
                assert msg.ranges.dtype == np.float32 and msg.ranges.size == 720
                assert np.isfinite(msg.ranges).sum() > 100  # the room's walls were seen
    assert {t: len(s) for t, s in stamps.items()} == {t: stats.messages[t] for t in stamps}
    for topic, values in stamps.items():  # one message each, in the node's order: none duplicated
        assert len(set(values)) == len(values) and values == sorted(values), topic
