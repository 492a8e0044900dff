"""Map tools' maths (pure): scale bar lengths, grid lines in view, pixel <-> map under zoom and follow,
distances; and the ``/initialpose`` message in both ROS spellings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pmk_nb.chair.link.goals.initialpose import VARIANCE_XY, VARIANCE_YAW, initial_pose_message
from pmk_nb.grid import OccupancyGrid
from pmk_nb.viewport import Viewport
from pmk_nb.viewport.maptools import (
    coordinates_text,
    distance,
    grid_lines,
    grid_spacing,
    heading,
    length_label,
    nice_length,
    pixel_to_map,
    scale_bar,
)
from pmk_nb.wire import yaw_from_quaternion


@pytest.mark.parametrize(
    ("at_most", "expected"),
    [(1.0, 1.0), (1.99, 1.0), (2.0, 2.0), (4.9, 2.0), (5.0, 5.0), (9.99, 5.0), (10.0, 10.0), (0.37, 0.2), (730, 500)],
)
def test_nice_length_is_the_largest_1_2_5_power_of_ten_below(at_most: float, expected: float) -> None:
    assert nice_length(at_most) == pytest.approx(expected)


@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf])
def test_nice_length_refuses_nonsense(bad: float) -> None:
    with pytest.raises(ValueError):
        nice_length(bad)


def test_scale_bar_fits_its_room_and_grows_with_zoom() -> None:
    view = Viewport(200, 100, 0.05, (0.0, 0.0), 400, 200)  # 10 m x 5 m on 400 px: 40 px/m
    bar = scale_bar(view.px_per_m, 120.0)
    assert (bar.metres, bar.label) == (2.0, "2 m") and bar.pixels == pytest.approx(80.0)
    view.set_zoom(view.max_zoom)  # 1.5^7 = 17x: 683 px/m
    zoomed = scale_bar(view.px_per_m, 120.0)
    assert zoomed.metres == pytest.approx(0.1) and zoomed.label == "10 cm"
    assert 0.4 * 120 < zoomed.pixels <= 120.0
    assert length_label(0.25) == "25 cm" and length_label(1500) == "1.5 km" and length_label(0.005) == "0.005 m"


def test_grid_lines_are_the_multiples_in_view_at_their_pixels() -> None:
    view = Viewport(200, 100, 0.05, (-2.0, -1.0), 400, 200)  # x -2..8 m, y -1..4 m at 40 px/m
    vertical, horizontal = grid_lines(view, 1.0)
    assert [m for m, _ in vertical] == [-2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]
    assert [round(p, 6) for _, p in vertical[:3]] == [0.0, 40.0, 80.0]
    assert [m for m, _ in horizontal] == [-1.0, 0.0, 1.0, 2.0, 3.0, 4.0]
    y0 = dict(horizontal)[0.0]
    assert y0 == pytest.approx(200 - 40.0)  # y up in the map, down on screen
    # zoomed in on a corner: only the lines in view; auto spacing keeps lines >= 40 px apart
    view.set_zoom(4)
    view.set_following(False)
    vertical, _ = grid_lines(view, grid_spacing(view.px_per_m, None))
    gaps = np.diff([p for _, p in vertical])
    assert len(vertical) >= 2 and np.all(gaps >= 40.0 - 1e-6) and np.all(gaps < 400.0)
    assert all(0.0 <= p <= view.canvas_width for _, p in vertical)
    assert grid_lines(Viewport(10000, 10000, 0.05, (0, 0), 100, 100), 0.001) == ([], [])  # too dense: none


def test_auto_grid_spacing_is_the_round_length_above_the_gap() -> None:
    assert grid_spacing(40.0, None, 40.0) == 1.0
    assert grid_spacing(30.0, None, 40.0) == 2.0
    assert grid_spacing(7.0, None, 40.0) == 10.0
    assert grid_spacing(40.0, 0.5) == 0.5
    with pytest.raises(ValueError):
        grid_spacing(40.0, -1.0)


def test_screen_and_map_coordinates_round_trip_under_zoom_and_follow() -> None:
    grid = OccupancyGrid(np.zeros((100, 200), np.int8), 0.05, (-3.0, 1.0, 0.0))
    view = Viewport.for_grid(grid, 400, 200)
    assert pixel_to_map(view, 0.0, 200.0) == pytest.approx((-3.0, 1.0))  # bottom-left pixel = origin
    view.set_zoom(3)
    view.see_chair(2.0, 2.5)  # following: the chair in the middle
    assert pixel_to_map(view, 200.0, 100.0) == pytest.approx((2.0, 2.5))
    for point in [(0.5, 1.5), (4.0, 3.25)]:
        px, py = view.world_to_pixel(*point)
        assert pixel_to_map(view, float(px), float(py)) == pytest.approx(point)
    assert pixel_to_map(view, math.nan, 1.0) is None
    assert coordinates_text((1.254, -3.4)) == "x 1.25 m, y -3.40 m" and coordinates_text(None) == ""


def test_distance_and_heading_of_two_taps() -> None:
    view = Viewport(200, 100, 0.05, (0.0, 0.0), 400, 200)
    a, b = pixel_to_map(view, 40.0, 160.0), pixel_to_map(view, 160.0, 0.0)  # (1, 1) and (4, 5)
    assert a is not None and b is not None
    assert distance(a, b) == pytest.approx(5.0)
    assert heading(a, b) == pytest.approx(math.atan2(4, 3))


@pytest.mark.parametrize("ros_version", [1, 2])
def test_initial_pose_message_as_rviz_sends_it(ros_version: int) -> None:
    msg = initial_pose_message(1.5, -2.0, math.pi / 2, ros_version, 1700000000.25)
    header = msg["header"]
    assert header["frame_id"] == "map"
    if ros_version == 1:
        assert header["stamp"] == {"secs": 1700000000, "nsecs": 250000000} and header["seq"] == 0
    else:
        assert header["stamp"] == {"sec": 1700000000, "nanosec": 250000000} and "seq" not in header
    pose = msg["pose"]["pose"]
    assert (pose["position"]["x"], pose["position"]["y"]) == (1.5, -2.0)
    assert yaw_from_quaternion(pose["orientation"]) == pytest.approx(math.pi / 2)
    cov = msg["pose"]["covariance"]
    assert len(cov) == 36 and cov[0] == cov[7] == VARIANCE_XY == 0.25 and cov[35] == pytest.approx(0.0685, abs=1e-4)
    assert cov[35] == VARIANCE_YAW and sum(1 for c in cov if c) == 3
    with pytest.raises(ValueError):
        initial_pose_message(math.nan, 0.0, 0.0, ros_version, 0.0)
    with pytest.raises(ValueError):
        initial_pose_message(0.0, 0.0, 0.0, 3, 0.0)
