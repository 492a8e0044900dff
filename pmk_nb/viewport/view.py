"""View maths of the live preview: zoom levels, follow, clamp, world <-> canvas pixel (pure NumPy).

The live view (``pmk_nb.ui.live.view``) only draws what this module computes, so every rule of the
original MapViewer (thesis 4.2.1.3) lives here and is tested without widgets:

* zoom level 1 shows the whole map (fitted and centred); each level up magnifies by ``zoom_step``;
* zoomed in, the view follows the chair (chair in the centre) but never shows beyond the map: near
  an edge the view stops and the chair moves off centre; along an axis where the map is smaller
  than the view, the map is centred;
* world metres -> map cells use the grid's origin and resolution, and the image's y is flipped
  (image row 0 is the top of the map, world y grows upwards).

Coordinates: "cells" are continuous map-image coordinates (u = column, v = row from the TOP, both in
cells, (0, 0) = top-left corner of the image); "pixels" are canvas pixels, (0, 0) = top-left corner
of the canvas.  The grid's yaw is ignored, as map_server consumers do (see ARCHITECTURE.md).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from pmk_nb.viewport.occlusion import Insets

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: Below this speed (m/s) the heading dot sits on the footprint's edge instead of at "where in 1 s",
#: so a standing chair still shows which way it faces.
STILL_SPEED = 0.05
#: Smallest chair circle drawn, in canvas pixels (a 0.35 m chair on a 200 m map is < 1 px otherwise).
MIN_CHAIR_RADIUS_PX = 4.0
#: Smallest heading dot drawn, in canvas pixels.
MIN_DOT_RADIUS_PX = 2.0


def _finite(value: float, name: str) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError) as err:
        raise ValueError(f"{name} must be a number, got {value!r}") from err
    if not math.isfinite(out):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return out


class Viewport:
    """Which part of a map a W x H canvas shows, and where world points land on it.

    Args:
        map_width, map_height: map size in cells (columns, rows).
        resolution: metres per cell.
        origin: world (x, y) of the map's lower-left corner, metres (a third element, yaw, is ignored).
        canvas_width, canvas_height: canvas size in pixels.
        zoom_step: magnification between two zoom levels (> 1).
        max_zoom: the highest zoom level (level 1 = whole map).

    Raises:
        ValueError: on non-positive sizes, resolution, or zoom settings.
    """

    def __init__(
        self,
        map_width: int,
        map_height: int,
        resolution: float,
        origin: tuple[float, ...] = (0.0, 0.0),
        canvas_width: int = 800,
        canvas_height: int = 600,
        *,
        zoom_step: float = 1.5,
        max_zoom: int = 8,
    ) -> None:
        if int(map_width) < 1 or int(map_height) < 1:
            raise ValueError(f"map must be at least 1x1 cells, got {map_width}x{map_height}")
        if int(canvas_width) < 1 or int(canvas_height) < 1:
            raise ValueError(f"canvas must be at least 1x1 px, got {canvas_width}x{canvas_height}")
        self.map_width = int(map_width)
        self.map_height = int(map_height)
        self.resolution = _finite(resolution, "resolution")
        if self.resolution <= 0:
            raise ValueError(f"resolution must be > 0 metres per cell, got {resolution}")
        self.origin = (_finite(origin[0], "origin x"), _finite(origin[1], "origin y"))
        self.canvas_width = int(canvas_width)
        self.canvas_height = int(canvas_height)
        self.zoom_step = _finite(zoom_step, "zoom_step")
        if self.zoom_step <= 1.0:
            raise ValueError(f"zoom_step must be > 1, got {zoom_step}")
        if int(max_zoom) < 1:
            raise ValueError(f"max_zoom must be >= 1, got {max_zoom}")
        self.max_zoom = int(max_zoom)
        self._zoom = 1
        # Centre of the view in cell coordinates; starts on the map's centre.
        self._center = (self.map_width / 2.0, self.map_height / 2.0)
        self._target: tuple[float, float] | None = None
        #: follow the chair (keep it centred); a pan turns it off, :meth:`set_following` back on
        self.following = True
        self._chair: tuple[float, float] | None = None  # the chair's last world position
        #: panels over the canvas (:mod:`pmk_nb.viewport.occlusion`): the focus is the centre of the rest
        self.insets = Insets()

    @classmethod
    def for_grid(cls, grid: object, canvas_width: int, canvas_height: int, **kw: object) -> Viewport:
        """A viewport for an ``OccupancyGrid`` (anything with width, height, resolution, origin)."""
        return cls(
            grid.width,  # type: ignore[attr-defined]
            grid.height,  # type: ignore[attr-defined]
            grid.resolution,  # type: ignore[attr-defined]
            grid.origin,  # type: ignore[attr-defined]
            canvas_width,
            canvas_height,
            **kw,  # type: ignore[arg-type]
        )

    # -- zoom --------------------------------------------------------------------------------------
    @property
    def zoom(self) -> int:
        """Current zoom level, 1 (whole map) .. max_zoom."""
        return self._zoom

    @property
    def zoom_factor(self) -> float:
        """Magnification relative to the whole-map fit (1.0 at level 1)."""
        return self.zoom_step ** (self._zoom - 1)

    @property
    def fit_scale(self) -> float:
        """Canvas pixels per cell at zoom level 1: the whole map fits in the canvas."""
        return min(self.canvas_width / self.map_width, self.canvas_height / self.map_height)

    @property
    def scale(self) -> float:
        """Canvas pixels per map cell at the current zoom."""
        return self.fit_scale * self.zoom_factor

    @property
    def px_per_m(self) -> float:
        return self.scale / self.resolution

    def clamp_zoom(self, level: object) -> int:
        """A valid zoom level from anything a widget might send (rounded, clamped; ValueError if NaN/text)."""
        value = _finite(level, "zoom level")  # type: ignore[arg-type]
        return int(min(max(round(value), 1), self.max_zoom))

    def set_zoom(self, level: object) -> int:
        """Set the zoom level (clamped to 1..max_zoom) and re-clamp the view; returns the level set."""
        self._zoom = self.clamp_zoom(level)
        self._apply_target()
        return self._zoom

    def zoom_in(self) -> int:
        return self.set_zoom(self._zoom + 1)

    def zoom_out(self) -> int:
        return self.set_zoom(self._zoom - 1)

    def zoom_for_pinch(self, start_zoom: int, ratio: float) -> int:
        """Zoom level for a two-finger pinch that began at ``start_zoom`` and has scaled by ``ratio``.

        ``ratio`` = current finger distance / distance at touch start; one level per ``zoom_step``.
        Non-positive or non-finite ratios keep ``start_zoom``.
        """
        try:
            r = float(ratio)
        except (TypeError, ValueError):
            return self.clamp_zoom(start_zoom)
        if not (math.isfinite(r) and r > 0):
            return self.clamp_zoom(start_zoom)
        steps = math.log(r) / math.log(self.zoom_step)
        return self.clamp_zoom(start_zoom + round(steps))

    # -- follow and clamp --------------------------------------------------------------------------
    @property
    def view_size_cells(self) -> tuple[float, float]:
        """Width and height of the visible area, in cells."""
        s = self.scale
        return self.canvas_width / s, self.canvas_height / s

    @property
    def center(self) -> tuple[float, float]:
        """Centre of the view in cell coordinates (after clamping)."""
        return self._center

    @property
    def top_left(self) -> tuple[float, float]:
        """Cell coordinates shown at canvas pixel (0, 0)."""
        vw, vh = self.view_size_cells
        return self._center[0] - vw / 2.0, self._center[1] - vh / 2.0

    def follow(self, x: float, y: float) -> None:
        """Centre the view on world point (x, y) as far as the map's edges allow."""
        u, v = self.world_to_cell(_finite(x, "x"), _finite(y, "y"))
        self._target = (float(u), float(v))
        self._apply_target()

    def center_on_cell(self, u: float, v: float) -> None:
        """Centre on cell coordinates (u, v) as far as the map's edges allow."""
        self._target = (_finite(u, "u"), _finite(v, "v"))
        self._apply_target()

    def see_chair(self, x: float, y: float) -> None:
        """The chair is at world (x, y): centre on it while following, else just remember it."""
        self._chair = (_finite(x, "x"), _finite(y, "y"))
        if self.following:
            self.follow(*self._chair)

    def forget_chair(self) -> None:
        """No chair any more (the link was detached): :meth:`centre` then centres on the map."""
        self._chair = None

    def set_following(self, on: bool) -> None:
        """Turn follow on (centres on the chair at once, if one was seen) or off (the view stays)."""
        self.following = bool(on)
        if self.following and self._chair is not None:
            self.follow(*self._chair)

    def pan_pixels(self, dx: float, dy: float) -> None:
        """Drag the map by (dx, dy) canvas pixels (the map moves with the finger); stops following.

        The pan starts from the clamped view, so dragging past an edge and back responds at once.
        """
        ddx, ddy = _finite(dx, "dx"), _finite(dy, "dy")
        self.following = False
        s = self.scale
        # the target sits where _apply_target put it: the centre of the uncovered part, not the view's
        du, dv = (d / s for d in self.insets.fitted(self.canvas_width, self.canvas_height).focus_offset())
        self._target = (self._center[0] + du - ddx / s, self._center[1] + dv - ddy / s)
        self._apply_target()

    def centre(self) -> None:
        """Centre on the chair if one was seen, else on the map (follow stays as it is)."""
        if self._chair is not None:
            self.follow(*self._chair)
        else:
            self._target = None
            self._apply_target()

    def _apply_target(self) -> None:
        # the target goes to the centre of the uncovered part (panels over the canvas), which is
        # clamped to the map as the whole view was; the view's centre is then that much off
        target = self._target or (self.map_width / 2.0, self.map_height / 2.0)
        vw, vh = self.view_size_cells
        s = self.scale
        ins = self.insets.fitted(self.canvas_width, self.canvas_height)
        du, dv = (d / s for d in ins.focus_offset())
        uw, uh = vw - (ins.left + ins.right) / s, vh - (ins.top + ins.bottom) / s
        self._center = (
            self._clamp_axis(target[0], uw, self.map_width) - du,
            self._clamp_axis(target[1], uh, self.map_height) - dv,
        )

    def set_insets(self, insets: Insets) -> None:
        """Panels now cover ``insets`` of the canvas: keep the followed target in the rest."""
        self.insets = insets.fitted(self.canvas_width, self.canvas_height)
        self._apply_target()

    def resize(self, canvas_width: int, canvas_height: int) -> None:
        """The canvas is now ``canvas_width`` x ``canvas_height`` px (the page's room for the map):
        zoom level and target are kept; level 1 fits the whole map in the new size."""
        if int(canvas_width) < 1 or int(canvas_height) < 1:
            raise ValueError(f"canvas must be at least 1x1 px, got {canvas_width}x{canvas_height}")
        self.canvas_width, self.canvas_height = int(canvas_width), int(canvas_height)
        self.insets = self.insets.fitted(self.canvas_width, self.canvas_height)
        self._apply_target()

    def chair_pixel(self) -> tuple[float, float] | None:
        """Where the chair last seen is drawn, in canvas pixels (None before one was seen)."""
        if self._chair is None:
            return None
        px, py = self.world_to_pixel(*self._chair)
        return float(px), float(py)

    @staticmethod
    def _clamp_axis(c: float, view: float, size: float) -> float:
        if view >= size:  # the map is narrower than the view: centre it
            return size / 2.0
        return min(max(c, view / 2.0), size - view / 2.0)

    def visible_cells(self) -> tuple[float, float, float, float]:
        """(u0, v0, u1, v1): the part of the map on screen, cell coordinates, clipped to the map."""
        u0, v0 = self.top_left
        vw, vh = self.view_size_cells
        return max(u0, 0.0), max(v0, 0.0), min(u0 + vw, self.map_width), min(v0 + vh, self.map_height)

    def pixel_origin(self) -> tuple[int, int]:
        """The map pixel (cell coordinates x scale, rounded) shown at canvas pixel (0, 0)."""
        u0, v0 = self.top_left
        s = self.scale
        return round(u0 * s), round(v0 * s)

    def state_key(self) -> tuple[object, ...]:
        """Changes exactly when the map layer must be redrawn (zoom, pan to a new whole pixel, size)."""
        u0, v0 = self.top_left
        s = self.scale
        return (self._zoom, self.canvas_width, self.canvas_height, round(u0 * s), round(v0 * s))

    # -- conversions (vectorised) ------------------------------------------------------------------
    def world_to_cell(self, x: ArrayLike, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """World metres -> cell coordinates (u from the left, v from the TOP)."""
        u = (np.asarray(x, dtype=np.float64) - self.origin[0]) / self.resolution
        v = self.map_height - (np.asarray(y, dtype=np.float64) - self.origin[1]) / self.resolution
        return u, v

    def cell_to_world(self, u: ArrayLike, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        x = self.origin[0] + np.asarray(u, dtype=np.float64) * self.resolution
        y = self.origin[1] + (self.map_height - np.asarray(v, dtype=np.float64)) * self.resolution
        return x, y

    def cell_to_pixel(self, u: ArrayLike, v: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        u0, v0 = self.top_left
        s = self.scale
        return (np.asarray(u, dtype=np.float64) - u0) * s, (np.asarray(v, dtype=np.float64) - v0) * s

    def pixel_to_cell(self, px: ArrayLike, py: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        u0, v0 = self.top_left
        s = self.scale
        return np.asarray(px, dtype=np.float64) / s + u0, np.asarray(py, dtype=np.float64) / s + v0

    def world_to_pixel(self, x: ArrayLike, y: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """World metres -> canvas pixels; works on scalars and arrays alike."""
        return self.cell_to_pixel(*self.world_to_cell(x, y))

    def pixel_to_world(self, px: ArrayLike, py: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        return self.cell_to_world(*self.pixel_to_cell(px, py))

    def metres_to_px(self, metres: float) -> float:
        return float(metres) * self.px_per_m

    # -- drawing helpers ---------------------------------------------------------------------------
    def chair_radius_px(self, footprint_radius: float) -> float:
        """Radius of the chair's circle in canvas pixels (never below MIN_CHAIR_RADIUS_PX)."""
        return max(self.metres_to_px(abs(_finite(footprint_radius, "footprint_radius"))), MIN_CHAIR_RADIUS_PX)

    def dot_radius_px(self, footprint_radius: float) -> float:
        """The heading dot has half the chair's radius (as in the original app)."""
        return max(self.chair_radius_px(footprint_radius) / 2.0, MIN_DOT_RADIUS_PX)

    def image_window(self, map_image: np.ndarray, fill: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """The visible part of ``map_image`` resampled (nearest) to the canvas size.

        Args:
            map_image: (map_height, map_width[, channels]) uint8 image, row 0 = top.
            fill: value for canvas pixels outside the map (letterbox).

        Returns:
            (image, inside): image of shape (canvas_height, canvas_width[, channels]) and a bool
            (canvas_height, canvas_width) mask of pixels that show the map.
        """
        if map_image.shape[:2] != (self.map_height, self.map_width):
            raise ValueError(
                f"map image is {map_image.shape[1]}x{map_image.shape[0]} px, viewport expects "
                f"{self.map_width}x{self.map_height} cells"
            )
        cols = np.floor(self.pixel_to_cell(np.arange(self.canvas_width) + 0.5, 0.0)[0]).astype(np.int64)
        rows = np.floor(self.pixel_to_cell(0.0, np.arange(self.canvas_height) + 0.5)[1]).astype(np.int64)
        col_ok = (cols >= 0) & (cols < self.map_width)
        row_ok = (rows >= 0) & (rows < self.map_height)
        out = map_image[np.clip(rows, 0, self.map_height - 1)[:, None], np.clip(cols, 0, self.map_width - 1)]
        inside = row_ok[:, None] & col_ok[None, :]
        if not inside.all():
            out = out.copy()
            out[~inside] = fill
        return out, inside


def fit_canvas(map_width: int, map_height: int, max_width: int, max_height: int, min_px: int = 160) -> tuple[int, int]:
    """Canvas size (px) with the map's aspect ratio, as large as fits in ``max_width`` x ``max_height``.

    A canvas of the map's own shape shows the whole map at zoom level 1 with no empty band around
    it (the page keeps its controls right next to the map).  Neither side goes below ``min_px``
    (capped by the maximum), so a long thin corridor map still gets a usable canvas; the view is
    then letterboxed along that side.

    Raises:
        ValueError: on non-positive sizes.
    """
    mw, mh, cw, ch = int(map_width), int(map_height), int(max_width), int(max_height)
    if min(mw, mh) < 1 or min(cw, ch) < 1:
        raise ValueError(f"sizes must be positive, got map {map_width}x{map_height}, max {max_width}x{max_height}")
    scale = min(cw / mw, ch / mh)
    # round up: the map then fills the limiting side exactly and leaves < 1 px on the other
    width = min(max(math.ceil(mw * scale - 1e-9), min(int(min_px), cw)), cw)
    height = min(max(math.ceil(mh * scale - 1e-9), min(int(min_px), ch)), ch)
    return int(width), int(height)


def heading_point(
    x: float, y: float, theta: float, v: float, footprint_radius: float, horizon: float = 1.0
) -> tuple[float, float]:
    """Where the chair will be after ``horizon`` seconds at speed ``v`` along ``theta`` (world metres).

    A chair slower than STILL_SPEED would hide the dot under its own circle, so the dot is then put
    on the footprint's edge along the heading: the heading stays visible while standing still.
    Reversing (v < 0) puts the dot behind the chair, which is where it is going.  Turning (w) is
    ignored: a straight-line guess is what the original app showed.
    """
    still = not math.isfinite(v) or abs(v) < STILL_SPEED
    d = abs(footprint_radius) if still else v * horizon
    return x + d * math.cos(theta), y + d * math.sin(theta)
