"""The map's frame, as the witness reads it: pixel centres in metres and shapes as pixel masks.

The witness draws nothing with the converter's code: a shape's mask is its own even-odd fill of pixel
centres (checked against shapely's ``contains_xy`` in the tests), so a fault of the rasteriser cannot
hide in a test written with the rasteriser's own code.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.grid import OccupancyGrid


@dataclass(frozen=True)
class Window:
    """Rows ``r0:r1`` and columns ``c0:c1`` of the grid (row 0 = the bottom row)."""

    r0: int
    r1: int
    c0: int
    c1: int

    @property
    def shape(self) -> tuple[int, int]:
        return (self.r1 - self.r0, self.c1 - self.c0)

    @property
    def empty(self) -> bool:
        return self.r1 <= self.r0 or self.c1 <= self.c0


@dataclass(frozen=True)
class MapFrame:
    """Where the written map sits: lower-left corner of pixel (0, 0), metres per pixel, size."""

    x0: float
    y0: float
    resolution: float
    width: int
    height: int

    @classmethod
    def of(cls, grid: OccupancyGrid) -> MapFrame:
        h, w = grid.data.shape
        return cls(grid.origin[0], grid.origin[1], grid.resolution, w, h)

    def window(self, bounds: tuple[float, float, float, float], pad_px: int = 0) -> Window:
        """The pixels whose centres may lie within ``bounds`` (minx, miny, maxx, maxy), padded, clipped."""
        r = self.resolution
        c0 = math.floor((bounds[0] - self.x0) / r) - pad_px
        c1 = math.ceil((bounds[2] - self.x0) / r) + 1 + pad_px
        r0 = math.floor((bounds[1] - self.y0) / r) - pad_px
        r1 = math.ceil((bounds[3] - self.y0) / r) + 1 + pad_px
        return Window(max(r0, 0), min(r1, self.height), max(c0, 0), min(c1, self.width))

    def centres(self, win: Window) -> tuple[np.ndarray, np.ndarray]:
        """The x and y of every pixel centre of ``win``, as two arrays of its shape."""
        xs = self.x0 + (np.arange(win.c0, win.c1) + 0.5) * self.resolution
        ys = self.y0 + (np.arange(win.r0, win.r1) + 0.5) * self.resolution
        return np.meshgrid(xs, ys)

    def mask(self, win: Window, geometry: BaseGeometry, outline: Outline | None = None) -> np.ndarray:
        """True where a pixel centre of ``win`` lies inside ``geometry`` (even-odd rule over every ring).

        The witness's own fill: each ring's edges cross the rows of pixel centres, crossings are paired
        along each row and the spans between them are set, so a shape costs its pixels plus its edges.
        ``outline``: the shape's :func:`outline`, for a shape drawn many times (once per strip).
        """
        edges, bounds = outline if outline is not None else (_edges(geometry), geometry.bounds)
        if win.empty or not len(edges):
            return np.zeros(win.shape, dtype=bool)
        box = self.window(bounds, 1)
        sub = Window(max(box.r0, win.r0), min(box.r1, win.r1), max(box.c0, win.c0), min(box.c1, win.c1))
        if sub == win:
            return self._fill(win, edges)
        out = np.zeros(win.shape, dtype=bool)
        if not sub.empty:
            out[sub.r0 - win.r0 : sub.r1 - win.r0, sub.c0 - win.c0 : sub.c1 - win.c0] = self._fill(sub, edges)
        return out

    def _fill(self, win: Window, edges: np.ndarray) -> np.ndarray:
        """The even-odd fill of ``edges`` over the pixel centres of ``win``."""
        r = self.resolution
        ya, yb = edges[:, 1], edges[:, 3]
        lo = np.maximum(np.ceil((np.minimum(ya, yb) - self.y0) / r - 0.5), win.r0).astype(np.int64)
        hi = np.minimum(np.ceil((np.maximum(ya, yb) - self.y0) / r - 0.5), win.r1).astype(np.int64)
        if len(edges) == 2 and lo[0] == lo[1] and hi[0] == hi[1] and (edges[:, 0] == edges[:, 2]).all():
            # an upright rectangle (most rooms): the same rows and columns as the general fill, as a slice
            out = np.zeros(win.shape, dtype=bool)
            cols = np.clip(np.ceil((np.sort(edges[:, 0]) - self.x0) / r - 0.5).astype(np.int64), win.c0, win.c1)
            if hi[0] > lo[0]:  # a rectangle wholly below the window: nothing (a negative end would wrap)
                out[lo[0] - win.r0 : hi[0] - win.r0, cols[0] - win.c0 : cols[1] - win.c0] = True
            return out
        spans = np.maximum(hi - lo, 0)
        if not spans.sum():
            return np.zeros(win.shape, dtype=bool)
        which = np.repeat(np.arange(len(edges)), spans)
        rows = lo[which] + (np.arange(spans.sum()) - np.repeat(np.cumsum(spans) - spans, spans))
        y = self.y0 + (rows + 0.5) * r
        e = edges[which]
        x = e[:, 0] + (y - e[:, 1]) * (e[:, 2] - e[:, 0]) / (e[:, 3] - e[:, 1])
        order = np.lexsort((x, rows))
        rows, x = rows[order], x[order]
        cols = np.clip(np.ceil((x - self.x0) / r - 0.5).astype(np.int64), win.c0, win.c1) - win.c0
        diff = np.zeros((win.shape[0], win.shape[1] + 1), dtype=np.int8)  # spans are disjoint: 0 or 1
        np.add.at(diff, (rows[0::2] - win.r0, cols[0::2]), 1)
        np.add.at(diff, (rows[1::2] - win.r0, cols[1::2]), -1)
        np.cumsum(diff, axis=1, dtype=np.int8, out=diff)
        return diff[:, :-1] > 0

    def rectangle(self, outline: Outline) -> Window | None:
        """The pixels :meth:`mask` sets for an upright rectangle (its :func:`outline`), as a window of the
        grid (maybe empty), so a caller can write them as a slice without drawing a mask; None for any
        other shape."""
        edges = outline[0]
        if len(edges) != 2 or not (edges[:, 0] == edges[:, 2]).all():
            return None
        r = self.resolution
        ya, yb = edges[:, 1], edges[:, 3]
        lo = np.ceil((np.minimum(ya, yb) - self.y0) / r - 0.5).astype(np.int64)
        hi = np.ceil((np.maximum(ya, yb) - self.y0) / r - 0.5).astype(np.int64)
        if lo[0] != lo[1] or hi[0] != hi[1]:
            return None
        cols = np.ceil((np.sort(edges[:, 0]) - self.x0) / r - 0.5).astype(np.int64)
        return Window(
            max(int(lo[0]), 0), min(int(hi[0]), self.height), max(int(cols[0]), 0), min(int(cols[1]), self.width)
        )

    def paste(self, win: Window, part: Window, mask: np.ndarray) -> np.ndarray:
        """``mask`` (over ``part``) placed in ``win``: False outside ``part``."""
        out = np.zeros(win.shape, dtype=bool)
        sub = Window(max(part.r0, win.r0), min(part.r1, win.r1), max(part.c0, win.c0), min(part.c1, win.c1))
        if not sub.empty:
            out[sub.r0 - win.r0 : sub.r1 - win.r0, sub.c0 - win.c0 : sub.c1 - win.c0] = mask[
                sub.r0 - part.r0 : sub.r1 - part.r0, sub.c0 - part.c0 : sub.c1 - part.c0
            ]
        return out

    def point(self, win: Window, row: float, col: float) -> tuple[float, float]:
        """The map-frame point of (fractional) pixel ``row``, ``col`` of ``win``."""
        return (
            self.x0 + (win.c0 + col + 0.5) * self.resolution,
            self.y0 + (win.r0 + row + 0.5) * self.resolution,
        )


#: a shape's edges (see :func:`_edges`) and its bounds: all :meth:`MapFrame.mask` reads of it
Outline = tuple[np.ndarray, tuple[float, float, float, float]]


def outline(geometry: BaseGeometry) -> Outline:
    """What :meth:`MapFrame.mask` reads of ``geometry``, taken once."""
    x0, y0, x1, y1 = geometry.bounds
    return _edges(geometry), (float(x0), float(y0), float(x1), float(y1))


def _edges(geometry: BaseGeometry) -> np.ndarray:
    """Every non-horizontal edge of every ring of the polygons in ``geometry``: rows xa, ya, xb, yb."""
    parts = []
    for poly in shapely.get_parts(geometry):
        if not isinstance(poly, shapely.Polygon) or poly.is_empty:
            continue
        for ring in (poly.exterior, *poly.interiors):
            xy = np.asarray(ring.coords, dtype=np.float64)[:, :2]
            if len(xy) >= 2:
                parts.append(np.hstack([xy[:-1], xy[1:]]))
    if not parts:
        return np.empty((0, 4))
    edges: np.ndarray = np.vstack(parts)
    return np.asarray(edges[edges[:, 1] != edges[:, 3]])
