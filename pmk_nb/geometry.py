"""Shapely helpers the openings plan and the rasteriser share: the polygon parts of geometries (what every
fill and wall step rasterises), a door cell's frame, bounding-box tests."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry


def polygons_of(geom: BaseGeometry | None) -> list[shapely.Polygon]:
    """The non-empty polygon parts of any geometry (Polygon, MultiPolygon, collections)."""
    if geom is None or geom.is_empty:
        return []
    if isinstance(geom, shapely.Polygon):
        return [geom]
    if isinstance(geom, shapely.MultiPolygon | shapely.GeometryCollection):
        return [p for part in geom.geoms for p in polygons_of(part)]
    return []


def door_frame(poly: BaseGeometry) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(centre, across, along) of ``poly``'s minimum rotated rectangle: the vectors of its short side
    (through the wall, for a door cell) and of its long side (along the wall); None when degenerate."""
    rect = shapely.get_coordinates(shapely.minimum_rotated_rectangle(poly))[:4]
    if len(rect) < 4:
        return None
    e1, e2 = rect[1] - rect[0], rect[2] - rect[1]
    short, long_ = (e1, e2) if np.hypot(*e1) <= np.hypot(*e2) else (e2, e1)
    return rect.mean(axis=0), short, long_


def polygon_parts(geoms: Sequence[BaseGeometry | None]) -> list[shapely.Polygon]:
    """:func:`polygons_of` over a list: one vectorised type test when they are all plain polygons
    (a storey's cells nearly always are), so thousands of cells cost no Python call each."""
    if not geoms:
        return []
    arr = np.asarray(geoms, dtype=object)
    if all(g is not None for g in geoms) and bool(
        (shapely.get_type_id(arr) == 3).all() and not shapely.is_empty(arr).any()
    ):
        return list(geoms)  # type: ignore[arg-type]
    return [p for g in geoms for p in polygons_of(g)]


def boxes_overlap(a: BaseGeometry, b: BaseGeometry) -> bool:
    """Whether the bounding boxes of ``a`` and ``b`` share some area: when not, the two share none either
    (their intersection's area is exactly 0), so an area test can be skipped (most linked cells touch)."""
    ax0, ay0, ax1, ay1 = a.bounds
    bx0, by0, bx1, by1 = b.bounds
    return bool(min(ax1, bx1) > max(ax0, bx0) and min(ay1, by1) > max(ay0, by0))


def grown_box(geom: Any, by: Any) -> Any:
    """The bounding box(es) of ``geom`` (one geometry or an array) grown by ``by`` on every side."""
    x0, y0, x1, y1 = np.moveaxis(shapely.bounds(geom), -1, 0)
    return shapely.box(x0 - by, y0 - by, x1 + by, y1 + by)
