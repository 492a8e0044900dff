"""Pure pieces of issue 29's plots and topic inspector: the odometry ring buffer and its plot lines,
the topic rate meter, message truncation and the topic list."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from pmk_nb.chair.link.streams.inspect import Rate, RateMeter, pretty_message, rate_text, topic_rows
from pmk_nb.viewport.history import OdomHistory, nice_limit, plot_lines


def test_the_ring_buffer_keeps_the_newest_samples_in_order() -> None:
    hist = OdomHistory(capacity=5)
    for i in range(8):
        assert hist.add(float(i), 0.1 * i, 0.0)
    assert len(hist) == 5
    assert hist.window(-math.inf)[:, 0].tolist() == [3.0, 4.0, 5.0, 6.0, 7.0]  # oldest fell out
    assert hist.window(5.5)[:, 0].tolist() == [6.0, 7.0]
    assert not hist.add(7.0, 1.0, 0.0)  # the same odometry message seen twice by the timer
    assert not hist.add(9.0, float("nan"), 0.0)
    hist.clear()
    assert len(hist) == 0 and hist.window(-math.inf).shape == (0, 3)
    with pytest.raises(ValueError):
        OdomHistory(capacity=1)


def test_plot_lines_scale_time_and_both_axes() -> None:
    samples = np.array([[90.0, 0.0, 0.0], [95.0, 0.5, math.radians(-30)], [100.0, -0.25, 0.0]])
    lines = plot_lines(samples, now=100.0, span_s=10.0, width=101, height=51)
    assert lines.speed_max == 0.5 and lines.turn_max == 50.0  # 1-2-5 steps above the peaks
    assert lines.speed[:, 0].tolist() == [0.0, 50.0, 100.0]  # time left to right
    assert lines.speed[:, 1].tolist() == [25.0, 0.0, 37.5]  # 0 in the middle, +max at the top
    assert lines.turn[1, 1] == pytest.approx(25.0 + 30 / 50 * 25.0)
    assert nice_limit(0.0, 0.2) == 0.2 and nice_limit(0.7, 0.2) == 1.0 and nice_limit(130.0, 10.0) == 200.0
    empty = plot_lines(np.empty((0, 3)), 0.0, 60.0, 100, 50)
    assert empty.speed.shape == (0, 2)


def test_rate_meter_counts_ros1_seq_and_says_at_least_for_a_throttled_topic() -> None:
    ros1 = RateMeter(throttle_ms=500)
    for i in range(5):  # arrivals every 0.5 s (throttled), seq says 10 messages went by each time
        ros1.add(10.0 + 0.5 * i, seq=100 + 10 * i)
    assert ros1.rate(12.1) == Rate(pytest.approx(20.0), False, pytest.approx(0.1))
    ros2 = RateMeter(throttle_ms=500)
    for i in range(5):
        ros2.add(10.0 + 0.5 * i)
    rate = ros2.rate(12.1)
    assert rate.at_least and rate_text(rate) == "at least 2.0 Hz"
    slow = RateMeter(throttle_ms=500)
    for i in range(3):
        slow.add(2.0 * i)
    assert rate_text(slow.rate(4.5)) == "0.5 Hz"
    assert rate_text(slow.rate(30.0)) == "silent for 26 s"
    assert rate_text(RateMeter().rate(0.0)) == "no messages yet"


def test_pretty_message_shortens_long_lists_and_cuts_long_text() -> None:
    scan = {"header": {"frame_id": "laser"}, "ranges": [1.0] * 720}
    text = pretty_message(scan)
    assert "… 708 more of 720" in text and text.count("1.0") == 12 and '"ranges": [1.0, 1.0,' in text
    assert json.loads(pretty_message({"a": 1})) == {"a": 1}
    big = pretty_message({f"k{i}": "x" * 100 for i in range(100)}, limit=500)
    assert len(big) < 600 and "more characters" in big
    assert "…" in pretty_message({"s": "y" * 1000})


def test_topic_rows_prefer_rosapi_and_fall_back_to_what_the_link_knows() -> None:
    known = {"/odom": "nav_msgs/Odometry", "/scan": "sensor_msgs/LaserScan"}
    assert topic_rows(None, known) == sorted(known.items())
    rows = topic_rows({"/odom": "", "/map": "nav_msgs/OccupancyGrid"}, known)
    assert rows == [("/map", "nav_msgs/OccupancyGrid"), ("/odom", "nav_msgs/Odometry")]
