"""A storey's free space labelled once, split by the cell each pixel lies in: a graph of regions.

Judging each pair of cells in its own window labelled the same pixels thousands of times (44 s of the
witness of a 100 M-cell storey). Here each pixel is labelled once per question, strip by strip and by
runs (no full-size label array): once for the free pixels, once for where the chair's centre may stand.
Regions never cross from one cell to another (a pixel's owner is the cell it lies in, its core when it
is well inside, or none), so the graph of regions that touch tells, for two cells, which ways the map
leaves between them. The graph decides only what it can prove, in the direction it can prove it:

* no way between two cells' cores through their own regions and regions outside every cell: no leak
  (the per-pair check of :mod:`.storey` looks at a subset of those pixels, so it finds no way either);
* a way through their own regions and regions outside every cell that lie wholly in the walls between
  them, farther than the per-pair check's margin from every other cell: connected (all those pixels
  are in the per-pair check's region).

Everything else, and any cell that shares pixels with another, goes to the per-pair check.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import shapely

from pmk_nb.grid import FREE
from pmk_nb.pixels import erode_rows, same_owner, sorted_unique, strip_rows, strip_run_labels, strip_runs
from pmk_nb.witness.frame import MapFrame, Outline, Window, outline

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Cell

#: pixels per strip at least: a strip is padded by the chair's radius of rows for the erosion (27 at
#: 0.0128 m) and each cell crossing a strip is drawn once more, but a strip's working arrays (its
#: owners, four bytes a pixel; the erosion's levels) add to the peak: 1 Mi pixels keeps a 100 M-cell
#: convert under three times its grid and file
STRIP_CELLS = 1 << 20
#: a region outside every cell may join two cells when this returns True for its label
Gate = Callable[[int], bool]


@dataclass
class RegionGraph:
    """Regions (compact labels 0..n-1) of one mask: each one's owner code, its extent, who touches whom."""

    owner: list[int]
    box: np.ndarray  # (n, 4) int: first row, last row, first column, last column of each region
    neighbours: list[list[int]]
    by_owner: dict[int, list[int]] = field(default_factory=dict)

    @classmethod
    def of(cls, parts: list[tuple[np.ndarray, ...]], width: int) -> RegionGraph:
        sr, sc, ec, run_label, label_owner, edges = strip_run_labels(parts, width)
        labels = sorted_unique(run_label)
        n = len(labels)
        box = _extents(np.searchsorted(labels, run_label), sr, sc, ec, n)
        owner = label_owner[labels].tolist()
        neighbours: list[list[int]] = [[] for _ in range(n)]
        if len(edges):
            a, b = np.searchsorted(labels, edges[:, 0]), np.searchsorted(labels, edges[:, 1])
            for x, y in zip(a.tolist(), b.tolist(), strict=True):
                neighbours[x].append(y)
                neighbours[y].append(x)
        by_owner: dict[int, list[int]] = {}
        for lab, code in enumerate(owner):
            by_owner.setdefault(code, []).append(lab)
        return cls(owner, box, neighbours, by_owner)

    def joins(self, starts: Iterable[int], ends: set[int], through: set[int], gate: Gate | None) -> bool:
        """Whether a region owned by a code in ``starts`` reaches one owned by a code in ``ends``, going
        through regions owned by codes in ``through`` (and ``ends``), and regions outside every cell
        (owner 0) that ``gate`` lets through (all of them when ``gate`` is None)."""
        frontier = [lab for code in starts for lab in self.by_owner.get(code, [])]
        seen = set(frontier)
        allowed = through | ends
        verdicts: dict[int, bool] = {}
        while frontier:
            lab = frontier.pop()
            if self.owner[lab] in ends:
                return True
            for nb in self.neighbours[lab]:
                if nb in seen:
                    continue
                code = self.owner[nb]
                if code == 0:
                    if gate is not None:
                        if nb not in verdicts:
                            verdicts[nb] = gate(nb)
                        if not verdicts[nb]:
                            continue
                elif code not in allowed:
                    continue
                seen.add(nb)
                frontier.append(nb)
        return False


def _extents(compact: np.ndarray, sr: np.ndarray, sc: np.ndarray, ec: np.ndarray, n: int) -> np.ndarray:
    """(n, 4): first row, last row, first column, last column of each region 0..n-1 (every one has runs),
    from its runs (``sr`` in row order): the runs sorted by region once and reduced per region, where four
    ``np.minimum.at`` / ``np.maximum.at`` calls took 0.35 s for a 100 M-cell storey's million runs."""
    box = np.empty((n, 4), dtype=np.int64)
    if n == 0:
        return box
    order = np.argsort(compact, kind="stable")  # rows stay in order within a region
    keys = compact[order]
    first = np.concatenate(([0], np.flatnonzero(keys[1:] != keys[:-1]) + 1))
    del keys  # a storey's runs are held meanwhile: only one run-sized array beside them at a time
    last = np.append(first[1:], len(order)) - 1
    box[:, 0], box[:, 1] = sr[order[first]], sr[order[last]]
    box[:, 2] = np.minimum.reduceat(sc[order], first)
    box[:, 3] = np.maximum.reduceat(ec[order], first) - 1
    return box


@dataclass
class StoreyRegions:
    """The two graphs of a storey and what the owner codes mean."""

    free: RegionGraph  # the free pixels
    chair: RegionGraph  # where the chair's centre may stand
    index: dict[str, int]  # cell id -> its code (1..n); its core's code is n + code
    cored: set[str]  # cells whose core has pixels (the others' core is the whole cell)
    shared: set[str]  # cells with pixels that another cell claims too: the graph cannot speak for them

    def codes(self, cell_id: str) -> set[int]:
        """Every code of a cell's pixels."""
        code = self.index[cell_id]
        return {code, code + len(self.index)}

    @property
    def both(self) -> int:
        """The code of pixels two cells claim (overlapping cells): in neither cell's regions."""
        return 2 * len(self.index) + 1

    def core(self, cell_id: str) -> int:
        """The code of a cell's core (its whole self when no core pixel was drawn)."""
        code = self.index[cell_id]
        return code + len(self.index) if cell_id in self.cored else code


def storey_regions(
    frame: MapFrame,
    data: np.ndarray,
    cells: dict[str, Cell],
    order: list[str],
    tree: shapely.STRtree,
    cores: Mapping[str, BaseGeometry | None],
    radius_px: float,
) -> StoreyRegions:
    """Label the storey's free pixels and the chair's room, strip by strip, each pixel owned by its cell.

    ``cores``: each cell's core (None for a cell that has none, a doorway: its core is itself)."""
    h, w = data.shape
    index = {cid: i + 1 for i, cid in enumerate(order)}
    n = len(order)
    painted = np.zeros(n + 1, dtype=np.int64)
    shared: set[str] = set()
    free_parts, chair_parts = [], []
    step = max(strip_rows(w, h), STRIP_CELLS // max(1, w))
    outlines: dict[object, Outline] = {cid: outline(cells[cid].footprint) for cid in order}
    outlines |= {(cid, "core"): outline(core) for cid, core in cores.items() if core is not None and not core.is_empty}
    rects = {key: frame.rectangle(shape) for key, shape in outlines.items()}
    for a, chair in erode_rows(lambda lo, hi: data[lo:hi] == FREE, h, w, radius_px, step):
        b = a + len(chair)
        own = _owners(frame, Window(a, b, 0, w), cells, order, tree, cores, painted, shared, outlines, rects)
        same = same_owner(own)  # one comparison of the four-byte owners for both masks
        free_parts.append(_narrow(strip_runs(a, data[a:b] == FREE, own, same)))
        chair_parts.append(_narrow(strip_runs(a, chair, own, same)))
    cored = {cid for cid in order if painted[index[cid]]}
    return StoreyRegions(RegionGraph.of(free_parts, w), RegionGraph.of(chair_parts, w), index, cored, shared)


def _narrow(runs: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """A strip's runs kept in four bytes a number (rows and columns of a grid under 2**31 cells a side):
    a 100 M-cell storey holds about a million runs until they are joined."""
    return tuple(np.asarray(x, dtype=np.int32) for x in runs)


def _owners(
    frame: MapFrame,
    strip: Window,
    cells: dict[str, Cell],
    order: list[str],
    tree: shapely.STRtree,
    cores: Mapping[str, BaseGeometry | None],
    painted: np.ndarray,
    shared: set[str],
    outlines: dict[object, Outline],
    rects: dict[object, Window | None],
) -> np.ndarray:
    """The owner code of each pixel of ``strip``: 0 outside every cell, i for the i-th cell, n + i in its
    core, 2n + 1 where two cells claim it; ``painted`` counts core pixels per cell, ``shared`` gains the
    cells that claim a pixel with another. ``rects``: the shapes that are upright rectangles, as the
    windows their masks set (:meth:`MapFrame.rectangle`), written as slices."""
    n = len(order)
    own = np.zeros(strip.shape, dtype=np.int32)
    r = frame.resolution
    box = shapely.box(frame.x0, frame.y0 + strip.r0 * r, frame.x0 + frame.width * r, frame.y0 + strip.r1 * r)
    for i in sorted(tree.query(box).tolist()):
        cid = order[i]
        foot = outlines[cid]
        rect = rects.get(cid)
        if rect is not None:  # an upright rectangle (most cells): its pixels are a slice, no mask drawn
            win = _clip(rect, strip)
            if win.empty:
                continue
            sub = own[win.r0 - strip.r0 : win.r1 - strip.r0, win.c0 : win.c1]
            both = sub != 0
            mask = None
        else:
            win = _clip(frame.window(foot[1], 1), strip)
            if win.empty:
                continue
            mask = frame.mask(win, cells[cid].footprint, foot)
            sub = own[win.r0 - strip.r0 : win.r1 - strip.r0, win.c0 : win.c1]
            both = mask & (sub != 0)
        if both.any():  # pixels two cells claim: owned by neither, but by the code of shared pixels
            claimed = sorted_unique(sub[both])
            shared.add(cid)
            shared.update(order[(int(c) - 1) % n] for c in claimed if c != 2 * n + 1)
            np.copyto(sub, i + 1, where=~both if mask is None else mask & ~both)
            sub[both] = 2 * n + 1
        elif mask is None:
            sub[...] = i + 1
        else:
            np.copyto(sub, i + 1, where=mask)
        core = cores.get(cid)
        if core is None or core.is_empty:
            continue
        inner = outlines[(cid, "core")]
        crect = rects.get((cid, "core"))
        cwin = _clip(frame.window(inner[1], 1) if crect is None else crect, strip)
        if cwin.empty:
            continue
        cpart = own[cwin.r0 - strip.r0 : cwin.r1 - strip.r0, cwin.c0 : cwin.c1]
        cmask = cpart == i + 1  # not where another cell claims it too
        if crect is None:
            cmask &= frame.mask(cwin, core, inner)
        np.copyto(cpart, n + i + 1, where=cmask)
        painted[i + 1] += int(np.count_nonzero(cmask))
    return own


def _clip(win: Window, strip: Window) -> Window:
    return Window(max(win.r0, strip.r0), min(win.r1, strip.r1), max(win.c0, strip.c0), min(win.c1, strip.c1))


def region_gate(
    frame: MapFrame,
    graph: RegionGraph,
    bands: list[BaseGeometry],
    tree: shapely.STRtree,
    order: list[str],
    members: set[str],
    margin: float,
) -> Gate:
    """A region outside every cell may join ``members`` when all of it lies in one of ``bands`` and no
    cell but ``members`` comes within ``margin`` of it (the per-pair check's region keeps it whole)."""
    r = frame.resolution
    for band in bands:
        shapely.prepare(band)

    def gate(lab: int) -> bool:
        r0, r1, c0, c1 = (int(v) for v in graph.box[lab])
        extent = shapely.box(frame.x0 + c0 * r, frame.y0 + r0 * r, frame.x0 + (c1 + 1) * r, frame.y0 + (r1 + 1) * r)
        if not any(band.contains(extent) for band in bands):
            return False
        near = tree.query(extent, predicate="dwithin", distance=margin)
        return all(order[i] in members for i in near.tolist())

    return gate
