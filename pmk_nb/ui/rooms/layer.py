"""The live view's rooms overlay: room names where they fit on screen, the planned route, the goal.

Drawn on the dynamic layer after the chair (:meth:`pmk_nb.ui.live.view.LiveView.overlays`), so the
names stay readable over the map: a name shows only when its room is wide enough on screen for the
text (at a whole-building zoom a small room's name would cover its neighbours), in dark text on a
light halo. The route is a dashed green polyline through the doorways; the goal a green ring.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ipycanvas import Canvas

    from pmk_nb.viewport import Viewport

NAME_FONT_PX = 14
CHAR_PX = 0.6 * NAME_FONT_PX  # average width of a character of the font, for the fit test
NAME_STYLE = "rgba(20, 40, 70, 0.95)"
HALO_STYLE = "rgba(255, 255, 255, 0.85)"
ROUTE_RGB = "rgb(0, 150, 70)"  # green: where the chair will go
GOAL_RADIUS_PX = 9.0


@dataclass
class RoomsOverlay:
    """What to draw: room labels (name, anchor x, y, room width and height in metres), route, goal.

    The screen code sets it; the render loop reads it (a lock keeps a frame from seeing half).
    ``version`` changes with every change, so a frame with new rooms or a new route is not skipped.
    """

    labels: list[tuple[str, float, float, float, float]] = field(default_factory=list)
    route: list[tuple[float, float]] = field(default_factory=list)
    goal: tuple[float, float] | None = None
    show_names: bool = True
    version: int = 0
    _lock: threading.Lock = field(default_factory=threading.Lock, repr=False)

    def set_labels(self, labels: list[tuple[str, float, float, float, float]]) -> None:
        with self._lock:
            self.labels = list(labels)
            self.version += 1

    def set_route(self, route: list[tuple[float, float]], goal: tuple[float, float] | None) -> None:
        with self._lock:
            self.route, self.goal = list(route), goal
            self.version += 1

    def clear_route(self) -> None:
        self.set_route([], None)

    def visible_labels(self, view: Viewport) -> list[tuple[str, float, float]]:
        """(name, pixel x, pixel y) of the labels whose room is wide enough on screen for the name."""
        with self._lock:
            labels = list(self.labels) if self.show_names else []
        if not labels:
            return []
        xs, ys = np.array([lb[1] for lb in labels]), np.array([lb[2] for lb in labels])
        px, py = view.world_to_pixel(xs, ys)
        ppm = view.px_per_m
        out = []
        for (name, _x, _y, wid, hei), u, v in zip(labels, np.asarray(px), np.asarray(py), strict=True):
            fits = wid * ppm >= len(name) * CHAR_PX + 8 and hei * ppm >= NAME_FONT_PX + 4
            if fits and -50 <= u <= view.canvas_width + 50 and -20 <= v <= view.canvas_height + 20:
                out.append((name, float(u), float(v)))
        return out

    def draw(self, layer: Canvas, view: Viewport) -> None:
        """Draw on ``layer`` (inside the frame's ``hold_canvas``)."""
        with self._lock:
            route, goal = list(self.route), self.goal
        if len(route) >= 2:
            px, py = view.world_to_pixel(np.array([p[0] for p in route]), np.array([p[1] for p in route]))
            pts = np.stack([np.asarray(px, dtype=float), np.asarray(py, dtype=float)], axis=1)
            layer.line_width = 4
            layer.stroke_style = ROUTE_RGB
            layer.set_line_dash([10, 6])
            layer.stroke_lines(pts)
            layer.set_line_dash([])
            layer.line_width = 1
        if goal is not None:
            gx, gy = view.world_to_pixel(goal[0], goal[1])
            layer.line_width = 4
            layer.stroke_style = ROUTE_RGB
            layer.stroke_circle(float(gx), float(gy), GOAL_RADIUS_PX)
            layer.line_width = 1
        names = self.visible_labels(view)
        if names:
            layer.font = f"bold {NAME_FONT_PX}px sans-serif"
            layer.text_align = "center"
            layer.text_baseline = "middle"
            layer.line_width = 4
            layer.stroke_style = HALO_STYLE
            layer.fill_style = NAME_STYLE
            for name, u, v in names:
                layer.stroke_text(name, u, v)
                layer.fill_text(name, u, v)
            layer.line_width = 1
