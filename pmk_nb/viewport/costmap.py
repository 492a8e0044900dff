"""A Nav2 / move_base costmap on the live map (issue 40): RViz's "costmap" colours, placement, updates.

A costmap arrives as a nav_msgs/OccupancyGrid (costs 0..100, -1 unknown; costmap_2d's translation
table makes 253 inscribed -> 99 and 254 lethal -> 100) and then, from Nav2 and move_base alike, as
map_msgs/OccupancyGridUpdate patches.  The picture is an RGBA image at one pixel per cell (RGBA, never
RGB: ipycanvas puts only greyscale or RGBA image data), coloured like RViz's "costmap" colour scheme,
and drawn scaled onto the map by a canvas transform: the grid's corner at its origin in the map frame,
turned by the origin's yaw.  Pure maths: the live view's layer only sends what this computes (the
link applies the update patches: ``pmk_nb.chair.link.streams.navlayers``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from pmk_nb.viewport.pose import Transform2D
from pmk_nb.viewport.view import Viewport

#: RViz's costmap display draws at alpha 0.7 by default: the map shows through.
COSTMAP_ALPHA = 0.7


def costmap_palette(alpha: float = COSTMAP_ALPHA) -> npt.NDArray[np.uint8]:
    """(256, 4) RGBA by cell value viewed as uint8 (-1 -> 255), as RViz's "costmap" scheme:
    0 clear, 1..98 blue to red, 99 inscribed cyan, 100 lethal magenta, 101..127 green and
    128..254 red to yellow (values a costmap never sends), 255 (unknown) faint grey-green."""
    lut = np.zeros((256, 4), dtype=np.float64)
    i = np.arange(1, 99)
    v = 255.0 * i / 100.0
    lut[1:99] = np.stack([v, np.zeros_like(v), 255.0 - v, np.full_like(v, 255.0)], axis=1)
    lut[99] = (0, 255, 255, 255)
    lut[100] = (255, 0, 255, 255)
    lut[101:128] = (0, 255, 0, 255)
    j = np.arange(128, 255)
    lut[128:255] = np.stack(
        [np.full(j.size, 255.0), 255.0 * (j - 128) / (254 - 128), np.zeros(j.size), np.full(j.size, 255.0)], axis=1
    )
    lut[255] = (0x70, 0x89, 0x86, 30)
    lut[:, 3] *= min(max(float(alpha), 0.0), 1.0)
    return np.round(lut).astype(np.uint8)


COSTMAP_LUT = costmap_palette()


def costmap_rgba(data: npt.ArrayLike, lut: npt.NDArray[np.uint8] = COSTMAP_LUT) -> npt.NDArray[np.uint8]:
    """Costs (int8, row 0 = bottom as ROS sends them) -> an RGBA image, row 0 = top, contiguous."""
    cells = np.asarray(data, dtype=np.int8)
    if cells.ndim != 2:
        raise ValueError(f"a costmap is 2-D, got shape {cells.shape}")
    return np.ascontiguousarray(lut[cells[::-1].view(np.uint8)])


#: The largest costmap image side sent to the page (cells): a bigger one is pooled first.
MAX_IMAGE_SIDE = 2048


def pooled_costs(data: npt.ArrayLike, max_side: int = MAX_IMAGE_SIDE) -> tuple[npt.NDArray[np.int8], int]:
    """``data`` reduced by a whole factor until neither side exceeds ``max_side``, each block showing its
    highest cost (a lethal cell is never pooled away; unknown, -1, only where a block knows nothing);
    returns (cells, factor): one image pixel then covers ``factor`` x ``factor`` cells."""
    cells = np.asarray(data, dtype=np.int8)
    rows, cols = cells.shape
    factor = max(1, -(-max(rows, cols) // max(int(max_side), 1)))
    if factor == 1:
        return cells, 1
    pad_r, pad_c = -rows % factor, -cols % factor
    padded = np.pad(cells, ((0, pad_r), (0, pad_c)), constant_values=-1)
    blocks = padded.reshape(padded.shape[0] // factor, factor, padded.shape[1] // factor, factor)
    return blocks.max(axis=(1, 3)).astype(np.int8), factor


@dataclass(frozen=True)
class CostmapPlacement:
    """How a costmap image goes on the canvas: translate to (``x``, ``y``) (the grid's origin corner,
    canvas pixels), rotate by ``angle`` (canvas radians, clockwise positive: -yaw), then draw the image
    at (0, -``height``) with size ``width`` x ``height`` canvas pixels."""

    x: float
    y: float
    angle: float
    width: float
    height: float

    def to_canvas(self, u: float, v: float) -> tuple[float, float]:
        """The canvas pixel of image point (``u``, ``v``) (image pixels from the top-left, scaled to
        ``width`` x ``height``): what the canvas transform does, for tests and hit checks."""
        c, s = math.cos(self.angle), math.sin(self.angle)
        lx, ly = u, v - self.height
        return self.x + c * lx - s * ly, self.y + s * lx + c * ly


def costmap_placement(
    view: Viewport,
    origin: tuple[float, float, float],
    resolution: float,
    size: tuple[int, int],
    map_from_frame: Transform2D | None = None,
) -> CostmapPlacement:
    """Where a costmap of ``size`` (cells: width, height) at ``resolution`` with ``origin`` (its
    cell (0, 0) corner in its own frame) is drawn; ``map_from_frame`` places that frame (a local
    costmap's ``odom``) in the map frame (identity when it is the map)."""
    corner = (map_from_frame or Transform2D()).compose(Transform2D(*origin))
    px, py = view.world_to_pixel(corner.x, corner.y)
    scale = float(resolution) * view.px_per_m
    return CostmapPlacement(float(px), float(py), -corner.theta, size[0] * scale, size[1] * scale)
