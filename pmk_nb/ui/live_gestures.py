"""The live canvas's zoom gestures: mouse wheel and two-finger pinch, mapped to zoom levels.

Front-end events are untrusted input (any page can send any JSON): garbage is ignored, never
raised.  The zoom rules themselves (clamping, pinch ratio -> level) live in the pure
:class:`pmk_nb.viewport.Viewport`; this only turns events into "set the zoom to N".
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

from ipycanvas import MultiCanvas

WHEEL_INTERVAL = 0.15  # s between two wheel zoom steps (trackpads send bursts of events)


def pinch_distance(touches: object) -> float | None:
    """Distance in pixels between the first two touches, or None for anything else."""
    try:
        (x0, y0), (x1, y1) = list(touches)[:2]  # type: ignore[call-overload]
        d = math.hypot(float(x1) - float(x0), float(y1) - float(y0))
    except (TypeError, ValueError):
        return None
    return d if math.isfinite(d) and d > 0 else None


class ZoomGestures:
    """Listens to a canvas's wheel and touch events and asks for zoom levels.

    Args:
        canvas: the canvas whose (top layer's) events are read.
        zoom: the current zoom level.
        set_zoom: sets a zoom level (clamped by the viewport).
        pinch_zoom: ``(zoom at pinch start, finger distance ratio) -> level``, or None without a map.
    """

    def __init__(
        self,
        canvas: MultiCanvas,
        zoom: Callable[[], int],
        set_zoom: Callable[[int], object],
        pinch_zoom: Callable[[int, float], int | None],
    ) -> None:
        self._zoom = zoom
        self._set_zoom = set_zoom
        self._pinch_zoom = pinch_zoom
        #: (finger distance, zoom level) when the current pinch began
        self.pinch: tuple[float, int] | None = None
        self.last_wheel = 0.0
        canvas.on_mouse_wheel(self.on_wheel)
        canvas.on_touch_start(self.on_touch)
        canvas.on_touch_move(self.on_touch)
        canvas.on_touch_end(self.on_touch_end)
        canvas.on_touch_cancel(self.on_touch_end)

    def on_wheel(self, dx: object, dy: object) -> None:
        """One zoom step per wheel burst: wheel up (negative delta) zooms in."""
        try:
            delta = float(dy)  # type: ignore[arg-type]
        except (TypeError, ValueError):
            return
        now = time.monotonic()
        if not math.isfinite(delta) or delta == 0 or now - self.last_wheel < WHEEL_INTERVAL:
            return
        self.last_wheel = now
        self._set_zoom(self._zoom() + (1 if delta < 0 else -1))

    def on_touch(self, touches: object) -> None:
        """Two fingers: the zoom follows the ratio of finger distances since the pinch began."""
        dist = pinch_distance(touches)
        if dist is None:
            self.pinch = None
            return
        if self.pinch is None:
            self.pinch = (dist, self._zoom())
            return
        start_dist, start_zoom = self.pinch
        level = self._pinch_zoom(start_zoom, dist / start_dist)
        if level is None:
            self.pinch = None
            return
        self._set_zoom(level)

    def on_touch_end(self, touches: object) -> None:
        try:
            fingers = len(list(touches))  # type: ignore[call-overload]
        except TypeError:
            fingers = 0
        if fingers < 2:
            self.pinch = None
