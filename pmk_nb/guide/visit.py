"""Send a chair to a room by name: plan the route, then hand the goal (and doorways) to its navigation.

Duck-typed on the link (``latest_pose``/``latest_odom`` and ``navigate_to``, as
:class:`pmk_nb.chair.link.client.ChairLink` has), so the guide stays free of the network code and
the dashboard and a notebook call the same function.
"""

from __future__ import annotations

from typing import Any, Protocol

from pmk_nb.access import DEFAULT_CHAIR_WIDTH
from pmk_nb.guide.errors import RouteError
from pmk_nb.guide.rooms import Room, RoomsMap
from pmk_nb.guide.route import Route, plan_route


class Navigator(Protocol):
    """What :func:`go_to` needs of a chair link."""

    def latest_pose(self) -> Any: ...
    def latest_odom(self) -> Any: ...
    def navigate_to(self, x: float, y: float, yaw: float, frame: str = "map", waypoints: Any = ()) -> Any: ...


def chair_xy(link: Navigator) -> tuple[float, float] | None:
    """Where the chair is now (map frame when the pose source gives it; odometry otherwise)."""
    pose = link.latest_pose() or link.latest_odom()
    return None if pose is None else (float(pose.x), float(pose.y))


def go_to(
    link: Navigator, rooms: RoomsMap, room: str | Room, chair_width: float = DEFAULT_CHAIR_WIDTH
) -> tuple[Route, Any]:
    """Plan the route from the chair to ``room`` and send the goal; returns (route, goal handle).

    Raises:
        RouteError: no pose from the chair yet, or no route (see :func:`pmk_nb.guide.plan_route`).
        NavigationError: the goal could not be sent (from the link).
    """
    where = chair_xy(link)
    if where is None:
        raise RouteError("no position from the chair yet", hint="Wait until the chair shows on the map.")
    route = plan_route(rooms, where, room, chair_width)
    doorways = [(x, y) for x, y, _ in route.goal_waypoints]
    return route, link.navigate_to(*route.goal, frame="map", waypoints=doorways)
