"""Where walls go and where doors open them: the vector geometry step before rasterising.

Rooms' rings become wall lines except where a door sits (door cells and door boundaries cut them,
found per room with an R-tree); door cells keep walls only on their jambs; each door gets a short
"passage" segment across the wall so the opening survives any resolution. Many files leave the wall
itself out, as a gap between cells: :func:`gap_walls` finds those gaps so they are drawn occupied.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from pmk_nb.geometry import door_frame, grown_box, polygon_parts, polygons_of
from pmk_nb.indoorgml import CellKind

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Boundary, Building, Cell, Link


def door_geometry(
    building: Building, storey: str, cells: list[Cell], skip: list[Boundary] | None = None
) -> tuple[list[Any], list[Any]]:
    """(door polygons, door lines) of a storey: door cells and door boundaries, but those in ``skip``."""
    polys = [c.footprint for c in cells if c.kind.is_door]
    lines: list[Any] = []
    skipped = {b.id for b in skip or []}
    geoms = [b.geometry for b in building.doors_of(storey) if b.id not in skipped and b.geometry is not None]
    if not geoms:
        return polys, lines
    parts = shapely.get_parts(np.asarray(geoms, dtype=object))  # in boundary order, as before
    kinds, areas, lengths = shapely.get_type_id(parts), shapely.area(parts), shapely.length(parts)
    for part, kind, area, length in zip(parts.tolist(), kinds.tolist(), areas.tolist(), lengths.tolist(), strict=True):
        if kind == 3 and area > 1e-9:
            polys.append(part)
        elif kind == 3 and not part.is_empty:  # a vertical surface seen from above: a line
            lines.append(shapely.LineString(part.exterior.coords))
        elif kind in (1, 2) and length > 0:
            lines.append(part)
    return polys, lines


def door_gaps(door_lines: list[Any], rooms: list[Any], max_gap: float) -> np.ndarray:
    """Per door line, how far it must reach to join a room on each side (0 when rooms share its edge).

    Some files model the wall between rooms as a gap, with the door line in the middle of it or on
    one room's edge; the wall cut and the opening must then reach across that gap. Each side of the
    line counts its nearest room only, so a third room further off never widens the opening, and a
    side with no room within ``max_gap`` (an outside door) counts 0.
    """
    gaps = np.zeros(len(door_lines))
    if not door_lines or not rooms:
        return gaps
    lines, room_arr = np.asarray(door_lines, dtype=object), np.asarray(rooms, dtype=object)
    tree = shapely.STRtree(room_arr)
    try:
        chords = _chords(lines)
        # fast path, the common case: rooms on both sides touch the line at its middle (1 mm probes)
        p0, p1 = (shapely.get_coordinates(shapely.get_point(chords, i)) for i in (0, -1))
        mid, d = (p0 + p1) / 2, p1 - p0
        normal = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.hypot(d[:, 0], d[:, 1])[:, None] * 1e-3
        both = np.ones(len(lines), dtype=bool)
        for probe in (mid + normal, mid - normal):
            hit = np.zeros(len(lines), dtype=bool)
            hit[tree.query(shapely.points(probe), predicate="intersects")[0]] = True
            both &= hit
        todo = np.flatnonzero(~both)
        for side in (1.0, -1.0):  # the strip left, then right, of each other door line
            strips = shapely.buffer(chords[todo], side * max_gap, single_sided=True, cap_style="flat")
            li, ri = tree.query(strips, predicate="intersects")
            near = np.full(len(todo), np.inf)
            parts = shapely.intersection(room_arr[ri], strips[li])
            inside = shapely.area(parts) > 1e-9  # a room merely touching the line lies on the other side
            np.minimum.at(near, li[inside], shapely.distance(chords[todo[li[inside]]], parts[inside]))
            gaps[todo] = np.maximum(gaps[todo], np.where(np.isfinite(near), near, 0.0))
    except shapely.errors.GEOSException:  # degenerate room geometry: the farthest room near the line
        pairs = tree.query(lines, predicate="dwithin", distance=max_gap)
        if pairs.shape[1]:
            np.maximum.at(gaps, pairs[0], shapely.distance(lines[pairs[0]], room_arr[pairs[1]]))
    return np.nan_to_num(gaps)


def _chords(lines: np.ndarray) -> np.ndarray:
    """Each line as one straight segment, from its first point to the point farthest from it: a door
    boundary taken from a vertical surface runs along the door and back, which has no left or right."""
    out = lines.copy()
    bent = np.flatnonzero(shapely.get_num_coordinates(lines) > 2)  # most door lines are one segment already
    if len(bent) == 0:
        return out
    coords, index = shapely.get_coordinates(lines[bent], return_index=True)
    groups = np.split(coords, np.cumsum(np.bincount(index, minlength=len(bent)))[:-1])
    for i, xy in zip(bent.tolist(), groups, strict=True):
        far = int(np.argmax(np.hypot(xy[:, 0] - xy[0, 0], xy[:, 1] - xy[0, 1])))
        out[i] = shapely.LineString([xy[0], xy[far]]) if far else lines[i]
    return out


def gap_walls(footprints: list[Any], door_lines: list[Any], gaps: np.ndarray, max_gap: float, tol: float) -> Any:
    """The regions between cells narrower than ``max_gap``: walls the file models as gaps.

    A mitre closing of the union of the storey's cells (grow by ``max_gap / 2``, shrink back) fills
    exactly where cells grown from two sides meet: gaps between cells up to ``max_gap`` wide, holes
    and notches narrower than that. Wider gaps (courtyards, light wells) stay open, and with mitre
    joins a building's own corners (convex or concave, e.g. the inner corner of an L) come back
    unchanged, so nothing outside the building is filled. Door boundaries cut the filled region
    along their length, as far as the rooms they join (``gaps``, from :func:`door_gaps`); door cells
    are cells, so they stay open by construction. Slivers from round-off are dropped.

    Returns a Polygon / MultiPolygon (empty when there is nothing to fill).
    """
    empty = shapely.Polygon()
    if max_gap <= 0 or not footprints:
        return empty
    valid = shapely.is_valid(np.asarray(footprints, dtype=object))
    polys = polygon_parts([g if ok else shapely.make_valid(g) for g, ok in zip(footprints, valid, strict=True)])
    if not polys:
        return empty
    try:
        union = _union(np.asarray(polys, dtype=object))
        # door cuts are made (and unioned) only where they meet the filled region: most files have no gaps
        cuts = (np.asarray(door_lines, dtype=object), np.asarray(gaps, dtype=np.float64) + tol) if door_lines else None
        # GEOS's mitre buffers occasionally lose their way for one exact radius (a shrink that leaves
        # metres of grown area behind); a piece thicker than max_gap is such an artefact, and a radius
        # a few micrometres larger usually computes cleanly, so try a few before giving up on a piece.
        good: list[Any] = []
        for extra in (1e-6, 2.3e-6, 4.1e-6, 7.7e-6):
            good, bad = _gap_pieces(union, cuts, max_gap / 2 + extra, tol)
            if not bad:
                break
    except shapely.errors.GEOSException:  # degenerate input geometry: draw the gaps as before
        return empty
    return shapely.MultiPolygon(good) if good else empty


def _union(polys: np.ndarray) -> Any:
    """The union of a storey's cells: a coverage union when the cells tile without overlaps (fast),
    otherwise the full overlay."""
    try:
        if len(polys) > 64 and shapely.coverage_is_valid(polys):
            return shapely.coverage_union_all(polys)
    except (shapely.errors.GEOSException, shapely.errors.UnsupportedGEOSVersionError):
        pass
    return shapely.union_all(polys)


def _gap_pieces(union: Any, cuts: Any, r: float, tol: float) -> tuple[list[Any], int]:
    """(pieces of the mitre closing of ``union`` by ``r`` not in ``union``, count of implausible pieces)."""
    with np.errstate(divide="ignore", invalid="ignore"):  # GEOS on near-degenerate corners; checked below
        closed = shapely.buffer(shapely.buffer(union, r, join_style="mitre"), -r, join_style="mitre")
    fill = shapely.difference(closed, union)
    if cuts is not None and not fill.is_empty:
        lines, widths = cuts
        cand = shapely.STRtree(lines).query(fill, predicate="dwithin", distance=float(widths.max()) + 1e-9)
        near = shapely.buffer(lines[cand], widths[cand], cap_style="flat")
        near = near[shapely.intersects(near, fill)]
        if len(near):
            fill = shapely.difference(fill, shapely.union_all(near))
    parts = np.asarray(polygons_of(fill), dtype=object)
    if len(parts) == 0:
        return [], 0
    # mean width 2 * area / perimeter: round-off slivers along shared edges are far below 0.1 mm
    width = 2 * shapely.area(parts) / np.maximum(shapely.length(parts), 1e-12)
    parts = parts[width > 1e-4]
    # a gap wall is at most 2 r thick: a piece that holds a wider disc is a buffer artefact
    with np.errstate(divide="ignore", invalid="ignore"):
        too_thick = ~shapely.is_empty(shapely.buffer(parts, -(r + max(tol, 1e-6)), join_style="mitre"))
    return parts[~too_thick].tolist(), int(too_thick.sum())


def wall_lines(
    rooms: list[Any], door_polys: list[Any], door_lines: list[Any], gaps: np.ndarray, tol: float
) -> list[Any]:
    """Rings of free cells minus the stretches doors occupy; door cells keep their jambs only."""
    room_arr = np.asarray(rooms, dtype=object)
    lines = shapely.boundary(room_arr) if len(room_arr) else np.empty(0, dtype=object)
    if (door_polys or door_lines) and len(lines):
        # each ring minus only the doors near it: one small difference per room, found by an R-tree
        cuts = np.concatenate(
            [
                shapely.buffer(np.asarray(door_polys, dtype=object), tol),
                shapely.buffer(np.asarray(door_lines, dtype=object), gaps + tol, cap_style="flat"),
            ]
        )
        pairs = shapely.STRtree(cuts).query(lines, predicate="intersects")
        lines = lines.copy()
        order = np.argsort(pairs[0], kind="stable")
        rooms_hit, starts = np.unique(pairs[0][order], return_index=True)
        groups = np.split(pairs[1][order], starts[1:]) if len(rooms_hit) else []
        # one vectorised difference per round: round k takes each room's k-th nearby cut
        sizes = np.array([len(g) for g in groups], dtype=np.int64)
        for k in range(int(sizes.max(initial=0))):
            has = sizes > k
            rooms_k = rooms_hit[has]
            cut_k = np.array([g[k] for g, h in zip(groups, has.tolist(), strict=True) if h], dtype=np.int64)
            lines[rooms_k] = shapely.difference(lines[rooms_k], cuts[cut_k])
    out = [g for g in lines.tolist() if g is not None and not g.is_empty]
    return out + door_jambs(room_arr, door_polys, tol)


def door_jambs(room_arr: np.ndarray, door_polys: list[Any], tol: float) -> list[Any]:
    """Door cells' outlines minus where they meet rooms or other door cells: the jambs."""
    out: list[Any] = []
    if not door_polys:
        return out
    tree = shapely.STRtree(room_arr) if len(room_arr) else None
    touching = _doors_within(door_polys, tol)
    arr = np.asarray(door_polys, dtype=object)
    grown, rings = shapely.buffer(arr, tol).tolist(), shapely.boundary(arr).tolist()  # array calls, not one each
    for i, ring in enumerate(rings):
        near = [door_polys[j] for j in touching[i]]
        if tree is not None:
            near += list(room_arr[tree.query(grown[i], predicate="intersects")])
        if near:
            ring = shapely.difference(ring, shapely.buffer(shapely.union_all(near), tol))
        if not ring.is_empty:
            out.append(ring)
    return out


def _doors_within(door_polys: list[Any], tol: float) -> list[list[int]]:
    """Per door polygon, the other door polygons at most ``tol`` away, in list order.

    An R-tree picks the candidates (bounding boxes within 2 ``tol``, so no pair at ``tol`` is lost to
    round-off) and the exact distance decides, as the pairwise test did: linear in the doors, not
    quadratic.
    """
    arr = np.asarray(door_polys, dtype=object)
    left, right = shapely.STRtree(arr).query(grown_box(arr, 2 * tol + 1e-9))
    keep = left != right
    left, right = left[keep], right[keep]
    keep = shapely.distance(arr[right], arr[left]) <= tol
    out: list[list[int]] = [[] for _ in door_polys]
    for i, j in sorted(zip(left[keep].tolist(), right[keep].tolist(), strict=True)):
        out[i].append(j)
    return out


def shrink_segments(segments: np.ndarray, by: float) -> np.ndarray:
    """Segments shortened by ``by`` at both ends (never past their midpoint)."""
    p0, p1 = segments[:, 0:2], segments[:, 2:4]
    d = p1 - p0
    length = np.hypot(d[:, 0], d[:, 1])[:, None]
    cut = np.minimum(by, length / 2) / np.where(length > 0, length, 1.0)
    return np.hstack([p0 + d * cut, p1 - d * cut])


def door_neighbours(door_cells: list[Cell], rooms: list[Cell], links: list[Link], reach: float) -> list[Any | None]:
    """Per door cell, the cells the graph links it to within 2 ``reach``, as one geometry; for a door cell
    the graph never names (a file without a graph), every nearby cell counts as linked. None for an
    entrance (AnchorSpace): every side opens, the outside too. (The other cells near it are not
    unioned: nothing asks for them, and a union each was a tenth of a large storey's door step.)"""
    linked: dict[str, set[str]] = {}
    for k in links:
        linked.setdefault(k.a, set()).add(k.b)
        linked.setdefault(k.b, set()).add(k.a)
    others = rooms + door_cells
    tree = shapely.STRtree([c.footprint for c in others]) if others else None
    out: list[Any | None] = []
    for door in door_cells:
        mine = linked.get(door.id)
        if door.kind is CellKind.ANCHOR or tree is None:
            out.append(None)
            continue
        hits = tree.query(door.footprint, predicate="dwithin", distance=2 * reach).tolist()
        near = [others[i] for i in hits if others[i].id != door.id]
        out.append(shapely.union_all([c.footprint for c in near if not mine or c.id in mine]))
    return out


def passages(
    door_polys: list[Any],
    door_segs: np.ndarray,
    seg_reach: np.ndarray,
    reach: float,
    sides: list[Any | None] | None = None,
) -> np.ndarray:
    """Segments across each door (perpendicular to the wall), ``reach`` beyond it on both sides.

    ``sides`` (from :func:`door_neighbours`, one per leading door polygon: the cells it is linked to)
    keeps a door cell's passage inside the door on a side where no cell it is linked to lies: the graph
    decides, and a door cell 0.13 m from a room it has no transition to must not join it (a leak); nor
    may a door cell standing out of the outer wall reach into the unknown outside (unless it is an
    entrance: ``sides`` None).
    """
    d = door_segs[:, 2:4] - door_segs[:, 0:2]
    length = np.hypot(d[:, 0], d[:, 1])
    keep = length > 0
    mid = (door_segs[keep, 0:2] + door_segs[keep, 2:4]) / 2
    normal = np.stack([-d[keep, 1], d[keep, 0]], axis=1) / length[keep, None] * seg_reach[keep, None]
    segs: list[np.ndarray] = [np.hstack([mid - normal, mid + normal])]
    for i, poly in enumerate(door_polys):
        for part in polygons_of(poly):
            frame = door_frame(part)
            if frame is None:
                continue
            c, short, long_ = frame
            ls = float(np.hypot(*short))
            if ls == 0 or np.hypot(*long_) < 1.3 * ls:
                continue  # no clear wall direction: the polygon fill alone opens it
            u = short / ls
            ends = [ls / 2 + reach, ls / 2 + reach]
            near = sides[i] if sides is not None and i < len(sides) else None
            for k, sign in enumerate((-1.0, 1.0)) if near is not None else ():
                probe = shapely.LineString([c + sign * u * ls / 2, c + sign * u * (ls / 2 + 2 * reach)])
                if not probe.intersects(near):
                    ends[k] = 0.0  # no cell the graph links on this side (or none at all): stop mid-door
            a, b = c - u * ends[0], c + u * ends[1]
            segs.append(np.array([[a[0], a[1], b[0], b[1]]]))
    return np.vstack(segs)
