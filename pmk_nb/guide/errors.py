"""The guide's errors: types with the facts a screen needs to say why (never text to match)."""

from __future__ import annotations

from pmk_nb.errors import PmkError


class RouteError(PmkError):
    """No route to a room (base of the guide's errors)."""


class UnknownRoom(RouteError):
    """No room of this storey has that name or id.

    Attributes:
        query: what was asked for.
        storey: the storey searched.
    """

    def __init__(self, query: str, storey: str) -> None:
        super().__init__(f"no room called {query!r} on storey {storey}", hint="Pick a room from the list.")
        self.query = query
        self.storey = storey


class NoAccessibleRoute(RouteError):
    """The room exists but the chair cannot get there.

    Attributes:
        room: the destination's name.
        narrow: ``(door name, free width in metres)`` of the doors on the best way in that are too
            narrow for the chair (empty when there is no way at all, even for a point).
        chair_width: the chair's width the rules were applied with (metres).
        not_checked: the transitions into the room's part of the storey that the map has no way through
            because one cell is not free (a window or sill by its floor height, or non-navigable in the
            file), as "A <-> B (why)": when the file says there is a door, this is where to look.
    """

    def __init__(
        self, room: str, narrow: list[tuple[str, float]], chair_width: float, not_checked: list[str] | None = None
    ) -> None:
        if narrow:
            doors = ", ".join(f"{name} ({width:.2f} m)" for name, width in narrow)
            why = f"too narrow for the {chair_width:.2f} m chair: {doors}"
        else:
            why = "the map has no way there (no passable transition joins it to where the chair is)"
        unchecked = list(not_checked or [])
        if unchecked:
            why += f"; not checked, the map has no way through: {', '.join(unchecked)}"
        super().__init__(f"no accessible route to {room}: {why}")
        self.room = room
        self.narrow = narrow
        self.chair_width = chair_width
        self.not_checked = unchecked


class NoGraph(RouteError):
    """The building plan gives no navigation graph on this storey (States but no Transitions, as in
    some editors' exports): rooms can be named but no route planned between them.

    Attributes:
        room: the destination's name.
    """

    def __init__(self, room: str) -> None:
        super().__init__(
            f"no route to {room}: the building plan has no navigation graph (no transitions) on this storey",
            hint="Tap the destination on the map instead (Set destination): the chair's own planner finds the way.",
        )
        self.room = room


class NotOnMap(RouteError):
    """The chair's position is in no room of this storey (off the map, or the map is not this one).

    Attributes:
        x, y: the position, map frame, metres.
    """

    def __init__(self, x: float, y: float) -> None:
        super().__init__(
            f"the chair at ({x:.2f}, {y:.2f}) m is in no room of this map",
            hint="Check that the chair runs the map shown on Home.",
        )
        self.x = x
        self.y = y
