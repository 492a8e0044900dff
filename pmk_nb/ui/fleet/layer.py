"""The live view's fleet overlay (issue 26): every other chair of the page's fleet as a dot in its
colour with its heading and name, and a ring in its colour around the chair in control.

The chair in control is drawn by the chair layer itself (blue, its footprint, the laser); its ring
is drawn where that layer drew it (:meth:`~pmk_nb.viewport.Viewport.chair_pixel`), so it never lags
behind.  The others move as their rows are read (the fleet panel's timer sets the markers), which
bumps ``version`` only when a marker moved: still chairs cost no frame.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ipycanvas import Canvas

    from pmk_nb.viewport import Viewport

MARKER_PX = 8.0  # a watched chair's dot at least (else its footprint's size on screen)
RING_PX = 16.0  # the ring around the chair in control
FONT_PX = 13
HALO_STYLE = "rgba(255, 255, 255, 0.9)"
TEXT_STYLE = "rgba(20, 20, 20, 0.95)"


@dataclass(frozen=True)
class Marker:
    """One chair on the map: name, colour, pose (x, y, yaw in the map frame), in control or not,
    its footprint's radius (m: the dot has the chair's size)."""

    name: str
    colour: str
    x: float
    y: float
    yaw: float
    controlled: bool = False
    radius_m: float = 0.35


class FleetLayer:
    """The markers to draw; set by the fleet panel, read by the live view's render loop."""

    def __init__(self) -> None:
        self.version = 0
        self._markers: tuple[Marker, ...] = ()
        self._lock = threading.Lock()

    @property
    def markers(self) -> tuple[Marker, ...]:
        with self._lock:
            return self._markers

    def set_markers(self, markers: list[Marker]) -> bool:
        """Show ``markers`` (only finite poses); True when they changed (a new frame is drawn)."""
        kept = tuple(m for m in markers if all(math.isfinite(v) for v in (m.x, m.y, m.yaw)))
        with self._lock:
            if kept == self._markers:
                return False
            self._markers = kept
            self.version += 1
            return True

    def draw(self, layer: Canvas, view: Viewport) -> None:
        """Draw on ``layer`` (inside the frame's ``hold_canvas``)."""
        markers = self.markers
        if not markers:
            return
        layer.font = f"bold {FONT_PX}px sans-serif"
        size = RING_PX
        layer.text_align = "left"
        layer.text_baseline = "middle"
        for m in markers:
            if m.controlled:
                at = view.chair_pixel()
                if at is None:
                    continue
                u, v = at
                layer.line_width = 4
                layer.stroke_style = m.colour
                layer.stroke_circle(float(u), float(v), RING_PX)
            else:
                pu, pv = view.world_to_pixel(m.x, m.y)
                u, v = float(pu), float(pv)
                size = max(MARKER_PX, m.radius_m * view.px_per_m) if math.isfinite(m.radius_m) else MARKER_PX
                layer.fill_style = m.colour
                layer.fill_circle(u, v, size)
                layer.line_width = 2
                layer.stroke_style = HALO_STYLE
                layer.stroke_circle(u, v, size)
                # heading: screen y grows downwards, map y upwards
                layer.stroke_line(u, v, u + size * math.cos(m.yaw), v - size * math.sin(m.yaw))
            label_x = u + (RING_PX if m.controlled else size) + 4
            layer.line_width = 4
            layer.stroke_style = HALO_STYLE
            layer.fill_style = TEXT_STYLE
            layer.stroke_text(m.name, label_x, v)
            layer.fill_text(m.name, label_x, v)
        layer.line_width = 1
