"""Map tools on the live canvas: scale bar, grid, pointer coordinates, Measure and Set pose (issue 29).

What a researcher used to RViz or Foxglove expects on a map. The maths is in the pure
:mod:`pmk_nb.viewport.maptools`; this draws it as one of :attr:`LiveView.map_overlays` (scale bar at
the lower left, always; grid lines when Grid is on) and holds the tools' buttons and read-out:

* the pointer's (mouse or one finger) position in the map frame, in the read-out;
* **Measure**: tap two points, the read-out says the distance in metres (a third tap starts again);
* **Set pose**: tap where the chair is, then tap the way it faces; that publishes ``/initialpose``
  (:meth:`pmk_nb.chair.link.client.ChairLink.set_initial_pose`, as RViz's 2D Pose Estimate) and
  the tool turns itself off. It changes the chair's localisation, so a locked kiosk refuses it.

Both tools are drag-free (taps only: a wobbling finger or a drag longer than :data:`TAP_PX` counts as
nothing), and while one is on, taps go to it instead of panning (pinch zoom stays).
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import ipywidgets as w
import numpy as np

from pmk_nb.errors import PmkError
from pmk_nb.ui.common.widgets import TOUCH_PX, escape
from pmk_nb.viewport import coordinates_text, distance, grid_lines, grid_spacing, heading, pixel_to_map, scale_bar

if TYPE_CHECKING:
    from ipycanvas import Canvas

    from pmk_nb.chair.link import PoseLink
    from pmk_nb.ui.common.context import AppContext
    from pmk_nb.ui.live.view import LiveView
    from pmk_nb.viewport import Viewport

Point = tuple[float, float]
TAP_PX = 12.0  # a press and release further apart is a drag, not a tap
SCALE_MAX_PX = 120.0  # the scale bar's room on screen
GRID_STYLE = "rgba(40, 110, 200, 0.35)"
TOOL_RGB = "rgb(230, 120, 0)"  # orange: measured points and the pose being set
TOOLS: tuple[tuple[str, str], ...] = (("Pan", "pan"), ("Measure", "measure"), ("Set pose", "pose"))


class TapPicker:
    """Press / move / release -> ``on_tap(map point)`` for taps only (see :data:`TAP_PX`)."""

    def __init__(self, view: Callable[[], Viewport | None], on_tap: Callable[[Point], object]) -> None:
        self._view, self._on_tap = view, on_tap
        self.start: Point | None = None
        self.end: Point | None = None

    @property
    def active(self) -> bool:
        return self.start is not None

    def press(self, point: Point | None) -> None:
        self.start = self.end = point

    def move(self, point: Point | None) -> None:
        if self.start is not None and point is not None:
            self.end = point

    def abort(self) -> None:
        self.start = self.end = None

    def release(self, point: Point | None = None) -> None:
        start, end = self.start, point or self.end
        self.start = self.end = None
        view = self._view()
        if start is None or end is None or view is None or math.dist(start, end) > TAP_PX:
            return
        where = pixel_to_map(view, *start)
        if where is not None:
            self._on_tap(where)


class MapToolsOverlay:
    """Scale bar, grid and the tools' marks: a map overlay (:attr:`LiveView.map_overlays`), drawn with the
    map when the view changes or ``version`` does, not in every frame of a moving chair."""

    def __init__(self) -> None:
        self.version = 0
        self.grid_on = False
        self.grid_spacing: float | None = None  # None: auto (lines >= 40 px apart)
        self.points: list[Point] = []  # the measured or pose points tapped so far
        self.mode = "pan"
        self.scale_label = ""  # the scale bar's text at the last frame (the read-out shows it too)
        self._lock = threading.Lock()

    def set(self, **changes: Any) -> None:
        with self._lock:
            for name, value in changes.items():
                setattr(self, name, value)
            self.version += 1

    def draw(self, layer: Canvas, view: Viewport) -> None:
        with self._lock:
            grid_on, spacing, points, mode = self.grid_on, self.grid_spacing, list(self.points), self.mode
        if grid_on:
            _draw_grid(layer, view, spacing)
        if points and mode in ("measure", "pose"):
            _draw_points(layer, view, points, mode)
        self.scale_label = _draw_scale_bar(layer, view)


def _draw_grid(layer: Canvas, view: Viewport, spacing: float | None) -> None:
    vertical, horizontal = grid_lines(view, grid_spacing(view.px_per_m, spacing))
    w_px, h_px = float(view.canvas_width), float(view.canvas_height)
    segs = [((px, 0.0), (px, h_px)) for _m, px in vertical] + [((0.0, py), (w_px, py)) for _m, py in horizontal]
    if segs:
        layer.line_width = 1
        layer.stroke_style = GRID_STYLE
        layer.stroke_line_segments(np.array(segs, dtype=float))


def _draw_points(layer: Canvas, view: Viewport, points: list[Point], mode: str) -> None:
    px, py = view.world_to_pixel(np.array([p[0] for p in points]), np.array([p[1] for p in points]))
    xy = [(float(a), float(b)) for a, b in zip(np.atleast_1d(px), np.atleast_1d(py), strict=True)]
    layer.line_width = 3
    layer.stroke_style = TOOL_RGB
    layer.fill_style = TOOL_RGB
    if len(xy) == 2:
        layer.stroke_line(*xy[0], *xy[1])
    for x, y in xy:
        layer.fill_circle(x, y, 5.0)
    if len(xy) == 2 and mode == "measure":
        mid = ((xy[0][0] + xy[1][0]) / 2, (xy[0][1] + xy[1][1]) / 2 - 10)
        _halo_text(layer, f"{distance(points[0], points[1]):.2f} m", *mid)
    layer.line_width = 1


def _draw_scale_bar(layer: Canvas, view: Viewport) -> str:
    bar = scale_bar(view.px_per_m, min(SCALE_MAX_PX, 0.4 * view.canvas_width))
    # the bottom-left corner of the part no panel covers: above Home's status pill, beside a left-hand
    # Drive panel (issue 40: the pill covered the bar, drawn at the canvas's own corner)
    ux, uy, _uw, uh = view.insets.uncovered(view.canvas_width, view.canvas_height)
    x0, y0 = float(ux) + 12.0, float(uy + uh) - 14.0
    layer.line_width = 6
    layer.stroke_style = "rgba(255, 255, 255, 0.85)"
    layer.stroke_line(x0, y0, x0 + bar.pixels, y0)
    layer.line_width = 3
    layer.stroke_style = "rgb(20, 20, 20)"
    layer.stroke_lines([(x0, y0 - 5), (x0, y0), (x0 + bar.pixels, y0), (x0 + bar.pixels, y0 - 5)])
    layer.line_width = 1
    _halo_text(layer, bar.label, x0 + bar.pixels / 2, y0 - 12)
    return bar.label


def _halo_text(layer: Canvas, text: str, x: float, y: float) -> None:
    layer.font = "bold 13px sans-serif"
    layer.text_align = "center"
    layer.text_baseline = "middle"
    layer.line_width = 4
    layer.stroke_style = "rgba(255, 255, 255, 0.9)"
    layer.fill_style = "rgb(20, 20, 20)"
    layer.stroke_text(text, x, y)
    layer.fill_text(text, x, y)
    layer.line_width = 1


class MapTools:
    """The tools' widgets (``widget``: mode buttons, Grid, read-out) wired to a :class:`LiveView`.

    Args:
        live: the live view drawn on and read from.
        ctx: the session (the kiosk lock for Set pose); None outside the app (notebooks, tests).
    """

    def __init__(self, live: LiveView, ctx: AppContext | None = None) -> None:
        self.live, self.ctx = live, ctx
        self.link: PoseLink | None = None
        self.overlay = MapToolsOverlay()
        live.map_overlays.append(self.overlay)
        self.picker = TapPicker(lambda: live.viewport, self._on_tap)
        self.mode = w.ToggleButtons(
            options=list(TOOLS),
            value="pan",
            tooltips=["Drag to pan", "Tap two points", "Tap where the chair is, then the way it faces"],
        )
        self.mode.style.button_width = "124px"  # "Set pose" in full at the kiosk's font
        self.mode.add_class("pmk-tools-mode")
        self.grid = w.ToggleButton(value=False, description="Grid", icon="th", tooltip="Grid lines in the map frame")
        self.grid.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="96px")
        self.grid.add_class("pmk-tools-grid")
        self.scale = w.HTML("")
        self.scale.add_class("pmk-tools-scale")
        self.pointer = w.HTML("")
        self.pointer.add_class("pmk-tools-pointer")
        self.readout = w.HTML("")
        self.readout.add_class("pmk-tools-readout")
        rows = [w.HBox([self.mode, self.grid, self.scale]), w.HBox([self.pointer, self.readout])]
        for row in rows:
            row.add_class("pmk-row")  # wraps on a narrow screen (the app's style sheet)
            row.layout.align_items = "center"
        self.widget = w.VBox(rows)
        self.widget.add_class("pmk-tools")
        self.mode.observe(self._on_mode, names="value")
        self.grid.observe(self._on_grid, names="value")
        live.gestures.on_point = self._on_pointer
        live.on_zoom_change(lambda _z: self.refresh_scale())
        self.refresh_scale()

    def attach(self, link: PoseLink | None) -> None:
        """The chair link Set pose publishes on (None: Set pose says it needs the preview)."""
        self.link = link

    def refresh_scale(self) -> None:
        """The scale bar's length in words, beside the buttons (the bar itself is on the canvas)."""
        view = self.live.viewport
        if view is not None:
            label = scale_bar(view.px_per_m, min(SCALE_MAX_PX, 0.4 * view.canvas_width)).label
            self.scale.value = f"Scale bar: <b>{escape(label)}</b>"

    # -- callbacks (front-end values are untrusted) ---------------------------------------------
    def _on_mode(self, change: dict[str, Any]) -> None:
        mode = change.get("new")
        mode = mode if isinstance(mode, str) and mode in {value for _l, value in TOOLS} else "pan"
        gestures = self.live.gestures
        if mode == "pan":
            if gestures.picker is self.picker:
                gestures.picker = None
        else:
            gestures.picker = self.picker
        self.picker.abort()
        self.overlay.set(mode=mode, points=[])
        self.readout.value = {
            "pan": "",
            "measure": "Tap two points to measure the distance between them.",
            "pose": "Tap where the chair is, then tap the way it faces.",
        }[mode]
        self.live.request_redraw()

    def _on_grid(self, change: dict[str, Any]) -> None:
        self.overlay.set(grid_on=change.get("new") is True)
        self.live.request_redraw()

    def _on_pointer(self, point: Point | None) -> None:
        view = self.live.viewport
        where = pixel_to_map(view, *point) if view is not None and point is not None else None
        if where is not None:
            self.pointer.value = f"<span class='pmk-tools-xy'>{coordinates_text(where)}</span>"

    def _on_tap(self, where: Point) -> None:
        points = [*self.overlay.points, where]
        if len(points) > 2:
            points = [where]
        mode = self.overlay.mode
        self.overlay.set(points=points)
        if mode == "measure":
            self.readout.value = (
                f"Distance: <b class='pmk-tools-distance'>{distance(points[0], points[1]):.2f} m</b>"
                if len(points) == 2
                else f"From {coordinates_text(where)}: tap the second point."
            )
        elif mode == "pose" and len(points) == 2:
            self._send_pose(points[0], heading(points[0], points[1]))
        elif mode == "pose":
            self.readout.value = f"Chair at {coordinates_text(where)}: now tap the way it faces."
        self.live.request_redraw()

    def _send_pose(self, at: Point, yaw: float) -> None:
        self.mode.value = "pan"  # one pose per press, as Set destination
        try:
            sent = self.set_initial_pose(at[0], at[1], yaw)
        except (PmkError, ValueError) as err:
            self.readout.value = f"<span class='pmk-warn'>Initial pose not sent: {escape(err)}</span>"
            return
        where = f"({at[0]:.2f}, {at[1]:.2f}), heading {round(math.degrees(yaw))}°"
        self.readout.value = (
            f"<span class='pmk-tools-pose-sent'>Initial pose sent: {where}</span>"
            if sent
            else "<span class='pmk-warn'>Initial pose not sent: start the preview (connect the chair) first.</span>"
        )

    def set_initial_pose(self, x: float, y: float, yaw: float) -> bool:
        """Publish ``/initialpose`` through the attached link; False without one (or not connected).

        Raises:
            KioskLocked: on a locked kiosk page (it changes where the chair thinks it is).
        """
        if self.ctx is not None:
            self.ctx.require_unlocked("Setting the initial pose")
        link = self.link
        return bool(link is not None and link.set_initial_pose(x, y, yaw))
