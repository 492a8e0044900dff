"""Home's rooms widgets: "You are in: …", a searchable "Go to…" list of this storey's rooms, Go / Cancel.

Only widgets and their arrangement; :mod:`pmk_nb.ui.rooms.guide` gives them behaviour. The CSS
classes (``pmk-rooms-*``) are what the browser test finds.
"""

from __future__ import annotations

import ipywidgets as w

from pmk_nb.ui.common.widgets import TOUCH_PX, button, escape, heading, html_slot

HERE_PREFIX = "You are in:"


class RoomsPanel:
    """``here`` goes in the info panel; ``widget`` (the Go to… box) under the map."""

    def __init__(self) -> None:
        self.here = html_slot("pmk-rooms-here")
        self.here_name: str | None = None
        self.title = heading("Go to…")
        self.search = w.Text(
            value="",
            placeholder="Search rooms",
            continuous_update=True,
            layout=w.Layout(width="100%", max_width="420px", height=f"{TOUCH_PX - 8}px"),
        )
        self.search.add_class("pmk-rooms-search")
        # the tooltip is the list's accessible name (its ``title``): a Select without a description has none
        self.list = w.Select(
            options=[], rows=6, tooltip="Rooms to go to", layout=w.Layout(width="100%", max_width="420px")
        )
        self.list.add_class("pmk-rooms-list")
        self.go_button = button("Go", "pmk-rooms-go", icon="location-arrow", style="primary")
        self.cancel_button = button("Cancel", "pmk-rooms-cancel", icon="times", tooltip="Cancel the goal")
        self.status = html_slot("pmk-rooms-status")
        self.note = html_slot("pmk-rooms-note")
        row = w.HBox([self.go_button, self.cancel_button])
        row.add_class("pmk-row")
        self.widget = w.VBox([self.title, self.note, self.search, self.list, row, self.status])
        self.widget.add_class("pmk-rooms")
        self.show_goal(False)

    def show_here(self, name: str | None) -> None:
        self.here_name = name  # Home's one-line status says it too
        self.here.value = "" if name is None else f"{HERE_PREFIX} <b>{escape(name)}</b>"

    def set_rooms(self, labels: list[str]) -> None:
        if list(self.list.options) == labels:
            return  # typing on in the search box: the same rooms, keep the user's pick untouched
        keep = self.list.value
        self.list.options = labels
        self.list.value = keep if keep in labels else (labels[0] if labels else None)

    def show_goal(self, active: bool) -> None:
        """Cancel while a goal runs, Go otherwise."""
        self.cancel_button.layout.display = "" if active else "none"
        self.go_button.disabled = active

    def show_available(self, available: bool, why: str = "") -> None:
        """The list and buttons only when the map has rooms; else the reason."""
        shown = "" if available else "none"
        for item in (self.search, self.list, self.go_button):
            item.layout.display = shown
        self.note.value = "" if available else f"<span class='pmk-rooms-none'>{escape(why)}</span>"

    def say(self, text: str, level: str = "info") -> None:
        self.status.value = f"<span class='pmk-rooms-{level}'>{escape(text)}</span>" if text else ""
