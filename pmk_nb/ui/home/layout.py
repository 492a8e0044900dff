"""The Home screen's widgets and their arrangement; no behaviour beyond showing and hiding.

The map is the screen (issue 28): the live canvas takes the whole width and the rest of the
window's height (:mod:`pmk_nb.ui.home.fit` sizes it), and everything else floats over it: one
compact tool bar along the top (``toolbar``; its ``controls`` box is the one container other
features append their buttons to, see :meth:`HomeLayout.add_tool`, with Follow / Centre and the
zoom buttons at its right end), one short status line along the bottom (where, speed, what the
chair is doing) and, on demand (**Details**), a card with the full text panel.  The CSS classes
(``pmk-home-*``) are what the style sheet (:mod:`pmk_nb.ui.home.style`) and the browser tests find.
"""

from __future__ import annotations

import ipywidgets as w

from pmk_nb.ui.common.widgets import TOUCH_PX, button, heading, html_slot


class HomeInfoPanel:
    """The Home screen's part of the information panel: map, state, position, speed, zoom."""

    def __init__(self) -> None:
        self.map = html_slot("pmk-home-info-map")
        self.state = html_slot("pmk-home-info-state")
        self.pos = html_slot("pmk-home-info-pos")
        self.speed = html_slot("pmk-home-info-speed")
        self.zoom = html_slot("pmk-home-info-zoom")
        self.laser = html_slot("pmk-home-info-laser")
        self.widget = w.VBox([self.map, self.state, self.pos, self.speed, self.zoom, self.laser])
        self.widget.add_class("pmk-home-info")


class HomeLayout:
    """Every widget of the Home screen; ``widget`` is the screen, ``info.widget`` its info panel part.

    Args:
        canvas: the live view's canvas, placed under the toolbar.
        live_tools: the live view's own buttons (Follow, Centre), placed before the zoom buttons.
    """

    def __init__(self, canvas: w.DOMWidget, live_tools: w.DOMWidget | None = None) -> None:
        self.canvas = canvas
        self.live_tools = live_tools
        self.map_label = html_slot("pmk-home-map")
        self.map_note = html_slot("pmk-home-map-note")
        self.chair_note = html_slot("pmk-home-chair-note")
        self.warning = html_slot("pmk-home-warning")
        self.status = html_slot("pmk-home-status")
        self.preview_button = button("Preview", "pmk-home-preview", icon="play", style="success")
        # not red and not "Disconnect": it stops only this page's preview, never the chair (a red
        # square reads as an emergency stop, which it is not)
        self.disconnect_button = button(
            "Stop preview",
            "pmk-home-disconnect",
            icon="pause",
            tooltip="Stop the live preview (the chair is not affected)",
        )
        # a toggle button rather than a checkbox: the whole 56 px control is the touch target
        self.sensors = w.ToggleButton(
            value=True, description="Show sensors", icon="eye", tooltip="Show the laser readings on the map"
        )
        self.sensors.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="160px")
        self.sensors.add_class("pmk-home-sensors")
        self.zoom_in_button = button("", "pmk-home-zoom-in", icon="search-plus", tooltip="Zoom in", width="64px")
        self.zoom_out_button = button("", "pmk-home-zoom-out", icon="search-minus", tooltip="Zoom out", width="64px")
        for btn in (self.zoom_in_button, self.zoom_out_button):
            btn.layout.min_width = f"{TOUCH_PX}px"
        # details on demand: the map's name, the warnings' context and the text panel, over the map
        self.details_toggle = w.ToggleButton(
            value=False, description="Details", icon="info-circle", tooltip="Show position, speed and state in full"
        )
        self.details_toggle.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width=f"{TOUCH_PX}px")
        self.details_toggle.add_class("pmk-home-details-toggle")
        self.details_toggle.observe(self._on_details, names="value")
        self.statusline = html_slot("pmk-home-statusline")
        self.info = HomeInfoPanel()
        self.widget = self._arrange()

    def _arrange(self) -> w.VBox:
        # one floating bar: the screen's controls (others append to ``controls``) and, at its right
        # end, the view's own tools and the zoom buttons; it wraps on a narrow screen
        tools = [self.live_tools] if self.live_tools is not None else []
        self.zoom_bar = w.HBox([*tools, self.zoom_out_button, self.zoom_in_button])
        self.zoom_bar.add_class("pmk-home-zoom")
        self.controls = w.HBox([self.preview_button, self.disconnect_button, self.sensors, self.details_toggle])
        self.controls.add_class("pmk-home-controls")
        self.toolbar = w.HBox([self.controls, self.zoom_bar])
        self.toolbar.add_class("pmk-home-toolbar")
        title = heading("Home")
        title.add_class("pmk-home-details-title")
        head = w.HBox([title, self.map_label])
        head.add_class("pmk-home-details-head")
        self.details = w.VBox([head, self.info.widget])
        self.details.add_class("pmk-home-details")
        self.details.layout.display = "none"
        # the canvas in a box of its own, everything over the map placed in it (the joystick too)
        self.map_stack = w.Box([self.canvas, self.toolbar, self.details, self.statusline])
        self.map_stack.add_class("pmk-home-map-stack")
        self.preview_box = w.VBox([self.map_stack])
        self.preview_box.add_class("pmk-home-preview-box")
        screen = w.VBox([self.map_note, self.chair_note, self.warning, self.preview_box, self.status])
        screen.add_class("pmk-home")
        return screen

    def add_tool(self, widget: w.DOMWidget) -> None:
        """Put ``widget`` (a button, 48 px or more) in the floating bar, before Details."""
        kids = list(self.controls.children)
        at = kids.index(self.details_toggle) if self.details_toggle in kids else len(kids)
        self.controls.children = (*kids[:at], widget, *kids[at:])

    def _on_details(self, change: dict[str, object]) -> None:
        on = change.get("new") is True  # a page may send anything: only a real True opens
        self.details.layout.display = "flex" if on else "none"
        self.details_toggle.icon = "times" if on else "info-circle"

    def show_running(self, running: bool, *, can_preview: bool) -> None:
        """Preview while stopped (if there is a map to preview); the live controls while running.

        The map, its zoom and its Follow / Centre buttons show whenever there is a map, live or not.
        """
        self.preview_button.layout.display = "" if not running and can_preview else "none"
        live = "" if running else "none"
        self.disconnect_button.layout.display = live
        self.sensors.layout.display = live
        has_map = "" if running or can_preview else "none"
        self.zoom_bar.layout.display = has_map
        self.canvas.layout.display = has_map
