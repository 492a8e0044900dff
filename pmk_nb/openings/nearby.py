"""What lies near a link: R-trees over a storey's cells, door boundaries and virtual boundaries.

Placing each opening once looked at every door, virtual boundary or cell of the storey, which made
:func:`pmk_nb.openings.plan.plan_openings` quadratic in the plan (issue 31: a 4x plan took 8-9x
the time). Each query here returns a superset of what the exact test keeps (or the exact answer), in
list order, as the loops over everything did, so the openings are the same.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cached_property
from typing import TYPE_CHECKING

import shapely

from pmk_nb.geometry import grown_box

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Boundary, Cell


class Nearby:
    """A storey's cells, door boundaries (with geometry) and virtual boundary geometries, indexed on
    first use."""

    def __init__(self, cells: Sequence[Cell], doors: Sequence[Boundary], virtual: Sequence[BaseGeometry]) -> None:
        self.cells, self.doors, self.virtual = tuple(cells), tuple(doors), tuple(virtual)

    def others(self, a: Cell, b: Cell, near: BaseGeometry) -> list[BaseGeometry]:
        """Footprints of the cells but ``a`` and ``b`` whose bounding boxes meet ``near``'s."""
        hits = sorted(self._cells.query(near).tolist())
        return [self.cells[i].footprint for i in hits if self.cells[i].id not in (a.id, b.id)]

    def doors_near(self, geom: BaseGeometry, reach: float) -> list[Boundary]:
        """The door boundaries that may lie within ``reach`` of ``geom`` (a superset: the caller decides)."""
        return [self.doors[i] for i in _within(self._doors, geom, 2 * reach)]

    def virtual_within(self, geom: BaseGeometry, reach: float) -> list[BaseGeometry]:
        """The virtual boundaries at most ``reach`` from ``geom``."""
        hits = [self.virtual[i] for i in _within(self._virtual, geom, 2 * reach)]
        return [v for v in hits if v.distance(geom) <= reach]

    @cached_property
    def _cells(self) -> shapely.STRtree:
        return shapely.STRtree([c.footprint for c in self.cells])

    @cached_property
    def _doors(self) -> shapely.STRtree:
        # STRtree skips None (shapely documents it); the stubs' GeoArrayLikeSeq leaves None out
        return shapely.STRtree([d.geometry for d in self.doors])  # type: ignore[arg-type]

    @cached_property
    def _virtual(self) -> shapely.STRtree:
        return shapely.STRtree(list(self.virtual))


def _within(tree: shapely.STRtree, geom: BaseGeometry, reach: float) -> list[int]:
    """Indices (ascending) of the tree's items whose bounding boxes come within ``reach`` (plus a
    nanometre) of ``geom``'s: every item at most ``reach`` away, and some further (GEOS's own dwithin
    query misses degenerate items, e.g. a zero-length line, so the boxes decide)."""
    return sorted(tree.query(grown_box(geom, reach + 1e-9)).tolist())
