"""Tap the map to set a destination, drag to give its heading; and the goal arrow drawn on the map.

No widgets here: :class:`GoalPicker` turns untrusted pointer events (canvas pixels) into a goal
(x, y, yaw) in the map frame through the pure :class:`pmk_nb.viewport.Viewport`; a tap without a
drag faces the goal away from the chair (the way it arrives). :class:`GoalOverlay` draws the goal
(and the arrow being dragged) on the live view's dynamic layer, as one of its ``overlays``.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ipycanvas import Canvas

    from pmk_nb.viewport import Viewport

MIN_DRAG_PX = 12.0  # a shorter drag is a tap (fingers wobble)
ARROW_PX = 34.0
GOAL_RGB = "rgb(200, 0, 160)"  # magenta: the tapped destination (rooms use green for their routes)
DRAG_STYLE = "rgba(200, 0, 160, 0.55)"
Goal = tuple[float, float, float]
Point = tuple[float, float]


def goal_from_pixels(
    view: Viewport,
    start: Point,
    end: Point,
    chair: Point | None = None,
    min_drag_px: float = MIN_DRAG_PX,
    heading: float | None = None,
) -> Goal | None:
    """The goal for a press at ``start`` and release at ``end`` (canvas pixels); None if not finite.

    The heading is the drag's direction in the world; a tap takes ``heading`` (radians, map frame:
    chosen with a button, no drag needed) or else faces away from the chair (0 without one).
    """
    if not all(math.isfinite(v) for v in (*start, *end)):
        return None
    wx, wy = (float(v) for v in view.pixel_to_world(start[0], start[1]))
    if not (math.isfinite(wx) and math.isfinite(wy)):
        return None
    if math.dist(start, end) >= min_drag_px:
        ex, ey = (float(v) for v in view.pixel_to_world(end[0], end[1]))
        return wx, wy, math.atan2(ey - wy, ex - wx)
    if heading is not None and math.isfinite(heading):
        return wx, wy, float(heading)
    if chair is not None and math.dist(chair, (wx, wy)) > 1e-6:
        return wx, wy, math.atan2(wy - chair[1], wx - chair[0])
    return wx, wy, 0.0


class GoalPicker:
    """Press / move / release (canvas pixels or None) -> ``on_goal(x, y, yaw)`` once per gesture.

    Args:
        view: the live view's current viewport (None without a map: events are ignored).
        chair: the chair's (x, y) when known, for the heading of a plain tap.
        on_goal: called with the goal when the finger or button is lifted.
        on_change: called while dragging (the overlay shows the arrow).
    """

    def __init__(
        self,
        view: Callable[[], Viewport | None],
        chair: Callable[[], Point | None],
        on_goal: Callable[[Goal], object],
        on_change: Callable[[], object] = lambda: None,
    ) -> None:
        self._view, self._chair, self._on_goal, self._on_change = view, chair, on_goal, on_change
        self.start: Point | None = None
        self.end: Point | None = None
        #: the heading a plain tap gives (radians, map frame), chosen without a drag; None: automatic
        self.heading: float | None = None

    @property
    def active(self) -> bool:
        return self.start is not None

    def press(self, point: Point | None) -> None:
        if point is not None and self._view() is not None:
            self.start = self.end = point
            self._on_change()

    def move(self, point: Point | None) -> None:
        if self.start is not None and point is not None:
            self.end = point
            self._on_change()

    def abort(self) -> None:
        if self.start is not None:
            self.start = self.end = None
            self._on_change()

    def release(self, point: Point | None = None) -> None:
        start, end = self.start, point or self.end
        self.start = self.end = None
        view = self._view()
        if start is None or end is None or view is None:
            return
        goal = goal_from_pixels(view, start, end, self._chair(), heading=self.heading)
        self._on_change()
        if goal is not None:
            self._on_goal(goal)

    def preview(self) -> Goal | None:
        """The goal the current drag would set (for drawing), else None."""
        view, start, end = self._view(), self.start, self.end
        if view is None or start is None or end is None:
            return None
        return goal_from_pixels(view, start, end, self._chair(), heading=self.heading)


class GoalOverlay:
    """The destination arrow (and the one being dragged) for :attr:`LiveView.overlays`."""

    def __init__(self, picker: GoalPicker | None = None) -> None:
        self.picker = picker
        self.goal: Goal | None = None
        self.version = 0
        self._lock = threading.Lock()

    def set_goal(self, goal: Goal | None) -> None:
        with self._lock:
            self.goal = goal
            self.version += 1

    def changed(self) -> None:
        with self._lock:
            self.version += 1

    def draw(self, layer: Canvas, view: Viewport) -> None:
        with self._lock:
            goal = self.goal
        dragged = self.picker.preview() if self.picker is not None else None
        for g, style in ((goal, GOAL_RGB), (dragged, DRAG_STYLE)):
            if g is not None:
                _arrow(layer, view, g, style)


def _arrow(layer: Canvas, view: Viewport, goal: Goal, style: str) -> None:
    px, py = (float(v) for v in view.world_to_pixel(goal[0], goal[1]))
    # the heading on screen: a world point 1 m ahead, so any axis flip of the view is respected
    hx, hy = (float(v) for v in view.world_to_pixel(goal[0] + math.cos(goal[2]), goal[1] + math.sin(goal[2])))
    angle = math.atan2(hy - py, hx - px)
    tip = (px + ARROW_PX * math.cos(angle), py + ARROW_PX * math.sin(angle))
    wing = 0.45 * ARROW_PX
    left = (tip[0] - wing * math.cos(angle - 0.5), tip[1] - wing * math.sin(angle - 0.5))
    right = (tip[0] - wing * math.cos(angle + 0.5), tip[1] - wing * math.sin(angle + 0.5))
    layer.line_width = 4
    layer.stroke_style = style
    layer.fill_style = style
    layer.stroke_line(px, py, tip[0], tip[1])
    layer.fill_polygon([tip, left, right])
    layer.stroke_circle(px, py, 8.0)
    layer.line_width = 1
