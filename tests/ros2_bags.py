"""A recording as another tool writes it: a rosbag2 MCAP (what ``ros2 bag record -s mcap`` writes),
made by rosbags' writer, of a chair driving a straight line at 0.5 m/s with a scan every 0.5 s."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

T0_NS = 1_765_000_000 * 10**9
SPEED = 0.5  # m/s along x


def write_drive_bag(folder: Path, seconds: float = 4.0, name: str = "bag", rays: int = 90, scan_every: int = 5) -> Path:
    """The bag's MCAP file (in ``folder/name/``): /odom at 10 Hz (x from 0 at SPEED), /scan of ``rays`` rays
    with every ``scan_every``-th odometry message (2 Hz; more rays, more often: a bigger file)."""
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as BagWriter
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    t = store.types
    cov = np.zeros(36, dtype=np.float64)

    def header(ns: int, frame: str) -> object:
        return t["std_msgs/msg/Header"](t["builtin_interfaces/msg/Time"](ns // 10**9, ns % 10**9), frame)

    def odom(ns: int, x: float) -> object:
        pose = t["geometry_msgs/msg/Pose"](
            t["geometry_msgs/msg/Point"](x, 1.0, 0.0), t["geometry_msgs/msg/Quaternion"](0.0, 0.0, 0.0, 1.0)
        )
        twist = t["geometry_msgs/msg/Twist"](
            t["geometry_msgs/msg/Vector3"](SPEED, 0.0, 0.0), t["geometry_msgs/msg/Vector3"](0.0, 0.0, 0.0)
        )
        return t["nav_msgs/msg/Odometry"](
            header(ns, "odom"),
            "base_link",
            t["geometry_msgs/msg/PoseWithCovariance"](pose, cov),
            t["geometry_msgs/msg/TwistWithCovariance"](twist, cov),
        )

    def scan(ns: int) -> object:
        ranges = np.full(rays, 2.0, dtype=np.float32)
        return t["sensor_msgs/msg/LaserScan"](
            header(ns, "base_link"), -math.pi / 2, math.pi / 2, math.pi / (rays - 1), 0.0, 0.1, 0.1, 10.0,
            ranges, np.zeros(0, dtype=np.float32),
        )  # fmt: skip

    with BagWriter(folder / name, version=9, storage_plugin=StoragePlugin.MCAP) as bag:
        odom_conn = bag.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=store)
        scan_conn = bag.add_connection("/scan", "sensor_msgs/msg/LaserScan", typestore=store)
        for i in range(int(seconds * 10) + 1):
            ns = T0_NS + i * 10**8
            bag.write(odom_conn, ns, store.serialize_cdr(odom(ns, SPEED * i / 10), "nav_msgs/msg/Odometry"))
            if i % scan_every == 0:
                bag.write(scan_conn, ns, store.serialize_cdr(scan(ns), "sensor_msgs/msg/LaserScan"))
    (file,) = (folder / name).glob("*.mcap")
    return file
