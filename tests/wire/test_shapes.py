"""Stamps, type spellings and quaternions in both ROS versions' shapes (moved here from tests/chair, issue 42)."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from pmk_nb.wire import (
    make_stamp,
    normalise_type,
    quaternion_from_yaw,
    spell_type,
    stamp_ros_version,
    stamp_to_sec,
    type_ros_version,
    type_spellings,
    yaw_from_quaternion,
)


def test_stamps_in_both_ros_spellings() -> None:
    assert stamp_to_sec({"secs": 12, "nsecs": 500_000_000}) == pytest.approx(12.5)
    assert stamp_to_sec({"sec": 12, "nanosec": 250_000_000}) == pytest.approx(12.25)
    assert stamp_to_sec(None) is None
    assert stamp_to_sec({"foo": 1}) is None
    assert stamp_ros_version({"secs": 1, "nsecs": 0}) == 1
    assert stamp_ros_version({"sec": 1, "nanosec": 0}) == 2
    assert make_stamp(3.75, 2) == {"sec": 3, "nanosec": 750_000_000}
    assert make_stamp(3.75, 1) == {"secs": 3, "nsecs": 750_000_000}


def test_type_spellings() -> None:
    assert type_spellings("nav_msgs/Odometry") == ["nav_msgs/Odometry", "nav_msgs/msg/Odometry"]
    assert type_spellings("nav_msgs/msg/Odometry") == ["nav_msgs/msg/Odometry", "nav_msgs/Odometry"]
    assert type_spellings("nav2_msgs/LoadMap", "srv")[1] == "nav2_msgs/srv/LoadMap"
    assert normalise_type("nav2_msgs/srv/LoadMap") == "nav2_msgs/LoadMap"
    assert type_ros_version("sensor_msgs/msg/LaserScan") == 2
    assert type_ros_version("sensor_msgs/LaserScan") == 1
    assert spell_type("nav_msgs/Odometry", 2) == "nav_msgs/msg/Odometry"
    assert spell_type("nav_msgs/msg/Odometry", 2) == "nav_msgs/msg/Odometry"
    assert spell_type("nav_msgs/msg/Odometry", 1) == "nav_msgs/Odometry"
    assert spell_type("nav_msgs/Odometry", None) == "nav_msgs/Odometry"


@given(st.floats(-math.pi + 1e-6, math.pi))
def test_quaternion_yaw_round_trip(yaw: float) -> None:
    assert yaw_from_quaternion(quaternion_from_yaw(yaw)) == pytest.approx(yaw, abs=1e-9)


def test_yaw_from_quaternion_with_roll_and_missing_fields() -> None:
    # 90 deg yaw: z = w = sqrt(0.5)
    assert yaw_from_quaternion({"x": 0, "y": 0, "z": math.sqrt(0.5), "w": math.sqrt(0.5)}) == pytest.approx(math.pi / 2)
    assert yaw_from_quaternion({}) == 0.0
    assert yaw_from_quaternion(None) == 0.0
    assert yaw_from_quaternion({"z": 1.0, "w": 0.0}) == pytest.approx(math.pi)
