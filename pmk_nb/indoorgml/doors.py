"""Which boundaries are doors, and which layers carry the building's geometry.

Doors, in order of evidence: a navi ConnectionBoundary/AnchorBoundary/NavigableBoundary/
TransferBoundary; a boundary that is the dual of a Transition (a passable boundary); a name,
id or description saying "door"; and, for bare CellSpaceBoundaries (PNU 313 writes doors only as
short LineStrings on a room's outline, with no name, type or duality), a boundary that covers only
part of the cell edge it lies on - a full edge is a wall, a partial one an opening.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable

import shapely
from shapely.geometry import LineString, Point
from shapely.geometry.base import BaseGeometry

DOOR_TYPES = {"connectionboundary", "anchorboundary", "navigableboundary", "transferboundary"}
DOOR_WORD = re.compile(r"door|t(?:ü|ue)r|porta|puerta|출입문", re.IGNORECASE)
CORRIDOR_WORD = re.compile(r"corridor|hall|flur|gang|korridor|diele|lobby|passage|복도|로비|통로", re.IGNORECASE)
PARTIAL = 0.9  # a boundary shorter than 90 % of the outline edge it sits on is an opening
NEAR = 0.15  # a boundary within 15 % of its length from an outline lies on it (hand-drawn doors)


def says_door(*texts: str) -> bool:
    return any(DOOR_WORD.search(t or "") for t in texts)


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
    ends = [Point(line.coords[0]), Point(line.coords[-1])]
    mid = line.interpolate(0.5, normalized=True)
    found = False
    for poly in cells:
        for ring in _rings(poly):
            run = _wall_run(list(ring.coords), mid, ends, eps)
            if run is None:
                continue
            found = True
            if run <= line.length / PARTIAL:
                return False
    return found


def _wall_run(coords: list[tuple[float, ...]], mid: Point, ends: list[Point], eps: float) -> float | None:
    """Length of the straight outline run holding ``mid`` (None if the line is not on this ring)."""
    pts = [c[:2] for c in coords[:-1]] if coords and coords[0] == coords[-1] else [c[:2] for c in coords]
    n = len(pts)
    if n < 2:
        return None
    segs = [(pts[i], pts[(i + 1) % n]) for i in range(n)]
    hit = next((i for i, (a, b) in enumerate(segs) if LineString([a, b]).distance(mid) <= eps), None)
    if hit is None:
        return None

    def direction(i: int) -> tuple[float, float]:
        (ax, ay), (bx, by) = segs[i % n]
        d = math.hypot(bx - ax, by - ay) or 1.0
        return (bx - ax) / d, (by - ay) / d

    base = direction(hit)
    lo = hi = hit
    while hi - lo < n - 1 and _parallel(direction(hi + 1), base):
        hi += 1
    while hi - lo < n - 1 and _parallel(direction(lo - 1), base):
        lo -= 1
    run = LineString([segs[lo % n][0], segs[hi % n][1]])
    if not all(run.distance(p) <= eps for p in ends):
        return None
    return run.length


def _parallel(u: tuple[float, float], v: tuple[float, float]) -> bool:
    return u[0] * v[0] + u[1] * v[1] > math.cos(math.radians(3.0))


def _rings(poly: BaseGeometry) -> list[LineString]:
    out: list[LineString] = []
    for part in shapely.get_parts(poly):
        if hasattr(part, "exterior"):
            out.append(part.exterior)
            out.extend(part.interiors)
    return out


def overlap_fraction(candidate: list[BaseGeometry], base: list[BaseGeometry]) -> float:
    """Share of ``candidate``'s area already covered by ``base`` (0 when either is empty)."""
    if not candidate or not base:
        return 0.0
    a = shapely.union_all(candidate)
    if a.area <= 0:
        return 0.0
    return float(a.intersection(shapely.union_all(base)).area / a.area)
