"""Laser scan -> canvas-pixel segments for the live view (pure NumPy), from the scanner's world pose.

Hits become red rays, +inf (nothing within range) faint rays up to ``range_max``, and rays that
say nothing (null, NaN, out of range) or "something closer than range_min" become short ticks at
the chair, never free space (REP 117; see :mod:`pmk_nb.chair.link.streams.ranges`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pmk_nb.viewport.view import Viewport


@dataclass(frozen=True)
class LaserSegments:
    """Laser rays as canvas-pixel line segments, ready for ``Canvas.stroke_line_segments``.

    Attributes:
        hits: float32 (n, 2, 2): rays that ended on an obstacle, [[x0, y0], [x1, y1]] each.
        max_rays: float32 (m, 2, 2): rays that saw nothing up to the sensor's range (+inf; drawn faint).
        blind_ticks: float32 (k, 2, 2): short ticks at the chair for rays that say nothing
            (unknown or invalid): never drawn as free space.
        close_ticks: float32 (j, 2, 2): short ticks at the chair for "object closer than range_min".
    """

    hits: np.ndarray
    max_rays: np.ndarray
    blind_ticks: np.ndarray = field(default_factory=lambda: np.empty((0, 2, 2), np.float32))
    close_ticks: np.ndarray = field(default_factory=lambda: np.empty((0, 2, 2), np.float32))

    @property
    def count(self) -> int:
        return int(self.hits.shape[0] + self.max_rays.shape[0])


def laser_segments(
    view: Viewport,
    pose: tuple[float, float, float],
    angle_min: float,
    angle_increment: float,
    ranges: np.ndarray,
    at_max: np.ndarray | None = None,
    range_max: float | None = None,
    min_spacing_px: float = 0.0,
    *,
    blind: np.ndarray | None = None,
    too_close: np.ndarray | None = None,
    tick: tuple[float, float] = (0.0, 0.0),
) -> LaserSegments:
    """Canvas-pixel segments from the scanner to each ray's end; NaN / inf / negative ranges skipped.

    ``pose`` is the scanner's world pose: the chair's pose composed with the laser's mount on it
    (``Scan.mount``, from /tf_static), so an off-centre or rotated lidar is drawn where it sits.
    Rays flagged ``at_max`` are returned separately; when their range is not finite they are drawn
    ``range_max`` long.
    Rays flagged ``blind`` (unknown, invalid) or ``too_close`` become ticks from ``tick[0]`` to
    ``tick[1]`` metres from the chair: a blind sensor is shown as blind, never as free floor.
    With ``min_spacing_px`` > 0 only every k-th ray is kept, k chosen so that neighbouring rays end
    at least that far apart at the scan's median range: a 1080-ray scan on a whole-map view would
    otherwise be a solid red fan of sub-pixel lines costing bandwidth and showing nothing more.
    """
    r = np.asarray(ranges, dtype=np.float64).ravel()
    n = r.size
    flags = _mask(at_max, n)
    if range_max is not None and math.isfinite(range_max) and range_max > 0:
        r = np.where(flags & ~np.isfinite(r), range_max, r)
    ok = np.isfinite(r) & (r >= 0)
    stride = ray_stride(view, r[ok], angle_increment, min_spacing_px)
    keep = np.ones(n, dtype=bool) if stride <= 1 else np.arange(n) % stride == 0
    ok &= keep
    x, y, theta = (float(p) for p in pose)
    ang = theta + angle_min + angle_increment * np.arange(n, dtype=np.float64)
    cos, sin = np.cos(ang), np.sin(ang)

    def segs(mask: np.ndarray, r0: float | np.ndarray, r1: float | np.ndarray) -> np.ndarray:
        x0, y0 = view.world_to_pixel(x + r0 * cos[mask], y + r0 * sin[mask])
        x1, y1 = view.world_to_pixel(x + r1 * cos[mask], y + r1 * sin[mask])
        out = np.empty((int(mask.sum()), 2, 2), dtype=np.float32)
        out[:, 0, 0], out[:, 0, 1], out[:, 1, 0], out[:, 1, 1] = x0, y0, x1, y1
        return out

    rm = np.where(ok, r, 0.0)
    return LaserSegments(
        hits=segs(ok & ~flags, 0.0, rm[ok & ~flags]),
        max_rays=segs(ok & flags, 0.0, rm[ok & flags]),
        blind_ticks=segs(_mask(blind, n) & keep, tick[0], tick[1]),
        close_ticks=segs(_mask(too_close, n), tick[0], tick[1]),
    )


def _mask(values: np.ndarray | None, n: int) -> np.ndarray:
    """A bool mask of length ``n`` (missing entries False)."""
    if values is None:
        return np.zeros(n, dtype=bool)
    mask = np.asarray(values, dtype=bool).ravel()[:n]
    return mask if mask.size == n else np.concatenate([mask, np.zeros(n - mask.size, dtype=bool)])


def ray_stride(view: Viewport, valid_ranges: np.ndarray, angle_increment: float, min_spacing_px: float) -> int:
    """Keep every k-th ray so rays end >= ``min_spacing_px`` apart at the median range (1 = all)."""
    if not (min_spacing_px > 0) or valid_ranges.size == 0:
        return 1
    spacing = float(np.median(valid_ranges)) * abs(float(angle_increment)) * view.px_per_m
    if not (math.isfinite(spacing) and spacing > 0):
        return 1
    return max(1, math.ceil(min_spacing_px / spacing))
