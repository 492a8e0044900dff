"""Laser rays cast over the map: which JSON ``null`` readings are the expected "nothing in range".

Over JSON rosbridge a ray that saw nothing within ``range_max`` (+inf) and an invalid one (NaN) both
arrive as ``null`` (:mod:`pmk_nb.chair.ranges`). Looking down a corridor longer than the laser's
range gives a fan of nulls that is no blindness at all. The map tells the two apart: cast each ray
over the grid from the scanner's pose; where no occupied cell lies within ``range_max`` the null is
the expected no-return; where the map has a wall within range, the sensor should have seen it and a
null there is a blind (or blocked) sensor.

Unknown cells and the space outside the grid are not walls: the map cannot say anything was there,
so a null ray over them is not counted as blind.  All rays are cast at once (NumPy), in chunks so a
1 000-ray scan over a 30 m range stays a few megabytes.
"""

from __future__ import annotations

import math

import numpy as np

from pmk_nb.grid import OccupancyGrid

__all__ = ["OCCUPIED_AT", "expected_no_return", "explain_nulls", "first_obstacle"]

#: Occupancy at or above which a cell is a wall (map_server's default ``occupied_thresh`` 0.65).
OCCUPIED_AT = 65
#: Rays cast per NumPy pass: bounds memory to chunk * samples booleans.
_CHUNK = 256


def first_obstacle(
    grid: OccupancyGrid,
    origin: tuple[float, float, float],
    angles: np.ndarray,
    max_range: float,
    *,
    min_range: float = 0.0,
) -> np.ndarray:
    """Distance (m) along each ray to the first wall cell of ``grid`` within ``[min_range, max_range]``.

    Args:
        grid: the map (``origin`` may carry a yaw).
        origin: the scanner's pose in the map frame (x, y, yaw).
        angles: ray directions in the scanner frame (radians).
        max_range, min_range: the laser's limits; nothing outside them is looked at.

    Returns:
        float64 per ray, ``inf`` where the map shows no wall within range.
    """
    a = np.asarray(angles, dtype=np.float64).ravel()
    out = np.full(a.size, np.inf)
    if a.size == 0 or not (math.isfinite(max_range) and max_range > 0):
        return out
    res = grid.resolution
    gx, gy, gyaw = grid.origin
    # the scanner and its rays in the grid's own (unrotated) frame
    c, s = math.cos(-gyaw), math.sin(-gyaw)
    dx, dy = origin[0] - gx, origin[1] - gy
    ox, oy = c * dx - s * dy, s * dx + c * dy
    # nothing beyond the grid's farthest corner can be a wall: a 100 m laser on a 20 m map casts 20 m
    w_m, h_m = grid.width * res, grid.height * res
    far = max(math.hypot(cx - ox, cy - oy) for cx in (0.0, w_m) for cy in (0.0, h_m))
    step = res / 2.0  # half a cell: a ray cannot jump over a one-cell wall
    t = np.arange(max(min_range, 0.0), min(max_range, far) + step / 2, step)
    if t.size == 0:
        return out
    heads = a + origin[2] - gyaw
    wall = grid.data >= OCCUPIED_AT  # int8: unknown (-1) is never a wall
    for lo in range(0, a.size, _CHUNK):
        h = heads[lo : lo + _CHUNK, None]
        col = np.floor((ox + np.cos(h) * t) / res).astype(np.int64)
        row = np.floor((oy + np.sin(h) * t) / res).astype(np.int64)
        inside = (col >= 0) & (col < grid.width) & (row >= 0) & (row < grid.height)
        hit = np.zeros(col.shape, dtype=bool)
        hit[inside] = wall[row[inside], col[inside]]
        any_hit = hit.any(axis=1)
        first = np.argmax(hit, axis=1)
        out[lo : lo + _CHUNK] = np.where(any_hit, t[first], np.inf)
    return out


def expected_no_return(
    grid: OccupancyGrid,
    origin: tuple[float, float, float],
    angles: np.ndarray,
    max_range: float,
    *,
    min_range: float = 0.0,
) -> np.ndarray:
    """True per ray where the map shows no wall within range: a ``null`` there is the expected +inf."""
    no_wall: np.ndarray = ~np.isfinite(first_obstacle(grid, origin, angles, max_range, min_range=min_range))
    return no_wall


def explain_nulls(
    nulls: np.ndarray,
    angles: np.ndarray,
    grid: OccupancyGrid | None,
    origin: tuple[float, float, float] | None,
    range_min: float,
    range_max: float,
) -> np.ndarray:
    """True per ray where a ``null`` reading (``nulls``) is explained by the map: no wall in range.

    Without a map or a pose nothing is explained (a null stays unknown, as before). Only the rays
    in ``nulls`` are cast: an explicit NaN (CBOR) is the sensor's own word and stays blind.
    """
    mask = np.asarray(nulls, dtype=bool).ravel()
    out = np.zeros(mask.size, dtype=bool)
    if grid is None or origin is None or not mask.any():
        return out
    idx = np.flatnonzero(mask)
    a = np.asarray(angles, dtype=np.float64).ravel()[: mask.size]
    out[idx] = expected_no_return(grid, origin, a[idx], range_max, min_range=range_min)
    return out
