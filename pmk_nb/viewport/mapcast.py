"""Laser rays cast over the map: which JSON ``null`` readings are the expected "nothing in range".

Over JSON rosbridge a ray that saw nothing within ``range_max`` (+inf) and an invalid one (NaN) both
arrive as ``null`` (:mod:`pmk_nb.chair.link.streams.ranges`). Looking down a corridor longer than the laser's
range gives a fan of nulls that is no blindness at all. The map tells the two apart: cast each ray
over the grid from the scanner's pose; where no occupied cell lies within ``range_max`` the null is
the expected no-return; where the map has a wall within range, the sensor should have seen it and a
null there is a blind (or blocked) sensor.

Unknown cells and the space outside the grid are not walls: the map cannot say anything was there,
so a null ray over them is not counted as blind. The rays are cast by the one ray caster
(:func:`pmk_nb.wire.first_hits`, the simulator's laser uses it too), all at once in blocks of steps.
"""

from __future__ import annotations

import math

import numpy as np

from pmk_nb.grid import OccupancyGrid
from pmk_nb.wire import first_hits

__all__ = ["OCCUPIED_AT", "expected_no_return", "explain_nulls", "first_obstacle"]

#: Occupancy at or above which a cell is a wall (map_server's default ``occupied_thresh`` 0.65).
OCCUPIED_AT = 65


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
    cos, sin = np.cos(heads)[:, None], np.sin(heads)[:, None]

    def cells(rays: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        tk = t[k.astype(np.intp)]  # the samples' distances (m), as arange spaced them
        return (ox + cos[rays] * tk) / res, (oy + sin[rays] * tk) / res

    first = first_hits(grid.data >= OCCUPIED_AT, cells, a.size, t.size)  # int8: unknown (-1) is never a wall
    found = first >= 0
    out[found] = t[first[found]]
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
