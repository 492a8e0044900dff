"""The replay timeline (issue 40): each layer shows its latest message at or before the slider's time."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pmk_nb.recordings import Timeline

T0 = 1_700_000_000.0


def _odom(t: float, x: float, yaw: float = 0.0) -> dict:
    return {
        "received": T0 + t,
        "stamp": T0 + t,
        "pose.pose.position.x": x,
        "pose.pose.position.y": 1.0,
        "pose.pose.orientation.z": math.sin(yaw / 2),
        "pose.pose.orientation.w": math.cos(yaw / 2),
    }


def _scan(t: float) -> dict:
    return {
        "received": T0 + t,
        "angle_min": -math.pi / 2,
        "angle_increment": math.pi / 2,
        "range_min": 0.1,
        "range_max": 10.0,
        "ranges": np.array([2.0, np.nan, 3.0]),  # right, unknown, left
    }


TYPES = {
    "/odom": "nav_msgs/msg/Odometry",
    "/scan": "sensor_msgs/msg/LaserScan",
    "/plan": "nav_msgs/msg/Path",
    "/map": "nav_msgs/msg/OccupancyGrid",
}


def _timeline() -> Timeline:
    rows = {
        "/odom": [_odom(0.0, 0.0), _odom(1.0, 1.0, math.pi / 2), _odom(2.0, 2.0, math.pi / 2)],
        "/scan": [_scan(1.5)],
        "/plan": [{"received": T0 + 0.5, "poses": [{"pose.position.x": 0.0, "pose.position.y": 1.0}] * 3}],
        "/map": [
            {
                "received": T0,
                "info.width": 3,
                "info.height": 2,
                "info.resolution": 0.5,
                "info.origin.position.x": -1.0,
                "info.origin.position.y": -2.0,
                "data": np.array([0, 100, -1, 0, 0, 0], dtype=np.int8),
            }
        ],
    }
    return Timeline(rows, TYPES)


def test_each_layer_shows_its_latest_message_at_or_before_the_time() -> None:
    timeline = _timeline()
    assert timeline.duration == 2.0 and timeline.pose_topic == "/odom"
    start = timeline.at(0.2)
    assert start.pose == (0.0, 1.0, 0.0) and start.laser is None and start.path is None
    middle = timeline.at(1.7)
    assert middle.pose is not None and middle.pose[0] == 1.0 and middle.pose[2] == pytest.approx(math.pi / 2)
    assert middle.path is not None and middle.path.shape == (3, 2)
    # facing +y at (1, 1): the right-hand hit 2 m away lies at (3, 1), the left one 3 m away at (-2, 1); NaN left out
    assert middle.laser is not None and np.allclose(middle.laser, [[3.0, 1.0], [-2.0, 1.0]])
    assert timeline.at(99.0).t == 2.0 and timeline.at(99.0).pose == timeline.at(2.0).pose  # clamped
    assert timeline.poses(until=1.0).tolist() == [[0.0, 1.0], [1.0, 1.0]]
    assert timeline.first_pose == 0.0


def test_the_recorded_map_is_the_background() -> None:
    grid = _timeline().grid
    assert grid is not None and grid.cells.shape == (2, 3) and grid.cells[0, 1] == 100
    assert grid.extent == (-1.0, 0.5, -2.0, -1.0)


def test_amcl_pose_wins_over_odometry_and_an_empty_recording_has_no_layers() -> None:
    amcl = {"received": T0, "pose.pose.position.x": 5.0, "pose.pose.position.y": 6.0}
    rows = {"/odom": [_odom(0.0, 0.0)], "/amcl_pose": [amcl]}
    types = {"/odom": TYPES["/odom"], "/amcl_pose": "geometry_msgs/msg/PoseWithCovarianceStamped"}
    assert Timeline(rows, types).at(0.0).pose == (5.0, 6.0, 0.0)
    late = Timeline({"/odom": [_odom(0.0, 0.0)], "/scan": [_scan(-1.0)]}, TYPES)
    assert late.first_pose == 1.0 and late.at(0.5).pose is None  # the scan came first
    empty = Timeline({}, {})
    assert empty.duration == 0.0 and empty.at(1.0).pose is None and empty.grid is None and empty.poses().shape == (0, 2)


def test_any_numeric_field_is_a_series_and_its_value_holds_until_the_next_message() -> None:
    timeline = _timeline()
    fields = timeline.numeric_fields()
    assert ("/odom", "pose.pose.position.x") in fields and ("/scan", "angle_increment") in fields
    assert not any(f in ("received", "stamp", "ranges", "data", "poses") for _, f in fields)  # arrays, times
    times, values = timeline.series("/odom", "pose.pose.position.x")
    assert times.tolist() == [0.0, 1.0, 2.0] and values.tolist() == [0.0, 1.0, 2.0]
    assert timeline.value_at("/odom", "pose.pose.position.x", 1.5) == 1.0
    assert timeline.value_at("/scan", "angle_min", 1.0) is None  # before the first scan
    _, missing = timeline.series("/odom", "no.such.field")
    assert np.isnan(missing).all()
    assert timeline.default_field() == fields[0]  # no speed recorded: the first number


def test_the_default_plot_is_the_chairs_speed() -> None:
    rows = {"/odom": [{**_odom(0.0, 0.0), "twist.twist.linear.x": 0.4}], "/other": [{"received": T0, "a": 1.0}]}
    assert Timeline(rows, TYPES).default_field() == ("/odom", "twist.twist.linear.x")
    assert Timeline({}, {}).default_field() is None


def test_a_scan_is_placed_at_the_pose_of_its_stamp_not_the_latest() -> None:
    """The chair turns a quarter between two poses; a scan stamped half-way (it arrives late) is cast
    from the pose half-way, as RViz places it; without a usable stamp, from the latest pose."""
    rows = {
        "/odom": [_odom(0.0, 0.0, 0.0), _odom(1.0, 1.0, math.pi / 2)],
        "/scan": [{**_scan(1.5), "stamp": T0 + 0.5}, {**_scan(1.8), "stamp": T0 + 9.0}],
    }
    timeline = Timeline(rows, TYPES)
    assert timeline.pose_at_stamp(T0 + 0.5) == pytest.approx((0.5, 1.0, math.pi / 4))
    assert timeline.pose_at_stamp(T0 + 9.0) is None and timeline.pose_at_stamp(None) is None
    frame = timeline.at(1.6)
    assert frame.pose == pytest.approx((1.0, 1.0, math.pi / 2))  # the chair is drawn where it is now
    right = (0.5 + 2.0 * math.cos(-math.pi / 4), 1.0 + 2.0 * math.sin(-math.pi / 4))  # 2 m to its right then
    assert frame.laser is not None and frame.laser[0] == pytest.approx(right)
    late = timeline.at(1.9).laser  # stamped far past every pose: the latest pose
    assert late is not None and late[0] == pytest.approx((1.0 + 2.0, 1.0))
