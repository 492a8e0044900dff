"""The live view's static layer: the map at screen resolution, moved (not re-sent) while following.

The map is rendered from the grid itself with :func:`pmk_nb.viewport.window_image` (every cell
counts, so a 0.1 m wall stays a line at any zoom) into a *tile*: a hidden canvas a margin larger
than the view.  Each frame whose view moved only puts the tile at its new offset (``drawImage``,
a few bytes); a new tile (tens of kilobytes of PNG) is rendered only on a zoom, a new map, a new
page, or when the view leaves the tile.  The tile canvas keeps one size for its whole life:
resizing a canvas travels on another comm than the drawing and could wipe a tile just drawn.

``mode="nearest"`` keeps the earlier look for comparisons (``bench/bench_live.py``): the map image
sampled one cell per pixel and sent whole on every pan.
"""

from __future__ import annotations

import numpy as np
from ipycanvas import Canvas

from pmk_nb.grid import OccupancyGrid
from pmk_nb.viewport import (
    GRAY_LUT,
    MapTile,
    Viewport,
    clean_occupancy,
    plan_tile,
    tile_covers,
    tile_size_for,
    window_image,
)

#: Spare map around the view, as a fraction of the canvas on each side.
TILE_MARGIN = 0.5


def draw_map_layer(layer: Canvas, view: Viewport, gray: np.ndarray) -> None:
    """Replace ``layer``'s content with the part of ``gray`` (uint8, row 0 = top) ``view`` shows,
    sampled one cell per pixel (the earlier look: thin walls may vanish)."""
    img, inside = view.image_window(gray)
    if not inside.all():  # letterbox: transparent outside the map (RGBA is lossless PNG)
        rgba = np.empty((*img.shape, 4), dtype=np.uint8)
        rgba[..., :3] = img[..., None]
        rgba[..., 3] = np.where(inside, 255, 0)
        img = rgba
    layer.clear()
    layer.put_image_data(img, 0, 0)


class MapLayer:
    """Keeps ``layer`` showing the map under the view.

    Args:
        layer: the bottom layer of the live view's MultiCanvas.
        max_canvas: the largest canvas size the view will have (sets the tile size once).
        margin: spare map on each side of the view, in canvas sizes.
        mode: "tile" (every wall kept, moved by offset) or "nearest" (the earlier look).
    """

    def __init__(
        self, layer: Canvas, max_canvas: tuple[int, int], *, margin: float = TILE_MARGIN, mode: str = "tile"
    ) -> None:
        if mode not in ("tile", "nearest"):
            raise ValueError(f"map layer mode must be 'tile' or 'nearest', got {mode!r}")
        self.layer = layer
        self.mode = mode
        self.margin = max(float(margin), 0.0)
        self.tile_size = tile_size_for(max_canvas, self.margin)
        self.tile_canvas = Canvas(width=self.tile_size[0], height=self.tile_size[1])
        self.tile: MapTile | None = None
        self._placed: tuple[int, int] | None = None
        self._data_top: np.ndarray | None = None
        self._gray: np.ndarray | None = None
        self._key: tuple[object, ...] | None = None  # nearest mode: the view last drawn
        #: True when the last :meth:`draw` cleared and drew the layer again (its overlays go again)
        self.repainted = False

    def set_grid(self, grid: OccupancyGrid) -> None:
        """Show ``grid`` from the next :meth:`draw` on."""
        self._data_top = clean_occupancy(grid.data)[::-1]  # image order: row 0 = top (a view, no copy)
        self._gray = None
        self.invalidate()

    def fit(self, max_canvas: tuple[int, int]) -> None:
        """The canvas may now be up to ``max_canvas``: a tile of the matching size from the next draw."""
        size = tile_size_for(max_canvas, self.margin)
        if size != self.tile_size:
            self.tile_size = size
            self.tile_canvas.width, self.tile_canvas.height = size
            self.invalidate()

    def repaint(self) -> None:
        """Clear and draw the layer again at the next :meth:`draw` (the tile is kept)."""
        self._placed = None
        self._key = None

    def invalidate(self) -> None:
        """Render and place everything again at the next :meth:`draw` (a new page, a new map)."""
        self.tile = None
        self.repaint()

    def draw(self, view: Viewport) -> bool:
        """Bring the layer up to date with ``view``; True when a new image (tile) was sent."""
        self.repainted = False
        if self._data_top is None:
            return False
        if self.mode == "nearest":
            return self._draw_nearest(view)
        origin = view.pixel_origin()
        canvas = (view.canvas_width, view.canvas_height)
        rendered = False
        if not tile_covers(self.tile, origin, canvas, view.scale):
            tile = plan_tile(origin, canvas, self.tile_size, view.scale)
            image = window_image(self._data_top, tile.scale, tile.x0, tile.y0, tile.width, tile.height)
            self.tile_canvas.clear()
            self.tile_canvas.put_image_data(image, 0, 0)
            self.tile, self._placed, rendered = tile, None, True
        if origin != self._placed and self.tile is not None:
            self.layer.clear()
            self.layer.draw_image(self.tile_canvas, self.tile.x0 - origin[0], self.tile.y0 - origin[1])
            self._placed = origin
            self.repainted = True
        return rendered

    def _draw_nearest(self, view: Viewport) -> bool:
        key = view.state_key()
        if key == self._key or self._data_top is None:
            return False
        if self._gray is None:
            self._gray = np.ascontiguousarray(GRAY_LUT[self._data_top.view(np.uint8)])
        draw_map_layer(self.layer, view, self._gray)
        self._key = key
        self.repainted = True
        return True
