"""Many polygons at once as row spans, and spans written to the grid as rectangles where they stack.

:func:`fill_polygon` in :mod:`pmk_nb.raster.scanline` walks one polygon at a time; a storey has
thousands of cells, and the per-call overhead then costs more than the pixels. Here every edge of
every polygon is crossed with the rows it spans in one vectorised pass (memory proportional to the
crossings, not to the grid), giving the same even-odd spans bit for bit (same formulas, same
per-polygon column origin). :func:`write_spans` then merges spans repeated on consecutive rows into
rectangles (a box-shaped room is one) and writes those as slices, so a large room costs one memset
instead of a flat index per cell; leftover short spans go through one flat scatter.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pmk_nb.geometry import polygon_parts
from pmk_nb.raster.scanline import Frame, Rects, Spans, span_rectangles, write_rects, write_spans

_CHUNK_CELLS = 1_000_000  # (edge, row) crossings computed at once at most


def _edges(polys: list[shapely.Polygon]) -> tuple[np.ndarray, np.ndarray]:
    """(E, 4) edges xa, ya, xb, yb of every ring of ``polys`` and the polygon index of each."""
    arr = np.asarray(polys, dtype=object)
    rings, poly_of = shapely.get_rings(arr, return_index=True)
    coords, ring_of = shapely.get_coordinates(rings, return_index=True)
    same = ring_of[1:] == ring_of[:-1]
    edges = np.hstack([coords[:-1][same], coords[1:][same]])
    owner = poly_of[ring_of[1:][same]]
    # rings are closed in shapely; a ring whose last point differs from its first gets its closing edge
    first = np.r_[0, np.flatnonzero(~same) + 1]
    last = np.r_[np.flatnonzero(~same), len(coords) - 1]
    open_ = ~np.all(coords[first] == coords[last], axis=1)
    if open_.any():
        extra = np.hstack([coords[last[open_]], coords[first[open_]]])
        edges = np.vstack([edges, extra])
        owner = np.concatenate([owner, poly_of[ring_of[first[open_]]]])
    return edges, owner


def polygon_cells(frame: Frame, geoms: Sequence[BaseGeometry]) -> tuple[Rects, Spans]:
    """The cells whose centres lie inside each of ``geoms`` (even-odd rule), as rectangles (row0, row1,
    start, stop; exclusive ends) for axis-aligned boxes and as spans (rows, starts, stops) for the rest.

    The same cells, computed the same way, as :func:`pmk_nb.raster.scanline.fill_polygon` on each
    polygon part in turn; shapes of different polygons may overlap.
    """
    polys = polygon_parts(geoms)
    empty = np.empty(0, np.int64)
    if not polys:
        return (empty,) * 4, (empty,) * 3
    res = frame.resolution
    b = shapely.bounds(np.asarray(polys, dtype=object))
    c0 = np.maximum(0, np.ceil((b[:, 0] - frame.x0) / res - 0.5))
    c1 = np.minimum(frame.width - 1, np.floor((b[:, 2] - frame.x0) / res - 0.5))
    r0 = np.maximum(0, np.ceil((b[:, 1] - frame.y0) / res - 0.5))
    r1 = np.minimum(frame.height - 1, np.floor((b[:, 3] - frame.y0) / res - 0.5))
    box = _boxes(polys, b)
    rects = _box_rects(frame, b[box], c0[box], c1[box], r0[box], r1[box])
    if box.all():
        return rects, (empty,) * 3
    rest = np.flatnonzero(~box)
    edges, owner = _edges([polys[i] for i in rest.tolist()])
    return rects, _scan(frame, edges, owner, c0[rest], c1[rest], r0[rest], r1[rest])


def _boxes(polys: list[shapely.Polygon], b: np.ndarray) -> np.ndarray:
    """Which polygons are axis-aligned rectangles (every vertex a bounding-box corner, full area)."""
    arr = np.asarray(polys, dtype=object)
    cand: np.ndarray = (shapely.get_num_coordinates(arr) == 5) & (shapely.get_num_interior_rings(arr) == 0)
    idx = np.flatnonzero(cand)
    if len(idx) == 0:
        return cand
    xy = shapely.get_coordinates(arr[idx]).reshape(len(idx), 5, 2)
    bb = b[idx]
    on_x = (xy[:, :, 0] == bb[:, None, 0]) | (xy[:, :, 0] == bb[:, None, 2])
    on_y = (xy[:, :, 1] == bb[:, None, 1]) | (xy[:, :, 1] == bb[:, None, 3])
    full = shapely.area(arr[idx]) == (bb[:, 2] - bb[:, 0]) * (bb[:, 3] - bb[:, 1])
    cand[idx] = on_x.all(axis=1) & on_y.all(axis=1) & full & (bb[:, 2] > bb[:, 0]) & (bb[:, 3] > bb[:, 1])
    return cand


def _box_rects(frame: Frame, b: np.ndarray, c0: np.ndarray, c1: np.ndarray, r0: np.ndarray, r1: np.ndarray) -> Rects:
    """Cell rectangles of axis-aligned boxes, the cells the even-odd scan gives: rows with ymin <=
    centre < ymax, columns from the two vertical edges, same per-polygon column origin as :func:`_scan`."""
    res = frame.resolution
    r0 = r0 + (frame.y0 + (r0 + 0.5) * res < b[:, 1])  # a centre rounded off the edge
    r1 = r1 - (frame.y0 + (r1 + 0.5) * res >= b[:, 3])
    ncols = c1 - c0 + 1
    xc0 = frame.x0 + (c0 + 0.5) * res
    cs = np.clip(np.ceil((b[:, 0] - xc0) / res), 0, ncols)
    ce = np.clip(np.ceil((b[:, 2] - xc0) / res), 0, ncols)
    ok = ncols > 0
    i64 = np.int64
    return r0[ok].astype(i64), (r1[ok] + 1).astype(i64), (c0 + cs)[ok].astype(i64), (c0 + ce)[ok].astype(i64)


def _scan(
    frame: Frame,
    edges: np.ndarray,
    owner: np.ndarray,
    c0: np.ndarray,
    c1: np.ndarray,
    r0: np.ndarray,
    r1: np.ndarray,
) -> Spans:
    """Even-odd spans of the polygons whose edges are ``edges`` (``owner``: polygon of each edge)."""
    res = frame.resolution
    ya, yb = edges[:, 1], edges[:, 3]
    keep = ya != yb
    edges, owner, ya, yb = edges[keep], owner[keep], ya[keep], yb[keep]
    # candidate rows of each edge (one row of slack each side; the exact test below decides)
    lo = np.maximum(np.floor((np.minimum(ya, yb) - frame.y0) / res - 0.5) - 1, r0[owner])
    hi = np.minimum(np.ceil((np.maximum(ya, yb) - frame.y0) / res - 0.5) + 1, r1[owner])
    n = np.maximum(hi - lo + 1, 0).astype(np.int64)
    e = np.repeat(np.arange(len(edges)), n)
    row = (np.repeat(lo.astype(np.int64), n) + np.arange(len(e)) - np.repeat(np.cumsum(n) - n, n)).astype(np.int64)
    yc = frame.y0 + (row + 0.5) * res
    cross = (ya[e] <= yc) != (yb[e] <= yc)
    e, row, yc = e[cross], row[cross], yc[cross]
    xa, xb, ya_e = edges[e, 0], edges[e, 2], ya[e]
    x = xa + (yc - ya_e) * ((xb - xa) / (yb[e] - ya_e))
    poly = owner[e]
    order = np.lexsort((x, row, poly))
    x, row, poly = x[order], row[order], poly[order]
    group = np.r_[True, (row[1:] != row[:-1]) | (poly[1:] != poly[:-1])]
    starts_at = np.flatnonzero(group)
    size = np.diff(np.r_[starts_at, len(x)])
    rank = np.arange(len(x)) - np.repeat(starts_at, size)
    left = np.flatnonzero((rank % 2 == 0) & (rank + 1 < np.repeat(size, size)))
    p, rr = poly[left], row[left]
    pc0 = c0[p]
    ncols = c1[p] - pc0 + 1
    xc0 = frame.x0 + (pc0 + 0.5) * res
    cs = np.clip(np.ceil((x[left] - xc0) / res), 0, ncols)
    ce = np.clip(np.ceil((x[left + 1] - xc0) / res), 0, ncols)
    ok = (ce > cs) & (ncols > 0)
    return rr[ok], (pc0 + cs)[ok].astype(np.int64), (pc0 + ce)[ok].astype(np.int64)


def fill_polygons(
    grid: np.ndarray, frame: Frame, geoms: Sequence[BaseGeometry], value: int, keep: tuple[int, ...] = ()
) -> None:
    """Set every cell whose centre lies inside one of ``geoms`` to ``value`` (sparing ``keep`` cells).

    Polygons are taken in batches of about a million (edge, row) crossings, so the memory held
    at once stays bounded however fine the grid.
    """
    polys = np.asarray(polygon_parts(geoms), dtype=object)
    if len(polys) == 0:
        return
    b = shapely.bounds(polys)
    work = shapely.get_num_coordinates(polys) * ((b[:, 3] - b[:, 1]) / frame.resolution + 2)
    batch = (np.cumsum(work) // _CHUNK_CELLS).astype(np.int64)
    cuts = [0, *(np.flatnonzero(np.diff(batch)) + 1).tolist(), len(polys)]
    for lo, hi in itertools.pairwise(cuts):
        rects, spans = polygon_cells(frame, polys[lo:hi].tolist())
        write_rects(grid, *rects, value, keep)
        write_spans(grid, *spans, value, keep)


def polygon_rects(frame: Frame, geoms: Sequence[BaseGeometry]) -> tuple[np.ndarray, ...]:
    """The cells :func:`fill_polygons` would set for ``geoms``, as rectangles (row0, row1, start, stop;
    exclusive ends), held instead of the cells: a caller can write them a strip of rows at a time."""
    rects, spans = polygon_cells(frame, geoms)
    more = span_rectangles(*spans) if len(spans[0]) else (*spans, spans[0])
    return tuple(np.concatenate([a, b]) for a, b in zip(rects, more, strict=True))


def polygon_rects_each(frame: Frame, geoms: Sequence[BaseGeometry]) -> list[tuple[np.ndarray, ...]]:
    """:func:`polygon_rects` of each of ``geoms`` on its own, the same rectangles: axis-aligned boxes (a
    storey's cells nearly always are) in one vectorised pass, any other shape by its own call, so
    thousands of cells do not pay a call's fixed cost each (about 1 s of a 100 M-cell storey's check)."""
    arr = np.asarray(geoms, dtype=object)
    out: list[tuple[np.ndarray, ...] | None] = [None] * len(geoms)
    if len(geoms):
        plain = np.flatnonzero((shapely.get_type_id(arr) == 3) & ~shapely.is_empty(arr))
        polys = arr[plain].tolist()
        b = shapely.bounds(arr[plain]).reshape(-1, 4)
        box = _boxes(polys, b) if polys else np.zeros(0, dtype=bool)
        res, bb = frame.resolution, b[box]
        c0 = np.maximum(0, np.ceil((bb[:, 0] - frame.x0) / res - 0.5))
        c1 = np.minimum(frame.width - 1, np.floor((bb[:, 2] - frame.x0) / res - 0.5))
        r0 = np.maximum(0, np.ceil((bb[:, 1] - frame.y0) / res - 0.5))
        r1 = np.minimum(frame.height - 1, np.floor((bb[:, 3] - frame.y0) / res - 0.5))
        ok = c1 - c0 + 1 > 0  # _box_rects drops these: kept here so each rectangle keeps its polygon
        rects = _box_rects(frame, bb, c0, c1, r0, r1)
        at = np.cumsum(ok) - 1
        for k, i in enumerate(plain[box].tolist()):
            j = int(at[k])
            out[i] = tuple(a[j : j + 1] if ok[k] else a[:0] for a in rects)
    return [polygon_rects(frame, [g]) if r is None else r for g, r in zip(geoms, out, strict=True)]
