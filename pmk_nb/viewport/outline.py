"""A laser scan as the room it sees: hit points and a free-space polygon, thinned to screen pixels.

Drawing 1080 rays from the chair is a red moiré once zoomed in, and it hides the map.  What a scan
says is (a) where obstacles are, the hit points, and (b) which floor is seen free, the area the
rays swept.  So the live view draws the hits as small dots, at most one per screen pixel, over a
light polygon through the rays' ends.  Readings that say nothing (JSON null, NaN, out of range,
"closer than range_min") pull the polygon back to the scanner: unknown is never shown as free
(REP 117, read in :mod:`pmk_nb.chair.link.streams.ranges`).  The polygon keeps at most one vertex per pixel of
its outline, then drops vertices that lie on a straight line with their neighbours (a wall seen by
300 rays is a handful of vertices), so a frame stays a few kilobytes at any zoom.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from pmk_nb.viewport.view import Viewport

#: A polygon vertex is dropped when it is closer than this (pixels) to the line through its neighbours.
SIMPLIFY_PX = 0.5
#: Hits further than this (pixels) outside the canvas are not sent.
OFFSCREEN_PX = 4.0


@dataclass(frozen=True)
class LaserOutline:
    """A scan in canvas pixels.

    Attributes:
        hits: float32 (n, 2): one point per screen pixel with an obstacle seen (pixel centres).
        polygon: float32 (m, 2): the free area seen, a closed ring (first vertex not repeated).
        at_max: number of rays that saw nothing up to the sensor's range (their ends bound the polygon).
        blind: number of rays that say nothing (pulled back to the scanner).
    """

    hits: np.ndarray
    polygon: np.ndarray
    at_max: int
    blind: int


def unique_pixels(
    x: np.ndarray, y: np.ndarray, width: int, height: int, cell: float = 1.0, margin: float = OFFSCREEN_PX
) -> np.ndarray:
    """Centres (float32 (n, 2)) of the distinct ``cell`` x ``cell`` pixel squares hit by points (x, y).

    ``cell`` = 1: at most one point per screen pixel.  A larger cell (the size of the dot drawn)
    drops points whose dots would cover each other anyway.  Points far off the canvas are dropped.
    """
    c = max(float(cell), 1.0)
    ok = np.isfinite(x) & np.isfinite(y)
    ok &= (x >= -margin) & (x < width + margin) & (y >= -margin) & (y < height + margin)
    ix = np.floor((x[ok] + margin) / c).astype(np.int64)
    iy = np.floor((y[ok] + margin) / c).astype(np.int64)
    if ix.size == 0:
        return np.empty((0, 2), dtype=np.float32)
    span = int((width + 2 * margin) / c) + 2
    key = np.unique(iy * span + ix)
    out = np.empty((key.size, 2), dtype=np.float32)
    out[:, 0] = (key % span + 0.5) * c - margin
    out[:, 1] = (key // span + 0.5) * c - margin
    return out


def dedupe_ring(points: np.ndarray) -> np.ndarray:
    """Drop consecutive vertices that fall in the same screen pixel (at most one vertex per pixel run)."""
    if points.shape[0] < 2:
        return points
    cells = np.floor(points).astype(np.int64)
    keep = np.ones(points.shape[0], dtype=bool)
    keep[1:] = np.any(cells[1:] != cells[:-1], axis=1)
    return points[keep]


def simplify_ring(points: np.ndarray, tol: float = SIMPLIFY_PX) -> np.ndarray:
    """Drop vertices so that the outline stays within ``tol`` pixels of the original (Douglas-Peucker,
    GEOS through shapely): a wall seen by 300 rays becomes a handful of vertices, a curve keeps its shape.

    The first and last vertices stay (the scanner, where the fan starts).  GEOS does in 0.07 ms what
    the earlier NumPy passes did in 1 ms, per frame of a 360-ray scan: a twelfth of a classroom
    page's kernel frame cost (bench/soak_classroom.py).
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.shape[0] <= 4 or tol <= 0:
        return pts.astype(np.float32)
    line = shapely.simplify(shapely.linestrings(pts), float(tol), preserve_topology=False)
    return shapely.get_coordinates(line).astype(np.float32)


def laser_outline(
    view: Viewport,
    pose: tuple[float, float, float],
    angle_min: float,
    angle_increment: float,
    ranges: np.ndarray,
    at_max: np.ndarray | None = None,
    range_max: float | None = None,
    *,
    unknown: np.ndarray | None = None,
    simplify_px: float = SIMPLIFY_PX,
    dot_px: float = 1.0,
) -> LaserOutline:
    """Hit points and the free-space polygon of one scan, in canvas pixels of ``view``.

    Args:
        view: the viewport the scan is drawn in.
        pose: the scanner's world pose (x, y, theta).
        angle_min, angle_increment, ranges: the LaserScan fields (ranges already read by REP 117:
            NaN = unknown).
        at_max: True where the ray saw nothing up to ``range_max`` (+inf): a polygon vertex at
            ``range_max``, not a hit.
        unknown: True where the reading says nothing about the ray (null, NaN, too close, out of
            range): the polygon goes back to the scanner there.
        simplify_px: tolerance of the polygon's straight-run simplification (0: none).
        dot_px: size of the hit dots drawn: at most one hit per dot-sized square is kept.
    """
    r = np.asarray(ranges, dtype=np.float64).ravel()
    n = r.size
    far = _mask(at_max, n)
    if range_max is not None and math.isfinite(range_max) and range_max > 0:
        r = np.where(far & ~np.isfinite(r), range_max, r)
    ok = np.isfinite(r) & (r >= 0) & ~_mask(unknown, n)
    x, y, theta = (float(p) for p in pose)
    ang = theta + float(angle_min) + float(angle_increment) * np.arange(n, dtype=np.float64)
    reach = np.where(ok, r, 0.0)  # nothing known: the ring goes back to the scanner
    px, py = view.world_to_pixel(x + reach * np.cos(ang), y + reach * np.sin(ang))
    hit = ok & ~far
    hits = unique_pixels(px[hit], py[hit], view.canvas_width, view.canvas_height, dot_px)
    ox, oy = view.world_to_pixel(x, y)
    ring = np.empty((n + 1, 2), dtype=np.float64)
    ring[0] = (float(ox), float(oy))  # a scan of less than a full turn is a fan from the scanner
    ring[1:, 0], ring[1:, 1] = px, py
    ring = dedupe_ring(ring)
    polygon = simplify_ring(ring, simplify_px) if simplify_px > 0 else ring.astype(np.float32)
    return LaserOutline(hits, polygon, int((ok & far).sum()), int(n - ok.sum()))


def _mask(values: np.ndarray | None, n: int) -> np.ndarray:
    if values is None:
        return np.zeros(n, dtype=bool)
    mask = np.asarray(values, dtype=bool).ravel()[:n]
    return mask if mask.size == n else np.concatenate([mask, np.zeros(n - mask.size, dtype=bool)])


def tick_segments(
    view: Viewport,
    pose: tuple[float, float, float],
    angle_min: float,
    angle_increment: float,
    mask: np.ndarray,
    r0: float,
    r1: float,
    min_spacing_px: float = 3.0,
) -> np.ndarray:
    """Short radial ticks from ``r0`` to ``r1`` metres for the rays in ``mask``, float32 (k, 2, 2).

    Ticks that would end closer than ``min_spacing_px`` on screen are thinned (every k-th ray kept):
    a blind sector stays readable as a grey fringe and costs a few hundred bytes, not 16 per ray.
    """
    m = np.asarray(mask, dtype=bool).ravel()
    spacing = abs(float(r1) * float(angle_increment)) * view.px_per_m
    stride = max(1, math.ceil(min_spacing_px / spacing)) if spacing > 0 and math.isfinite(spacing) else 1
    idx = np.flatnonzero(m & (np.arange(m.size) % stride == 0))
    x, y, theta = (float(p) for p in pose)
    ang = theta + float(angle_min) + float(angle_increment) * idx
    cos, sin = np.cos(ang), np.sin(ang)
    x0, y0 = view.world_to_pixel(x + r0 * cos, y + r0 * sin)
    x1, y1 = view.world_to_pixel(x + r1 * cos, y + r1 * sin)
    out = np.empty((idx.size, 2, 2), dtype=np.float32)
    out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1] = x0, y0, x1, y1
    return out
