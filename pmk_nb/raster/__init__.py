"""Rasteriser: one storey of a :class:`~pmk_nb.indoorgml.Building` -> an occupancy grid.

Read top to bottom: ``storey`` (plan the frame, then cells, walls, doors, grid), ``walls``
(wall lines, gap closing, door openings) and ``scanline`` (the array primitives that fill cells).
"""

from __future__ import annotations

from pmk_nb.raster.scanline import Frame, write_rects
from pmk_nb.raster.spans import polygon_rects, polygon_rects_each
from pmk_nb.raster.storey import (
    DEFAULT_MAX_CELLS,
    DEFAULT_MAX_WALL_GAP,
    DEFAULT_WALL_THICKNESS,
    NAV2_MAX_CELLS_PER_SIDE,
    plan_storey,
    rasterise,
    rasterise_storey,
)

__all__ = [
    "DEFAULT_MAX_CELLS",
    "DEFAULT_MAX_WALL_GAP",
    "DEFAULT_WALL_THICKNESS",
    "NAV2_MAX_CELLS_PER_SIDE",
    "Frame",
    "plan_storey",
    "polygon_rects",
    "polygon_rects_each",
    "rasterise",
    "rasterise_storey",
    "write_rects",
]
