"""Where the navigation graph says a chair may pass, and where in the wall the opening goes.

Every transition between two free cells of a storey is a :class:`~pmk_nb.indoorgml.model.Link`; its
opening is found on the cells' shared boundary (the part of one cell's outline within the gap that
separates them, up to ``max_gap``), by the first rule with evidence:

1. ``door``: door geometry - a door cell (Connection/AnchorSpace) on either side (the whole shared
   boundary), or a door boundary lying on the shared boundary; of several, only the strongest kind
   (a ConnectionBoundary or a boundary named "door", then a partial edge, then a transition's dual
   face) - so a plain wall that a transition is merely dual to is not opened when a real door sits
   beside it, and a dual face that spans the whole wall is no door at all;
2. ``line``: where the transition's own LineString crosses the shared boundary, ``door_width`` wide, on
   one straight stretch clear of corners and crossing walls (:mod:`pmk_nb.openings.doorslide`);
3. ``corridor``: both cells corridor-like (TransitionSpace, or named corridor/hall/lobby), or the
   boundary is virtual, or the file draws walls as gaps and these two cells touch (no wall): the
   whole shared boundary;
4. ``middle``: ``door_width`` at the middle of the longest straight stretch of the shared boundary.

Two cells further apart than ``max_gap`` share no wall to open. When the space between them (at most
:data:`MAX_BRIDGE` metres, along the transition's own line or else the shortest way) crosses no other
cell, the graph still decides: rule ``bridge`` lays a ``door_width`` passage across the gap (a stair
landing the file leaves out); otherwise the link stays ``apart`` and the report names it. A link to a
cell that is not free (a window the file links, or a cell the reader judged a window) gets no opening:
it is kept as :class:`Skipped`, so the report names it as not checked rather than losing it.

The rasteriser clears wall cells (never obstacles, never outside) in each opening's rectangle after
drawing the walls, so no wall band, supercover line or gap filling narrows it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely
from shapely import ops

from pmk_nb.defaults import DEFAULT_DOOR_WIDTH, DEFAULT_MAX_WALL_GAP
from pmk_nb.geometry import boxes_overlap
from pmk_nb.indoorgml import CellKind, says_corridor
from pmk_nb.openings.doorface import door_face
from pmk_nb.openings.doorslide import DEFAULT_INSET, place
from pmk_nb.openings.model import SKIP_DECLARED, SKIP_WINDOW, Opening, OpeningPlan, Skipped
from pmk_nb.openings.nearby import Nearby
from pmk_nb.openings.outside import outer_guesses
from pmk_nb.openings.slab import align_slabs
from pmk_nb.openings.thickness import MIN_WALL

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Boundary, Building, Cell, Link

RULES = ("door", "line", "corridor", "middle", "bridge")
MAX_BRIDGE = 3.0  # metres: the widest gap between two linked cells that a passage is laid across
_EVIDENCE_RANK = {"type": 0, "name": 0, "partial": 1, "duality": 2}
_TOUCH = 0.02  # metres: cells closer than this share a face with no wall drawn between them
_FULL = 0.95  # a dual face covering 95 % of the shared boundary is the wall itself, not a door
_ENDS_MID = np.array([0.0, 0.5, 1.0])  # where a segment's local gap is measured (normalised)
_ALONG = 0.5  # a door line lies on a shared boundary when it covers this share of it (or of itself) there


def _label(cell: Cell) -> str:
    return cell.name or cell.id


def _shared(a: Cell, b: Cell, gap: float, tol: float, near: BaseGeometry | None = None) -> BaseGeometry:
    """The part of ``a``'s outline within ``gap`` (+ ``tol``) of ``b``, as merged lines.

    A cell drawn inside another (a room inside a hall's footprint) shares its own outline, less
    what lies on the outer cell's outline. ``near``: that part before merging, when computed already
    for cells whose boxes do not overlap (:func:`_near_outlines`).
    """
    small, big = sorted((a, b), key=lambda c: c.footprint.area)
    overlap = (
        shapely.intersection(small.footprint, big.footprint).area
        if near is None and boxes_overlap(a.footprint, b.footprint)
        else 0.0
    )
    if overlap > 0.5 * small.footprint.area:
        line = shapely.difference(
            shapely.intersection(shapely.boundary(small.footprint), big.footprint),
            shapely.buffer(shapely.boundary(big.footprint), tol),
        )
    elif near is not None:
        line = near
    else:
        line = shapely.intersection(shapely.boundary(a.footprint), shapely.buffer(b.footprint, gap + tol))
    parts = [p for p in shapely.get_parts(line) if p.geom_type == "LineString" and p.length > 2 * tol]
    if not parts:
        return shapely.MultiLineString()
    merged = ops.linemerge(shapely.MultiLineString(parts))
    return merged


def _runs(shared: BaseGeometry) -> list[shapely.LineString]:
    return sorted(shapely.get_parts(shared).tolist(), key=lambda g: -g.length)


def _door_lines(link: Link, shared: BaseGeometry, doors: list[Boundary], gap: float, tol: float) -> list[BaseGeometry]:
    """Door boundary lines on the shared boundary, strongest evidence only; a full dual face is a wall."""
    near = shapely.buffer(shared, gap + tol)
    found: list[tuple[int, BaseGeometry]] = []
    for door in doors:
        g = door.geometry
        if g is None or g.is_empty or g.geom_type not in ("LineString", "MultiLineString"):
            continue
        mid = g.interpolate(0.5, normalized=True)
        if not near.contains(mid):
            continue
        rank = _EVIDENCE_RANK.get(door.evidence, 0)
        if rank == 2 and g.length >= _FULL * shared.length:
            continue
        found.append((rank, g))
    if not found:
        return []
    best = min(r for r, _ in found)
    return [g for r, g in found if r == best]


def _project(run: shapely.LineString, geoms: list[BaseGeometry]) -> list[BaseGeometry]:
    """Door lines as stretches of the shared run (a door line in a gap lies beside it, not on it).

    A door that runs along the run covers at least half of the run or of itself there; one that only
    ends at it (the door of a neighbouring wall, meeting this one at a corner) projects to a sliver
    and is not this boundary's door."""
    out: list[BaseGeometry] = []
    for g in geoms:
        ends = shapely.get_coordinates(g)
        d = sorted(run.project(shapely.Point(p)) for p in (ends[0], ends[-1]))
        if d[1] - d[0] >= _ALONG * min(g.length, run.length):
            out.append(ops.substring(run, d[0], d[1]))
    return out


def _corridor_like(a: Cell, b: Cell, virtual: bool, walls_as_gaps: bool, gap: float) -> bool:
    both = all(c.kind is CellKind.TRANSITION or says_corridor(c.name) for c in (a, b))
    return both or virtual or (walls_as_gaps and gap <= _TOUCH)


def _made(link: Link, rule: str, segs: Sequence[BaseGeometry], a: Cell, b: Cell, gap: float, ctx: _Context) -> Opening:
    """An opening with each segment's local gap: how far its ends and middle are from either cell's
    outline (a gap between the cells, or an overlap where both outlines are drawn as walls)."""
    rings = shapely.boundary(np.array([a.footprint, b.footprint], dtype=object))
    # ends and middle of every segment, each one's distance to both outlines: two array calls
    pts = shapely.line_interpolate_point(
        np.repeat(np.array(segs, dtype=object), 3), np.tile(_ENDS_MID, len(segs)), normalized=True
    )
    dist = shapely.distance(rings[:, None], pts[None, :]).reshape(2, len(segs), 3).transpose(1, 0, 2)
    reaches = []
    for d in dist.reshape(len(segs), 6).tolist():
        far = max(d)  # ring by ring, point by point, as a loop over them would
        reaches.append(min(max(far, gap), ctx.max_gap))
    width = min((s.length for s in segs), default=0.0)
    return Opening(link, rule, tuple(segs), width, gap, (_label(a), _label(b)), tuple(reaches))


def _opening(link: Link, cells: dict[str, Cell], ctx: _Context, gap: float, outline: BaseGeometry | None) -> Opening:
    """``gap``: the distance between the two cells; ``outline``: see :func:`_shared`."""
    a, b = cells[link.a], cells[link.b]
    shared = _shared(a, b, gap, ctx.tol, outline) if gap <= ctx.max_gap else shapely.MultiLineString()
    if shared.is_empty:
        return _bridge(link, a, b, gap, ctx) or Opening(link, "apart", (), 0.0, gap, (_label(a), _label(b)))
    runs = _runs(shared)
    if a.kind.is_door or b.kind.is_door:
        door, room = (a, b) if a.kind.is_door else (b, a)  # a door askew keeps its width: its face, if longer
        face = door_face(door.footprint, room.footprint, gap, ctx.max_gap + ctx.tol, ctx.tol)
        return _made(link, "door", _runs(face) if face.length > shared.length + 2 * ctx.tol else runs, a, b, gap, ctx)
    near = ctx.max_gap + ctx.tol
    lines = _door_lines(link, shared, ctx.near.doors_near(shared, near + ctx.tol), near, ctx.tol)
    if lines:
        segs = [s for run in runs for s in _project(run, [g for g in lines if run.distance(g) <= near])]
        if segs:
            return _made(link, "door", segs, a, b, gap, ctx)
    if link.line is not None:
        crossing = shapely.intersection(link.line, shapely.buffer(shared, gap + ctx.tol))
        if not crossing.is_empty:
            point = crossing.centroid
            return _made(link, "line", [place(runs, ctx.door_width, ctx.inset, point)], a, b, gap, ctx)
    virtual = bool(ctx.near.virtual_within(shared, gap + ctx.tol))
    if _corridor_like(a, b, virtual, ctx.walls_as_gaps, gap):
        return _made(link, "corridor", runs, a, b, gap, ctx)
    return _made(link, "middle", [place(runs, ctx.door_width, ctx.inset)], a, b, gap, ctx)


def _slab_face(o: Opening, cells: dict[str, Cell], ctx: _Context) -> Sequence[BaseGeometry]:
    """The runs of ``o``'s shared boundary, where :func:`~pmk_nb.openings.slab.align_slabs` re-places it."""
    a, b = cells[o.link.a], cells[o.link.b]
    return _runs(_shared(a, b, o.gap, ctx.tol))


def _bridge(link: Link, a: Cell, b: Cell, gap: float, ctx: _Context) -> Opening | None:
    """A door-wide passage across the gap between two linked cells, or None: too far, or another cell
    lies in the way. Its segment is the passage's cross-section at the middle (where it is measured)."""
    if gap > MAX_BRIDGE or gap <= 0:
        return None
    both = shapely.union(a.footprint, b.footprint)
    path = None
    if link.line is not None:
        for piece in shapely.get_parts(shapely.difference(link.line, both)).tolist():
            ends = [shapely.Point(xy) for xy in shapely.get_coordinates(piece)[[0, -1]]]
            if piece.geom_type == "LineString" and all(
                min(c.footprint.distance(e) for e in ends) <= ctx.tol for c in (a, b)
            ):
                path = piece
                break
    if path is None:
        path = shapely.shortest_line(a.footprint, b.footprint)
    lane = shapely.buffer(path, ctx.door_width / 2, cap_style="flat")
    if any(shapely.intersection(lane, c).area > ctx.tol * ctx.door_width for c in ctx.near.others(a, b, lane)):
        return None
    mid = path.interpolate(0.5, normalized=True)
    xy = shapely.get_coordinates(path)
    d = xy[-1] - xy[0]
    n = float((d**2).sum() ** 0.5) or 1.0
    half = [-d[1] / n * ctx.door_width / 2, d[0] / n * ctx.door_width / 2]
    across = shapely.LineString([(mid.x - half[0], mid.y - half[1]), (mid.x + half[0], mid.y + half[1])])
    return Opening(link, "bridge", (across,), ctx.door_width, gap, (_label(a), _label(b)), (0.0,), path)


@dataclass(frozen=True)
class _Context:
    doors: list[Boundary]
    virtual: list[BaseGeometry]
    door_width: float
    max_gap: float
    tol: float
    walls_as_gaps: bool
    near: Nearby  # the doors, virtual boundaries and cells near a link (R-trees: linear, not quadratic)
    inset: float = DEFAULT_INSET


def plan_openings(
    building: Building,
    storey: str,
    *,
    door_width: float = DEFAULT_DOOR_WIDTH,
    max_gap: float = DEFAULT_MAX_WALL_GAP,
    tol: float = 0.01,
    inset: float = DEFAULT_INSET,
) -> OpeningPlan:
    """The openings of every same-storey link between two free cells, and the door lines left shut.
    ``inset``: how far a door placed by rule line or middle keeps from a corner or crossing wall."""
    cells = {c.id: c for c in building.cells_of(storey) if c.footprint is not None and not c.footprint.is_empty}
    links: list[Link] = []
    not_free: list[Link] = []  # a link to a window or obstacle: no opening, named as not checked
    for k in building.links_of(storey):
        if k.a in cells and k.b in cells:
            (links if cells[k.a].kind.is_free and cells[k.b].kind.is_free else not_free).append(k)
    doors = [d for d in building.doors_of(storey) if d.geometry is not None]
    virtual = [bd.geometry for bd in building.boundaries_of(storey) if bd.virtual and bd.geometry]
    # the distances and near outlines of all links in a few array calls (a call per link was most of the time)
    ends = [np.array([cells[getattr(k, end)].footprint for k in links], dtype=object) for end in ("a", "b")]
    gaps = shapely.distance(*ends) if links else np.zeros(0)
    walls_as_gaps = len(gaps) > 0 and int(np.count_nonzero(gaps > _TOUCH)) * 2 > len(gaps)
    near = Nearby(list(cells.values()), doors, virtual)
    ctx = _Context(doors, virtual, door_width, max_gap, tol, walls_as_gaps, near, inset)
    outlines = _near_outlines(ends[0], ends[1], gaps, tol, max_gap) if links else []
    openings = [_opening(k, cells, ctx, g, o) for k, g, o in zip(links, gaps.tolist(), outlines, strict=True)]
    openings = align_slabs(openings, cells, lambda o: _slab_face(o, cells, ctx), door_width, inset)
    graph = _Graph.of(cells, links)
    shut = _shut(doors, graph, max_gap)
    if links:  # a transition's dual face is not door geometry of its own: the openings place the door
        shut += [d for d in doors if d.evidence == "duality" and d not in shut]
    crossing = [k.line for k in building.links if k.line is not None and storey in k.storeys]
    reach = max(MIN_WALL, max_gap) + tol  # a cell across the thickest wall faces the door: not the outside
    shut += [d for d in outer_guesses(doors, [c.footprint for c in cells.values()], crossing, reach) if d not in shut]
    skipped = tuple(_skipped(k, cells) for k in not_free)
    return OpeningPlan(openings, shut, bool(links), tuple(_seams(graph, tol)), skipped)


def _near_outlines(fa: np.ndarray, fb: np.ndarray, gaps: np.ndarray, tol: float, max_gap: float) -> list[Any]:
    """Per link (footprints ``fa[i]``, ``fb[i]``), what :func:`_shared` takes for the part of a's outline
    near b, for all links at once; None where it decides itself (the cells' boxes overlap: one may be
    drawn inside the other) or where the cells are further apart than ``max_gap``."""
    ba, bb = shapely.bounds(fa), shapely.bounds(fb)
    overlap = (np.minimum(ba[:, 2], bb[:, 2]) > np.maximum(ba[:, 0], bb[:, 0])) & (
        np.minimum(ba[:, 3], bb[:, 3]) > np.maximum(ba[:, 1], bb[:, 1])
    )
    todo = np.flatnonzero(~overlap & (gaps <= max_gap))
    out: list[Any] = [None] * len(fa)
    lines = shapely.intersection(shapely.boundary(fa[todo]), shapely.buffer(fb[todo], gaps[todo] + tol))
    for i, line in zip(todo.tolist(), lines.tolist(), strict=True):
        out[i] = line
    return out


def _skipped(link: Link, cells: dict[str, Cell]) -> Skipped:
    ends = (cells[link.a], cells[link.b])
    window = all(c.window for c in ends if not c.kind.is_free)
    return Skipped(link, (_label(ends[0]), _label(ends[1])), SKIP_WINDOW if window else SKIP_DECLARED)


@dataclass(frozen=True)
class _Graph:
    """A storey's free cells in one tree, and what its links say of them: which cells the graph knows
    (a cell it is silent about keeps the old rules) and which pairs it joins."""

    free: list[Cell]
    tree: shapely.STRtree
    known: frozenset[str]
    joined: frozenset[frozenset[str]]

    @staticmethod
    def of(cells: dict[str, Cell], links: list[Link]) -> _Graph:
        free = [c for c in cells.values() if c.kind.is_free]
        return _Graph(
            free,
            shapely.STRtree([c.footprint for c in free]),
            frozenset(c for k in links for c in (k.a, k.b)),
            frozenset(frozenset((k.a, k.b)) for k in links),
        )


def _seams(graph: _Graph, tol: float) -> list[BaseGeometry]:
    """Where two touching free cells that the graph knows but does not join meet, less any other free
    cell lying there (a door cell drawn across their wall). The rasteriser draws these last: an
    opening's reach or a door line running past a partition's end (two doors meeting at it, a door
    line spanning two rooms) must not join the rooms on either side of the partition."""
    if not graph.joined:
        return []
    free = graph.free
    left, right = graph.tree.query([c.footprint for c in free], predicate="dwithin", distance=_TOUCH)
    out = []
    for i, j in zip(left.tolist(), right.tolist(), strict=True):
        a, b = free[i], free[j]
        if i >= j or not {a.id, b.id} <= graph.known or frozenset((a.id, b.id)) in graph.joined:
            continue
        seam = _shared(a, b, float(a.footprint.distance(b.footprint)), tol)
        if seam.is_empty:
            continue
        across = [free[k].footprint for k in graph.tree.query(seam) if free[k].id not in (a.id, b.id)]
        if across:
            seam = shapely.difference(seam, shapely.union_all(across))
        if not seam.is_empty:
            out.append(seam)
    return out


def _shut(doors: list[Boundary], graph: _Graph, max_gap: float) -> list[Boundary]:
    """Door boundaries between two cells the graph knows but does not join: the graph keeps them shut."""
    if not graph.joined or not graph.free:
        return []
    free, tree = graph.free, graph.tree
    shut = []
    for door in doors:
        if door.geometry is None or door.geometry.geom_type not in ("LineString", "MultiLineString"):
            continue
        near = [free[i] for i in tree.query(door.geometry, predicate="dwithin", distance=max_gap)]
        sides = [c.id for c in near if _along(door.geometry, c)]
        if len(sides) < 2 or not all(n in graph.known for n in sides):
            continue  # an outside door, or a cell the graph is silent about
        if not any(frozenset((x, y)) in graph.joined for x in sides for y in sides if x != y):
            shut.append(door)
    return shut


def _along(line: BaseGeometry, cell: Cell) -> bool:
    """Whether ``cell`` lies along ``line`` (over at least half its length, at its own distance from it),
    not merely at one end: a cell round the corner of a door's wall is not a side the door joins, and a
    transition to it must not keep the door between two other cells open."""
    d = float(cell.footprint.distance(line))
    cover = shapely.intersection(line, shapely.buffer(cell.footprint, d + _TOUCH)).length
    return cover >= _ALONG * line.length
