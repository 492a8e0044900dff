"""The live view's pure maths: zoom, follow, pan, clamp, world <-> canvas pixel, map and laser.

No widgets here: ``pmk_nb.ui`` only draws what this package computes. ``view`` holds
:class:`Viewport` (the rules of the original MapViewer, plus pan and follow on/off), ``mapimage``
reduces the grid to screen pixels without losing a wall, ``outline`` turns a scan into hit points
and a free-space polygon, ``laser`` into rays (the optional look), ``pose`` composes planar
(x, y, yaw) transforms (a sensor's pose on the chair; the link's tf tree), ``occlusion`` the parts of
the canvas panels cover (the follow target sits in the centre of the rest), ``tftree`` the latest
transform per frame (the link's tf tree: map -> odom -> base_link), ``path`` the planned path still
ahead of the chair, ``posetrail`` the odometry by header stamp (a scan drawn where it was cast),
``costmap`` (RViz's costmap colours, a costmap's place on the canvas) and ``markers`` (marker shapes ->
canvas steps) for the navigation layers, ``seriesplot`` any field's samples over a time window,
``tfframes`` the TF tree view's rows (per frame: parent, rate, age, children), ``glide`` where the
page draws the chair between the kernel's updates (interpolated, never more than one update ahead).
"""

from __future__ import annotations

from pmk_nb.viewport.costmap import (
    COSTMAP_LUT,
    CostmapPlacement,
    costmap_palette,
    costmap_placement,
    costmap_rgba,
    pooled_costs,
)
from pmk_nb.viewport.glide import (
    FEED_POSES,
    HEARTBEAT_S,
    LATE_GRACE_S,
    OFFSET_WINDOW,
    ClockOffset,
    StampedPose,
    late,
    pixel_affine,
    pose_at,
)
from pmk_nb.viewport.history import OdomHistory, plot_lines
from pmk_nb.viewport.laser import LaserSegments, laser_segments, ray_stride
from pmk_nb.viewport.mapcast import explain_nulls
from pmk_nb.viewport.mapimage import (
    GRAY_LUT,
    MapTile,
    clean_occupancy,
    plan_tile,
    pool_window,
    tile_covers,
    tile_size_for,
    window_image,
)
from pmk_nb.viewport.maptools import (
    coordinates_text,
    distance,
    grid_lines,
    grid_spacing,
    heading,
    pixel_to_map,
    scale_bar,
)
from pmk_nb.viewport.markers import MarkerDraw, PlanarMarker, framed_pixels, marker_draws
from pmk_nb.viewport.occlusion import Insets, insets_from_boxes
from pmk_nb.viewport.outline import LaserOutline, laser_outline, tick_segments
from pmk_nb.viewport.path import ARRIVED_M, ahead_of
from pmk_nb.viewport.pose import Transform2D, mounted
from pmk_nb.viewport.posetrail import TRAIL_SIZE, PoseTrail, pose_at_stamp
from pmk_nb.viewport.seriesplot import SeriesLines, SeriesRing, series_lines
from pmk_nb.viewport.tfframes import RATE_WINDOW_S, FrameRow, edge_rate, frame_rows, frame_text, tree_rows
from pmk_nb.viewport.tftree import EdgeRecord, FramedTransform, TfTree, normalise_frame
from pmk_nb.viewport.view import (
    MIN_CHAIR_RADIUS_PX,
    MIN_DOT_RADIUS_PX,
    STILL_SPEED,
    Viewport,
    fit_canvas,
    heading_point,
)

__all__ = [
    "ARRIVED_M",
    "COSTMAP_LUT",
    "FEED_POSES",
    "GRAY_LUT",
    "HEARTBEAT_S",
    "LATE_GRACE_S",
    "MIN_CHAIR_RADIUS_PX",
    "MIN_DOT_RADIUS_PX",
    "OFFSET_WINDOW",
    "RATE_WINDOW_S",
    "STILL_SPEED",
    "TRAIL_SIZE",
    "ClockOffset",
    "CostmapPlacement",
    "EdgeRecord",
    "FrameRow",
    "FramedTransform",
    "Insets",
    "LaserOutline",
    "LaserSegments",
    "MapTile",
    "MarkerDraw",
    "OdomHistory",
    "PlanarMarker",
    "PoseTrail",
    "SeriesLines",
    "SeriesRing",
    "StampedPose",
    "TfTree",
    "Transform2D",
    "Viewport",
    "ahead_of",
    "clean_occupancy",
    "coordinates_text",
    "costmap_palette",
    "costmap_placement",
    "costmap_rgba",
    "distance",
    "edge_rate",
    "explain_nulls",
    "fit_canvas",
    "frame_rows",
    "frame_text",
    "framed_pixels",
    "grid_lines",
    "grid_spacing",
    "heading",
    "heading_point",
    "insets_from_boxes",
    "laser_outline",
    "laser_segments",
    "late",
    "marker_draws",
    "mounted",
    "normalise_frame",
    "pixel_affine",
    "pixel_to_map",
    "plan_tile",
    "plot_lines",
    "pool_window",
    "pooled_costs",
    "pose_at",
    "pose_at_stamp",
    "ray_stride",
    "scale_bar",
    "series_lines",
    "tick_segments",
    "tile_covers",
    "tile_size_for",
    "tree_rows",
    "window_image",
]
