"""The wheelchair accessibility report: does the written map let a chair go where the graph says?

For each storey, on the grid actually written, for a chair of a given width:

* every link (a transition between two cells of the storey) is *passable* when a free path joins the
  two cells while staying inside them and the wall between them, for a point (r = 0) and for the
  chair: for the chair the path runs in its configuration space (the free pixels farther than its
  half-width r from every pixel that is not free, occupied and unknown alike, see
  :mod:`pmk_nb.pixels`) and goes from the *core* of one cell to the core of the other. A
  cell's core is where the chair fits wholly inside it: its pixels at least r inside its outline,
  or all its pixels for a cell no chair fits in (a doorway, a porch; for one thinner than a pixel,
  the pixels within half a cell of it). So a chair that only noses past a door cut into a corner
  does not count as in the room, and a porch too shallow for the chair against the unknown outside
  is not passable however wide its opening (still named);
* a link passable for a point but not for the chair is a *narrow door*, named by its cells;
* cells the graph joins to the storey but the chair cannot reach are *unreachable*;
* two cells with no transition between them that are joined in the map (r = 0) *leak*;
* a link to a cell that is not free (a window the file links, or a cell the reader judged a window or
  sill from its floor height) has no opening to test: it is *not checked*, named but not a failure,
  since a misjudged window would otherwise hide a door from the check.

A path may only cross the two cells, the walls and gaps between cells and the storey's door cells (a
doorway drawn as a cell of its own is part of the wall, see :class:`_Regions`), so a way round through
a third room does not count. A leak must join the two rooms without crossing a door cell.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, fields, is_dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from pmk_nb.access.widths import free_widths
from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH as DEFAULT_CHAIR_WIDTH  # declared once there, re-exported here
from pmk_nb.defaults import DEFAULT_MAX_WALL_GAP, DEFAULT_WALL_THICKNESS
from pmk_nb.grid import FREE, UNKNOWN
from pmk_nb.openings import SKIP_WINDOW
from pmk_nb.pixels import disc_radius_px, erode_rows, join_strip_runs, strip_runs
from pmk_nb.raster import Frame, polygon_rects, polygon_rects_each, write_rects

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.indoorgml import Cell, Link
    from pmk_nb.openings import Opening, Skipped

SKIP_OUTSIDE = "outside"  # a doorway that opens onto the map's edge: where it leads is not drawn


@dataclass(frozen=True)
class LinkCheck:
    link: str
    cells: tuple[str, str]
    names: tuple[str, str]
    rule: str
    width: float  # metres, the planned opening (0 when the cells are apart)
    point: bool  # passable for a point (r = 0)
    chair: bool  # passable for the chair
    free_width: float = 0.0  # metres, the widest free stretch along the opening in the written grid

    def describe(self) -> str:
        what = f"{self.names[0]} <-> {self.names[1]}"
        if self.rule == "apart":
            return f"{what}: the cells do not touch (no shared wall to open)"
        if not self.point:
            return f"{what}: no way through in the map (opening by rule '{self.rule}')"
        return f"{what}: narrower than the chair (opening {self.width:.2f} m)"


@dataclass(frozen=True)
class Leak:
    cells: tuple[str, str]
    names: tuple[str, str]


@dataclass(frozen=True)
class NotChecked:
    """A link the check cannot test: one of its cells is not free, so the grid has no way into it."""

    link: str
    cells: tuple[str, str]
    names: tuple[str, str]
    reason: str  # "window": judged a window/sill from its floor height; "non-navigable": declared by the file
    cell: str  # the name of the cell that is not free (the first, when both are not)

    def describe(self) -> str:
        other = self.names[1] if self.cell == self.names[0] else self.names[0]
        why = {SKIP_WINDOW: "judged a window/sill", SKIP_OUTSIDE: "a doorway out of the map: nothing drawn beyond it"}
        why_text = why.get(self.reason, "non-navigable in the file")
        return f"{other} <-> {self.cell} ({why_text})"


@dataclass
class StoreyReport:
    storey: str
    chair_width: float
    resolution: float
    graph: bool  # False: the file gives no transitions on this storey; nothing to check against
    links: list[LinkCheck] = field(default_factory=list)
    unreachable: list[str] = field(default_factory=list)  # cell names
    leaks: list[Leak] = field(default_factory=list)
    rules: dict[str, int] = field(default_factory=dict)
    not_checked: list[NotChecked] = field(default_factory=list)  # never a failure: see the module note
    graph_lost: str = ""  # why the plan's navigation graph could not be used (GraphStatus.reason), if lost

    @property
    def blocked(self) -> list[LinkCheck]:
        return [k for k in self.links if not k.chair]

    @property
    def narrow(self) -> list[LinkCheck]:
        """Doors a point passes but the chair does not: findings about the building (or a narrow room)."""
        return [k for k in self.links if k.point and not k.chair]

    @property
    def checked(self) -> bool:
        """The graph said something about this storey: links to check, or links named as not checked."""
        return not self.graph_lost and (self.graph or bool(self.not_checked))

    @property
    def ok(self) -> bool:
        """Checked and no problem: a storey with no graph (absent or lost) is never "ok"."""
        return self.checked and not self.blocked and not self.unreachable and not self.leaks

    def counts(self) -> dict[str, int]:
        return {
            "links": len(self.links),
            "passable_point": sum(k.point for k in self.links),
            "passable_chair": sum(k.chair for k in self.links),
            "narrow": len(self.narrow),
            "unreachable": len(self.unreachable),
            "leaks": len(self.leaks),
            "to_windows": sum(k.reason == SKIP_WINDOW for k in self.not_checked),
            "to_outside": sum(k.reason == SKIP_OUTSIDE for k in self.not_checked),
            "to_non_navigable": sum(k.reason not in (SKIP_WINDOW, SKIP_OUTSIDE) for k in self.not_checked),
        }

    def summary(self) -> str:
        c = self.counts()
        if self.graph_lost:
            return f"storey {self.storey}: NOTHING CHECKED: {self.graph_lost}"
        if not self.graph and not self.not_checked:
            return f"storey {self.storey}: NOTHING CHECKED: no transition of the navigation graph on this storey"
        head = (
            f"storey {self.storey}: {c['passable_chair']}/{c['links']} transitions passable for a "
            f"{self.chair_width:.2f} m chair ({c['passable_point']}/{c['links']} for a point)"
            if self.graph
            else f"storey {self.storey}: no transition between two free cells to check"
        )
        extra = [f"{c[k]} {k}" for k in ("narrow", "unreachable", "leaks") if c[k]]
        out = head + (f"; {', '.join(extra)}" if extra else "")
        for key, what in (
            ("to_windows", "cells judged windows/sills"),
            ("to_outside", "doorways out of the map"),
            ("to_non_navigable", "non-navigable cells"),
        ):
            if c[key]:
                out += f"; {c[key]} transition{' leads' if c[key] == 1 else 's lead'} to {what} (not checked)"
        return out

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = _as_plain(self)
        out["counts"] = self.counts()
        out["ok"] = self.ok
        out["checked"] = self.checked
        return out


def _as_plain(value: Any) -> Any:
    """``dataclasses.asdict`` for the report's plain fields (str, numbers, bools, lists, tuples, dicts):
    the same mapping, without asdict's deep copy of every leaf (0.3 s for 3000 links)."""
    if is_dataclass(value) and not isinstance(value, type):
        return {f.name: _as_plain(getattr(value, f.name)) for f in fields(value)}
    if isinstance(value, list | tuple):
        return type(value)(_as_plain(v) for v in value)
    if isinstance(value, dict):
        return {_as_plain(k): _as_plain(v) for k, v in value.items()}
    return value


class _Regions:
    """Free regions of the written grid that never cross from one cell into another, and how they touch.

    Pixels are owned by the cell whose footprint holds their centre (0: in no cell - walls, gaps and
    the openings cut in them). Two cells are joined when a chain of touching regions owned by one of
    them or by no cell leads from one to the other: labelled once per storey, asked per link. With
    ``core``, owners are ``2 * cell + (1 in the cell's core)`` (see :class:`_Owners`) and the chain
    must start and end in the cores.
    """

    def __init__(self, runs: list[tuple[np.ndarray, ...]], width: int, *, core: bool = False) -> None:
        labels, owner, edges = join_strip_runs(runs, width)
        self.shift = int(core)
        self.owner = owner >> self.shift  # the cell
        self.start = owner if core else None  # the cell and whether in its core
        self.by_owner: dict[int, list[int]] = {}
        for lab, own in zip(labels.tolist(), self.owner[labels].tolist(), strict=True):
            self.by_owner.setdefault(int(own), []).append(lab)
        self.next: dict[int, list[int]] = {}
        for u, v in edges.tolist():
            self.next.setdefault(u, []).append(v)
            self.next.setdefault(v, []).append(u)

    def joined(self, a: int, b: int, via: frozenset[int] = frozenset()) -> bool:
        """Whether a chain of regions owned by ``a``, ``b``, no cell or a cell of ``via`` joins them."""
        allowed = {a, b, 0, *via}
        todo = list(self.by_owner.get(a, []))
        if self.start is not None:
            todo = [lab for lab in todo if self.start[lab] & 1]
        seen = set(todo)
        while todo:
            lab = todo.pop()
            if self.owner[lab] == b and (self.start is None or self.start[lab] & 1):
                return True
            for nxt in self.next.get(lab, []):
                if nxt not in seen and int(self.owner[nxt]) in allowed:
                    seen.add(nxt)
                    todo.append(nxt)
        return False


class _Owners:
    """Per pixel, 1 + the index of the cell holding its centre (0: none), painted a strip of rows at a
    time from each cell's rectangles of pixels, so the check never holds a full-size owner array.

    Cells are painted largest first, so a room drawn inside a hall's footprint keeps its own pixels; a
    door cell also owns the half cell round it: the jamb pixels its openings clear are the doorway, not
    a leak. The narrowest integer type that holds every value is used (one byte for up to 126 cells).
    With ``core_radius`` (the chair's half-width, metres) the value is ``2 * (1 + index) + 1`` in the
    cell's core (see the module note), ``2 * (1 + index)`` elsewhere in it, 0 in no cell.
    """

    def __init__(self, grid: OccupancyGrid, cells: list[Cell], core_radius: float | None = None) -> None:
        frame = Frame(float(grid.origin[0]), float(grid.origin[1]), grid.resolution, grid.width, grid.height)
        self.width = grid.width
        top = (2 * len(cells) + 1) if core_radius is not None else len(cells)
        self.dtype = np.uint8 if top < 255 else np.int16 if top < 32767 else np.int32
        self.layers: list[tuple[int, tuple[np.ndarray, ...]]] = []
        order = sorted(range(len(cells)), key=lambda i: -cells[i].footprint.area)
        shapes = [cells[i].footprint for i in order]
        doors = [k for k, i in enumerate(order) if cells[i].kind.is_door]  # grown in one array call
        grown = shapely.buffer(
            np.array([shapes[k] for k in doors], dtype=object), grid.resolution / 2, join_style="mitre"
        )
        for k, g in zip(doors, grown.tolist(), strict=True):
            shapes[k] = g
        painted = polygon_rects_each(frame, shapes)  # all cells at once, not a call each
        cores = None
        if core_radius is not None:
            cores = core_rects_each(frame, [cells[i].footprint for i in order], core_radius)
        for k, (i, rects) in enumerate(zip(order, painted, strict=True)):
            if not len(rects[0]):
                continue
            if cores is None:
                self.layers.append((i + 1, rects))
            else:  # the core is painted over its own cell's pixels, before any smaller cell
                core = cores[k]
                self.layers += [(2 * (i + 1), rects)] + ([(2 * (i + 1) + 1, core)] if len(core[0]) else [])
        self.top = np.array([int(r[0].min()) for _, r in self.layers], dtype=np.int64)
        self.bottom = np.array([int(r[1].max()) for _, r in self.layers], dtype=np.int64)

    def rows(self, a: int, b: int) -> np.ndarray:
        """Owners of grid rows ``a:b``."""
        out = np.zeros((b - a, self.width), dtype=self.dtype)
        for k in np.flatnonzero((self.top < b) & (self.bottom > a)).tolist():
            value, (ra, rb, s, t) = self.layers[k]
            write_rects(out, np.maximum(ra, a) - a, np.minimum(rb, b) - a, s, t, value)
        return out


def core_rects(frame: Frame, footprint: BaseGeometry, depth: float) -> tuple[np.ndarray, ...]:
    """The pixels of ``footprint`` at least ``depth`` inside it (where a chair of radius ``depth`` is
    wholly in the cell), or all its pixels when none is (a doorway, a porch: no chair fits in it), or
    for a cell thinner than a pixel (a door drawn as a 4 cm sliver) the pixels within half a cell."""
    for shape in (shapely.buffer(footprint, -depth), footprint):
        rects = polygon_rects(frame, [shape])
        if len(rects[0]):
            return rects
    return polygon_rects(frame, [shapely.buffer(footprint, frame.resolution / 2, join_style="mitre")])


def core_rects_each(frame: Frame, footprints: list[BaseGeometry], depth: float) -> list[tuple[np.ndarray, ...]]:
    """:func:`core_rects` of each footprint, each step for all footprints at once."""
    out = polygon_rects_each(frame, list(shapely.buffer(np.asarray(footprints, dtype=object), -depth)))
    for fallback in (
        lambda fp: fp,
        lambda fp: shapely.buffer(fp, frame.resolution / 2, join_style="mitre"),
    ):
        empty = [k for k, r in enumerate(out) if not len(r[0])]
        if not empty:
            break
        for k, r in zip(empty, polygon_rects_each(frame, [fallback(footprints[k]) for k in empty]), strict=True):
            out[k] = r
    return out


def _strips(
    grid: OccupancyGrid, owners: _Owners, radius_px: float
) -> Iterator[tuple[int, np.ndarray, np.ndarray, np.ndarray]]:
    """(first row, free pixels, free pixels eroded by ``radius_px``, owners) strip by strip."""
    data = np.asarray(grid.data)
    for a, eroded in erode_rows(lambda lo, hi: data[lo:hi] == FREE, grid.height, grid.width, radius_px):
        b = a + len(eroded)
        yield a, data[a:b] == FREE, eroded, owners.rows(a, b)


def check_storey(
    storey: str,
    grid: OccupancyGrid,
    cells: list[Cell],
    openings: list[Opening],
    *,
    chair_width: float = DEFAULT_CHAIR_WIDTH,
    wall_thickness: float = DEFAULT_WALL_THICKNESS,
    max_gap: float = DEFAULT_MAX_WALL_GAP,
    skipped: Sequence[Skipped] = (),
) -> StoreyReport:
    """The report for one storey's written grid, its cells and the openings the converter planned
    (``skipped``: the links it left without an opening, named in the report as not checked)."""
    report = StoreyReport(storey, chair_width, grid.resolution, graph=bool(openings))
    by_id = {c.id: c for c in cells}
    report.not_checked = [_not_checked(k, by_id) for k in skipped]
    if not openings:
        return report
    index = {c.id: i + 1 for i, c in enumerate(cells)}
    doors = frozenset(index[c.id] for c in cells if c.kind.is_door)
    point_runs, chair_runs = [], []  # one sweep: each strip's owners are painted once for both
    owners = _Owners(grid, cells, chair_width / 2)
    for a, free, eroded, own in _strips(grid, owners, disc_radius_px(chair_width / 2, grid.resolution)):
        point_runs.append(strip_runs(a, free, own >> 1))
        chair_runs.append(strip_runs(a, eroded, own))
    point, chair = _Regions(point_runs, grid.width), _Regions(chair_runs, grid.width, core=True)
    for o, wide in zip(openings, free_widths(grid, [o.segments for o in openings]), strict=True):
        a, b = index[o.link.a], index[o.link.b]
        passes = point.joined(a, b, doors)
        fits = chair.joined(a, b, doors)  # on the grid alone: the opening's width only informs
        report.links.append(
            LinkCheck(o.link.id, (o.link.a, o.link.b), o.names, o.rule, round(o.width, 3), passes, fits, round(wide, 3))
        )
        report.rules[o.rule] = report.rules.get(o.rule, 0) + 1
    _doorways_out(report, grid, by_id)
    report.unreachable = _unreachable(report.links, by_id) if report.links else []
    report.leaks = _leaks([o.link for o in openings], cells, index, point, max_gap)
    return report


def _doorways_out(report: StoreyReport, grid: OccupancyGrid, by_id: dict[str, Cell]) -> None:
    """Move to ``not_checked`` the links into a doorway (a door cell, or a cell too thin for the chair) that
    opens onto the map's edge, an entrance whose outside the plan does not draw: a point passes, but no
    chair can stand in a 0.3 m doorway with nothing known beyond it. That is not a narrow door, and the map
    cannot say where it leads."""
    kept = []
    for k in report.links:
        door = None  # looked for only where it matters: a link a point passes and the chair does not
        if k.point and not k.chair:
            door = next(
                (c for c in k.cells if _doorway(by_id[c], report.chair_width / 2) and _touches_unknown(grid, by_id[c])),
                None,
            )
        if door is not None:
            ends = (by_id[k.cells[0]].name or k.cells[0], by_id[k.cells[1]].name or k.cells[1])
            report.not_checked.append(NotChecked(k.link, k.cells, ends, SKIP_OUTSIDE, by_id[door].name or door))
        else:
            kept.append(k)
    report.links = kept


def _doorway(cell: Cell, radius: float) -> bool:
    """A door cell, or a cell no chair of ``radius`` fits in (a 0.3 m niche in the outer wall)."""
    return cell.kind.is_door or shapely.buffer(cell.footprint, -radius).is_empty


def _touches_unknown(grid: OccupancyGrid, cell: Cell) -> bool:
    """Whether an unknown pixel lies within a pixel and a half of ``cell``'s outline."""
    res = grid.resolution
    x0, y0, x1, y1 = cell.footprint.buffer(1.5 * res).bounds
    c0, c1 = max(int((x0 - grid.origin[0]) / res), 0), min(int((x1 - grid.origin[0]) / res) + 1, grid.width)
    r0, r1 = max(int((y0 - grid.origin[1]) / res), 0), min(int((y1 - grid.origin[1]) / res) + 1, grid.height)
    block = np.asarray(grid.data)[r0:r1, c0:c1]
    rows, cols = np.nonzero(block == UNKNOWN)
    if not len(rows):
        return False
    xs = grid.origin[0] + (cols + c0 + 0.5) * res
    ys = grid.origin[1] + (rows + r0 + 0.5) * res
    return bool(shapely.dwithin(cell.footprint, shapely.points(xs, ys), 1.5 * res).any())


def _not_checked(skip: Skipped, by_id: dict[str, Cell]) -> NotChecked:
    ends = (skip.link.a, skip.link.b)
    shut = [i for i, c in enumerate(ends) if c in by_id and not by_id[c].kind.is_free]
    return NotChecked(skip.link.id, ends, skip.names, skip.reason, skip.names[shut[0] if shut else 1])


def _unreachable(links: list[LinkCheck], by_id: dict[str, Cell]) -> list[str]:
    """Cells of the graph outside its largest chair-passable component (by area)."""
    parent = {c: c for k in links for c in k.cells}

    def find(x: str) -> str:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for k in links:
        if k.chair:
            parent[find(k.cells[0])] = find(k.cells[1])
    area: dict[str, float] = {}
    for c in parent:
        area[find(c)] = area.get(find(c), 0.0) + by_id[c].footprint.area
    main = max(area, key=lambda r: area[r])
    return sorted(by_id[c].name or c for c in parent if find(c) != main)


def _leaks(links: list[Link], cells: list[Cell], index: dict[str, int], point: _Regions, max_gap: float) -> list[Leak]:
    """Pairs of graph cells, within ``max_gap`` of each other, with no link but a free way between them."""
    joined = {frozenset((k.a, k.b)) for k in links}
    in_graph = {c for k in links for c in (k.a, k.b)}
    free = [c for c in cells if c.kind.is_free and c.id in in_graph]
    ftree = shapely.STRtree([c.footprint for c in free]) if free else None
    leaks: list[Leak] = []
    if ftree is None:
        return leaks
    left, right = ftree.query([c.footprint for c in free], predicate="dwithin", distance=max_gap)
    for i, j in zip(left.tolist(), right.tolist(), strict=True):
        if i >= j or frozenset((free[i].id, free[j].id)) in joined:
            continue
        a, b = free[i], free[j]
        if point.joined(index[a.id], index[b.id]):
            leaks.append(Leak((a.id, b.id), (a.name or a.id, b.name or b.id)))
    return leaks
