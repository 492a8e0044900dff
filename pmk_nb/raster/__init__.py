"""Rasteriser: one storey of a :class:`~pmk_nb.indoorgml.Building` -> an occupancy grid.

``options`` (:class:`RasterOptions`: how a storey is drawn, passed whole; every default is
:mod:`pmk_nb.defaults`'s). Read top to bottom: ``storey`` (plan the frame, then cells, walls, doors, grid), ``walls``
(wall lines, gap closing, door openings) and ``scanline`` (the array primitives that fill cells).
"""

from __future__ import annotations

from pmk_nb.raster.options import RasterOptions
from pmk_nb.raster.scanline import Frame, write_rects
from pmk_nb.raster.spans import polygon_rects, polygon_rects_each
from pmk_nb.raster.storey import plan_storey, rasterise, rasterise_storey

__all__ = [
    "Frame",
    "RasterOptions",
    "plan_storey",
    "polygon_rects",
    "polygon_rects_each",
    "rasterise",
    "rasterise_storey",
    "write_rects",
]
