"""visualization_msgs/Marker shapes -> canvas drawing steps (issue 40), seen from above.

A researcher's node publishes markers (a MarkerArray) to show what it thinks: a line strip of a
trajectory, points of detections, an arrow of an estimate, a label.  The live view is a top view,
so each marker is read in the plane: its pose (x, y, yaw), its points, its scale in metres, its
colour.  This turns one marker into the few batched canvas calls that draw it (:class:`MarkerDraw`):
lines, line segments, squares, a filled polygon or a text.  The link reads the JSON and keeps the
markers by (namespace, id); this module is the geometry only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from pmk_nb.viewport.pose import Transform2D
from pmk_nb.viewport.view import Viewport

# visualization_msgs/Marker types
ARROW, CUBE, SPHERE, CYLINDER, LINE_STRIP, LINE_LIST = 0, 1, 2, 3, 4, 5
CUBE_LIST, SPHERE_LIST, POINTS, TEXT_VIEW_FACING = 6, 7, 8, 9
MESH_RESOURCE_KIND = 10  # not drawn: a mesh seen from above is not a shape this view can show
#: Lines and points stay visible however far out the view is zoomed.
MIN_PX = 1.0
MIN_FONT_PX = 9.0
#: RViz draws a pose arrow's head over this share of its length, twice the shaft's width.
HEAD_SHARE = 0.23
CIRCLE_SIDES = 20


@dataclass(frozen=True)
class PlanarMarker:
    """One marker in the plane: ``kind`` (the Marker type), ``pose`` (x, y, yaw) in its frame,
    ``scale`` (x, y, z metres), ``rgba`` (0..1 each), ``points`` (n, 2) in the marker's own frame, ``text``."""

    kind: int
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    rgba: tuple[float, float, float, float] = (1.0, 1.0, 1.0, 1.0)
    points: npt.NDArray[np.float64] = field(default_factory=lambda: np.empty((0, 2)))
    text: str = ""


@dataclass(frozen=True)
class MarkerDraw:
    """One canvas step: ``op`` "lines" (a polyline, ``xy`` (n, 2)), "segments" (``xy`` (n, 2, 2)),
    "squares" (centres (n, 2), side ``size``), "polygon" (filled, ``xy`` (n, 2)) or "text" (at ``xy``
    (1, 2), ``size`` font px); ``style`` a CSS colour; ``size`` the line width for lines."""

    op: str
    xy: npt.NDArray[np.float64]
    style: str
    size: float
    text: str = ""


def css_rgba(rgba: tuple[float, float, float, float]) -> str:
    """A marker colour (0..1, out-of-range clamped, NaN as 0) as CSS ``rgba(r, g, b, a)``."""
    r, g, b, a = (min(max(v, 0.0), 1.0) if math.isfinite(v) else 0.0 for v in rgba)
    return f"rgba({round(r * 255)}, {round(g * 255)}, {round(b * 255)}, {a:.3g})"


def framed_pixels(view: Viewport, tf: Transform2D, pts: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Points in a frame placed by ``tf`` (map <- frame) -> canvas pixels (n, 2)."""
    if pts.shape[0] == 0:
        return np.empty((0, 2))
    c, s = math.cos(tf.theta), math.sin(tf.theta)
    x = tf.x + c * pts[:, 0] - s * pts[:, 1]
    y = tf.y + s * pts[:, 0] + c * pts[:, 1]
    px, py = view.world_to_pixel(x, y)
    return np.stack([np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64)], axis=1)


def arrow_outline(length: float, shaft: float, head: float, head_length: float) -> npt.NDArray[np.float64]:
    """An arrow along +x from the origin, as a 7-point polygon (metres): ``shaft`` and ``head`` widths."""
    base = max(length - head_length, 0.0)
    hs, hh = shaft / 2.0, head / 2.0
    return np.array([[0, -hs], [base, -hs], [base, -hh], [length, 0], [base, hh], [base, hs], [0, hs]], dtype=float)


def _arrow(marker: PlanarMarker) -> tuple[Transform2D, npt.NDArray[np.float64]]:
    """The arrow's polygon and the transform (marker frame <- arrow) that places it."""
    sx, sy, sz = marker.scale
    if marker.points.shape[0] >= 2:  # start and end points: scale is shaft and head diameter, head length
        (x0, y0), (x1, y1) = marker.points[0], marker.points[1]
        length = math.hypot(x1 - x0, y1 - y0)
        head_len = sz if sz > 0 else min(length * HEAD_SHARE * 2, sy * 2)
        return Transform2D(x0, y0, math.atan2(y1 - y0, x1 - x0)), arrow_outline(length, sx, sy, head_len)
    return Transform2D(), arrow_outline(sx, sy, 2 * sy, sx * HEAD_SHARE)


def _circle(rx: float, ry: float) -> npt.NDArray[np.float64]:
    t = np.linspace(0.0, 2.0 * math.pi, CIRCLE_SIDES, endpoint=False)
    return np.stack([rx * np.cos(t), ry * np.sin(t)], axis=1)


def marker_draws(marker: PlanarMarker, view: Viewport, map_from_frame: Transform2D | None = None) -> list[MarkerDraw]:
    """The canvas steps that draw ``marker`` (its frame placed in the map by ``map_from_frame``);
    an empty list for kinds a top view cannot show (meshes, triangle lists) or nothing to draw."""
    tf = (map_from_frame or Transform2D()).compose(Transform2D(*marker.pose))
    style = css_rgba(marker.rgba)
    sx, sy, _sz = marker.scale
    pts = marker.points
    kind = marker.kind
    if kind == LINE_STRIP and pts.shape[0] >= 2:
        return [MarkerDraw("lines", framed_pixels(view, tf, pts), style, max(view.metres_to_px(sx), MIN_PX))]
    if kind == LINE_LIST and pts.shape[0] >= 2:
        even = pts[: pts.shape[0] // 2 * 2]
        segs = framed_pixels(view, tf, even).reshape(-1, 2, 2)
        return [MarkerDraw("segments", segs, style, max(view.metres_to_px(sx), MIN_PX))]
    if kind in (POINTS, CUBE_LIST, SPHERE_LIST) and pts.shape[0]:
        return [MarkerDraw("squares", framed_pixels(view, tf, pts), style, max(view.metres_to_px(sx), 2 * MIN_PX))]
    if kind == TEXT_VIEW_FACING and marker.text:
        font = max(view.metres_to_px(marker.scale[2]), MIN_FONT_PX)
        return [MarkerDraw("text", framed_pixels(view, tf, np.zeros((1, 2))), style, font, marker.text)]
    if kind == ARROW:
        place, outline = _arrow(marker)
        return [MarkerDraw("polygon", framed_pixels(view, tf.compose(place), outline), style, 0.0)]
    if kind == CUBE:
        box = np.array([[-sx / 2, -sy / 2], [sx / 2, -sy / 2], [sx / 2, sy / 2], [-sx / 2, sy / 2]])
        return [MarkerDraw("polygon", framed_pixels(view, tf, box), style, 0.0)]
    if kind in (SPHERE, CYLINDER):
        return [MarkerDraw("polygon", framed_pixels(view, tf, _circle(sx / 2, sy / 2)), style, 0.0)]
    return []
