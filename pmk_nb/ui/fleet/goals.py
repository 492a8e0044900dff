"""A chair's goals travel with it when control moves (issue 26, Fleet).

Home's Set destination (:class:`~pmk_nb.ui.goals.panel.GoalPanel`) and Go to
(:class:`~pmk_nb.ui.rooms.guide.RoomsGuide`) each follow one goal of the chair in control: its
handle, and the arrow or route drawn on the map.  When another chair takes control, those are
parked with the chair that was given them (the goal keeps running on it, and its row keeps saying
how it goes), and Home starts clean for the new chair: its Cancel button must never stop a chair
that is not in control, nor its map show another chair's route.  When control comes back, a goal
still running is shown again.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pmk_nb.ui.fleet.home_role import FleetHome


@dataclass(frozen=True)
class ParkedGoals:
    """What Home followed for one chair when control moved away from it."""

    goal: Any = None  # the tapped destination (goals.picker.Goal) and its handle
    handle: Any = None
    route: Any = None  # the Go to route (guide.route.Route) and its handle
    room_handle: Any = None

    def newest(self) -> Any:
        """The goal handle sent last (None: none)."""
        handles = [h for h in (self.handle, self.room_handle) if h is not None]
        return max(handles, key=lambda h: h.sent_at) if handles else None


def _running(handle: Any) -> bool:
    return handle is not None and not handle.progress().done


def park(home: FleetHome) -> ParkedGoals:
    """Take Home's goals (Set destination, Go to) away from it; returns them for the chair."""
    goal, rooms = home.goal, home.rooms
    parked = ParkedGoals(goal.goal, goal.handle, rooms.route, rooms.handle)
    goal.goal, goal.handle = None, None
    goal.overlay.set_goal(None)
    goal.refresh()
    rooms.route, rooms.handle = None, None
    rooms.overlay.clear_route()
    return parked


def resume(home: FleetHome, parked: ParkedGoals | None) -> None:
    """Give Home back a chair's goals that still run (an ended one stays in the chair's row only)."""
    if parked is None:
        return
    goal, rooms = home.goal, home.rooms
    if _running(parked.handle):
        goal.goal, goal.handle = parked.goal, parked.handle
        goal.overlay.set_goal(parked.goal)
        goal.refresh()
    if _running(parked.room_handle) and parked.route is not None:
        rooms.route, rooms.handle = parked.route, parked.room_handle
        rooms.overlay.set_route(parked.route.points, parked.route.goal[:2])
