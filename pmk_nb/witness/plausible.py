"""Plan-only findings: cells that overlap, and sizes no building has in the unit the plan was read in.

A wrong unit makes every size wrong by the same factor (a clinic 100 times too small), so the test is
on the storey as a whole (its rooms' median area, its extent) and on its doors, not on one room: a
broom cupboard or an atrium is a real room.
"""

from __future__ import annotations

from statistics import median
from typing import TYPE_CHECKING

import shapely

from pmk_nb.witness.findings import Finding, FindingKind

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Cell

#: overlaps below both of these are drawing slop, not two cells claiming one floor
OVERLAP_M2 = 0.05
OVERLAP_SHARE = 0.01
ROOM_M2 = (1.0, 5000.0)  # the median room, m²
STOREY_M = (3.0, 2000.0)  # the storey's longer side, m
DOOR_M = (0.4, 12.0)  # the median door, m


def overlaps(storey: str, cells: dict[str, Cell], tree: shapely.STRtree, order: list[str]) -> list[Finding]:
    """Pairs of navigable cells whose footprints share floor (an obstacle inside a room is expected)."""
    out = []
    index = {c: i for i, c in enumerate(order)}
    for cid, cell in cells.items():
        if not cell.kind.is_free:
            continue
        for i in tree.query(cell.footprint, predicate="intersects"):
            other = cells[order[i]]
            if index[other.id] <= index[cid] or not other.kind.is_free or _stacked(cell, other):
                continue
            shared = cell.footprint.intersection(other.footprint)
            area = shared.area
            smaller = min(cell.footprint.area, other.footprint.area)
            if area > OVERLAP_M2 and area > OVERLAP_SHARE * smaller:
                detail = f"they overlap by {area:.2f} m² ({area / smaller:.0%} of the smaller)"
                at = shared.representative_point()
                names = (cell.name or cell.id, other.name or other.id)
                out.append(Finding(FindingKind.OVERLAP, storey, (cid, other.id), names, (at.x, at.y), detail, area))
    return out


def _stacked(a: Cell, b: Cell) -> bool:
    """Two cells one above the other (their heights do not meet): one floor plan, two levels of it."""
    if None in (a.z_min, a.z_max, b.z_min, b.z_max):
        return False
    return bool(a.z_max <= b.z_min + 0.01 or b.z_max <= a.z_min + 0.01)  # type: ignore[operator]


def implausible(storey: str, cells: dict[str, Cell], doors: list[BaseGeometry | None]) -> list[Finding]:
    """The storey's extent, its median room and its median door, against what buildings measure."""
    walk = [c.footprint for c in cells.values() if c.kind.is_free and not c.kind.is_door]
    if not walk:
        return []
    whole = shapely.union_all(walk)
    x0, y0, x1, y1 = whole.bounds
    centre = whole.centroid
    out = []

    def flag(what: str, value: float, limits: tuple[float, float], unit: str) -> None:
        if not limits[0] <= value <= limits[1]:
            detail = f"{what} is {value:.3g} {unit}, outside {limits[0]:g}-{limits[1]:g} {unit}: is the unit right?"
            out.append(Finding(FindingKind.IMPLAUSIBLE, storey, (), (), (centre.x, centre.y), detail, value))

    flag("the storey's longer side", max(x1 - x0, y1 - y0), STOREY_M, "m")
    flag("the median room", median(f.area for f in walk), ROOM_M2, "m²")
    widths = [door_width(g) for g in doors if g is not None and not g.is_empty]
    if widths:
        flag("the median door", median(widths), DOOR_M, "m")
    return out


def door_width(geometry: BaseGeometry) -> float:
    """A door line's length, or a door polygon's (a doorway cell's) longer side."""
    if geometry.geom_type in ("LineString", "MultiLineString"):
        return float(geometry.length)
    rect = geometry.minimum_rotated_rectangle
    xy = list(rect.exterior.coords) if hasattr(rect, "exterior") else []
    if len(xy) < 4:
        return float(geometry.length)
    sides = [shapely.Point(xy[i]).distance(shapely.Point(xy[i + 1])) for i in range(2)]
    return float(max(sides))
