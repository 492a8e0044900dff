"""Which boundaries lead out of the building: the only openings the map leaves open to the outside.

IndoorGML says where a building is entered in two ways: the boundary's type (navi:AnchorBoundary, the
face of an AnchorSpace), or the navigation graph, with a transition from a room to a state that stands
for no cell (UCLM's put-outer writes an ``OUTSIDE`` state). The rasteriser walls every other edge of
the free space that faces the outside (:mod:`pmk_nb.raster.seal`).
"""

from __future__ import annotations

from collections.abc import Container, Mapping
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pmk_nb.indoorgml.scan import RawDocument


def entrance_ids(doc: RawDocument, cell_of: Mapping[str, str | None], cells: Container[str]) -> set[str]:
    """Ids of the AnchorBoundaries, and of the boundaries dual to a transition between a kept cell and
    a state with no cell.

    ``cell_of``: state id -> the cell it stands for (None: the file gives it none); ``cells``: the
    kept cells. A state missing from the file is a dangling reference, not the outside.
    """
    out = {rb.id for rb in doc.boundaries if rb.kind_name == "anchorboundary"}
    for t in doc.transitions:
        if not t.duality or len(t.connects) < 2:
            continue
        ends = t.connects[:2]
        inside = [cell_of.get(ref, ref) in cells for ref in ends]
        bare = [ref in cell_of and cell_of[ref] is None for ref in ends]
        if (inside[0] and bare[1]) or (inside[1] and bare[0]):
            out.add(t.duality)
    return out
