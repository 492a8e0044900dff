"""The live view's static layer: the map image cropped to the view, sent only when the view changes.

A NumPy crop of the map image (nearest neighbour, canvas size) sent with ``put_image_data``; the
live view calls this on a zoom, a pan of at least one pixel, a new map or a new page, never per
frame (an 800 x 600 PNG is tens of kilobytes, the chair layer a few).
"""

from __future__ import annotations

import numpy as np
from ipycanvas import Canvas

from pmk_nb.viewport import Viewport


def draw_map_layer(layer: Canvas, view: Viewport, gray: np.ndarray) -> None:
    """Replace ``layer``'s content with the part of ``gray`` (uint8, row 0 = top) ``view`` shows."""
    img, inside = view.image_window(gray)
    if not inside.all():  # letterbox: transparent outside the map (RGBA is lossless PNG)
        rgba = np.empty((*img.shape, 4), dtype=np.uint8)
        rgba[..., :3] = img[..., None]
        rgba[..., 3] = np.where(inside, 255, 0)
        img = rgba
    layer.clear()
    layer.put_image_data(img, 0, 0)
