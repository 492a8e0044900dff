"""The one ray caster gives its two callers exactly what their own casters gave (issue 42).

The simulator's laser and the live view's map cast each had a ray caster; they now share
:func:`pmk_nb.wire.first_hits`. Below are the two casters as they were (frozen copies), compared
ray for ray with the adapters on a real map (the sample clinic floor, converted from its IndoorGML
plan), from many poses: inside rooms, on cell corners, outside the grid, and with a turned grid.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pmk_nb.grid import OccupancyGrid
from pmk_nb.sim import Laser, World, sample_floor
from pmk_nb.viewport.mapcast import OCCUPIED_AT, first_obstacle
from pmk_nb.wire import first_hits


def old_first_obstacle(
    grid: OccupancyGrid, origin: tuple[float, float, float], angles: np.ndarray, max_range: float, min_range: float
) -> np.ndarray:
    """viewport/mapcast.first_obstacle before issue 42, verbatim but for the docstring."""
    a = np.asarray(angles, dtype=np.float64).ravel()
    out = np.full(a.size, np.inf)
    if a.size == 0 or not (math.isfinite(max_range) and max_range > 0):
        return out
    res = grid.resolution
    gx, gy, gyaw = grid.origin
    c, s = math.cos(-gyaw), math.sin(-gyaw)
    dx, dy = origin[0] - gx, origin[1] - gy
    ox, oy = c * dx - s * dy, s * dx + c * dy
    w_m, h_m = grid.width * res, grid.height * res
    far = max(math.hypot(cx - ox, cy - oy) for cx in (0.0, w_m) for cy in (0.0, h_m))
    step = res / 2.0
    t = np.arange(max(min_range, 0.0), min(max_range, far) + step / 2, step)
    if t.size == 0:
        return out
    heads = a + origin[2] - gyaw
    wall = grid.data >= OCCUPIED_AT
    for lo in range(0, a.size, 256):
        h = heads[lo : lo + 256, None]
        col = np.floor((ox + np.cos(h) * t) / res).astype(np.int64)
        row = np.floor((oy + np.sin(h) * t) / res).astype(np.int64)
        inside = (col >= 0) & (col < grid.width) & (row >= 0) & (row < grid.height)
        hit = np.zeros(col.shape, dtype=bool)
        hit[inside] = wall[row[inside], col[inside]]
        any_hit = hit.any(axis=1)
        first = np.argmax(hit, axis=1)
        out[lo : lo + 256] = np.where(any_hit, t[first], np.inf)
    return out


def old_cast(laser: Laser, hit: np.ndarray, resolution: float, origin: tuple[float, float], pose: tuple) -> np.ndarray:
    """sim/laser.Laser.cast before issue 42, verbatim (MAX_BLOCK 192)."""
    h, w = hit.shape
    x, y, theta = pose
    step = 0.5 * resolution
    n_steps = int(laser.range_max / step) + 1
    gx, gy = (x - origin[0]) / resolution, (y - origin[1]) / resolution
    ang = theta + laser.angles
    dx, dy = np.cos(ang) * 0.5, np.sin(ang) * 0.5
    ranges = np.full(laser.rays, np.inf, dtype=np.float32)
    active = np.arange(laser.rays)
    first, size = 0, laser.block
    while first < n_steps:
        t = np.arange(first, min(first + size, n_steps), dtype=np.float64)
        cols = np.floor(gx + dx[active, None] * t).astype(np.intp)
        rows = np.floor(gy + dy[active, None] * t).astype(np.intp)
        inside = (cols >= 0) & (cols < w) & (rows >= 0) & (rows < h)
        hits = hit[np.clip(rows, 0, h - 1), np.clip(cols, 0, w - 1)] & inside
        got = hits.any(axis=1)
        if got.any():
            k = hits[got].argmax(axis=1)
            r = (first + k - 0.5) * step
            ranges[active[got]] = np.maximum(r, laser.range_min)
        keep = ~got & inside[:, -1]
        active = active[keep]
        if active.size == 0:
            break
        first, size = first + size, min(2 * size, 192)
    if laser._blind_mask is not None:
        ranges[laser._blind_mask] = np.nan
    return ranges


@pytest.fixture(scope="module")
def clinic() -> OccupancyGrid:
    grid = sample_floor()
    assert grid is not None, "the sample clinic floor (sample_maps/clinic_floor.gml) did not convert"
    return grid


def _poses(grid: OccupancyGrid, n: int, seed: int) -> list[tuple[float, float, float]]:
    """Random poses over the grid and a margin around it, and poses on cell corners facing along the axes."""
    rng = np.random.default_rng(seed)
    ox, oy, _ = grid.origin
    w_m, h_m = grid.width * grid.resolution, grid.height * grid.resolution
    poses = [
        (float(ox + rng.uniform(-2, w_m + 2)), float(oy + rng.uniform(-2, h_m + 2)), float(rng.uniform(-4, 4)))
        for _ in range(n)
    ]
    for i in range(n // 4):
        col, row = int(rng.integers(0, grid.width)), int(rng.integers(0, grid.height))
        x, y = ox + col * grid.resolution, oy + row * grid.resolution
        poses += [(x, y, k * math.pi / 2) for k in range(4)]
        poses.append((x + grid.resolution / 2, y + grid.resolution / 2, (i % 8) * math.pi / 4))
    return poses


@pytest.mark.slow
def test_the_simulated_laser_reads_as_before(clinic: OccupancyGrid) -> None:
    world = World(clinic)
    lasers = [Laser(), Laser(rays=360, range_max=30.0, block=8), Laser(rays=90, blind=(-0.3, 0.2), range_min=0.3)]
    free = np.argwhere(~world.blocked)
    rng = np.random.default_rng(7)
    compared = 0
    for laser in lasers:
        for row, col in free[rng.choice(len(free), 60, replace=False)]:
            pose = (
                clinic.origin[0] + (col + rng.uniform()) * clinic.resolution,
                clinic.origin[1] + (row + rng.uniform()) * clinic.resolution,
                float(rng.uniform(-4, 4)),
            )
            new = laser.cast(world.hit, clinic.resolution, clinic.origin[:2], pose)
            old = old_cast(laser, world.hit, clinic.resolution, clinic.origin[:2], pose)
            np.testing.assert_array_equal(new, old)
            compared += int(np.isfinite(old).sum())
    assert compared > 10_000  # the rays met walls: the comparison is about ranges, not only "nothing"


@pytest.mark.slow
@pytest.mark.parametrize("turned", [False, True], ids=["grid", "turned-grid"])
def test_the_map_cast_reads_as_before(clinic: OccupancyGrid, turned: bool) -> None:
    grid = OccupancyGrid(clinic.data, clinic.resolution, origin=(3.0, -1.0, 0.7)) if turned else clinic
    angles = -math.radians(135) + math.radians(0.5) * np.arange(541)
    hits = 0
    for i, pose in enumerate(_poses(grid, 80, seed=3 if turned else 5)):
        max_range, min_range = (8.0, 0.1) if i % 2 else (30.0, 0.0)
        new = first_obstacle(grid, pose, angles, max_range, min_range=min_range)
        old = old_first_obstacle(grid, pose, angles, max_range, min_range)
        np.testing.assert_array_equal(new, old, err_msg=f"pose {pose}")
        hits += int(np.isfinite(old).sum())
    assert hits > 10_000


def test_first_hits_marches_into_a_grid_from_outside_and_stops_where_it_leaves() -> None:
    """A ray from outside the grid is marched until it enters (the map cast's scanner may stand off the
    map); one that left never counts a cell again."""
    hit = np.zeros((4, 40), dtype=bool)
    hit[:, 30] = True

    def along_x(start: float):
        return lambda rays, t: (start + 0.5 * t + 0.0 * rays[:, None], 1.5 + 0.0 * t + 0.0 * rays[:, None])

    assert first_hits(hit, along_x(-50.0), 1, 400).tolist() == [160]  # enters at step 100, wall at col 30
    assert first_hits(hit, along_x(31.0), 1, 400).tolist() == [-1]  # past the wall, leaves at col 40
