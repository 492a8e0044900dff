"""The live view's pure maths: zoom, follow, clamp, world <-> canvas pixel, laser segments.

No widgets here: ``pmk_nb.ui`` only draws what this package computes. ``view`` holds
:class:`Viewport` (the rules of the original MapViewer), ``laser`` turns a scan into segments.
"""

from __future__ import annotations

from pmk_nb.viewport.laser import LaserSegments, laser_segments, ray_stride
from pmk_nb.viewport.view import (
    MIN_CHAIR_RADIUS_PX,
    MIN_DOT_RADIUS_PX,
    STILL_SPEED,
    Viewport,
    fit_canvas,
    heading_point,
)

__all__ = [
    "MIN_CHAIR_RADIUS_PX",
    "MIN_DOT_RADIUS_PX",
    "STILL_SPEED",
    "LaserSegments",
    "Viewport",
    "fit_canvas",
    "heading_point",
    "laser_segments",
    "ray_stride",
]
