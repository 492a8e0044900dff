"""Routes over the building's navigation graph: door to door, through rooms the chair fits.

The graph's transitions are the truth about where one may pass; the accessibility check
(:func:`pmk_nb.access.check_storey` on the written map, for this chair's width) says which of them
the chair fits through. A route is a shortest walk over the passable transitions, measured from
the chair through each doorway's middle to a goal well inside the destination room. When the
destination is reachable only through transitions too narrow for the chair, the error names them.

The chair's own planner (Nav2, move_base, the simulator) drives on the map; it gets the goal
alone, plus the doorways as waypoints when the storey has passages the graph and the chair disagree
about (a door too narrow for the chair, or a leak between rooms), where its planner could pick a
way the route does not take.
"""

from __future__ import annotations

import heapq
import itertools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from pmk_nb.access import DEFAULT_CHAIR_WIDTH
from pmk_nb.guide.errors import NoAccessibleRoute, NoGraph, NotOnMap, RouteError, UnknownRoom
from pmk_nb.guide.goal import goal_in_room

if TYPE_CHECKING:
    from pmk_nb.access import LinkCheck, StoreyReport
    from pmk_nb.guide.rooms import Room, RoomsMap
    from pmk_nb.openings import Opening

__all__ = ["NoAccessibleRoute", "NotOnMap", "Route", "RouteError", "UnknownRoom", "plan_route"]

Point = tuple[float, float]
Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Route:
    """How to get from where the chair is to a room.

    Attributes:
        start: the room the chair is in.
        destination: the room to go to.
        rooms: every cell passed, start and destination included (doors too).
        points: the polyline to draw, map frame: the chair, each doorway, the goal.
        goal: ``(x, y, yaw)`` inside the destination, facing the way the chair came in.
        waypoints: ``(x, y, yaw)`` at the doorways passed (the goal not included).
        needs_waypoints: send the waypoints too (see the module's docstring).
        length: metres along ``points``.
    """

    start: Room
    destination: Room
    rooms: list[Room]
    points: list[Point]
    goal: Pose
    waypoints: list[Pose] = field(default_factory=list)
    needs_waypoints: bool = False

    @property
    def length(self) -> float:
        return sum(math.dist(a, b) for a, b in itertools.pairwise(self.points))

    @property
    def goal_waypoints(self) -> list[Pose]:
        """What to send before the goal: the doorways when the chair's planner needs them, else none."""
        return list(self.waypoints) if self.needs_waypoints else []


def _middle(o: Opening) -> Point:
    seg = max(o.segments, key=lambda s: s.length)
    p = seg.interpolate(0.5, normalized=True)
    return (float(p.x), float(p.y))


def _walk(
    rooms: RoomsMap, start: Room, start_xy: Point, dest: Room, ok: dict[str, bool]
) -> list[tuple[str, Opening]] | None:
    """Dijkstra over cells: the cell, and the point it was entered at; edges are openings with
    ``ok[link]``. Returns the (cell entered, opening) steps, or None when ``dest`` is not reached."""
    adj: dict[str, list[tuple[str, Opening]]] = {}
    for o in rooms.openings:
        if ok.get(o.link.id, False):
            adj.setdefault(o.link.a, []).append((o.link.b, o))
            adj.setdefault(o.link.b, []).append((o.link.a, o))
    best = {start.id: 0.0}
    came: dict[str, tuple[str, Opening]] = {}
    at: dict[str, Point] = {start.id: start_xy}
    todo = [(0.0, start.id)]
    while todo:
        d, cell = heapq.heappop(todo)
        if cell == dest.id:
            steps = []
            while cell != start.id:
                prev, o = came[cell]
                steps.append((cell, o))
                cell = prev
            return steps[::-1]
        if d > best.get(cell, math.inf):
            continue
        for nxt, o in adj.get(cell, []):
            mid = _middle(o)
            nd = d + math.dist(at[cell], mid)
            if nd < best.get(nxt, math.inf):
                best[nxt], came[nxt], at[nxt] = nd, (cell, o), mid
                heapq.heappush(todo, (nd, nxt))
    return None


def _door_label(rooms: RoomsMap, check: LinkCheck) -> str:
    """A narrow passage in the user's words: the door cell's name, else "A - B"."""
    for cid, name in zip(check.cells, check.names, strict=True):
        room = rooms.by_id(cid)
        if room.kind.is_door:
            return name
    return f"{check.names[0]} - {check.names[1]}"


def _unchecked_into(report: StoreyReport, cell: str) -> list[str]:
    """The not-checked links (one cell not free) that touch ``cell``'s part of the storey: the cells a
    point reaches from it through the map. A door misjudged as a window shows up here."""
    adj: dict[str, list[str]] = {}
    for k in report.links:
        if k.point:
            adj.setdefault(k.cells[0], []).append(k.cells[1])
            adj.setdefault(k.cells[1], []).append(k.cells[0])
    seen, todo = {cell}, [cell]
    while todo:
        for nxt in adj.get(todo.pop(), []):
            if nxt not in seen:
                seen.add(nxt)
                todo.append(nxt)
    return [k.describe() for k in report.not_checked if seen & set(k.cells)]


def _heading(a: Point, b: Point) -> float:
    return math.atan2(b[1] - a[1], b[0] - a[0]) if math.dist(a, b) > 1e-6 else 0.0


def _doorways(rooms: RoomsMap, steps: list[tuple[str, Opening]]) -> list[Point]:
    """One point per doorway: a door cell's middle for the two openings around it, else the opening's."""
    points: list[Point] = []
    skip_next = False
    for i, (cell, o) in enumerate(steps):
        if skip_next:
            skip_next = False
            continue
        room = rooms.by_id(cell)
        if room.kind.is_door and i + 1 < len(steps):
            c = room.polygon.representative_point() if not room.polygon.contains(room.polygon.centroid) else None
            p = c or room.polygon.centroid
            points.append((round(float(p.x), 3), round(float(p.y), 3)))
            skip_next = True
        else:
            points.append(_middle(o))
    return points


def plan_route(
    rooms: RoomsMap, start_xy: Point, destination: str | Room, chair_width: float = DEFAULT_CHAIR_WIDTH
) -> Route:
    """The route from ``start_xy`` (the chair, map frame) to ``destination`` (a name, id or Room).

    Raises:
        UnknownRoom: no room by that name.
        NotOnMap: the chair is in no room of this storey.
        NoAccessibleRoute: only passages too narrow for the chair lead there (they are named), or none.
        NoGraph: the plan gives no navigation graph on this storey.
        RouteError: the room has no free spot the chair fits in.
    """
    dest = destination if not isinstance(destination, str) else rooms.room(destination)
    start = rooms.room_at(*start_xy)
    if start is None:
        raise NotOnMap(*start_xy)
    report = rooms.access(chair_width)
    if not report.graph and start.id != dest.id:
        raise NoGraph(dest.label)
    checks = {k.link: k for k in report.links}
    steps = [] if start.id == dest.id else _walk(rooms, start, start_xy, dest, {k: c.chair for k, c in checks.items()})
    if steps is None:
        by_point = _walk(rooms, start, start_xy, dest, {k: c.point for k, c in checks.items()})
        narrow: dict[str, float] = {}  # a door cell has two openings: name it once, at its narrowest
        for _, o in by_point or []:
            check = checks[o.link.id]
            if not check.chair:
                label = _door_label(rooms, check)
                narrow[label] = min(narrow.get(label, math.inf), check.free_width)
        raise NoAccessibleRoute(dest.label, list(narrow.items()), chair_width, _unchecked_into(report, dest.id))
    spot = goal_in_room(rooms, dest, chair_width)
    if spot is None:
        raise RouteError(f"{dest.label}: no free spot in the map where a {chair_width:.2f} m chair fits")
    doors = _doorways(rooms, steps)
    points = [(float(start_xy[0]), float(start_xy[1])), *doors, spot]
    headings = [_heading(a, b) for a, b in itertools.pairwise(points)]
    waypoints = [(x, y, headings[i + 1]) for i, (x, y) in enumerate(doors)]
    goal = (spot[0], spot[1], headings[-1])
    cells = [start, *(rooms.by_id(c) for c, _ in steps)]
    needs = bool(report.narrow or report.leaks)
    return Route(start, dest, cells, points, goal, waypoints, needs)


def narrow_passages(rooms: RoomsMap, chair_width: float = DEFAULT_CHAIR_WIDTH) -> list[tuple[str, float]]:
    """Every passage of the storey the chair does not fit through, by name, with its free width."""
    return [(_door_label(rooms, k), k.free_width) for k in rooms.access(chair_width).links if k.point and not k.chair]
