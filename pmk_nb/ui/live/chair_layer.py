"""The live view's dynamic layer: the chair, its heading/velocity dot and the laser scan.

Cleared and redrawn every frame with batched calls; the geometry comes from the pure
:mod:`pmk_nb.viewport`.  The scan is drawn as the room it sees (the default, ``"points"``): a light
free-space polygon (one ``fill_polygon``) under the hit points (one ``fill_rects``, at most one
per screen pixel), with blind rays as grey ticks at the chair.  ``"rays"`` draws every ray as a
line instead (one ``stroke_line_segments`` per ray kind), the earlier look.  The scan is drawn
from the pose the chair had at the scan's header stamp (:class:`PoseHistory`, odometry by stamp), so a
turning chair's scan does not cut through walls.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from ipycanvas import Canvas

from pmk_nb.chair import Odometry, Pose2D, Scan
from pmk_nb.viewport import (
    TRAIL_SIZE,
    PoseTrail,
    Viewport,
    heading_point,
    laser_outline,
    laser_segments,
    mounted,
    pose_at_stamp,
    tick_segments,
)

CHAIR_RGB = (31, 111, 235)  # blue
HEADING_RGB = (245, 196, 0)  # yellow
STALE_RGB = (140, 140, 140)  # grey: the last known pose, no fresh data
HIT_STYLE = "rgba(220, 20, 20, 0.6)"  # red: the ray ended on an obstacle
MAX_STYLE = "rgba(220, 20, 20, 0.15)"  # faint red: nothing seen up to the sensor's range (+inf)
BLIND_STYLE = "rgba(110, 110, 110, 0.9)"  # grey tick at the chair: the sensor says nothing there
CLOSE_STYLE = "rgba(255, 120, 0, 1.0)"  # orange tick: something closer than the sensor's range_min
FREE_STYLE = "rgba(30, 144, 255, 0.16)"  # light blue: floor the scan saw free
POINT_STYLE = "rgb(220, 20, 20)"  # red: an obstacle seen
#: Hit dots are this many metres wide on screen, within POINT_PX (pixels).
POINT_M = 0.05
POINT_PX = (2.0, 4.0)
LASER_STYLES = ("points", "rays")
#: Ticks for blind / too-close rays run from the footprint's edge this far out (metres), at least
#: TICK_MIN_PX on screen so they stay visible on a whole-building view.
TICK_M = 0.25
TICK_MIN_PX = 6.0

Pose = Pose2D | Odometry


class PoseHistory:
    """The chair's odometry by header stamp (:class:`~pmk_nb.viewport.posetrail.PoseTrail`), to find
    where it was when a scan was cast: at the scan's header stamp, not when the scan arrived."""

    def __init__(self, size: int = TRAIL_SIZE) -> None:
        self.trail = PoseTrail(size)

    def clear(self) -> None:
        self.trail.clear()

    def remember(self, odom: Pose) -> None:
        """Add an odometry sample (a pose without a header stamp adds nothing)."""
        self.trail.add(odom.stamp, (float(odom.x), float(odom.y), float(odom.theta)))

    def scan_pose(self, pose: Pose, scan: Scan) -> tuple[float, float, float]:
        """Where the rays start: the scanner on the chair (its /tf_static mount) at the pose the chair
        had at the scan's stamp (``pose`` moved back by the odometry since), else at ``pose``."""
        now = (float(pose.x), float(pose.y), float(pose.theta))
        then = pose_at_stamp(now, self.trail, scan.stamp)
        return mounted(now if then is None else then, scan.mount)


@dataclass(frozen=True)
class ChairLook:
    """How the chair is drawn: its radius in metres, grey when stale, ray thinning, scan look."""

    footprint_radius: float
    stale: bool
    ray_spacing_px: float
    laser_style: str = "points"
    #: False when the page draws the chair itself (issue 41: :mod:`pmk_nb.ui.live.page_script`)
    chair: bool = True


def draw_outline(
    layer: Canvas, view: Viewport, origin: tuple[float, float, float], scan: Scan, radius: float = 0.0
) -> tuple[int, int]:
    """Fill the free area the scan saw and dot its hits; returns (hit dots, max-range rays).

    Blind rays pull the polygon back to the scanner and get grey ticks at the chair's edge
    (``radius``), "too close" rays orange ones: unknown is never painted as free floor.
    """
    blind, close = scan.blind, scan.too_close
    size = min(max(view.metres_to_px(POINT_M), POINT_PX[0]), POINT_PX[1])
    shape = laser_outline(
        view,
        origin,
        float(scan.angle_min),
        float(scan.angle_increment),
        scan.ranges,
        scan.at_max,
        float(scan.range_max),
        unknown=blind | close,
        dot_px=size,
    )
    if shape.polygon.shape[0] >= 3:
        layer.fill_style = FREE_STYLE
        layer.fill_polygon(shape.polygon)
    if shape.hits.shape[0]:
        layer.fill_style = POINT_STYLE
        layer.fill_rects(shape.hits[:, 0] - np.float32(size / 2), shape.hits[:, 1] - np.float32(size / 2), size)
    tick = (radius, radius + max(TICK_M, TICK_MIN_PX / max(view.px_per_m, 1e-9)))
    args = (view, origin, float(scan.angle_min), float(scan.angle_increment))
    layer.line_width = 1
    for style, mask, width in ((BLIND_STYLE, blind, 1), (CLOSE_STYLE, close, 3)):
        if mask.any():
            layer.line_width = width
            layer.stroke_style = style
            layer.stroke_line_segments(tick_segments(*args, mask, *tick))
    layer.line_width = 1
    return shape.hits.shape[0], shape.at_max


def draw_rays(
    layer: Canvas, view: Viewport, origin: tuple[float, float, float], scan: Scan, spacing: float, radius: float = 0.0
) -> tuple[int, int]:
    """Stroke the scan's rays from ``origin``; returns (hits, max-range rays) drawn.

    Blind rays (JSON null, NaN, out of range) are grey ticks at the chair's edge (``radius``) and
    "too close" rays orange ticks: neither is ever drawn as a free ray across the floor.
    """
    tick = max(TICK_M, TICK_MIN_PX / max(view.px_per_m, 1e-9))
    segs = laser_segments(
        view,
        origin,
        float(scan.angle_min),
        float(scan.angle_increment),
        scan.ranges,
        scan.at_max,
        float(scan.range_max),
        min_spacing_px=spacing,
        blind=scan.blind,
        too_close=scan.too_close,
        tick=(radius, radius + tick),
    )
    layer.line_width = 1
    for style, lines in ((MAX_STYLE, segs.max_rays), (HIT_STYLE, segs.hits), (BLIND_STYLE, segs.blind_ticks)):
        if lines.shape[0]:
            layer.stroke_style = style
            layer.stroke_line_segments(lines)
    if segs.close_ticks.shape[0]:
        layer.line_width = 3
        layer.stroke_style = CLOSE_STYLE
        layer.stroke_line_segments(segs.close_ticks)
        layer.line_width = 1
    return segs.hits.shape[0], segs.max_rays.shape[0]


def draw_chair_layer(
    layer: Canvas,
    view: Viewport,
    pose: Pose | None,
    odom: Odometry | None,
    scan: Scan | None,
    look: ChairLook,
    history: PoseHistory,
) -> tuple[int, int]:
    """Redraw the dynamic layer; returns the (hits, max-range rays) drawn (0, 0 without a scan).

    Hits are rays in the "rays" look and distinct hit pixels in the "points" look.
    """
    layer.clear()
    if pose is None:
        return 0, 0
    x, y, theta = float(pose.x), float(pose.y), float(pose.theta)
    rays = (0, 0)
    if scan is not None and look.laser_style == "rays":
        rays = draw_rays(layer, view, history.scan_pose(pose, scan), scan, look.ray_spacing_px, look.footprint_radius)
    elif scan is not None:
        rays = draw_outline(layer, view, history.scan_pose(pose, scan), scan, look.footprint_radius)
    if not look.chair:
        return rays
    v = float(odom.v) if odom is not None else 0.0
    hx, hy = heading_point(x, y, theta, v, look.footprint_radius)
    px, py = view.world_to_pixel(np.array([x, hx]), np.array([y, hy]))
    radius = view.chair_radius_px(look.footprint_radius)
    layer.fill_styled_circles(
        px.astype(np.float32),
        py.astype(np.float32),
        np.array([radius, view.dot_radius_px(look.footprint_radius)], dtype=np.float32),
        np.array([STALE_RGB if look.stale else CHAIR_RGB, HEADING_RGB], dtype=np.uint8),
    )
    return rays
