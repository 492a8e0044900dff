"""Vectorised rasterisation primitives: polygon scanline fill and supercover line cells.

Both work directly at the target resolution on a grid frame (origin + resolution), row 0 = bottom,
and touch only the rows and columns a shape covers, processed in bounded chunks, so memory stays
proportional to the grid however fine the resolution. A cell belongs to a polygon when its centre is
inside (even-odd rule over all rings, so holes are respected).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pmk_nb.geometry import polygons_of

# (block view of the grid, boolean mask of the same shape) -> None; updates the block in place
CellOp = Callable[[np.ndarray, np.ndarray], None]
#: cell rectangles as four arrays (row0, row1, start, stop; exclusive ends): what write_rects takes
Rects = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
#: cell spans as three arrays (rows, starts, stops; exclusive stops): what write_spans takes
Spans = tuple[np.ndarray, np.ndarray, np.ndarray]
_CHUNK_CROSSINGS = 2_000_000  # rows x edges evaluated at once
_CHUNK_CELLS = 1_000_000  # rows x columns of a block (or cells of a scatter) at once
_SCATTER_CELLS = 65_536  # cells written through one flat index array at once (512 KB of int64; its temporaries
# peaked at 3x the grid of a 100 x 100 m storey at 262 144)
_RECT_MIN_CELLS = 256  # spans stacked into a rectangle at least this big are written as one slice


@dataclass(frozen=True)
class Frame:
    """Where a grid sits: lower-left corner of cell (0, 0), metres per cell, size in cells."""

    x0: float
    y0: float
    resolution: float
    width: int
    height: int

    def col_range(self, xmin: float, xmax: float) -> tuple[int, int]:
        """Columns whose centres lie in [xmin, xmax], clipped (may be empty: start > stop)."""
        r = self.resolution
        c0 = max(0, math.ceil((xmin - self.x0) / r - 0.5))
        c1 = min(self.width - 1, math.floor((xmax - self.x0) / r - 0.5))
        return c0, c1

    def row_range(self, ymin: float, ymax: float) -> tuple[int, int]:
        r = self.resolution
        r0 = max(0, math.ceil((ymin - self.y0) / r - 0.5))
        r1 = min(self.height - 1, math.floor((ymax - self.y0) / r - 0.5))
        return r0, r1


def _ring_edges(polygon: shapely.Polygon) -> np.ndarray:
    """All edges of all rings as an (E, 4) array xa, ya, xb, yb."""
    parts = []
    for ring in (polygon.exterior, *polygon.interiors):
        xy = np.asarray(ring.coords, dtype=np.float64)[:, :2]
        if len(xy) < 2:
            continue
        if not np.array_equal(xy[0], xy[-1]):
            xy = np.vstack([xy, xy[:1]])
        parts.append(np.hstack([xy[:-1], xy[1:]]))
    if not parts:
        return np.empty((0, 4))
    return np.vstack(parts)


def fill_polygon(grid: np.ndarray, frame: Frame, polygon: shapely.Polygon, op: CellOp) -> None:
    """Apply ``op`` to the cells whose centres are inside ``polygon`` (even-odd scanline fill)."""
    edges = _ring_edges(polygon)
    if len(edges) == 0:
        return
    xmin, ymin, xmax, ymax = polygon.bounds
    c0, c1 = frame.col_range(xmin, xmax)
    r0, r1 = frame.row_range(ymin, ymax)
    if c0 > c1 or r0 > r1:
        return
    ncols = c1 - c0 + 1
    lo_y = np.minimum(edges[:, 1], edges[:, 3])
    hi_y = np.maximum(edges[:, 1], edges[:, 3])
    step = max(1, min(_CHUNK_CELLS // ncols, _CHUNK_CROSSINGS // max(1, len(edges))))
    res = frame.resolution
    for start in range(r0, r1 + 1, step):
        stop = min(r1 + 1, start + step)
        rows = np.arange(start, stop)
        yc = frame.y0 + (rows + 0.5) * res
        near = (hi_y >= yc[0]) & (lo_y <= yc[-1])  # only edges spanning this band of rows
        e = edges[near]
        if len(e) == 0:
            continue
        inside = _scan_rows(e, yc, frame.x0 + (c0 + 0.5) * res, res, ncols)
        if inside is not None:
            op(grid[start:stop, c0 : c1 + 1], inside)


def _scan_rows(e: np.ndarray, yc: np.ndarray, xc0: float, res: float, ncols: int) -> np.ndarray | None:
    """Even-odd inside mask (rows, ncols) for row centres ``yc`` and column centres xc0 + k*res."""
    xa, ya, xb, yb = e[:, 0], e[:, 1], e[:, 2], e[:, 3]
    crosses = (ya[None, :] <= yc[:, None]) != (yb[None, :] <= yc[:, None])
    if not crosses.any():
        return None
    dy = np.where(ya == yb, 1.0, yb - ya)
    slope = (xb - xa) / dy
    xs = np.where(crosses, xa[None, :] + (yc[:, None] - ya[None, :]) * slope[None, :], np.inf)
    xs.sort(axis=1)
    counts = crosses.sum(axis=1)
    k = int(counts.max()) & ~1
    if k == 0:
        return None
    starts, ends = xs[:, 0:k:2], xs[:, 1:k:2]
    valid = np.isfinite(ends)
    # columns whose centre x satisfies start <= x < end
    cs = np.clip(np.ceil((starts - xc0) / res), 0, ncols).astype(np.int64)
    ce = np.clip(np.ceil((ends - xc0) / res), 0, ncols).astype(np.int64)
    valid &= ce > cs
    nrows = len(yc)
    row_idx = np.broadcast_to(np.arange(nrows)[:, None], cs.shape)
    width = ncols + 1
    flat_s = (row_idx * width + cs)[valid]
    flat_e = (row_idx * width + ce)[valid]
    # even-odd intervals of one polygon never overlap, so no start repeats: a +1/-1 int8 difference
    # row (ends may meet the next start; the separate += and -= then cancel) and a running sum
    diff = np.zeros(nrows * width, dtype=np.int8)
    diff[flat_s] += 1
    diff[flat_e] -= 1
    return np.cumsum(diff.reshape(nrows, width), axis=1, dtype=np.int8)[:, :ncols].view(np.bool_)


def fill_geometry(grid: np.ndarray, frame: Frame, geom: BaseGeometry | None, op: CellOp) -> None:
    for poly in polygons_of(geom):
        fill_polygon(grid, frame, poly, op)


def line_segments(lines: Sequence[BaseGeometry]) -> np.ndarray:
    """(S, 4) array xa, ya, xb, yb of the straight segments of LineStrings / rings / their multis."""
    return segments_with_owner(lines)[0]


def segments_with_owner(lines: Sequence[BaseGeometry]) -> tuple[np.ndarray, np.ndarray]:
    """Segments as in :func:`line_segments`, plus the index in ``lines`` each one came from."""
    arr = np.asarray(lines, dtype=object)
    if arr.size == 0:
        return np.empty((0, 4)), np.empty(0, np.int64)
    parts, owner = shapely.get_parts(arr, return_index=True)
    keep = np.isin(shapely.get_type_id(parts), (1, 2)) & ~shapely.is_empty(parts)
    parts, owner = parts[keep], owner[keep]
    if len(parts) == 0:
        return np.empty((0, 4)), np.empty(0, np.int64)
    coords, index = shapely.get_coordinates(parts, return_index=True)
    same = index[1:] == index[:-1]
    return np.hstack([coords[:-1][same], coords[1:][same]]), owner[index[1:][same]]


def supercover_cells(segments: np.ndarray, frame: Frame) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of every cell a segment passes through (4-connected; both cells at corners).

    Vectorised over all segments: the crossings of each segment with the grid lines are generated
    with ``np.repeat``, sorted per segment, and the cell at each midpoint is taken.
    """
    if len(segments) == 0:
        return np.empty(0, np.int64), np.empty(0, np.int64)
    res = frame.resolution
    u0 = (segments[:, 0] - frame.x0) / res
    v0 = (segments[:, 1] - frame.y0) / res
    du = (segments[:, 2] - frame.x0) / res - u0
    dv = (segments[:, 3] - frame.y0) / res - v0
    fu0, fu1 = np.floor(u0), np.floor(u0 + du)
    fv0, fv1 = np.floor(v0), np.floor(v0 + dv)
    nu = np.abs(fu1 - fu0).astype(np.int64)
    nv = np.abs(fv1 - fv0).astype(np.int64)
    seg_ids = np.arange(len(segments))
    t_parts = [np.zeros(len(segments)), np.ones(len(segments))]
    id_parts = [seg_ids, seg_ids]
    for n, f0, d, p0 in ((nu, fu0, du, u0), (nv, fv0, dv, v0)):
        ids = np.repeat(seg_ids, n)
        if len(ids) == 0:
            continue
        k = np.arange(len(ids)) - np.repeat(np.cumsum(n) - n, n)  # 0..n-1 within each segment
        sign = np.sign(d[ids])
        line = f0[ids] + np.where(sign > 0, k + 1, -k)  # grid lines crossed, in travel order
        t_parts.append((line - p0[ids]) / d[ids])
        id_parts.append(ids)
    t = np.concatenate(t_parts).clip(0.0, 1.0)
    ids = np.concatenate(id_parts)
    order = np.lexsort((t, ids))
    t, ids = t[order], ids[order]
    same = ids[1:] == ids[:-1]
    tm = ((t[1:] + t[:-1]) / 2)[same]
    sid = ids[1:][same]
    cu = np.floor(u0[sid] + du[sid] * tm).astype(np.int64)
    cv = np.floor(v0[sid] + dv[sid] * tm).astype(np.int64)
    # where consecutive cells of a segment differ in both axes (a corner was hit) add both neighbours
    diag = (sid[1:] == sid[:-1]) & (cu[1:] != cu[:-1]) & (cv[1:] != cv[:-1])
    cu = np.concatenate([cu, cu[1:][diag], cu[:-1][diag]])
    cv = np.concatenate([cv, cv[:-1][diag], cv[1:][diag]])
    keep = (cu >= 0) & (cu < frame.width) & (cv >= 0) & (cv < frame.height)
    return cv[keep], cu[keep]


def fill_segment_bands(
    grid: np.ndarray,
    frame: Frame,
    segments: np.ndarray,
    half: float | np.ndarray,
    value: int,
    keep: tuple[int, ...] = (),
    *,
    caps: bool = True,
) -> None:
    """Set cells whose centres lie in the rectangle of half-width ``half`` around each segment (one
    value, or one per segment) to ``value``, sparing cells that hold a ``keep`` value.

    With ``caps`` the rectangles extend ``half`` beyond both ends (square caps, so consecutive
    segments of a ring join without notches). All segments are processed at once: one (segment, row)
    pair per covered row gives an x-interval, and only the covered cells are written.
    """
    halves = np.broadcast_to(np.asarray(half, dtype=np.float64), (len(segments),))[:, None]
    if len(segments) == 0 or not (halves > 0).any():
        return
    p0, p1 = segments[:, 0:2], segments[:, 2:4]
    d = p1 - p0
    length = np.hypot(d[:, 0], d[:, 1])
    u = np.where(length[:, None] > 0, d / np.where(length > 0, length, 1.0)[:, None], [1.0, 0.0])
    n = np.stack([-u[:, 1], u[:, 0]], axis=1) * halves
    if caps:
        p0, p1 = p0 - u * halves, p1 + u * halves
    quad = np.stack([p0 + n, p1 + n, p1 - n, p0 - n], axis=1)  # (S, 4, 2)
    res = frame.resolution
    ys = quad[:, :, 1]
    r0 = np.maximum(0, np.ceil((ys.min(axis=1) - frame.y0) / res - 0.5)).astype(np.int64)
    r1 = np.minimum(frame.height - 1, np.floor((ys.max(axis=1) - frame.y0) / res - 0.5)).astype(np.int64)
    axis = (d[:, 0] == 0) | (d[:, 1] == 0)
    if axis.any():  # an axis-aligned band is a rectangle of cells: no per-row work
        _axis_bands(grid, frame, quad[axis], r0[axis], r1[axis], value, keep)
        quad, r0, r1 = quad[~axis], r0[~axis], r1[~axis]
        segments = segments[~axis]
    count = np.maximum(0, r1 - r0 + 1)
    seg = np.repeat(np.arange(len(segments)), count)
    if len(seg) == 0:
        return
    row = r0[seg] + (np.arange(len(seg)) - np.repeat(np.cumsum(count) - count, count))
    yc = frame.y0 + (row + 0.5) * res
    xl = np.full(len(seg), np.inf)
    xr = np.full(len(seg), -np.inf)
    for i in range(4):
        a, b = quad[seg, i], quad[seg, (i + 1) % 4]
        lo, hi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
        spans = (lo <= yc) & (yc <= hi) & (hi > lo)
        dy = np.where(hi > lo, b[:, 1] - a[:, 1], 1.0)
        x = a[:, 0] + (yc - a[:, 1]) * (b[:, 0] - a[:, 0]) / dy
        xl = np.where(spans, np.minimum(xl, x), xl)
        xr = np.where(spans, np.maximum(xr, x), xr)
    cs = np.clip(np.ceil((xl - frame.x0) / res - 0.5), 0, frame.width)
    ce = np.clip(np.floor((xr - frame.x0) / res - 0.5) + 1, 0, frame.width)
    ok = np.isfinite(xl) & (ce > cs)
    write_spans(grid, row[ok], cs[ok].astype(np.int64), ce[ok].astype(np.int64), value, keep)


def _axis_bands(
    grid: np.ndarray,
    frame: Frame,
    quad: np.ndarray,
    r0: np.ndarray,
    r1: np.ndarray,
    value: int,
    keep: tuple[int, ...],
) -> None:
    """The cells of axis-aligned band quads, exactly as the per-row rule in fill_segment_bands gives."""
    res = frame.resolution
    ymin, ymax = quad[:, :, 1].min(axis=1), quad[:, :, 1].max(axis=1)
    r0 = r0 + (frame.y0 + (r0 + 0.5) * res < ymin)  # a centre rounded off the band's edge
    r1 = r1 - (frame.y0 + (r1 + 0.5) * res > ymax)
    xl, xr = quad[:, :, 0].min(axis=1), quad[:, :, 0].max(axis=1)
    cs = np.clip(np.ceil((xl - frame.x0) / res - 0.5), 0, frame.width).astype(np.int64)
    ce = np.clip(np.floor((xr - frame.x0) / res - 0.5) + 1, 0, frame.width).astype(np.int64)
    tall = ymax > ymin
    write_rects(grid, r0[tall], r1[tall] + 1, cs[tall], ce[tall], value, keep)


def axis_line_rects(segments: np.ndarray, frame: Frame) -> tuple[np.ndarray, np.ndarray, Rects]:
    """Split ``segments``: (mask of the axis-aligned ones, the others, their supercover cells as
    rectangles r0, r1, c0, c1 with exclusive ends) - the same cells :func:`supercover_cells` gives."""
    res = frame.resolution
    u0 = (segments[:, 0] - frame.x0) / res
    v0 = (segments[:, 1] - frame.y0) / res
    du = (segments[:, 2] - frame.x0) / res - u0
    dv = (segments[:, 3] - frame.y0) / res - v0
    axis = (du == 0) | (dv == 0)
    cu0, cu1 = _axis_ends(u0[axis], du[axis])
    cv0, cv1 = _axis_ends(v0[axis], dv[axis])
    c0 = np.maximum(np.minimum(cu0, cu1), 0).astype(np.int64)
    c1 = np.minimum(np.maximum(cu0, cu1) + 1, frame.width).astype(np.int64)
    r0 = np.maximum(np.minimum(cv0, cv1), 0).astype(np.int64)
    r1 = np.minimum(np.maximum(cv0, cv1) + 1, frame.height).astype(np.int64)
    return axis, segments[~axis], (r0, r1, c0, c1)


def _axis_ends(p0: np.ndarray, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First and last cell along one axis, with the very float steps of :func:`supercover_cells` (its
    first and last midpoints), so a start a hair below a grid line rounds the same way."""
    f0, f1 = np.floor(p0), np.floor(p0 + d)
    n = np.abs(f1 - f0)
    sign = np.sign(d)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_first = ((f0 + np.where(sign > 0, 1, 0)) - p0) / d
        t_last = ((f0 + np.where(sign > 0, n, -(n - 1))) - p0) / d
    t_first, t_last = np.clip(t_first, 0.0, 1.0), np.clip(t_last, 0.0, 1.0)
    one = n == 0
    tm_first = np.where(one, 0.5, (t_first + 0.0) / 2)
    tm_last = np.where(one, 0.5, (1.0 + t_last) / 2)
    return np.floor(p0 + d * tm_first), np.floor(p0 + d * tm_last)


def span_rectangles(rows: np.ndarray, starts: np.ndarray, stops: np.ndarray) -> Rects:
    """Spans merged into rectangles: (row0, row1 exclusive, start, stop), one per run of equal spans
    on consecutive rows (duplicates dropped)."""
    order = np.lexsort((rows, stops, starts))
    r, s, t = rows[order], starts[order], stops[order]
    dup = np.r_[False, (r[1:] == r[:-1]) & (s[1:] == s[:-1]) & (t[1:] == t[:-1])]
    r, s, t = r[~dup], s[~dup], t[~dup]
    new = np.r_[True, (s[1:] != s[:-1]) | (t[1:] != t[:-1]) | (r[1:] != r[:-1] + 1)]
    first = np.flatnonzero(new)
    end = np.r_[first[1:], len(r)]
    return r[first], r[end - 1] + 1, s[first], t[first]


def write_spans(
    grid: np.ndarray, rows: np.ndarray, starts: np.ndarray, stops: np.ndarray, value: int, keep: tuple[int, ...] = ()
) -> None:
    """Set ``grid[row, start:stop] = value`` for every span, except cells holding a ``keep`` value.

    Spans that stack into rectangles of at least a few hundred cells are written as slices; the
    rest through flat indices a few hundred thousand cells at a time, so memory stays bounded.
    """
    if len(rows) == 0:
        return
    if not grid.flags.c_contiguous:
        raise ValueError("write_spans needs a C-contiguous grid (it writes through a flat view)")
    write_rects(grid, *span_rectangles(rows, starts, stops), value, keep)


def write_rects(
    grid: np.ndarray,
    ra: np.ndarray,
    rb: np.ndarray,
    s: np.ndarray,
    t: np.ndarray,
    value: int,
    keep: tuple[int, ...] = (),
) -> None:
    """Set ``grid[ra:rb, s:t] = value`` for every rectangle, except cells holding a ``keep`` value:
    big ones as slices, small ones through one flat scatter."""
    if not grid.flags.c_contiguous:
        raise ValueError("write_rects needs a C-contiguous grid (it writes through a flat view)")
    ok = (rb > ra) & (t > s)
    ra, rb, s, t = ra[ok], rb[ok], s[ok], t[ok]
    big = (rb - ra) * (t - s) >= _RECT_MIN_CELLS
    for a, b_, c, d in zip(ra[big].tolist(), rb[big].tolist(), s[big].tolist(), t[big].tolist(), strict=True):
        block = grid[a:b_, c:d]
        if keep:
            mask = block != keep[0]
            for k in keep[1:]:
                mask &= block != k
            np.copyto(block, value, where=mask, casting="unsafe")
        else:
            block[...] = value
    small = ~big
    if not small.any():
        return
    ra, rb, s, t = ra[small], rb[small], s[small], t[small]
    area = (rb - ra) * (t - s)
    group = (np.cumsum(area) - area) // _SCATTER_CELLS  # rectangles expanded a few hundred thousand cells at a time
    cuts = [0, *(np.flatnonzero(np.diff(group)) + 1).tolist(), len(area)]
    for lo, hi in itertools.pairwise(cuts):
        n_rows = rb[lo:hi] - ra[lo:hi]
        row = np.repeat(ra[lo:hi], n_rows) + (np.arange(n_rows.sum()) - np.repeat(np.cumsum(n_rows) - n_rows, n_rows))
        _scatter(grid, row, np.repeat(s[lo:hi], n_rows), np.repeat(t[lo:hi], n_rows), value, keep)


def _scatter(
    grid: np.ndarray, rows: np.ndarray, starts: np.ndarray, stops: np.ndarray, value: int, keep: tuple[int, ...]
) -> None:
    flat_grid = grid.reshape(-1)
    width = grid.shape[1]
    lengths = stops - starts
    group = (np.cumsum(lengths) - lengths) // _SCATTER_CELLS
    cuts = [0, *(np.flatnonzero(np.diff(group)) + 1).tolist(), len(lengths)]
    for lo, hi in itertools.pairwise(cuts):
        n = lengths[lo:hi]
        first = rows[lo:hi] * width + starts[lo:hi]
        idx = np.repeat(first, n) + (np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n))
        if keep:
            current = flat_grid[idx]
            ok = current != keep[0]
            for k in keep[1:]:
                ok &= current != k
            idx = idx[ok]
        flat_grid[idx] = value
