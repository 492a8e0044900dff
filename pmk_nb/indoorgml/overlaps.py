"""Cells of one storey that overlap: IndoorGML's cells partition space (a cell space of a layer shares no
volume with another of that layer), so a plan whose rooms overlap is drawn wrong somewhere, and the map
would silently merge the two rooms. Each pair is reported with how much they share.

Pairs come from an R-tree (no step looks at all pairs). A sliver is no overlap: two rooms drawn a few
millimetres into their shared wall overlap along the whole wall, but by a strip thinner than
:data:`SLIVER_WIDTH`. Cells stacked in height (a landing under a room, both on one storey) share no
volume and are not reported either.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np
import shapely

from pmk_nb.indoorgml.model import Cell, CellOverlap

SLIVER_WIDTH = 0.02  # m: an overlap whose mean width (2 x area / perimeter) is thinner is drawing noise
SLIVER_AREA = 0.01  # m²: and one smaller than this, however shaped
Z_TOUCH = 0.05  # m: cells whose height ranges share less than this are stacked, not overlapping


def _stacked(a: Cell, b: Cell) -> bool:
    """Both have heights and their height ranges share (almost) nothing."""
    if None in (a.z_min, a.z_max, b.z_min, b.z_max):
        return False
    assert a.z_min is not None and a.z_max is not None and b.z_min is not None and b.z_max is not None
    return min(a.z_max, b.z_max) - max(a.z_min, b.z_min) < Z_TOUCH


def storey_overlaps(storey: str, cells: list[Cell]) -> list[CellOverlap]:
    """The overlapping pairs among ``cells`` (one storey), largest overlap first."""
    if len(cells) < 2:
        return []
    geoms = np.asarray([c.footprint for c in cells], dtype=object)
    left, right = shapely.STRtree(geoms).query(geoms, predicate="intersects")
    pairs = left < right
    left, right = left[pairs], right[pairs]
    if not len(left):
        return []
    shared = shapely.intersection(geoms[left], geoms[right])
    area = np.asarray(shapely.area(shared))
    width = 2 * area / np.maximum(np.asarray(shapely.length(shared)), 1e-12)
    smaller = np.minimum(np.asarray(shapely.area(geoms[left])), np.asarray(shapely.area(geoms[right])))
    out = []
    for i, j, a, wide, small in zip(left, right, area, width, smaller, strict=True):
        if a < SLIVER_AREA or wide < SLIVER_WIDTH or _stacked(cells[i], cells[j]):
            continue
        out.append(CellOverlap(storey, cells[i].id, cells[j].id, float(a), float(min(1.0, a / small))))
    return sorted(out, key=lambda o: -o.area)


def find_overlaps(storeys: Iterable[tuple[str, list[Cell]]]) -> list[CellOverlap]:
    """:func:`storey_overlaps` of each (storey, its cells)."""
    return [o for name, cells in storeys for o in storey_overlaps(name, cells)]
