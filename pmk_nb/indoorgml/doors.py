"""Which boundaries are doors, and which layers carry the building's geometry.

Doors, in order of evidence: a navi ConnectionBoundary/AnchorBoundary/NavigableBoundary/
TransferBoundary; a name, id or description saying "door" (one saying "window" is wall, unless a
transition is dual to it); for bare CellSpaceBoundaries (PNU 313 writes doors only as short
LineStrings on a room's outline, with no name, type or duality), a boundary that covers only part
of the cell edge it lies on - a full edge is a wall, a partial one an opening; and a boundary that
is the dual of a Transition (a passable boundary).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable

import numpy as np
import shapely
from shapely.geometry import LineString
from shapely.geometry.base import BaseGeometry

DOOR_TYPES = {"connectionboundary", "anchorboundary", "navigableboundary", "transferboundary"}
DOOR_WORD = re.compile(r"door|t(?:ü|ue)r|porta|puerta|출입문", re.IGNORECASE)
# a window in any language exporters write: no door, whatever its length (Fenstertür included)
WINDOW_WORD = re.compile(r"window|fenster|fen[eê]tre|finestra|ventana|janela|okno|창문|창호|窗|窓", re.IGNORECASE)
# an entrance, said of a boundary (not of a cell: an "entrance hall" is a room)
ENTRANCE_WORD = re.compile(r"entrance|entry|eingang|entr[ée]e|ingresso|entrada|입구|出入口|入口", re.IGNORECASE)
CORRIDOR_WORD = re.compile(r"corridor|hall|flur|gang|korridor|diele|lobby|passage|복도|로비|통로", re.IGNORECASE)
PARTIAL = 0.9  # a boundary shorter than 90 % of the outline edge it sits on is an opening
NEAR = 0.15  # a boundary within 15 % of its length from an outline lies on it (hand-drawn doors)
DOOR_DEPTH = 1.0  # m: the deepest a door cell is (a leaf and its frame in a thick wall)
DOOR_SPAN = 4.0  # m: the widest a door cell is (a wide double or sliding door; pnu_abc's Door1 is 3.05 m)


def says_door(*texts: str) -> bool:
    return any(DOOR_WORD.search(t or "") for t in texts)


def named_evidence(dual: bool, *texts: str) -> str | None:
    """A boundary's door evidence from its words (type, id, name, description), or None when they say
    nothing: a window is wall (``""``) unless a transition is dual to it (``"duality"``): a
    floor-to-ceiling window is short along its wall, but no way out; a door or entrance by name is
    ``"name"``."""
    if any(WINDOW_WORD.search(t or "") for t in texts):
        return "duality" if dual else ""
    return "name" if says_door(*texts) or any(ENTRANCE_WORD.search(t or "") for t in texts) else None


def rect_sides(geom: BaseGeometry) -> tuple[float, float]:
    """Short and long side of ``geom``'s minimum rotated rectangle: a cell's depth and width whatever its
    angle on the plan."""
    xy = shapely.get_coordinates(shapely.minimum_rotated_rectangle(geom))
    sides = sorted(math.dist(xy[i], xy[i + 1]) for i in range(min(2, len(xy) - 1)))
    return (sides[0], sides[-1]) if sides else (0.0, 0.0)


def door_sized(geom: BaseGeometry | None, scale: float, depth: bool = True) -> bool:
    """Whether a cell or boundary (file units, ``scale`` metres per unit) is no larger than a door: at most
    :data:`DOOR_SPAN` wide and (``depth``: a cell) :data:`DOOR_DEPTH` deep. A name saying "door" decides only
    for such a shape; a shape without geometry has no size to refute it."""
    if geom is None:
        return True
    short, long = rect_sides(geom)
    return long * scale <= DOOR_SPAN and (not depth or short * scale <= DOOR_DEPTH)


def named_doors(
    cells: Iterable[tuple[str, str, BaseGeometry]],
    boundaries: list[tuple[str, BaseGeometry | None]],
    scale: float,
    notes: list[str],
) -> tuple[set[str], list[str]]:
    """Which of the plain cells (id, name, footprint: no navi type says what they are) that their id or name
    calls a door, and of the boundaries (id, geometry) only their name calls one, are door-sized at ``scale``
    metres per file unit: (ids of door cells, ids of boundaries to keep as walls); ``notes`` gets what was
    decided. The name decides only then: a 5 x 4 m "Door-side lounge" is a room, and is listed."""
    cells = [(cid, name, geom) for cid, name, geom in cells if says_door(cid, name)]
    doors = {cid for cid, _, geom in cells if door_sized(geom, scale)}
    rooms = [f"{cid} ({name})" if name else cid for cid, name, _ in cells if cid not in doors]
    walls = [bid for bid, geom in boundaries if not door_sized(geom, scale, depth=False)]
    if doors:
        notes.append(f"{len(doors)} plain CellSpaces named 'door' treated as connection (door) cells")
    if rooms:
        notes.append(
            f"{len(rooms)} cells named 'door' kept as rooms: larger than a door ({DOOR_DEPTH:g} m deep, "
            f"{DOOR_SPAN:g} m wide): {rooms[:8]}"
        )
    if walls:
        notes.append(f"{len(walls)} boundaries named 'door' kept as walls: wider than {DOOR_SPAN:g} m: {walls[:8]}")
    return doors, walls


def says_corridor(*texts: str) -> bool:
    """A name saying corridor, hall or lobby: a space people pass through, open to its neighbours."""
    return any(CORRIDOR_WORD.search(t or "") for t in texts)


def partial_edge(line: BaseGeometry, cells: Iterable[BaseGeometry]) -> bool:
    """True if ``line`` lies on cell outlines and is clearly shorter than the straight wall there.

    Editors split outlines at door jambs, so the wall is the run of collinear outline segments
    around the one the boundary lies on. A boundary spanning a whole wall of any cell it touches
    is a wall, not an opening.
    """
    if not isinstance(line, LineString) or line.length <= 0:
        return False
    eps = max(NEAR * line.length, 1e-9)
    xy = shapely.get_coordinates(line)
    ends = (xy[0].tolist(), xy[-1].tolist())
    centre = line.interpolate(0.5, normalized=True)
    mid = shapely.get_coordinates(centre)[0]
    rings = shapely.get_rings(shapely.get_parts(list(cells)))
    found = False
    for ring in rings[shapely.dwithin(rings, centre, eps)]:  # one GEOS call keeps the few rings it lies on
        xy = shapely.get_coordinates(ring)
        run = _wall_run(xy[:-1] if len(xy) > 1 and (xy[0] == xy[-1]).all() else xy, mid, ends, eps)
        if run is None:
            continue
        found = True
        if run <= line.length / PARTIAL:
            return False
    return found


def _wall_run(pts: np.ndarray, mid: np.ndarray, ends: tuple[list[float], ...], eps: float) -> float | None:
    """Length of the straight outline run holding ``mid`` (None if the line is not on this ring).

    ``pts``: the ring's vertices, the closing one left out. Plain arrays, no shapely object per
    segment: outlines are walked for every candidate door line of the file."""
    n = len(pts)
    if n < 2:
        return None
    d = np.roll(pts, -1, axis=0) - pts
    near = np.flatnonzero(_segment_distances(pts, d, mid) <= eps)
    if not len(near):
        return None
    hit = int(near[0])
    length = np.hypot(d[:, 0], d[:, 1])
    unit = (d / np.where(length > 0, length, 1.0)[:, None]).tolist()
    base = unit[hit]
    lo = hi = hit
    while hi - lo < n - 1 and _parallel(unit[(hi + 1) % n], base):
        hi += 1
    while hi - lo < n - 1 and _parallel(unit[(lo - 1) % n], base):
        lo -= 1
    (ax, ay), (bx, by) = pts[lo % n].tolist(), pts[(hi + 1) % n].tolist()
    if not all(_point_segment(float(x), float(y), ax, ay, bx, by) <= eps for x, y in ends):
        return None
    return math.hypot(bx - ax, by - ay)


def _point_segment(x: float, y: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx, dy = bx - ax, by - ay
    den = dx * dx + dy * dy
    t = 0.0 if den <= 0 else min(1.0, max(0.0, ((x - ax) * dx + (y - ay) * dy) / den))
    return math.hypot(ax + t * dx - x, ay + t * dy - y)


def _segment_distances(a: np.ndarray, d: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Distance from point ``p`` to each segment a[i] -> a[i] + d[i]."""
    den = (d * d).sum(axis=1)
    t = np.clip(((p[0] - a[:, 0]) * d[:, 0] + (p[1] - a[:, 1]) * d[:, 1]) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    dist: np.ndarray = np.hypot(a[:, 0] + t * d[:, 0] - p[0], a[:, 1] + t * d[:, 1] - p[1])
    return dist


def _parallel(u: list[float], v: list[float]) -> bool:
    return u[0] * v[0] + u[1] * v[1] > _COS3


_COS3 = math.cos(math.radians(3.0))


def near(
    tree: shapely.STRtree, geoms: list[BaseGeometry], line: BaseGeometry, share: float = NEAR
) -> list[BaseGeometry]:
    """The ``geoms`` (indexed by ``tree``) within ``share`` of the line's length of it. Asked only by
    the rules that need it: on stacked 2D storeys every boundary is near a cell of each storey."""
    return [geoms[i] for i in tree.query(line, predicate="dwithin", distance=1e-6 + share * line.length)]


def continues_door(line: BaseGeometry, doors: list[BaseGeometry]) -> bool:
    """True if ``line`` runs on from one of ``doors`` (door lines marked by type or name) along the same
    straight wall: the piece of wall beside a door, which a file that splits its walls at the jambs
    writes as a short bare boundary. Its being short is then no sign of an opening."""
    if not isinstance(line, LineString) or line.length <= 0 or not doors:
        return False
    (ax, ay), (bx, by) = shapely.get_coordinates(line)[[0, -1]].tolist()
    u = [(bx - ax) / line.length, (by - ay) / line.length]
    eps = max(1e-3 * line.length, 1e-9)
    for door in doors:
        if not isinstance(door, LineString) or door.length <= 0 or line.distance(door) > eps:
            continue
        (cx, cy), (dx, dy) = shapely.get_coordinates(door)[[0, -1]].tolist()
        v = [(dx - cx) / door.length, (dy - cy) / door.length]
        off_line = abs(u[0] * (cy - ay) - u[1] * (cx - ax))  # the door's start from the line through ``line``
        if abs(u[0] * v[0] + u[1] * v[1]) > _COS3 and off_line <= eps:
            return True
    return False
