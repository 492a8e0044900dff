"""What the Fleet panel uses of Home, as a Protocol: Home makes the panel, so the panel names Home by
this part (its live view, its bar, its Set destination and Go to, and its preview to start and stop)
instead of importing the screen (no import cycle, type-only ones included).
:class:`~pmk_nb.ui.home.screen.HomeScreen` is the one implementation.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from pmk_nb.ui.goals.panel import GoalPanel
    from pmk_nb.ui.home.layout import HomeLayout
    from pmk_nb.ui.live.view import LiveView
    from pmk_nb.ui.rooms.guide import RoomsGuide


class FleetHome(Protocol):
    """Home as the Fleet panel drives it: the chair in control is shown there, its goals parked there."""

    @property
    def live(self) -> LiveView: ...

    @property
    def ui(self) -> HomeLayout: ...

    @property
    def goal(self) -> GoalPanel: ...

    @property
    def rooms(self) -> RoomsGuide: ...

    @property
    def running(self) -> bool: ...

    def start_preview(self) -> bool: ...

    def stop_preview(self) -> None: ...
