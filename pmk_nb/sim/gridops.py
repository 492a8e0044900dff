"""Whole-array grid operations (no per-cell Python loops): disk dilation and wavefront distances.

These replace scipy.ndimage for the two things the simulator needs: inflating obstacles by the
chair's footprint and computing a cost-to-go field for planning / clearance. Both cost a handful of
NumPy passes over the grid.
"""

from __future__ import annotations

import math

import numpy as np

_SQRT2 = math.sqrt(2.0)
# (drow, dcol, cost) of the 8-neighbourhood
NEIGHBOURS: tuple[tuple[int, int, float], ...] = (
    (-1, 0, 1.0),
    (1, 0, 1.0),
    (0, -1, 1.0),
    (0, 1, 1.0),
    (-1, -1, _SQRT2),
    (-1, 1, _SQRT2),
    (1, -1, _SQRT2),
    (1, 1, _SQRT2),
)


def dilate_disk(mask: np.ndarray, radius_cells: float) -> np.ndarray:
    """Cells within ``radius_cells`` (Euclidean, centre to centre) of a True cell.

    Horizontal sliding-window ORs done with prefix sums (plain slices, no fancy indexing), one per
    distinct half-width of the disk, each then ORed in at every disk row with that half-width: the
    cost is O(rows_of_disk * H * W) whatever the radius, in whole-array NumPy passes that release
    the GIL (the simulator runs this in a worker thread while its loop keeps publishing).
    """
    mask = np.asarray(mask, dtype=bool)
    r = math.floor(radius_cells)
    if r <= 0:
        return mask.copy()
    h, w = mask.shape
    csum = np.zeros((h, w + 2 * r + 1), dtype=np.int32)
    np.cumsum(mask, axis=1, out=csum[:, r + 1 : r + 1 + w])
    csum[:, r + 1 + w :] = csum[:, r + w : r + w + 1]
    halves: dict[int, list[int]] = {}
    for dy in range(-r, r + 1):
        halves.setdefault(math.floor(math.sqrt(max(radius_cells * radius_cells - dy * dy, 0.0))), []).append(dy)
    out = np.zeros((h + 2 * r, w), dtype=bool)  # padded rows so every shift is a plain slice
    for half, dys in halves.items():
        row_or = csum[:, r + half + 1 : r + half + 1 + w] > csum[:, r - half : r - half + w]
        for dy in dys:  # out[y] |= row_or[y + dy]
            out[r - dy : r - dy + h] |= row_or
    return out[r : r + h]


def shift(arr: np.ndarray, drow: int, dcol: int, fill: float) -> np.ndarray:
    """``out[r, c] = arr[r + drow, c + dcol]`` with ``fill`` outside."""
    h, w = arr.shape
    out = np.full_like(arr, fill)
    rs, re = max(0, -drow), min(h, h - drow)
    cs, ce = max(0, -dcol), min(w, w - dcol)
    out[rs:re, cs:ce] = arr[rs + drow : re + drow, cs + dcol : ce + dcol]
    return out


def wavefront(
    free: np.ndarray, sources: np.ndarray, max_iter: int | None = None, weight: np.ndarray | None = None
) -> np.ndarray:
    """8-connected path cost from any source cell to every cell, inf where unreachable.

    A step costs 1 (or sqrt 2 diagonally) times ``weight`` of the cell it enters (default 1).
    Bellman-Ford style relaxation over the whole array at once; converges after about as many
    passes as the longest shortest path has cells.
    """
    dist = np.where(sources & free, 0.0, np.inf)
    w = np.ones(free.shape) if weight is None else weight
    limit = max_iter if max_iter is not None else 4 * sum(free.shape)
    for _ in range(limit):
        best = dist.copy()
        for drow, dcol, cost in NEIGHBOURS:
            np.minimum(best, shift(dist, drow, dcol, np.inf) + cost * w, out=best)
        best[~free] = np.inf
        if not (best < dist).any():
            break
        dist = best
    return dist


def descend(dist: np.ndarray, start: tuple[int, int]) -> list[tuple[int, int]]:
    """Follow ``dist`` downhill from ``start`` (row, col) to a zero cell; [] if unreachable."""
    h, w = dist.shape
    r, c = start
    if not np.isfinite(dist[r, c]):
        return []
    path = [(r, c)]
    for _ in range(h * w):
        if dist[r, c] == 0.0:
            break
        best, nxt = dist[r, c], None
        for drow, dcol, _ in NEIGHBOURS:  # steepest descent: the cost field strictly decreases
            rr, cc = r + drow, c + dcol
            if 0 <= rr < h and 0 <= cc < w and dist[rr, cc] < best:
                best, nxt = dist[rr, cc], (rr, cc)
        if nxt is None:
            return []
        r, c = nxt
        path.append(nxt)
    return path


def erosion_depth(free: np.ndarray, cap: int) -> np.ndarray:
    """How many 4-neighbour erosions each free cell survives (Manhattan clearance, capped at ``cap``).

    Boolean array passes only, so it is cheap enough to run at full map resolution.
    """
    depth = np.zeros(free.shape, dtype=np.int16)
    cur = free.copy()
    for _ in range(cap):
        depth += cur
        nxt = cur.copy()
        nxt[1:, :] &= cur[:-1, :]
        nxt[:-1, :] &= cur[1:, :]
        nxt[:, 1:] &= cur[:, :-1]
        nxt[:, :-1] &= cur[:, 1:]
        if not nxt.any():
            break
        cur = nxt
    return depth


def clearance(free: np.ndarray) -> np.ndarray:
    """Approximate distance (cells) from each free cell to the nearest non-free cell or the border."""
    blocked = ~free
    border = np.zeros_like(free)
    border[0, :] = border[-1, :] = border[:, 0] = border[:, -1] = True
    everywhere = np.ones_like(free)
    return wavefront(everywhere, blocked | border)
