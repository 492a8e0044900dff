"""The live canvas's gestures: wheel and two-finger pinch zoom, mouse and one-finger drag pan.

Front-end events are untrusted input (any page can send any JSON): garbage is ignored, never
raised.  The rules themselves (clamping, pinch ratio -> level, pan -> view, a pan stops following)
live in the pure :class:`pmk_nb.viewport.Viewport`; this only turns events into "set the zoom to
N" and "move the map by (dx, dy) pixels". While a :class:`PointPicker` is set (Home's "Set
destination"), press, drag and release go to it instead of the pan; pinch zoom stays.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

import ipywidgets as w
from ipycanvas import MultiCanvas

from pmk_nb.clock import MONOTONIC, Clock
from pmk_nb.ui.common.page_numbers import page_number
from pmk_nb.ui.common.widgets import TOUCH_PX, button

WHEEL_INTERVAL = 0.15  # s between two wheel zoom steps (trackpads send bursts of events)


def touch_point(touches: object) -> tuple[float, float] | None:
    """The first touch's (x, y) when exactly one finger is down, else None."""
    try:
        points = list(touches)  # type: ignore[call-overload]
        if len(points) != 1:
            return None
        x, y = points[0]
    except (TypeError, ValueError):
        return None
    return _point(x, y)


def pinch_distance(touches: object) -> float | None:
    """Distance in pixels between the first two touches, or None for anything else."""
    try:
        (x0, y0), (x1, y1) = list(touches)[:2]  # type: ignore[call-overload]
    except (TypeError, ValueError):
        return None
    first, second = _point(x0, y0), _point(x1, y1)
    if first is None or second is None:
        return None
    d = math.hypot(second[0] - first[0], second[1] - first[1])
    return d if d > 0 else None


class PointPicker(Protocol):
    """Takes pointer events instead of the pan (e.g. :class:`pmk_nb.ui.goals.picker.GoalPicker`)."""

    @property
    def active(self) -> bool: ...
    def press(self, point: tuple[float, float] | None) -> None: ...
    def move(self, point: tuple[float, float] | None) -> None: ...
    def release(self, point: tuple[float, float] | None = None) -> None: ...
    def abort(self) -> None: ...


class ZoomGestures:
    """Listens to a canvas's wheel, mouse and touch events and asks for zoom levels and pans.

    Args:
        canvas: the canvas whose (top layer's) events are read.
        zoom: the current zoom level.
        set_zoom: sets a zoom level (clamped by the viewport).
        pinch_zoom: ``(zoom at pinch start, finger distance ratio) -> level``, or None without a map.
        pan: moves the map by (dx, dy) canvas pixels; None: no drag to pan.
        clock: the wheel bursts' time (a ``VirtualClock`` in tests).
    """

    def __init__(
        self,
        canvas: MultiCanvas,
        zoom: Callable[[], int],
        set_zoom: Callable[[int], object],
        pinch_zoom: Callable[[int, float], int | None],
        pan: Callable[[float, float], object] | None = None,
        *,
        clock: Clock = MONOTONIC,
    ) -> None:
        self._clock = clock
        self._zoom = zoom
        self._set_zoom = set_zoom
        self._pinch_zoom = pinch_zoom
        self._pan = pan
        #: (finger distance, zoom level) when the current pinch began
        self.pinch: tuple[float, int] | None = None
        #: where the mouse button or the one finger was at the last event of a drag
        self.drag: tuple[float, float] | None = None
        self.last_wheel = 0.0
        #: while set ("Set destination" on), press / drag / release go to it instead of panning
        self.picker: PointPicker | None = None
        #: told where the pointer is (mouse moves, one finger), e.g. the map tools' coordinates
        self.on_point: Callable[[tuple[float, float] | None], object] | None = None
        canvas.on_mouse_wheel(self.on_wheel)
        canvas.on_mouse_down(self.on_mouse_down)
        canvas.on_mouse_move(self.on_mouse_move)
        canvas.on_mouse_up(self.on_mouse_up)
        canvas.on_mouse_out(self.on_mouse_up)
        canvas.on_touch_start(self.on_touch)
        canvas.on_touch_move(self.on_touch)
        canvas.on_touch_end(self.on_touch_end)
        canvas.on_touch_cancel(self.on_touch_end)

    def on_wheel(self, dx: object, dy: object) -> None:
        """One zoom step per wheel burst: wheel up (negative delta) zooms in."""
        delta = page_number(dy)
        now = self._clock.now()
        if delta is None or delta == 0 or now - self.last_wheel < WHEEL_INTERVAL:
            return
        self.last_wheel = now
        self._set_zoom(self._zoom() + (1 if delta < 0 else -1))

    def on_mouse_down(self, x: object, y: object) -> None:
        if self.picker is not None:
            self.picker.press(_point(x, y))
            return
        self.drag = _point(x, y)

    def on_mouse_move(self, x: object, y: object) -> None:
        """With the button down, the map follows the mouse."""
        self._tell_point(_point(x, y))
        if self.picker is not None:
            self.picker.move(_point(x, y))
            return
        self._drag_to(_point(x, y))

    def on_mouse_up(self, x: object = None, y: object = None) -> None:
        if self.picker is not None:
            self.picker.release(_point(x, y))
        self.drag = None

    def _tell_point(self, point: tuple[float, float] | None) -> None:
        if self.on_point is not None and point is not None:
            self.on_point(point)

    def _drag_to(self, point: tuple[float, float] | None) -> None:
        start = self.drag
        if start is None or point is None:
            return
        self.drag = point
        dx, dy = point[0] - start[0], point[1] - start[1]
        if self._pan is not None and (dx or dy):
            self._pan(dx, dy)

    def on_touch(self, touches: object) -> None:
        """One finger drags the map; two: the zoom follows the ratio of finger distances."""
        one = touch_point(touches)
        self._tell_point(one)
        if self.picker is not None and one is not None:
            (self.picker.move if self.picker.active else self.picker.press)(one)
            return
        if self.picker is not None and pinch_distance(touches) is not None:
            self.picker.abort()  # two fingers: a pinch, not a destination
        if one is not None:
            self.pinch = None
            if self.drag is None:
                self.drag = one
            else:
                self._drag_to(one)
            return
        self.drag = None
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
        if self.picker is not None and fingers == 0:
            self.picker.release(None)
        if fingers < 2:
            self.pinch = None
        if fingers != 1:
            self.drag = None  # lifting one of two fingers must not jump the map to the other one
        else:
            self.drag = touch_point(touches)


def _point(x: object, y: object) -> tuple[float, float] | None:
    """A canvas point from the page's numbers (each checked by :func:`page_number`), else None."""
    px, py = page_number(x), page_number(y)
    return None if px is None or py is None else (px, py)


class LiveToolbar:
    """The live view's own buttons: Follow (on/off) and Centre; the screen places :attr:`widget`.

    Both are full touch targets with a visible label (their accessible name). The zoom buttons stay
    with the screen that owns the toolbar row (Home puts them at the map's upper-right corner).
    """

    def __init__(self) -> None:
        self.follow = w.ToggleButton(
            value=True, description="Follow", icon="location-arrow", tooltip="Keep the chair in the middle of the map"
        )
        self.follow.layout = w.Layout(height=f"{TOUCH_PX}px", width="auto", min_width="112px")
        self.follow.add_class("pmk-live-follow")
        self.centre = button("Centre", "pmk-live-centre", icon="crosshairs", tooltip="Centre the map on the chair")
        self.widget = w.HBox([self.follow, self.centre], layout=w.Layout(align_items="center"))
        self.widget.add_class("pmk-live-toolbar")
