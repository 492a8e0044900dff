"""Go to a room in two taps: **Go to** in Home's tool bar, then the room (issue 28).

A card over the map lists the map's rooms as big buttons, favourites first, then the recent ones
(:class:`pmk_nb.ui.rooms.picks.RoomPicks`), then the rest; a star beside each room makes it a
favourite.  Tapping a room closes the card and sends the chair through the rooms guide (the same
``go`` as the Go to… list under the map: route, goal, speech).  The room a tap names is looked up
in the map's own rooms (a page can send any click), never taken from the page.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import TYPE_CHECKING

import ipywidgets as w

from pmk_nb.ui.common.widgets import TOUCH_PX, button, heading, html_slot
from pmk_nb.ui.rooms.picks import RoomPicks

if TYPE_CHECKING:
    from pmk_nb.ui.rooms.guide import RoomsGuide

log = logging.getLogger(__name__)
NO_ROOMS = "This map has no rooms by name: convert the building again on the Maps screen."
MAX_ROOMS = 60  # a storey with more rooms is searched in the Go to… list under the map


class RoomPicker:
    """``button`` goes in Home's tool bar, ``card`` over the map."""

    def __init__(self, guide: RoomsGuide, picks: RoomPicks, map_name: Callable[[], str | None]) -> None:
        self.guide = guide
        self.picks = picks
        self.map_name = map_name
        self.button = w.ToggleButton(value=False, description="Go to", icon="map-signs", tooltip="Go to a room")
        self.button.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width=f"{TOUCH_PX}px")
        self.button.add_class("pmk-home-goto")
        self.button.observe(self._on_toggle, names="value")
        self.note = html_slot("pmk-goto-note")
        self.rows = w.VBox([])
        self.rows.add_class("pmk-goto-rooms")
        self.close_button = button("Close", "pmk-goto-close", icon="times")
        self.close_button.on_click(lambda _b: self.close())
        self.card = w.VBox([heading("Go to…"), self.note, self.rows, self.close_button])
        self.card.add_class("pmk-home-goto-card")
        self.card.layout.display = "none"

    def set_stopped(self, stopped: bool) -> None:
        """A Stop holds for this chair (Home's tick, issue 38): Go to is greyed and its card closed;
        the guide refuses a goal anyway (the link's goal gate)."""
        if self.button.disabled != stopped:
            self.button.disabled = stopped
            if stopped:
                self.close()

    def rooms(self) -> list[str]:
        """The map's rooms in the picker's order (favourites, recent, the rest)."""
        rooms = self.guide.rooms
        if rooms is None:
            return []
        labels = [r.label for r in rooms.destinations()][:MAX_ROOMS]
        name = self.map_name()
        return self.picks.order(name, labels) if name else labels

    def open(self) -> None:
        """Show the card with the rooms (built now: the order follows the last picks)."""
        labels = self.rooms()
        name = self.map_name()
        favs = set(self.picks.favourites(name)) if name else set()
        recent = set(self.picks.recent(name)) if name else set()
        self.rows.children = tuple(self._row(label, label in favs, label in recent) for label in labels)
        self.note.value = "" if labels else NO_ROOMS
        self.card.layout.display = "flex"
        if not self.button.value:
            self.button.value = True

    def close(self) -> None:
        self.card.layout.display = "none"
        if self.button.value:
            self.button.value = False

    def _row(self, label: str, favourite: bool, recent: bool) -> w.HBox:
        go = button(label, "pmk-goto-room", icon="history" if recent and not favourite else "")
        go.on_click(lambda _b, room=label: self.pick(room))
        star = w.Button(
            description="",
            icon="star" if favourite else "star-o",
            tooltip=f"{'Remove' if favourite else 'Make'} {label} {'from' if favourite else 'a'} favourite"
            + ("s" if favourite else ""),
            layout=w.Layout(height=f"{TOUCH_PX}px", width=f"{TOUCH_PX}px"),
        )
        star.add_class("pmk-goto-fav")
        star.on_click(lambda _b, room=label: self.favourite(room))
        row = w.HBox([go, star])
        row.add_class("pmk-goto-row")
        return row

    def pick(self, room: str) -> bool:
        """The rider tapped ``room``: go there (a name not among the map's rooms is ignored)."""
        if room not in self.rooms():
            return False
        self.close()
        route = self.guide.go(room)
        if route is None:  # no route, no preview: the card again, saying why (the guide's words)
            self.open()
            self.note.value = self.guide.panel.status.value
            return False
        name = self.map_name()
        if name:
            try:
                self.picks.remember(name, room)
            except OSError as err:  # the settings folder is read-only: the chair still goes
                log.warning("remembering the room failed: %s", err)
        return True

    def favourite(self, room: str) -> None:
        name = self.map_name()
        if not name or room not in self.rooms():
            return
        try:
            self.picks.toggle_favourite(name, room)
        except OSError as err:
            log.warning("saving the favourite failed: %s", err)
        self.open()

    def _on_toggle(self, change: dict[str, object]) -> None:
        if change.get("new") is True:
            self.open()
        else:
            self.close()
