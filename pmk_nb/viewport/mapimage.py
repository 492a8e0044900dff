"""The map at screen resolution: a window of the occupancy grid reduced to canvas pixels (pure NumPy).

Sampling one cell per screen pixel (nearest neighbour) drops every wall thinner than a pixel: a
0.1 m wall on a whole-building view comes out dotted or vanishes.  Here every cell counts: when
several cells fall into one pixel the pixel shows the "strongest" of them, occupied over free over
unknown (a max-pool, since ROS occupancy values already order that way: -1 < 0 < 1..99 < 100).
When a cell is larger than a pixel each pixel shows the cell under its centre.  Both reductions are
separable, so they run as two ``np.maximum.reduceat`` passes over the visible window only.

The live view renders a *tile* larger than the canvas (the view plus a margin) and moves it with a
cheap ``drawImage`` while the chair is followed; a new tile is rendered only when the zoom changes
or the view leaves it (:func:`plan_tile`, :func:`tile_covers`).

Pixel coordinates here are "map pixels": a cell's left edge ``u`` (cells) is at ``u * scale``
map pixels, (0, 0) = the map's top-left corner; the canvas shows map pixels ``origin .. origin +
size`` (:meth:`pmk_nb.viewport.Viewport.pixel_origin`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pmk_nb.grid import GRAY_LUT as GRAY_LUT  # the map file's greys, so the live map looks like it
from pmk_nb.grid import GRAY_UNKNOWN as GRAY_UNKNOWN


def clean_occupancy(data: np.ndarray) -> np.ndarray:
    """``data`` as int8 with values outside -1..100 made unknown (-1), so they never win the max-pool.

    Returns ``data`` itself (no copy) when every value is valid, which is the usual case.
    """
    arr = np.asarray(data).astype(np.int8, copy=False)
    bad = (arr < -1) | (arr > 100)
    return np.where(bad, np.int8(-1), arr) if bad.any() else arr


def _axis(n_cells: int, scale: float, start_px: int, n_px: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per output pixel: first cell, end cell (exclusive), and whether it shows any cell of the map."""
    i = np.arange(n_px, dtype=np.float64) + start_px
    if scale < 1.0:  # several cells per pixel: the cells whose left edge lies in the pixel
        first = np.ceil(i / scale - 1e-9)
        end = np.ceil((i + 1.0) / scale - 1e-9)
    else:  # a cell spans one or more pixels: the cell under the pixel's centre
        first = np.floor((i + 0.5) / scale)
        end = first + 1.0
    first = np.clip(first, 0, n_cells).astype(np.int64)
    end = np.clip(end, 0, n_cells).astype(np.int64)
    return first, end, end > first


def pool_window(
    data_top: np.ndarray, scale: float, x0: int, y0: int, width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """Occupancy of map pixels ``[x0, x0 + width) x [y0, y0 + height)``, every cell counted.

    Args:
        data_top: int8 (rows, cols) occupancy, row 0 = the TOP of the map (image order), values
            -1..100 (see :func:`clean_occupancy`).
        scale: map pixels per cell (> 0).
        x0, y0: the window's top-left corner in map pixels (integers; may be negative).
        width, height: the window's size in pixels.

    Returns:
        (values, inside): int8 (height, width) occupancy per pixel (max over its cells; -1 outside
        the map) and a bool mask of the pixels that show part of the map.
    """
    if not (scale > 0 and math.isfinite(scale)):
        raise ValueError(f"scale must be a positive number of pixels per cell, got {scale}")
    rows, cols = data_top.shape
    r_first, r_end, r_in = _axis(rows, scale, int(y0), int(height))
    c_first, c_end, c_in = _axis(cols, scale, int(x0), int(width))
    out = np.full((int(height), int(width)), -1, dtype=np.int8)
    inside = r_in[:, None] & c_in[None, :]
    if not (r_in.any() and c_in.any()):
        return out, inside
    # the pixels that show the map form one contiguous run per axis; their cell ranges are
    # consecutive (several cells per pixel) or repeat (a cell over several pixels), which is
    # exactly what reduceat reduces or repeats
    rs, cs = np.flatnonzero(r_in), np.flatnonzero(c_in)
    r_lo, r_hi = int(r_first[rs[0]]), int(r_end[rs[-1]])
    c_lo, c_hi = int(c_first[cs[0]]), int(c_end[cs[-1]])
    window = data_top[r_lo:r_hi, c_lo:c_hi]
    pooled = np.maximum.reduceat(window, r_first[rs] - r_lo, axis=0)
    pooled = np.maximum.reduceat(pooled, c_first[cs] - c_lo, axis=1)
    out[rs[0] : rs[-1] + 1, cs[0] : cs[-1] + 1] = pooled
    return out, inside


def window_image(data_top: np.ndarray, scale: float, x0: int, y0: int, width: int, height: int) -> np.ndarray:
    """The window as an image for ``put_image_data``: grey (h, w) uint8, or RGBA with transparent
    pixels where the window reaches beyond the map (a letterbox shows the page, not grey)."""
    values, inside = pool_window(data_top, scale, x0, y0, width, height)
    gray = GRAY_LUT[values.view(np.uint8)]
    if inside.all():
        return gray
    rgba = np.empty((*gray.shape, 4), dtype=np.uint8)
    rgba[..., :3] = gray[..., None]
    rgba[..., 3] = np.where(inside, 255, 0)
    return rgba


@dataclass(frozen=True)
class MapTile:
    """A rendered part of the map: map pixels ``[x0, x0 + width) x [y0, y0 + height)`` at ``scale``."""

    x0: int
    y0: int
    width: int
    height: int
    scale: float


def tile_size_for(canvas: tuple[int, int], margin: float) -> tuple[int, int]:
    """Tile size for a canvas of at most ``canvas`` with ``margin`` x its size spare on each side."""
    w, h = (max(int(v), 1) for v in canvas)
    m = max(float(margin), 0.0)
    return w + 2 * math.ceil(w * m), h + 2 * math.ceil(h * m)


def plan_tile(origin: tuple[int, int], canvas: tuple[int, int], tile_size: tuple[int, int], scale: float) -> MapTile:
    """A ``tile_size`` tile with the canvas at ``origin`` (map pixels) in its middle.

    A tile no larger than the canvas is exactly the canvas (a new tile on every pan).
    """
    tw, th = max(int(tile_size[0]), canvas[0]), max(int(tile_size[1]), canvas[1])
    return MapTile(origin[0] - (tw - canvas[0]) // 2, origin[1] - (th - canvas[1]) // 2, tw, th, float(scale))


def tile_covers(tile: MapTile | None, origin: tuple[int, int], canvas: tuple[int, int], scale: float) -> bool:
    """True when ``tile`` (rendered at ``scale``) contains the whole canvas placed at ``origin``."""
    return (
        tile is not None
        and tile.scale == float(scale)
        and tile.x0 <= origin[0]
        and tile.y0 <= origin[1]
        and origin[0] + canvas[0] <= tile.x0 + tile.width
        and origin[1] + canvas[1] <= tile.y0 + tile.height
    )
