"""Room outlines cut where doors sit, as wall segments, in numpy where the cut is a plain rectangle.

:func:`pmk_nb.raster.walls.wall_lines` subtracts every door's cut region from every room's ring
with GEOS, one difference per room and door: on a storey of thousands of rooms that is most of the
rasteriser's time. Almost every cut is a door line buffered with flat caps - a rectangle - so here
each ring segment is clipped against those rectangles in closed form (slab test, one vectorised pass
over all (segment, rectangle) pairs) and what is left of each segment is kept. Rooms touched by any
other cut (a door cell, a door line with a bend) still go through GEOS, exactly as before.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely

from pmk_nb.raster.scanline import line_segments, segments_with_owner
from pmk_nb.raster.walls import door_jambs


def _door_rects(door_lines: list[Any], widths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per door line: is its cut a rectangle (a straight two-point line), and (px, py, ux, uy, L, w)."""
    n = len(door_lines)
    rect = np.zeros(n, dtype=bool)
    geo = np.zeros((n, 6))
    if n == 0:
        return rect, geo
    arr = np.asarray(door_lines, dtype=object)
    two = (shapely.get_num_coordinates(arr) == 2) & (shapely.get_type_id(arr) == 1)
    idx = np.flatnonzero(two)
    xy = shapely.get_coordinates(arr[idx]).reshape(len(idx), 2, 2)
    d = xy[:, 1] - xy[:, 0]
    length = np.hypot(d[:, 0], d[:, 1])
    ok = length > 0
    idx, xy, d, length = idx[ok], xy[ok], d[ok], length[ok]
    rect[idx] = True
    geo[idx] = np.column_stack([xy[:, 0], d / length[:, None], length, widths[idx]])
    return rect, geo


def _door_cuts(door_lines: list[Any], widths: np.ndarray, rect: np.ndarray, geo: np.ndarray) -> np.ndarray:
    """Each door line's cut region: the flat-capped buffer, built in closed form for straight lines
    (thousands of GEOS buffers were a tenth of a large storey's time)."""
    arr = np.asarray(door_lines, dtype=object)
    out = np.empty(len(arr), dtype=object)
    if len(arr) == 0:
        return out
    p, u, length, w = geo[rect, 0:2], geo[rect, 2:4], geo[rect, 4:5], geo[rect, 5:6]
    n = np.stack([-u[:, 1], u[:, 0]], axis=1)
    q = p + u * length
    ring = np.stack([p + n * w, q + n * w, q - n * w, p - n * w, p + n * w], axis=1)
    out[rect] = shapely.polygons(ring)
    other = ~rect
    if other.any():
        out[other] = shapely.buffer(arr[other], widths[other], cap_style="flat")
    return out


def _clip(segs: np.ndarray, geo: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(t_in, t_out) of each segment inside its rectangle (t_in >= t_out: no overlap)."""
    p0, d = segs[:, 0:2], segs[:, 2:4] - segs[:, 0:2]
    rel = p0 - geo[:, 0:2]
    u = geo[:, 2:4]
    nrm = np.stack([-u[:, 1], u[:, 0]], axis=1)
    t_in, t_out = np.zeros(len(segs)), np.ones(len(segs))
    for axis, lo, hi in ((u, np.zeros(len(segs)), geo[:, 4]), (nrm, -geo[:, 5], geo[:, 5])):
        v0 = (rel * axis).sum(axis=1)
        dv = (d * axis).sum(axis=1)
        flat = dv == 0
        with np.errstate(divide="ignore", invalid="ignore"):
            t1, t2 = (lo - v0) / dv, (hi - v0) / dv
        lo_t = np.where(flat, np.where((v0 >= lo) & (v0 <= hi), -np.inf, np.inf), np.minimum(t1, t2))
        hi_t = np.where(flat, np.where((v0 >= lo) & (v0 <= hi), np.inf, -np.inf), np.maximum(t1, t2))
        t_in, t_out = np.maximum(t_in, lo_t), np.minimum(t_out, hi_t)
    return t_in, t_out


def _remaining(segs: np.ndarray, seg_of: np.ndarray, t_in: np.ndarray, t_out: np.ndarray) -> np.ndarray:
    """The parts of ``segs`` outside the intervals [t_in, t_out] of segment ``seg_of`` (as segments)."""
    cut = t_out > t_in
    seg_of, t_in, t_out = seg_of[cut], t_in[cut], t_out[cut]
    order = np.lexsort((t_in, seg_of))
    seg_of, t_in, t_out = seg_of[order], t_in[order], t_out[order]
    # covered so far within each segment: a running max keyed by segment (t lies in [0, 1])
    covered = np.maximum.accumulate(seg_of * 4.0 + t_out) - seg_of * 4.0
    first = np.r_[True, seg_of[1:] != seg_of[:-1]]
    before = np.where(first, 0.0, np.r_[0.0, covered[:-1]])
    gap = t_in > before
    ends = np.flatnonzero(np.r_[seg_of[1:] != seg_of[:-1], len(seg_of) > 0])  # left after the last cut
    hit = np.zeros(len(segs), dtype=bool)
    hit[seg_of] = True
    untouched = np.flatnonzero(~hit)
    pieces = [
        (seg_of[gap], before[gap], t_in[gap]),
        (seg_of[ends], covered[ends], np.ones(len(ends))),
        (untouched, np.zeros(len(untouched)), np.ones(len(untouched))),
    ]
    s = np.concatenate([p[0] for p in pieces])
    a = np.concatenate([p[1] for p in pieces])
    b = np.concatenate([p[2] for p in pieces])
    keep = b > a
    s, a, b = s[keep], a[keep], b[keep]
    p0, p1 = segs[s, 0:2], segs[s, 2:4]
    d = p1 - p0
    start = np.where(a[:, None] == 0, p0, p0 + a[:, None] * d)
    stop = np.where(b[:, None] == 1, p1, p0 + b[:, None] * d)
    return np.hstack([start, stop])


def wall_segments(
    rooms: list[Any], door_polys: list[Any], door_lines: list[Any], gaps: np.ndarray, tol: float
) -> np.ndarray:
    """(S, 4) wall segments: rings of free cells minus the stretches doors occupy, plus door jambs.

    The same walls as ``line_segments(wall_lines(...))`` up to round-off in the cut points.
    """
    room_arr = np.asarray(rooms, dtype=object)
    lines = shapely.boundary(room_arr) if len(room_arr) else np.empty(0, dtype=object)
    parts: list[np.ndarray] = []
    if len(lines):
        rect, geo = _door_rects(door_lines, gaps + tol)
        cuts = np.concatenate(
            [
                shapely.buffer(np.asarray(door_polys, dtype=object), tol),
                _door_cuts(door_lines, gaps + tol, rect, geo),
            ]
        )
        is_rect = np.concatenate([np.zeros(len(door_polys), dtype=bool), rect])
        pairs = _touching(lines, cuts, is_rect)
        geo = np.concatenate([np.zeros((len(door_polys), 6)), geo])
        slow = np.zeros(len(lines), dtype=bool)
        slow[pairs[0][~is_rect[pairs[1]]]] = True
        parts.append(_slow_rooms(lines, cuts, pairs, slow))
        fast = np.flatnonzero(~slow)
        segs, owner = segments_with_owner(lines[fast].tolist())
        room_of_seg = fast[owner]
        keep = ~slow[pairs[0]]
        parts.append(_cut_fast(segs, room_of_seg, pairs[0][keep], geo[pairs[1][keep]]))
    parts.append(line_segments(door_jambs(room_arr, door_polys, tol)))
    return np.vstack(parts)


def _touching(lines: np.ndarray, cuts: np.ndarray, is_rect: np.ndarray) -> np.ndarray:
    """(2, P) pairs (room ring, cut) that may meet: boxes only for rectangles (the clip that follows is
    exact, and GEOS's ring-polygon predicate was a tenth of a large storey's time), exact otherwise."""
    if len(cuts) == 0:
        return np.zeros((2, 0), dtype=np.int64)
    pairs = shapely.STRtree(cuts).query(lines)
    other = ~is_rect[pairs[1]]
    if other.any():
        meets = np.ones(pairs.shape[1], dtype=bool)
        meets[other] = shapely.intersects(lines[pairs[0][other]], cuts[pairs[1][other]])
        pairs = pairs[:, meets]
    return pairs


def _cut_fast(segs: np.ndarray, room_of_seg: np.ndarray, pair_room: np.ndarray, pair_geo: np.ndarray) -> np.ndarray:
    """Every segment of a room clipped against every rectangle cut of that room."""
    if len(segs) == 0:
        return segs
    order = np.argsort(room_of_seg, kind="stable")
    segs, room_of_seg = segs[order], room_of_seg[order]
    first = np.searchsorted(room_of_seg, pair_room, side="left")
    count = np.searchsorted(room_of_seg, pair_room, side="right") - first
    seg_idx = np.repeat(first, count) + (np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count))
    geo = np.repeat(pair_geo, count, axis=0)
    t_in, t_out = _clip(segs[seg_idx], geo)
    return _remaining(segs, seg_idx, t_in, t_out)


def _slow_rooms(lines: np.ndarray, cuts: np.ndarray, pairs: np.ndarray, slow: np.ndarray) -> np.ndarray:
    """Rooms with a cut that is not a rectangle: GEOS differences, one round per nearby cut."""
    idx = np.flatnonzero(slow)
    if len(idx) == 0:
        return np.empty((0, 4))
    sel = slow[pairs[0]]
    left, right = pairs[0][sel], pairs[1][sel]
    order = np.argsort(left, kind="stable")
    rooms_hit, starts = np.unique(left[order], return_index=True)
    groups = np.split(right[order], starts[1:])
    out = lines[rooms_hit].copy()
    sizes = np.array([len(g) for g in groups], dtype=np.int64)
    for k in range(int(sizes.max(initial=0))):
        has = sizes > k
        cut_k = np.array([g[k] for g, h in zip(groups, has.tolist(), strict=True) if h], dtype=np.int64)
        out[has] = shapely.difference(out[has], cuts[cut_k])
    return line_segments([g for g in out.tolist() if g is not None and not g.is_empty])
