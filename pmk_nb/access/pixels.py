"""Pixel tools for the accessibility check, in numpy alone: erode by a disc, label connected regions.

The erosion is where a chair's centre may be: a free pixel whose every pixel centre within the
chair's radius less half a cell is free: a chair of width w needs 2 * floor(w / 2 / res - 0.5) + 1
free pixels across (13 for 0.70 m at 0.05 m), so a door as wide as the chair passes even when the
rasteriser rounds a cell off its jambs, and one a tenth of a metre narrower does not.
Labelling works on runs of pixels per row, joined across rows with a vectorised union-find, so a
storey of a few million pixels labels in well under a second without scipy.
"""

from __future__ import annotations

import math

import numpy as np


def disc_radius_px(radius_m: float, resolution: float) -> float:
    """The disc used for a chair of ``radius_m`` on a grid of ``resolution`` (pixels, may be 0)."""
    return max(0.0, radius_m / resolution - 0.5 + 1e-9)  # 0.35 / 0.05 is 6.999...


def erode(mask: np.ndarray, radius_px: float) -> np.ndarray:
    """Pixels of ``mask`` whose whole disc of ``radius_px`` lies in ``mask`` (outside the array = not free)."""
    if radius_px < 1.0:
        return mask.copy()
    r = math.floor(radius_px)
    h, w = mask.shape
    padded = np.zeros((h + 2 * r, w + 2 * r), dtype=bool)
    padded[r : r + h, r : r + w] = mask
    blocked = np.cumsum(~padded, axis=1, dtype=np.int32)
    blocked = np.pad(blocked, ((0, 0), (1, 0)))
    out = np.ones((h, w), dtype=bool)
    for dy in range(-r, r + 1):
        half = math.floor(math.sqrt(max(radius_px * radius_px - dy * dy, 0.0)))
        rows = blocked[r + dy : r + dy + h]
        # blocked pixels in columns [x - half, x + half] of row y + dy (padded column x + r)
        out &= (rows[:, r + half + 1 : r + half + 1 + w] - rows[:, r - half : r - half + w]) == 0
    return out


def label(mask: np.ndarray, owner: np.ndarray | None = None) -> np.ndarray:
    """4-connected regions of ``mask``: an int32 array, 0 outside, 1..n inside (labels not compact)."""
    return regions(mask, owner)[0]


def regions(mask: np.ndarray, owner: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Regions of ``mask`` that never cross a change of ``owner``, and how they touch.

    Returns (labels, owner of each label (index = label), edges): ``edges`` is a (k, 2) array of label
    pairs of different owners that share a pixel edge. With no ``owner`` this is plain labelling.
    """
    h, w = mask.shape
    labels = np.zeros((h, w), dtype=np.int32)
    own = np.zeros((h, w), dtype=np.int32) if owner is None else owner.astype(np.int32, copy=False)
    if not mask.any():
        return labels, np.zeros(1, dtype=np.int32), np.zeros((0, 2), dtype=np.int64)
    m = np.pad(mask, ((0, 0), (1, 1)))
    o = np.pad(own, ((0, 0), (1, 1)), constant_values=-1)
    inner = m[:, 1:] & m[:, :-1] & (o[:, 1:] == o[:, :-1])  # pixel pairs in one run
    inside = m[:, 1 : w + 1]  # inner[:, k] joins padded pixels k and k + 1 (original k - 1 and k)
    sr, sc = np.nonzero(inside & ~inner[:, 0:w])  # run starts: (row, first column)
    _, ec = np.nonzero(inside & ~inner[:, 1 : w + 1])
    ec = ec + 1  # column after the last
    n = len(sr)
    run_owner = own[sr, sc]
    # runs on consecutive rows that overlap in columns touch: for run i on row y, the runs j on row
    # y + 1 with start_j < end_i and end_j > start_i, found for all runs at once by sorted keys
    stride = w + 2
    row = sr.astype(np.int64)
    key_start, key_end, nxt = row * stride + sc, row * stride + ec, (row + 1) * stride
    lo = np.searchsorted(key_end, nxt + sc, side="right")
    hi = np.searchsorted(key_start, nxt + ec, side="left")
    counts = np.maximum(hi - lo, 0)
    ii = np.repeat(np.arange(n), counts)
    jj = np.repeat(lo, counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))
    same = run_owner[ii] == run_owner[jj]
    parent = _union(n, ii[same], jj[same])
    run_label = (parent + 1).astype(np.int32)
    lengths = ec - sc
    rows = np.repeat(sr, lengths)
    cols = np.repeat(sc, lengths) + (np.arange(lengths.sum()) - np.repeat(np.cumsum(lengths) - lengths, lengths))
    labels[rows, cols] = np.repeat(run_label, lengths)
    label_owner = np.zeros(n + 1, dtype=np.int32)
    label_owner[run_label] = run_owner
    # touching runs of different owners: across rows (above) and along a row (end of one = start of next)
    side = (ec[:-1] == sc[1:]) & (sr[:-1] == sr[1:])
    pairs = np.concatenate([
        np.stack([run_label[ii[~same]], run_label[jj[~same]]], axis=1),
        np.stack([run_label[:-1][side], run_label[1:][side]], axis=1),
    ]).astype(np.int64)  # fmt: skip
    return labels, label_owner, np.unique(pairs, axis=0) if len(pairs) else pairs


def _union(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Root of each of ``n`` items joined by the pairs (a, b): min-label propagation, pointer jumping."""
    parent = np.arange(n, dtype=np.int64)
    if len(a) == 0:
        return parent
    while True:
        pa, pb = parent[a], parent[b]
        low = np.minimum(pa, pb)
        if not ((pa != low) | (pb != low)).any():
            break
        np.minimum.at(parent, pa, low)
        np.minimum.at(parent, pb, low)
        parent = parent[parent]
    while True:
        nxt = parent[parent]
        if np.array_equal(nxt, parent):
            return parent
        parent = nxt
