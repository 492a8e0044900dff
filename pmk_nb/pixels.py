"""Pixel tools, in numpy alone: erode by a disc, label connected regions (the accessibility check, the guide
and the witness use them; a leaf, so the witness shares no decision of the converter by using them).

The erosion is the chair's configuration space, as Nav2's inflation sees it: the free pixels whose
distance to the nearest pixel that is not free (occupied or unknown; outside the grid counts as not
free) is more than the chair's half-width, pixel centre to pixel centre, i.e. whose closed disc of
that radius holds only free pixels. It is exact (the same pixels as
``scipy.ndimage.distance_transform_edt(free) > r``): a chair of width w needs
2 * floor(w / 2 / res) + 1 free pixels across (15 for 0.70 m at 0.05 m). It runs on row strips packed
64 pixels to a word, with runs of free pixels per row doubled level by level (ANDs and shifts only),
many times faster than scipy's distance transform on the same strips and without its float64 and int32
arrays.
Labelling works on runs of pixels per row, joined across rows with a vectorised union-find, so a
storey of a few million pixels labels in well under a second, and it can keep regions of different
owners apart and say which touch, which scipy's labelling cannot.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator

import numpy as np

STRIP_MIN_CELLS = 1 << 16
STRIP_MAX_CELLS = 1 << 20


def disc_radius_px(radius_m: float, resolution: float) -> float:
    """The disc used for a chair of ``radius_m`` on a grid of ``resolution`` (pixels, may be 0): a pixel at
    exactly this distance blocks the chair (Nav2 calls it inscribed), so the disc is closed."""
    return max(0.0, radius_m / resolution + 1e-9)  # 0.35 / 0.05 is 6.999...


def erode(mask: np.ndarray, radius_px: float) -> np.ndarray:
    """Pixels of ``mask`` whose whole closed disc of ``radius_px`` lies in ``mask`` (outside the array = not
    free): where the distance transform of ``mask`` exceeds ``radius_px``."""
    if radius_px < 1.0:
        return mask.copy()
    h, w = mask.shape
    out = np.empty((h, w), dtype=bool)
    for a, strip in erode_rows(lambda lo, hi: mask[lo:hi], h, w, radius_px):
        out[a : a + len(strip)] = strip
    return out


def strip_rows(width: int, height: int) -> int:
    """Rows per strip: about 1/16 of the grid, between 64 Ki and 1 Mi cells, so a strip's working
    arrays stay a fraction of the grid on small maps and a few MB on large ones, while the chair's
    radius of rows padded on each side of a strip (27 at 0.0128 m) stays a small share of its rows
    (512 Ki-cell strips did twice the erosion's work on a 100 M-cell storey)."""
    cells = min(STRIP_MAX_CELLS, max(STRIP_MIN_CELLS, width * height // 16))
    return max(16, cells // max(1, width))


def erode_rows(
    mask_rows: Callable[[int, int], np.ndarray], h: int, w: int, radius_px: float, step: int | None = None
) -> Iterator[tuple[int, np.ndarray]]:
    """:func:`erode` of the (h, w) mask whose rows ``lo:hi`` ``mask_rows(lo, hi)`` gives, strip by strip:
    yields (first row, eroded rows), so the whole eroded mask is never held (nor its int32 sums)."""
    step = step or strip_rows(w, h)
    if radius_px < 1.0:
        for a in range(0, h, step):
            yield a, np.array(mask_rows(a, min(h, a + step)), dtype=bool)
        return
    r = math.floor(radius_px)
    for a in range(0, h, step):
        b = min(h, a + step)
        lo, hi = max(0, a - r), min(h, b + r)
        padded = np.zeros((b - a + 2 * r, w + 2 * r), dtype=bool)
        padded[lo - a + r : hi - a + r, r : r + w] = mask_rows(lo, hi)
        yield a, _erode_padded(padded, radius_px, r, b - a, w)


def _erode_padded(padded: np.ndarray, radius_px: float, r: int, n: int, w: int) -> np.ndarray:
    """The ``n`` middle rows of ``padded`` (r rows and columns of margin) eroded by the disc."""
    # the strip is packed 64 pixels to a word (bit x of a row = column x), so each AND below is on an
    # eighth of the bytes a bool array takes (the erosion was 0.9 s of CPU a 100 M-cell storey, twice)
    rows, p = padded.shape
    words = (p + 63) // 64
    packed = np.zeros((rows, words * 8), dtype=np.uint8)
    packed[:, : (p + 7) // 8] = np.packbits(padded, axis=1, bitorder="little")
    # runs[k]: bit x is set when the 2**k padded columns from x on are all free (doubling: one AND per
    # level), so any window of L columns is two overlapping runs of the largest 2**k <= L
    runs = [packed.view("<u8")]
    while 2 ** len(runs) <= 2 * r + 1:
        prev, step = runs[-1], 2 ** (len(runs) - 1)
        runs.append(prev & shift_bits(prev, step))
    out = np.full((n, words), np.uint64(0xFFFFFFFFFFFFFFFF), dtype="<u8")
    clear = out
    last = -1
    for dy in range(r + 1):
        half = math.floor(math.sqrt(max(radius_px * radius_px - dy * dy, 0.0)))
        # rows whose columns [x - half, x + half] are all free (padded column x + r, bit x), once for
        # rows +-dy and once for every dy of the same half (17 windows, not 28, at 0.0128 m)
        if half != last:
            size = 2 * half + 1
            k = size.bit_length() - 1
            lo, hi = r - half, r - half + size - 2**k
            clear = shift_bits(runs[k], lo)
            if hi != lo:
                clear &= shift_bits(runs[k], hi)
            last = half
        out &= clear[r + dy : r + dy + n]
        if dy:
            out &= clear[r - dy : r - dy + n]
    return np.unpackbits(out.view(np.uint8), axis=1, count=w, bitorder="little").view(bool)


def shift_bits(words: np.ndarray, k: int) -> np.ndarray:
    """Rows of pixels packed in little-endian 64-bit words (bit x = column x), moved ``k`` >= 0 columns
    to the left: bit x of the result is bit x + k of ``words``, zeros coming in at the end."""
    count = words.shape[1]
    q, s = divmod(k, 64)
    out = np.empty_like(words)
    if q >= count:
        out[:] = 0
        return out
    src = words[:, q:]
    if s == 0:
        out[:, : count - q] = src
    else:
        np.right_shift(src, np.uint64(s), out=out[:, : count - q])
        out[:, : count - q - 1] |= src[:, 1:] << np.uint64(64 - s)
    out[:, count - q :] = 0
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
    sr, sc, ec, run_owner = strip_runs(0, mask, own)
    parent, label_owner, edges = _join_runs(sr, sc, ec, run_owner, w)
    lengths = ec - sc
    rows = np.repeat(sr, lengths)
    cols = np.repeat(sc, lengths) + (np.arange(lengths.sum()) - np.repeat(np.cumsum(lengths) - lengths, lengths))
    labels[rows, cols] = np.repeat((parent + 1).astype(np.int32), lengths)
    return labels, label_owner, edges


def least_roots(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Root of each of ``n`` items joined by the pairs (a, b): the least item of its component.

    Chains first: a pair a < b where a has no other pair to a later item and b none from an earlier one
    (a room's runs, row after row) joins b to a's chain, whose least item is its first; chains are
    followed by pointer jumping, and only the other pairs, between chain heads, go through the
    min-label propagation (a 100 M-cell storey's million pairs took ten rounds of it, 0.15 s a graph)."""
    if len(a) == 0:
        return np.arange(n, dtype=np.int64)
    down = a < b
    later = np.bincount(a[down], minlength=n)  # pairs from each item to a later one
    earlier = np.bincount(b[down], minlength=n)  # pairs to each item from an earlier one
    chain = down & (later[a] == 1) & (earlier[b] == 1)
    del down, later, earlier  # the storey's runs are held meanwhile
    head = np.arange(n, dtype=np.int64)
    head[b[chain]] = a[chain]  # each b once: it has one pair from an earlier item
    while True:
        nxt = head[head]
        if np.array_equal(nxt, head):
            break
        head = nxt
    rest = ~chain
    root = _propagate(n, head[a[rest]], head[b[rest]])
    return root[head]


def _propagate(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The least item of each component of ``n`` items joined by (a, b): min-label propagation, pointer
    jumping."""
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


def strip_runs(row0: int, mask: np.ndarray, own: np.ndarray, same: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """Runs of ``mask`` that keep one owner, per row: (row, first column, column after, owner).

    Works on the strip as it is (bool masks of its size, the owners in their own narrow type).
    ``same``: :func:`same_owner` of ``own``, when the caller runs several masks over the same owners."""
    w = mask.shape[1]
    go_on = mask[:, 1:] & mask[:, :-1]  # the run goes on from column c to c + 1 ...
    go_on &= same_owner(own) if same is None else same  # ... when both are in the mask and share an owner
    stop = np.logical_not(go_on, out=go_on)
    start = mask.copy()
    start[:, 1:] &= stop
    end = mask.copy()
    end[:, :-1] &= stop
    first = np.flatnonzero(start)
    last = np.flatnonzero(end)
    sr, sc = np.divmod(first, w)
    return (
        (sr + row0).astype(np.int64),
        sc.astype(np.int64),
        (last % w + 1).astype(np.int64),
        own.reshape(-1)[first].astype(np.int32),
    )


def same_owner(own: np.ndarray) -> np.ndarray:
    """(h, w - 1) bools: pixel c of a row has the owner of pixel c + 1."""
    return np.asarray(own[:, 1:] == own[:, :-1])


def run_regions(
    strips: Iterable[tuple[int, np.ndarray, np.ndarray]], w: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`regions` from row strips (first row, mask rows, owner rows), holding only the runs.

    Returns (the labels that exist, owner of each label (index = label), edges), the same labels,
    owners and edges :func:`regions` gives, without its full-size label array.
    """
    return join_strip_runs([strip_runs(a, m, o) for a, m, o in strips], w)


def join_strip_runs(parts: list[tuple[np.ndarray, ...]], w: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`run_regions` from the :func:`strip_runs` of every strip, in row order."""
    sr, sc, ec, run_owner = (np.concatenate(x) for x in zip(*parts, strict=True))
    if len(sr) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(1, dtype=np.int32), np.zeros((0, 2), dtype=np.int64)
    parent, label_owner, edges = _join_runs(sr, sc, ec, run_owner, w)
    return sorted_unique(parent + 1), label_owner, edges


def strip_run_labels(parts: list[tuple[np.ndarray, ...]], w: int) -> tuple[np.ndarray, ...]:
    """:func:`join_strip_runs`, keeping the runs: (row, first column, column after, label of each run,
    owner of each label (index = label), edges), so a caller can measure each region (its extent)
    without a full-size label array."""
    sr, sc, ec, run_owner = (np.concatenate(x) for x in zip(*parts, strict=True))
    if len(sr) == 0:
        empty = np.zeros(0, dtype=np.int64)
        return empty, empty, empty, empty, np.zeros(1, dtype=np.int32), np.zeros((0, 2), dtype=np.int64)
    parent, label_owner, edges = _join_runs(sr, sc, ec, run_owner, w)
    return sr, sc, ec, parent + 1, label_owner, edges


def _join_runs(
    sr: np.ndarray, sc: np.ndarray, ec: np.ndarray, run_owner: np.ndarray, w: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(root run of each run, owner of each label = root + 1, label pairs of different owners that
    touch): runs on consecutive rows that overlap in columns touch, found for all runs at once by
    sorted keys; runs end to end on one row touch too."""
    n = len(sr)
    stride = w + 2
    # temporaries dropped as soon as used: a 100 M-cell storey has about a million runs, 8 MB an array
    base = sr.astype(np.int64) * stride
    nxt = base + stride
    lo = np.searchsorted(base + ec, nxt + sc, side="right")
    hi = np.searchsorted(base + sc, nxt + ec, side="left")
    del base, nxt
    counts = np.maximum(hi - lo, 0)
    del hi
    ii = np.repeat(np.arange(n), counts)
    jj = np.repeat(lo, counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts))
    del lo, counts
    same = run_owner[ii] == run_owner[jj]
    parent = least_roots(n, ii[same], jj[same])
    run_label = parent + 1
    label_owner = np.zeros(n + 1, dtype=np.int32)
    label_owner[run_label] = run_owner
    side = (ec[:-1] == sc[1:]) & (sr[:-1] == sr[1:])
    pairs = np.concatenate(
        [
            np.stack([run_label[ii[~same]], run_label[jj[~same]]], axis=1),
            np.stack([run_label[:-1][side], run_label[1:][side]], axis=1),
        ]
    ).astype(np.int64)
    if not len(pairs):
        return parent, label_owner, pairs
    key = sorted_unique(pairs[:, 0] * (n + 2) + pairs[:, 1])  # labels are 1..n: one key per pair, same order
    return parent, label_owner, np.stack([key // (n + 2), key % (n + 2)], axis=1)


def sorted_unique(values: np.ndarray) -> np.ndarray:
    """``np.unique`` of a 1-D integer array by sorting: the same result, without numpy's hash path, which
    imports ``numpy.ma`` (about 0.05 s of a small plan's 0.5 s convert)."""
    out = np.sort(values, axis=None)
    if len(out) > 1:
        out = out[np.concatenate(([True], out[1:] != out[:-1]))]
    return out
