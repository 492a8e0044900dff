"""Scans drawn at their header stamps (issue 40): a turning simulated chair's hits stay on the walls.

The simulated chair stamps each scan with the instant of the pose it was cast from, as a laser stamps
the instant it measured. While the chair turns, the newest odometry is already some degrees further
round when the scan is drawn: hits placed from it fall off the walls, hits placed from the pose at the
scan's stamp (the live view's :class:`PoseHistory`, odometry by stamp) stay on them.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from pmk_nb.chair import Odometry, Scan
from pmk_nb.grid import OccupancyGrid
from pmk_nb.ui.live.chair_layer import PoseHistory
from pmk_nb.viewport import mounted
from tests.fixtures_sim import room_grid

TURN = 1.2  # rad/s, the simulated chair's limit
BEHIND_S = 0.3  # the newest odometry is at least this much newer than the scan compared


def wall_fraction(grid: OccupancyGrid, origin: tuple[float, float, float], scan: Scan) -> float:
    """Share of the scan's hits, cast from ``origin``, that land on or next to an occupied cell."""
    occupied = np.asarray(grid.data) >= 65  # row 0 = bottom (ROS order)
    ok = np.isfinite(scan.ranges)
    ang = origin[2] + scan.angles()[ok]
    x = origin[0] + scan.ranges[ok] * np.cos(ang)
    y = origin[1] + scan.ranges[ok] * np.sin(ang)
    col = np.floor((x - grid.origin[0]) / grid.resolution).astype(int)
    row = np.floor((y - grid.origin[1]) / grid.resolution).astype(int)
    near = np.zeros(col.size, dtype=bool)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            r, c = np.clip(row + dr, 0, grid.height - 1), np.clip(col + dc, 0, grid.width - 1)
            near |= occupied[r, c]
    return float(near.mean())


@pytest.mark.slow
def test_a_turning_chairs_scan_hits_stay_on_the_walls_at_the_scans_stamp(
    sim_factory: Callable[..., Any], link_factory: Callable[[Any], Any]
) -> None:
    grid = room_grid(6.0, 4.0, wall_x=4.0, door=(1.5, 2.5))  # walls at many angles: a turn shows
    sim = sim_factory(grid=grid, start_pose=(2.0, 2.0, 0.0), odom_rate=50.0, scan_rate=10.0, rays=360)
    link = link_factory(sim)
    odoms: list[Odometry] = []
    lock = threading.Lock()

    def keep(odom: Odometry) -> None:
        with lock:
            odoms.append(odom)

    link.add_listener("odom", keep)
    link.start_streams()
    deadline = time.monotonic() + 30.0
    found: tuple[Scan, list[Odometry]] | None = None
    scan: Scan | None = None
    while time.monotonic() < deadline and found is None:
        link.publish_cmd_vel(0.0, TURN)  # turn on the spot (the sim stops after 0.5 s without a command)
        time.sleep(0.05)
        latest = link.latest_scan()
        if scan is None and latest is not None and latest.stamp is not None:
            with lock:
                turning = len(odoms) > 2 and abs(odoms[-1].w) > TURN / 2
            scan = latest if turning else None
        with lock:
            seen = list(odoms)
        if scan is not None and seen and seen[-1].stamp is not None and seen[-1].stamp >= scan.stamp + BEHIND_S:
            found = (scan, seen)
    assert found is not None, "no scan of a turning chair with odometry after it within 30 s"
    scan, seen = found
    history = PoseHistory()
    for odom in seen:
        history.remember(odom)
    newest = seen[-1]
    stamped = history.scan_pose(newest, scan)
    drawn_late = mounted((newest.x, newest.y, newest.theta), scan.mount)
    turned = abs(math.remainder(drawn_late[2] - stamped[2], math.tau))
    assert turned > 0.2, f"the chair turned only {turned:.2f} rad between the scan and the newest odometry"
    on_walls = wall_fraction(grid, stamped, scan)
    assert on_walls >= 0.95, f"only {on_walls:.0%} of the hits drawn at the scan's stamp are on walls"
    late = wall_fraction(grid, drawn_late, scan)
    assert late < 0.8, f"{late:.0%} of the hits drawn from the newest pose are on walls: the test shows nothing"
