"""How wide the written grid is free along each planned opening: informative beside the chair's verdict,
which is decided on the grid alone (see :mod:`pmk_nb.access.report`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import shapely

from pmk_nb.grid import FREE

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.grid import OccupancyGrid


def free_widths(grid: OccupancyGrid, openings: Sequence[Sequence[BaseGeometry]]) -> list[float]:
    """Per opening, the longest free stretch along any of its segments in ``grid`` (metres), sampled
    every half cell: informative (the chair's verdict is on the grid), all openings in one pass."""
    segs = [(i, seg) for i, segments in enumerate(openings) for seg in segments]
    best = [0.0] * len(openings)
    if not segs:
        return best
    res = grid.resolution
    lines = np.asarray([seg for _, seg in segs], dtype=object)
    lengths = shapely.length(lines)
    n = np.maximum(2, (lengths / (res / 2)).astype(np.int64) + 1)  # samples per segment
    first = np.cumsum(n) - n
    k = np.arange(int(n.sum())) - np.repeat(first, n)  # sample index within its segment
    along = k * np.repeat(lengths / (n - 1), n)
    pts = _sample(lines, n, along)
    cols = np.floor((pts[:, 0] - grid.origin[0]) / res).astype(np.int64)
    rows = np.floor((pts[:, 1] - grid.origin[1]) / res).astype(np.int64)
    ok = (cols >= 0) & (cols < grid.width) & (rows >= 0) & (rows < grid.height)
    free = np.zeros(len(k), dtype=bool)
    free[ok] = np.asarray(grid.data)[rows[ok], cols[ok]] == FREE
    # longest run of free samples per segment: samples since the last blocked one (or the segment's start)
    idx = np.arange(len(k))
    last = np.where(~free, idx, np.where(k == 0, idx - 1, -1))
    np.maximum.accumulate(last, out=last)
    run = np.where(free, idx - last, 0)
    longest = np.maximum.reduceat(run, first)
    for (i, _), m, steps, length in zip(segs, longest.tolist(), n.tolist(), lengths.tolist(), strict=True):
        best[i] = max(best[i], max(m - 1, 0) * length / (steps - 1))
    return best


def _sample(lines: np.ndarray, n: np.ndarray, along: np.ndarray) -> np.ndarray:
    """(x, y) of ``shapely.line_interpolate_point`` at ``along`` on each line repeated ``n`` times, the same
    floats: two-point lines (nearly every opening) in numpy with GEOS's own formula, p0 + (p1 - p0) *
    along / length, clamped to the ends (checked against GEOS on millions of points), not as a Point
    object each (1 s of a 100 M-cell storey's check); other lines through GEOS."""
    two = (shapely.get_type_id(lines) == 1) & (shapely.get_num_coordinates(lines) == 2)
    out = np.empty((len(along), 2))
    each = np.repeat(two, n)
    if (~two).any():
        out[~each] = shapely.get_coordinates(
            shapely.line_interpolate_point(np.repeat(lines[~two], n[~two]), along[~each])
        )
    if two.any():
        xy = shapely.get_coordinates(lines[two]).reshape(-1, 2, 2)
        p0, p1, at = np.repeat(xy[:, 0], n[two], axis=0), np.repeat(xy[:, 1], n[two], axis=0), along[each]
        d = p1 - p0
        length = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1])
        frac = at / np.where(length > 0, length, 1.0)
        mid = (at > 0) & (length > at) & (frac > 0) & (frac < 1)
        start = (at <= 0) | ((length > at) & ~(frac > 0))
        out[each] = np.where(start[:, None], p0, np.where(mid[:, None], d * frac[:, None] + p0, p1))
    return out


def free_width(grid: OccupancyGrid, segments: Sequence[BaseGeometry]) -> float:
    """The longest free stretch along any of ``segments`` in ``grid`` (metres): :func:`free_widths` of one."""
    return free_widths(grid, [segments])[0]
