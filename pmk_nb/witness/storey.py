"""The witness of one storey: the written grid judged against the plan's cells and graph alone.

It shares no code with the openings planner or the rasteriser (``tests/project/test_layout.py`` holds
that: this package may import only the reader, the map files and the shared leaves), so a wrong
decision of the converter is not repeated here. Its rules follow what the plan says:

* a navigable cell's interior (eroded by half a wall and a pixel) is free, but for the non-navigable
  cells inside it; a non-navigable cell's interior is not free;
* two touching cells that no transition (nor a door boundary they share) joins are not connected in
  the map through the wall between them (a *leak*), any other cell being excluded from the way;
* a transition joins its two cells for the chair: its centre stays farther than half its width from
  every pixel that is not free (an exact disc erosion), from one cell to the other,
  within the two cells and the wall between them;
* a cell no chair fits in (a door slab) is crossed: the chair goes from each of its rooms to every
  other through it, so openings on its two faces must line up.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import shapely
from shapely.ops import nearest_points

from pmk_nb.defaults import DEFAULT_MAX_WALL_GAP, DEFAULT_WALL_THICKNESS
from pmk_nb.grid import FREE
from pmk_nb.pixels import disc_radius_px, erode, label
from pmk_nb.witness.findings import Finding, FindingKind, WitnessReport
from pmk_nb.witness.frame import MapFrame, Window, outline
from pmk_nb.witness.plausible import door_width, implausible, overlaps
from pmk_nb.witness.regions import StoreyRegions, region_gate, storey_regions

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.indoorgml import Building, Cell

#: a cell's interior may have this share of its pixels wrong before it is a finding (pixel rounding)
TOLERANCE = 0.01
MIN_PIXELS = 3


@dataclass
class _Storey:
    """What every rule of one storey reads: the map, its frame, the cells and the graph's pairs."""

    name: str
    frame: MapFrame
    data: np.ndarray  # the grid's values (row 0 = bottom)
    cells: dict[str, Cell]
    tree: shapely.STRtree
    order: list[str]  # cell ids in the tree's order
    joined: set[frozenset[str]]
    door_widths: dict[frozenset[str], float]  # the plan's door lines between two cells, metres
    links: list[tuple[str, str]]
    erode: float  # metres a cell's outline is drawn into it (half a wall and a pixel)
    gap: float  # cells this far apart share a wall
    radius: float  # the chair's half-width
    regions: StoreyRegions | None = None  # the storey's regions, labelled once (:mod:`.regions`)
    # per cell and grow, drawn once and kept a bit a pixel (a 100 M-cell storey's cells held as bytes
    # cost over a gigabyte)
    masks: dict[tuple[str, float], tuple[Window, np.ndarray]] = field(default_factory=dict)
    adjacent: dict[str, set[str]] = field(default_factory=dict)  # the cells a transition joins to each
    thin: dict[str, bool] = field(default_factory=dict)  # cells no chair fits in, decided once
    grown_by_gap: dict[str, BaseGeometry] = field(default_factory=dict)
    bands: dict[tuple[str, str], BaseGeometry] = field(default_factory=dict)  # (a, b): see band()

    def cell_mask(self, win: Window, cell_id: str, grow: float = 0.0) -> np.ndarray:
        """A cell's pixels in ``win``, its outline moved out by ``grow`` metres (in, when negative);
        each drawn once per storey."""
        key = (cell_id, grow)
        if key not in self.masks:
            foot = self.cells[cell_id].footprint
            shape = foot.buffer(grow) if grow else foot
            own = self.frame.window(shape.bounds, 1) if not shape.is_empty else Window(0, 0, 0, 0)
            self.masks[key] = (own, np.packbits(self.frame.mask(own, shape), axis=1))
        own, packed = self.masks[key]
        mask = np.unpackbits(packed, axis=1, count=own.shape[1]).view(bool)
        return self.frame.paste(win, own, mask)

    def free_in(self, win: Window) -> np.ndarray:
        """The free pixels of ``win`` (drawn when asked: the whole map's as bools cost 100 MB at 100 M cells)."""
        return np.asarray(self.data[win.r0 : win.r1, win.c0 : win.c1] == FREE)

    def graphs(self) -> StoreyRegions:
        """The free pixels and the chair's room, labelled once for the storey, each pixel owned by its cell."""
        if self.regions is None:
            cores = {c: None if _thin(self, c) else self.cells[c].footprint.buffer(-self.erode) for c in self.order}
            radius = disc_radius_px(self.radius, self.frame.resolution)
            self.regions = storey_regions(self.frame, self.data, self.cells, self.order, self.tree, cores, radius)
        return self.regions

    def proven(self, members: list[str], bands: list[BaseGeometry], ends: tuple[str, str], *, chair: bool) -> bool:
        """Whether the labelled storey shows a way from one end's core to the other's inside the per-pair
        check's region (False: not shown, the per-pair check decides)."""
        g = self.graphs()
        graph = g.chair if chair else g.free
        through = {code for c in members for code in g.codes(c)}
        margin = self.erode + self.frame.resolution
        gate = region_gate(self.frame, graph, bands, self.tree, self.order, set(members), margin)
        return graph.joins([g.core(ends[0])], {g.core(ends[1])}, through, gate)

    def may_leak(self, a: str, b: str) -> bool:
        """Whether the labelled storey leaves any way between the cores of ``a`` and ``b`` through their
        own pixels and pixels outside every cell (False proves no leak)."""
        g = self.graphs()
        if a in g.shared and b in g.shared:
            return True
        # a cell overlapping another owns some of its pixels only as "claimed by two": any such region
        # may be its own, so it may start (or end) the way and any may lie on it
        starts = [g.core(a), g.both] if a in g.shared else [g.core(a)]
        ends = {g.core(b), g.both} if b in g.shared else {g.core(b)}
        return g.free.joins(starts, ends, g.codes(a) | g.codes(b) | {g.both}, None)

    def neighbours(self, cell_id: str) -> set[str]:
        """The cells a transition joins to ``cell_id``."""
        return self.adjacent.get(cell_id, set())

    def name_of(self, cell_id: str) -> str:
        return self.cells[cell_id].name or cell_id

    def band(self, a: str, b: str) -> BaseGeometry:
        """Where the wall between ``a`` and ``b`` may be drawn."""
        if (a, b) not in self.bands:
            self.bands_of([(a, b)])
        return self.bands[(a, b)]

    def bands_of(self, pairs: list[tuple[str, str]]) -> None:
        """:meth:`band` of every pair, drawn in one array call each for the grown cells and their
        intersections (the same geometries as one call a pair, without a call's cost 7000 times)."""
        todo = [p for p in dict.fromkeys(pairs) if p not in self.bands]
        if not todo:
            return
        self.grow([c for p in todo for c in p])
        left = np.array([self.grown_by_gap[a] for a, _ in todo], dtype=object)
        right = np.array([self.grown_by_gap[b] for _, b in todo], dtype=object)
        self.bands.update(zip(todo, shapely.intersection(left, right).tolist(), strict=True))

    def grown(self, cell_id: str) -> BaseGeometry:
        """A cell's outline moved out by the wall gap, drawn once."""
        self.grow([cell_id])
        return self.grown_by_gap[cell_id]

    def grow(self, cell_ids: list[str]) -> None:
        """:meth:`grown` of each of ``cell_ids``, the ones not drawn yet in one array call (with the
        method's 16 segments a quarter circle: the array function's default is 8)."""
        todo = [c for c in dict.fromkeys(cell_ids) if c not in self.grown_by_gap]
        if todo:
            shapes = np.array([self.cells[c].footprint for c in todo], dtype=object)
            self.grown_by_gap.update(zip(todo, shapely.buffer(shapes, self.gap, quad_segs=16).tolist(), strict=True))


def witness_storey(
    building: Building, storey: str, grid: OccupancyGrid, *, chair_width: float, wall_thickness: float | None = None
) -> WitnessReport:
    """Judge one storey's written ``grid`` against ``building`` (read from the plan itself)."""
    st = _prepare(building, storey, grid, chair_width, wall_thickness)
    status = building.graph_status
    graph = not status.lost and bool(st.links)
    report = WitnessReport(storey, chair_width, grid.resolution, graph)
    report.findings += _interiors(st)
    report.findings += overlaps(storey, st.cells, st.tree, st.order)
    report.findings += implausible(storey, st.cells, [b.geometry for b in building.doors_of(storey)])
    report.counts = {"cells": len(st.cells)}
    if graph:
        pairs = _touching_pairs(st)
        report.findings += _leaks(st, pairs)
        report.findings += _transitions(st)
        report.findings += _passages(st)
        report.counts |= {"touching pairs": len(pairs), "transitions": len(st.links)}
    return report


def _prepare(
    building: Building, storey: str, grid: OccupancyGrid, chair_width: float, wall_thickness: float | None
) -> _Storey:
    cells = {c.id: c for c in building.cells_of(storey) if c.footprint is not None and not c.footprint.is_empty}
    order = list(cells)
    tree = shapely.STRtree([cells[c].footprint for c in order])
    joined: set[frozenset[str]] = set()
    links: list[tuple[str, str]] = []
    for link in building.links_of(storey):
        if link.a in cells and link.b in cells and link.a != link.b:
            joined.add(frozenset((link.a, link.b)))
            if _walkable(cells[link.a]) and _walkable(cells[link.b]):
                links.append((link.a, link.b))
    doors = {b.id for b in building.doors_of(storey)}
    owners: dict[str, list[str]] = {}
    for c in cells.values():
        for bid in c.boundary_ids:
            if bid in doors:
                owners.setdefault(bid, []).append(c.id)
    joined |= {frozenset(o[:2]) for o in owners.values() if len(o) >= 2}
    door_lines = [b.geometry for b in building.doors_of(storey) if b.geometry is not None and not b.geometry.is_empty]
    joined |= _silent_doors(cells, door_lines, links_known={c for pair in joined for c in pair})
    door_widths: dict[frozenset[str], float] = {}
    for b in building.doors_of(storey):
        pair = frozenset(owners.get(b.id, [])[:2])
        if len(pair) == 2 and b.geometry is not None and not b.geometry.is_empty:
            door_widths[pair] = max(door_widths.get(pair, 0.0), door_width(b.geometry))
    thick = DEFAULT_WALL_THICKNESS if wall_thickness is None else wall_thickness
    return _Storey(
        name=storey,
        frame=MapFrame.of(grid),
        data=grid.data,
        cells=cells,
        tree=tree,
        order=order,
        joined=joined,
        door_widths=door_widths,
        links=sorted(set(links)),
        adjacent=_adjacency(links),
        erode=thick / 2 + grid.resolution,
        gap=max(DEFAULT_MAX_WALL_GAP, thick + 2 * grid.resolution),
        radius=chair_width / 2,
    )


def _silent_doors(cells: dict[str, Cell], door_lines: list[BaseGeometry], links_known: set[str]) -> set[frozenset[str]]:
    """A cell the graph is silent about (in no transition, while the storey has some) is read as in a
    plan without a graph: a door cell touching it, or a door line between it and another cell, is a
    door. The graph says nothing of it, so what its doors join is no leak; its walls must still hold."""
    if not links_known:
        return set()
    silent = [c for c in cells.values() if c.id not in links_known and c.kind.is_free and not c.kind.is_door]
    if not silent:
        return set()
    free = [c for c in cells.values() if c.kind.is_free]
    tree = shapely.STRtree([c.footprint for c in free])
    out: set[frozenset[str]] = set()
    for cell in silent:
        for i in tree.query(cell.footprint, predicate="dwithin", distance=DEFAULT_MAX_WALL_GAP):
            if free[int(i)].kind.is_door and free[int(i)].id != cell.id:
                out.add(frozenset((cell.id, free[int(i)].id)))
        for line in door_lines:
            if cell.footprint.distance(line) > DEFAULT_MAX_WALL_GAP:
                continue
            for i in tree.query(line, predicate="dwithin", distance=DEFAULT_MAX_WALL_GAP):
                if free[int(i)].id != cell.id:
                    out.add(frozenset((cell.id, free[int(i)].id)))
    return out


def _adjacency(links: list[tuple[str, str]]) -> dict[str, set[str]]:
    out: dict[str, set[str]] = {}
    for a, b in links:
        out.setdefault(a, set()).add(b)
        out.setdefault(b, set()).add(a)
    return out


def _labels_in(labels: np.ndarray, where: np.ndarray) -> np.ndarray:
    """Which labels occur at ``where``: a bool table indexed by label (0, outside, never set)."""
    table = np.zeros(int(labels.max()) + 1, dtype=bool)
    table[labels[where]] = True
    table[0] = False
    return table


def _walkable(cell: Cell) -> bool:
    return cell.kind.is_free and not cell.window


def _interiors(st: _Storey) -> list[Finding]:
    """Rooms free, obstacles not free, every cell on the map."""
    out: list[Finding] = []
    obstacles = [c.footprint for c in st.cells.values() if not c.kind.is_free]
    blocked = shapely.union_all(obstacles).buffer(st.erode) if obstacles else None
    for cell in st.cells.values():
        if cell.window:
            continue
        inner: BaseGeometry = cell.footprint.buffer(-st.erode)
        if cell.kind.is_free and blocked is not None:
            inner = inner.difference(blocked)
        if inner.is_empty:
            continue
        win = st.frame.window(inner.bounds)
        expected = inner.area / st.frame.resolution**2
        if _rectangle_holds(st, win, inner, cell.kind.is_free, expected):
            continue
        mask = st.frame.mask(win, inner)
        drawn = int(np.count_nonzero(mask))  # not .sum(): a bool sum widens every pixel (0.7 s at 100 M cells)
        if drawn < 0.5 * expected - MIN_PIXELS:
            out.append(_finding(st, FindingKind.OUTSIDE_MAP, (cell.id,), inner.centroid, "the map does not cover it"))
            continue
        sub = st.free_in(win)
        wrong = mask & (~sub if cell.kind.is_free else sub)
        count = int(np.count_nonzero(wrong))
        share = count / max(drawn, 1)
        if count >= MIN_PIXELS and share > TOLERANCE:
            kind = FindingKind.ROOM_NOT_FREE if cell.kind.is_free else FindingKind.OBSTACLE_FREE
            what = "not free" if cell.kind.is_free else "free"
            place = _centroid(st, win, wrong)
            out.append(_finding(st, kind, (cell.id,), place, f"{share:.0%} of its interior is {what}", share))
    return out


def _rectangle_holds(st: _Storey, win: Window, inner: BaseGeometry, free: bool, expected: float) -> bool:
    """Whether ``inner``, when an upright rectangle (most rooms), is on the map and right (free for a
    ``free`` cell, not free otherwise) to :data:`TOLERANCE`, counted on the map's own slice without
    drawing its mask (three passes over a storey's pixels fewer); False sends it to the drawn check,
    which finds the same and says where."""
    rect = st.frame.rectangle(outline(inner))
    if rect is None:
        return False
    box = Window(max(rect.r0, win.r0), min(rect.r1, win.r1), max(rect.c0, win.c0), min(rect.c1, win.c1))
    drawn = 0 if box.empty else box.shape[0] * box.shape[1]
    if drawn < 0.5 * expected - MIN_PIXELS:
        return False
    part = st.data[box.r0 : box.r1, box.c0 : box.c1]
    count = int(np.count_nonzero(part != FREE if free else part == FREE))
    return not (count >= MIN_PIXELS and count / max(drawn, 1) > TOLERANCE)


def _touching_pairs(st: _Storey) -> list[tuple[str, str]]:
    """Walkable cells close enough to share a wall, each pair once."""
    walk = [c for c in st.order if _walkable(st.cells[c])]
    index = {c: i for i, c in enumerate(st.order)}
    pairs = set()
    for c in walk:
        for i in st.tree.query(st.cells[c].footprint, predicate="dwithin", distance=st.gap):
            other = st.order[i]
            if other != c and _walkable(st.cells[other]):
                pairs.add((c, other) if index[c] < index[other] else (other, c))
    return sorted(pairs, key=lambda p: (index[p[0]], index[p[1]]))


def _region(st: _Storey, members: list[str], bands: list[BaseGeometry], pad: int) -> tuple[Window, np.ndarray]:
    """The pixels of the cells ``members`` and of the walls ``bands`` between them; the walls lose any other
    cell with the wall drawn round it (so a doorway cell's jambs are its own, not a way past it)."""
    shapes = [st.cells[c].footprint for c in members] + bands
    bounds = np.array([g.bounds for g in shapes if not g.is_empty])
    box = (bounds[:, 0].min(), bounds[:, 1].min(), bounds[:, 2].max(), bounds[:, 3].max())
    win = st.frame.window(box, pad)
    walls = np.zeros(win.shape, dtype=bool)
    for band in bands:
        walls |= st.frame.mask(win, band)
    for i in st.tree.query(shapely.box(*box).buffer(st.erode)):
        if st.order[i] not in members:
            walls &= ~st.cell_mask(win, st.order[i], st.erode)
    for c in members:
        walls |= st.cell_mask(win, c)
    return win, walls


def _core(st: _Storey, win: Window, cell_id: str) -> np.ndarray:
    """A cell's pixels well inside it; all its pixels for a cell no chair fits in (a doorway): a chair
    is in such a cell wherever its centre is."""
    if _thin(st, cell_id):
        return st.cell_mask(win, cell_id)
    core = st.cell_mask(win, cell_id, -st.erode)
    return core if core.any() else st.cell_mask(win, cell_id)


def _thin(st: _Storey, cell_id: str) -> bool:
    """A cell no chair fits in wholly."""
    if cell_id not in st.thin:
        st.thin[cell_id] = bool(st.cells[cell_id].footprint.buffer(-st.radius).is_empty)
    return st.thin[cell_id]


def _leaks(st: _Storey, pairs: list[tuple[str, str]]) -> list[Finding]:
    out = []
    for a, b in pairs:
        if frozenset((a, b)) in st.joined or not st.may_leak(a, b):
            continue
        band = st.band(a, b)
        win, region = _region(st, [a, b], [band], 1)
        ways = st.free_in(win) & region
        labels = label(ways)
        common = _labels_in(labels, _core(st, win, a)) & _labels_in(labels, _core(st, win, b))
        if common.any():
            joined = common[labels] & st.frame.mask(win, band)
            place = _centroid(st, win, joined) if joined.any() else band.centroid
            out.append(_finding(st, FindingKind.LEAK, (a, b), place, "joined in the map but not in the graph"))
    return out


def _chair_room(st: _Storey, win: Window) -> np.ndarray:
    """Where the chair's centre may stand in ``win``: farther than its half-width from anything not free
    (the exact disc erosion of :mod:`pmk_nb.pixels`, the same pixels as SciPy's distance transform),
    from ``win`` grown by the disc (outside the grid is not free, as for the whole map). Only the ways
    the labelled storey cannot show come here."""
    radius = disc_radius_px(st.radius, st.frame.resolution)
    pad = int(np.ceil(radius)) + 1
    h, w = st.data.shape
    big = Window(max(0, win.r0 - pad), min(h, win.r1 + pad), max(0, win.c0 - pad), min(w, win.c1 + pad))
    room = erode(st.free_in(big), radius)
    return room[win.r0 - big.r0 : win.r1 - big.r0, win.c0 - big.c0 : win.c1 - big.c0]


def _connected(st: _Storey, members: list[str], bands: list[BaseGeometry], ends: list[str], *, chair: bool) -> bool:
    """Whether the free pixels of the region of ``members`` and ``bands`` join the cores of all ``ends``."""
    pad = int(np.ceil(st.radius / st.frame.resolution)) + 2
    win, region = _region(st, members, bands, pad)
    room = _chair_room(st, win) if chair else st.free_in(win)
    labels = label(room & region)
    if not ends:
        return False
    common = _labels_in(labels, _core(st, win, ends[0]))
    for c in ends[1:]:
        common &= _labels_in(labels, _core(st, win, c))
    return bool(common.any())


def _transitions(st: _Storey) -> list[Finding]:
    out = []
    ends = _degrees(st)
    st.bands_of([p for a, b in st.links for p in _link_bands(st, a, b)])
    for a, b in st.links:
        fa, fb = st.cells[a].footprint, st.cells[b].footprint
        if fa.distance(fb) > st.gap:
            continue  # apart: the graph joins them through cells between, which their own links judge
        # the graph may also join them through doorway cells: a way through one of those counts
        via = _via(st, a, b)
        members = [a, b, *via]
        bands = [st.band(a, b)] + [st.band(x, c) for c in via for x in (a, b)]
        # a way out (a doorway no chair fits in, with nothing beyond it in the graph): nothing is drawn
        # past it, so a chair cannot be shown through; the map must still leave a way for a point
        exit_ = any(ends.get(c, 0) == 1 and _thin(st, c) for c in (a, b))
        if st.proven(members, bands, (a, b), chair=not exit_):
            continue
        if not exit_ and _connected(st, members, bands, [a, b], chair=True):
            continue
        point = _connected(st, members, bands, [a, b], chair=False)
        if exit_ and point:
            continue
        kind, why = _narrow_or_blocked(st, point, _plan_width(st, a, b, via))
        p, q = nearest_points(fa, fb)
        place = shapely.Point((p.x + q.x) / 2, (p.y + q.y) / 2)
        out.append(_finding(st, kind, (a, b), place, f"a transition joins them: {why}"))
    return out


def _via(st: _Storey, a: str, b: str) -> list[str]:
    """The doorway cells (no chair fits in) the graph joins to both ``a`` and ``b``."""
    return sorted(c for c in st.neighbours(a) & st.neighbours(b) if _thin(st, c))


def _link_bands(st: _Storey, a: str, b: str) -> list[tuple[str, str]]:
    """The walls a way from ``a`` to ``b`` may cross: theirs, and each one's with a doorway between them
    (for transitions of cells close enough to share a wall; none otherwise)."""
    if st.cells[a].footprint.distance(st.cells[b].footprint) > st.gap:
        return []
    return [(a, b)] + [(x, c) for c in _via(st, a, b) for x in (a, b)]


def _plan_width(st: _Storey, a: str, b: str, via: list[str]) -> float | None:
    """How wide the plan makes the way from ``a`` to ``b``: its door line between them, or the doorway
    cells among them and between them (their longer side); None when the plan gives no width."""
    widths = [door_width(st.cells[c].footprint) for c in (a, b, *via) if _thin(st, c)]
    if frozenset((a, b)) in st.door_widths:
        widths.append(st.door_widths[frozenset((a, b))])
    return max(widths) if widths else None


def _narrow_or_blocked(st: _Storey, point: bool, width: float | None) -> tuple[FindingKind, str]:
    """A way the chair cannot take: BLOCKED when the map is to blame (no way at all, or a door the plan
    makes wide enough with two pixels to spare drawn too narrow), else NARROW (the plan's own door is
    that narrow, or the plan gives no width)."""
    if not point:
        return FindingKind.BLOCKED, "no way through at all"
    if width is not None and width >= 2 * st.radius + 2 * st.frame.resolution:
        return FindingKind.BLOCKED, f"the plan's door is {width:.2f} m wide, the map lets only a point through"
    said = "" if width is None else f" (the plan's door is {width:.2f} m wide)"
    return FindingKind.NARROW, f"a point passes, the chair does not{said}"


def _degrees(st: _Storey) -> dict[str, int]:
    """How many transitions of the storey each cell has."""
    out: dict[str, int] = {}
    for a, b in st.links:
        out[a] = out.get(a, 0) + 1
        out[b] = out.get(b, 0) + 1
    return out


def _passages(st: _Storey) -> list[Finding]:
    """A cell no chair fits in, joined to two or more cells: the chair must cross it between them."""
    out = []
    crossings = [
        (cell_id, a, b)
        for cell_id, cell in st.cells.items()
        if _walkable(cell) and _thin(st, cell_id)
        for a, b in itertools.combinations(sorted(st.neighbours(cell_id)), 2)
        if frozenset((a, b)) not in st.joined
    ]
    st.bands_of([p for c, a, b in crossings for p in ((a, c), (c, b))])
    for cell_id, a, b in crossings:
        cell = st.cells[cell_id]
        bands = [st.band(a, cell_id), st.band(cell_id, b)]
        if st.proven([a, cell_id, b], bands, (a, b), chair=True):
            continue
        if _connected(st, [a, cell_id, b], bands, [a, b], chair=True):
            continue
        width = door_width(cell.footprint)
        kind, detail = (
            FindingKind.NO_WAY_THROUGH,
            (
                f"the chair cannot cross {st.name_of(cell_id)!r} ({width:.2f} m wide) between them "
                "(openings not in line?)"
            ),
        )
        if width < 2 * st.radius + 2 * st.frame.resolution:
            kind, detail = (
                FindingKind.NARROW,
                f"{st.name_of(cell_id)!r} is {width:.2f} m wide: the chair does not fit",
            )
        out.append(_finding(st, kind, (a, cell_id, b), cell.footprint.centroid, detail))
    return out


def _centroid(st: _Storey, win: Window, mask: np.ndarray) -> shapely.Point:
    rows, cols = np.nonzero(mask)
    return shapely.Point(st.frame.point(win, float(rows.mean()), float(cols.mean())))


def _finding(
    st: _Storey, kind: FindingKind, cells: tuple[str, ...], place: shapely.Point, detail: str, amount: float = 0.0
) -> Finding:
    names = tuple(st.name_of(c) for c in cells)
    return Finding(kind, st.name, cells, names, (float(place.x), float(place.y)), detail, float(amount))
