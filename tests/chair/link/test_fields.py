"""Any numeric field of any topic (issue 40): paths from rosapi's type definitions, values from messages."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pmk_nb.chair.link.streams.fields import field_value, numeric_fields, sample_fields
from pmk_nb.sim.messages import Names
from pmk_nb.sim.msgtypes import typedefs as sim_typedefs
from pmk_nb.viewport.seriesplot import SeriesRing, series_lines


def typedefs(names: Names, type_name: str) -> list:
    """What the simulator's rosapi answers for ``type_name`` (its own spelling of rosapi 1.x or 2.x)."""
    return sim_typedefs(type_name, names.ros) or []


@pytest.mark.parametrize("ros", ["ros1", "ros2"])
def test_numeric_fields_of_odometry_and_a_scan_from_their_definitions(ros: str) -> None:
    names = Names(ros)  # type: ignore[arg-type]
    odom = numeric_fields(typedefs(names, names.msg("nav_msgs", "Odometry")), names.msg("nav_msgs", "Odometry"))
    assert {"header.stamp", "twist.twist.linear.x", "pose.pose.orientation.w", "pose.covariance[35]"} <= set(odom)
    assert "child_frame_id" not in odom and "header.frame_id" not in odom  # strings are not plotted
    assert not any(f.startswith("header.stamp.") for f in odom)  # a stamp is one value, in seconds
    scan = numeric_fields(typedefs(names, "sensor_msgs/LaserScan"), "sensor_msgs/LaserScan")
    assert "range_max" in scan and not any(f.startswith("ranges") for f in scan)  # variable arrays: no item
    assert numeric_fields([], "nav_msgs/Odometry") == []


def test_field_values_read_numbers_booleans_and_stamps() -> None:
    msg = {
        "header": {"stamp": {"secs": 10, "nsecs": 500_000_000}},
        "twist": {"twist": {"linear": {"x": 0.25}}},
        "pose": {"covariance": [0.0] * 35 + [2.0]},
        "flag": True,
        "gone": None,
    }
    assert field_value(msg, "twist.twist.linear.x") == 0.25
    assert field_value(msg, "header.stamp") == pytest.approx(10.5)
    assert field_value(msg, "pose.covariance[35]") == 2.0
    assert field_value(msg, "flag") == 1.0
    for missing in ("gone", "twist.twist.angular.z", "pose.covariance[36]", "twist[0]", "a..b", "header"):
        assert field_value(msg, missing) is None, missing
    covariance = [f"pose.covariance[{i}]" for i in range(36)]
    assert sample_fields(msg) == ["header.stamp", "twist.twist.linear.x", *covariance, "flag"]  # booleans: 0/1


def test_series_share_one_axis_over_the_time_window() -> None:
    a, b = SeriesRing(capacity=4), SeriesRing()
    for t in range(6):
        a.add(float(t), float(t))
    assert len(a) == 4 and a.window(0.0)[:, 0].tolist() == [2.0, 3.0, 4.0, 5.0]  # bounded: the oldest go
    assert not a.add(5.0, 1.0) and not a.add(6.0, math.nan)  # not newer, not finite
    b.add(4.0, -3.0)
    b.add(5.0, 1.0)
    plot = series_lines([a.window(3.0), b.window(3.0)], now=5.0, span_s=2.0, width=101, height=101)
    assert (plot.y_min, plot.y_max) == (-5.0, 5.0)  # holds both: -3 .. 5, rounded out
    assert plot.lines[0][:, 0].tolist() == [0.0, 50.0, 100.0]  # 3 s at the left edge, now at the right
    assert plot.lines[0][-1, 1] == pytest.approx(0.0) and plot.lines[1][0, 1] == pytest.approx(80.0)
    empty = series_lines([np.empty((0, 2))], now=1.0, span_s=10.0, width=10, height=10)
    assert empty.lines[0].shape == (0, 2) and (empty.y_min, empty.y_max) == (-1.0, 1.0)
