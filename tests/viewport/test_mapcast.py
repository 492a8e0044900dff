"""The blind-ahead warning reads JSON nulls against the map (issue 29, item 7): rays cast over the grid."""

from __future__ import annotations

import math

import numpy as np

from pmk_nb.chair.link.streams.messages import Pose2D, parse_scan
from pmk_nb.chair.link.streams.ranges import INVALID, UNKNOWN
from pmk_nb.grid import OCCUPIED, OccupancyGrid
from pmk_nb.ui.home.info import laser_text
from pmk_nb.viewport.mapcast import expected_no_return, explain_nulls, first_obstacle

RES = 0.05


def corridor(length_m: float, *, end_wall_at: float | None = None) -> OccupancyGrid:
    """A 2 m wide corridor along +x from x=0, walls at y=±1 m; optionally a wall across it."""
    w, h = int(length_m / RES), int(2.4 / RES)
    data = np.zeros((h, w), np.int8)
    data[0:4, :] = OCCUPIED  # y -1.2 .. -1.0
    data[-4:, :] = OCCUPIED  # y 1.0 .. 1.2
    if end_wall_at is not None:
        col = int(end_wall_at / RES)
        data[:, col : col + 2] = OCCUPIED
    return OccupancyGrid(data, RES, origin=(0.0, -1.2, 0.0))


def scan(raw: list, range_max: float = 8.0) -> object:
    return parse_scan(
        {
            "ranges": raw,
            "angle_min": -math.radians(135),
            "angle_increment": math.radians(1),
            "range_min": 0.1,
            "range_max": range_max,
        },
        received=0.0,
    )


def test_first_obstacle_finds_walls_and_their_distance() -> None:
    grid = corridor(30.0, end_wall_at=5.0)
    pose = (1.0, 0.0, 0.0)
    dist = first_obstacle(grid, pose, np.array([0.0, math.pi / 2, -math.pi / 2, math.pi]), 8.0)
    assert abs(dist[0] - 4.0) <= RES  # the wall across at x=5
    assert abs(dist[1] - 1.0) <= RES and abs(dist[2] - 1.0) <= RES  # the side walls
    assert not np.isfinite(dist[3])  # behind: off the map's edge, no wall the map knows
    # a grid origin with a yaw: the same corridor turned 90° left still has its wall 4 m ahead
    turned = OccupancyGrid(np.ascontiguousarray(grid.data), RES, origin=(1.2, 0.0, math.pi / 2))
    assert abs(first_obstacle(turned, (0.0, 1.0, math.pi / 2), np.array([0.0]), 8.0)[0] - 4.0) <= RES
    assert expected_no_return(grid, (1.0, 0.0, 0.0), np.array([0.0]), 3.0).tolist() == [True]


def test_long_corridor_beyond_the_range_is_no_warning() -> None:
    """Nulls straight down a 30 m corridor with an 8 m laser: nothing to see, so no warning."""
    grid = corridor(30.0)
    # ±6° ahead: null (the side walls at 1 m are first met 1 / sin 6° = 9.6 m out, beyond 8 m)
    raw = [1.0] * 129 + [None] * 13 + [1.0] * 129
    text_without_map = laser_text(scan(raw))
    assert "Laser blind ahead" in text_without_map  # today's behaviour with no map
    text = laser_text(scan(raw), grid, Pose2D(1.0, 0.0, 0.0, "map", 0.0))
    assert "blind" not in text and text == "Laser: 271 rays, 0 unknown"


def test_blocked_sensor_before_a_wall_is_a_warning() -> None:
    """Every ray null while the map has a wall 1 m ahead: the sensor should have seen it."""
    grid = corridor(30.0, end_wall_at=2.0)
    text = laser_text(scan([None] * 271), grid, Pose2D(1.0, 0.0, 0.0, "map", 0.0))
    assert "Laser blind ahead" in text and "pmk-msg-warning" in text


def test_only_nulls_are_explained_and_nothing_without_a_map() -> None:
    kinds = np.array([UNKNOWN, UNKNOWN, INVALID], np.uint8)  # INVALID: an explicit NaN (CBOR)
    angles = np.zeros(3)
    grid = corridor(30.0)
    assert explain_nulls(kinds == UNKNOWN, angles, grid, (1.0, 0.0, 0.0), 0.1, 8.0).tolist() == [True, True, False]
    assert not explain_nulls(kinds == UNKNOWN, angles, None, (1.0, 0.0, 0.0), 0.1, 8.0).any()


def test_the_screen_reader_hears_what_the_panel_shows_down_a_corridor_and_at_a_wall() -> None:
    """The live region's alerts come from the same map-aware reading as the panel's line: no spoken
    "Laser blind ahead" down a long corridor, one before a wall the laser should have seen."""
    from pmk_nb.ui.home.info import info_texts
    from pmk_nb.ui.home.live_region import Announcer

    pose = Pose2D(1.0, 0.0, 0.0, "map", 0.0)
    raw = [1.0] * 129 + [None] * 13 + [1.0] * 129
    said: list[str] = []
    for grid, nulls, expect in ((corridor(30.0), raw, False), (corridor(30.0, end_wall_at=2.0), [None] * 271, True)):
        texts = info_texts("live", 0.1, pose, None, 0, 1.0, scan(nulls), grid)
        assert ("blind" in texts.alerts) is expect, texts
        ann = Announcer()
        ann.say = lambda text, _urgency="polite", _said=said: _said.append(text)  # type: ignore[method-assign]
        ann.tick("live", alerts=texts.alerts)
        assert ("Laser blind ahead." in said) is expect, said
        said.clear()
