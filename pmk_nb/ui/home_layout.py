"""The Home screen's widgets and their arrangement; no behaviour beyond showing and hiding.

As in the original app (thesis 4.2.1.1, 5.2.3.4): the map's name as the title, warnings below it,
one toolbar row with Preview / Stop preview and Show sensors on the left and the zoom buttons at
the right end, right above the map's upper-right corner, then the live canvas.  On a narrow screen
the toolbar wraps rather than cutting its buttons short.  The CSS classes
(``pmk-home-*``) are what the kiosk page's style sheet and the browser test find.
"""

from __future__ import annotations

import ipywidgets as w

from pmk_nb.ui.widgets import TOUCH_PX, button, heading, html_slot


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
            value=True, description="Show sensors", icon="check", tooltip="Show the laser readings on the map"
        )
        self.sensors.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="160px")
        self.sensors.add_class("pmk-home-sensors")
        self.zoom_in_button = button("", "pmk-home-zoom-in", icon="search-plus", tooltip="Zoom in", width="64px")
        self.zoom_out_button = button("", "pmk-home-zoom-out", icon="search-minus", tooltip="Zoom out", width="64px")
        for btn in (self.zoom_in_button, self.zoom_out_button):
            btn.layout.min_width = f"{TOUCH_PX}px"
        self.info = HomeInfoPanel()
        self.widget = self._arrange()

    def _arrange(self) -> w.VBox:
        # the toolbar box is as wide as the canvas, which has the map's shape, so nothing floats in
        # an empty band
        # rows wrap on a narrow screen (gaps and wrapping in the style sheet) instead of squeezing
        # the buttons into "Disconn…"; the zoom buttons stay at the right end
        tools = [self.live_tools] if self.live_tools is not None else []
        self.zoom_bar = w.HBox([*tools, self.zoom_out_button, self.zoom_in_button])
        self.zoom_bar.add_class("pmk-home-zoom")
        self.controls = w.HBox(
            [self.preview_button, self.disconnect_button, self.sensors], layout=w.Layout(align_items="center")
        )
        self.controls.add_class("pmk-home-controls")
        self.toolbar = w.HBox(
            [self.controls, self.zoom_bar],
            layout=w.Layout(justify_content="space-between", align_items="center", width="100%"),
        )
        self.toolbar.add_class("pmk-home-toolbar")
        # the canvas in a box of its own: panels drawn over the map (the joystick) are placed in it
        self.map_stack = w.Box([self.canvas], layout=w.Layout(max_width="100%"))
        self.map_stack.add_class("pmk-home-map-stack")
        self.preview_box = w.VBox([self.toolbar, self.map_stack], layout=w.Layout(align_items="flex-start"))
        self.preview_box.add_class("pmk-home-preview-box")
        title = w.HBox([heading("Home"), self.map_label])
        title.add_class("pmk-home-title")
        screen = w.VBox([title, self.map_note, self.chair_note, self.warning, self.preview_box, self.status])
        screen.add_class("pmk-home")
        return screen

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
