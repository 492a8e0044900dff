"""The navigation stack's planned path on the live map (issue 29): Nav2's /plan, move_base's plan.

An overlay of :class:`pmk_nb.ui.live.view.LiveView` (drawn after the chair, like the rooms route):
a solid blue line from the chair along the part of the path still ahead of it
(:func:`pmk_nb.viewport.path.ahead_of`), gone once the chair is at its end. The path comes
from :class:`~pmk_nb.chair.link.streams.planpath.PlanWatch` (its own throttled subscription); Home's info
timer calls :meth:`LivePathLayer.tick`, which only bumps ``version`` when the path or the chair's
place along it changed, so the render loop redraws then and skips otherwise.
"""

from __future__ import annotations

import threading
from typing import TYPE_CHECKING, Any

import numpy as np

from pmk_nb.chair.link import AUTO, LinkCore, PlanWatch
from pmk_nb.viewport import ahead_of

if TYPE_CHECKING:
    from ipycanvas import Canvas

    from pmk_nb.viewport import Viewport

PATH_RGB = "rgba(140, 50, 200, 0.85)"  # violet: the plan, unlike the blue chair (the rooms route: green, dashed)
PATH_WIDTH_PX = 3


class LivePathLayer:
    """The planned path overlay; ``attach(link, topic)`` starts following, ``attach(None)`` stops."""

    def __init__(self) -> None:
        self.version = 0
        self._lock = threading.Lock()
        self._points = np.empty((0, 2))
        self._link: LinkCore | None = None
        self._watch: PlanWatch | None = None
        self._seen: tuple[int, tuple[float, float] | None] | None = None

    @property
    def points(self) -> np.ndarray:
        """The path drawn now (world metres, (n, 2)); empty when there is none."""
        with self._lock:
            return self._points

    def attach(self, link: LinkCore | None, topic: str = AUTO) -> None:
        """Follow ``link``'s plan topic (None: stop and clear)."""
        if self._watch is not None:
            self._watch.stop()
        self._link = link
        self._watch = PlanWatch(topic, lookup=lambda: link.discovery.topics(timeout=3.0)) if link is not None else None
        self._set(np.empty((0, 2)))
        self._seen = None

    def tick(self, pose: Any) -> None:
        """From Home's info timer: (re)subscribe on the link's current socket, take the latest path."""
        watch, link = self._watch, self._link
        if watch is None or link is None:
            return
        watch.follow(link.ros if link.is_connected else None)
        path = watch.latest
        x, y = getattr(pose, "x", None), getattr(pose, "y", None)
        chair = (round(float(x), 2), round(float(y), 2)) if isinstance(x, float) and isinstance(y, float) else None
        key = (watch.count, chair)
        if key == self._seen:
            return
        self._seen = key
        self._set(ahead_of(path.points, chair) if path is not None else np.empty((0, 2)))

    def _set(self, points: np.ndarray) -> None:
        with self._lock:
            if points.shape == self._points.shape and np.array_equal(points, self._points):
                return
            self._points = points
            self.version += 1

    def draw(self, layer: Canvas, view: Viewport) -> None:
        """Draw on ``layer`` (inside the frame's ``hold_canvas``)."""
        pts = self.points
        if pts.shape[0] < 2:
            return
        px, py = view.world_to_pixel(pts[:, 0], pts[:, 1])
        line = np.stack([np.asarray(px, dtype=float), np.asarray(py, dtype=float)], axis=1)
        layer.line_width = PATH_WIDTH_PX
        layer.stroke_style = PATH_RGB
        layer.stroke_lines(line)
        layer.line_width = 1
