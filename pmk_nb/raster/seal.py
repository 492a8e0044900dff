"""The free space's outer edge is a wall: no free cell touches the unknown outside, but at entrances.

Nav2's planners take unknown as passable by default (``allow_unknown: true``), so a free cell beside an
unknown one is a way out of the building that nobody drew. Walls along cell outlines close every edge
the file draws, but openings cut afterwards can reach past it: a door cell standing out of the outer
wall (a free bar into the unknown), a door boundary in a façade, the band that opens a door across a
gap between rooms. :func:`seal_outside` is the one rule behind all of them: every unknown cell next
to a free one (8-neighbourhood, so no diagonal slips through) becomes occupied - one cell of wall on
the free space's outer edge - except next to an entrance's own opening, where the file itself says
the building is left: an AnchorSpace cell, an AnchorBoundary, or the face of a transition to a state with
no cell (see :attr:`pmk_nb.indoorgml.model.Boundary.entrance`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
import shapely

from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN
from pmk_nb.indoorgml import CellKind
from pmk_nb.openings import facing_outside
from pmk_nb.raster.scanline import Frame
from pmk_nb.raster.spans import fill_polygons
from pmk_nb.raster.walls import door_gaps, door_geometry

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Building, Cell
    from pmk_nb.openings import OpeningPlan


class _StoreyPlan(Protocol):
    """What :func:`seal_storey` reads of the rasteriser's storey plan."""

    frame: Frame
    half: float
    cells: list[Cell]
    openings: OpeningPlan
    outside_mark: int


_ENTRY = 103  # transient: a free cell of an entrance's own opening, which may face the outside


def seal_storey(
    grid: np.ndarray, building: Building, storey: str, plan: _StoreyPlan, max_gap: float, wall: int
) -> None:
    """The step after the doors: seal the free space's outer edge, but at entrances (nothing to do when
    everything outside the cells becomes occupied anyway). ``wall``: the rasteriser's wall mark."""
    if plan.outside_mark == UNKNOWN:
        seal_outside(grid, plan.frame, entrance_zones(building, storey, plan, max_gap), UNKNOWN, (wall,))


def entrance_zones(building: Building, storey: str, plan: _StoreyPlan, max_gap: float) -> list[Any]:
    """The free cells of each way out's own opening: AnchorSpace cells, and door lines drawn as openings
    that face the outside (no cell on one side within ``max_gap``: a door the file gives there, by type,
    name or transition; rule 4 has shut the guessed ones), each as far as its opening reaches (half a
    wall and a cell, plus the gap its line bridges), plus a cell for rounding. Free cells beyond (a
    room, a lane laid along the facade, a door cell standing out) are sealed as any other."""
    cells = plan.cells
    reach = plan.half + plan.frame.resolution
    pad = reach + plan.frame.resolution
    zones: list[Any] = [shapely.buffer(c.footprint, pad) for c in cells if c.kind is CellKind.ANCHOR]
    _, lines = door_geometry(building, storey, [], skip=plan.openings.shut_doors)
    outward = facing_outside(lines, [c.footprint for c in cells], max_gap) if lines else []
    ways = [line for line, out in zip(lines, outward, strict=True) if out]
    if ways:
        rooms = [c.footprint for c in cells if c.kind.is_free and not c.kind.is_door]
        gaps = door_gaps(ways, rooms, max_gap=max_gap)
        zones += [shapely.buffer(g, gap + pad, cap_style="flat") for g, gap in zip(ways, gaps, strict=True)]
    return zones


def seal_outside(grid: np.ndarray, frame: Frame, zones: list[Any], outside: int, keep: tuple[int, ...]) -> int:
    """Every ``outside`` cell 8-adjacent to a free cell becomes occupied, unless its only free
    neighbours lie in ``zones`` (entrances' openings: the way out stays open).

    ``keep``: the other values the grid holds while drawing (marked walls), never touched.
    Works in strips of 64 Ki cells with a one-row halo: no full-size temporary, linear in the grid.
    Returns the number of cells sealed.
    """
    if zones:
        fill_polygons(grid, frame, zones, _ENTRY, keep=(OCCUPIED, outside, *keep))
    height, width = grid.shape
    step = max(1, 65536 // max(1, width))
    sealed = 0
    for start in range(0, height, step):
        stop = min(height, start + step)
        lo, hi = max(0, start - 1), min(height, stop + 1)
        free = grid[lo:hi] == FREE
        if not free.any():
            continue
        wide = free.copy()  # free or beside a free cell in its row, then in the rows above and below
        wide[:, 1:] |= free[:, :-1]
        wide[:, :-1] |= free[:, 1:]
        mid, n = start - lo, stop - start
        near = wide[mid : mid + n].copy()
        near[1:] |= wide[mid : mid + n - 1]  # the row below (row 0 = bottom), then the row above
        near[:-1] |= wide[mid + 1 : mid + n]
        if mid:
            near[0] |= wide[0]
        if hi > stop:
            near[-1] |= wide[-1]
        block = grid[start:stop]
        near &= block == outside
        if near.any():
            sealed += int(np.count_nonzero(near))
            np.copyto(block, OCCUPIED, where=near)
    if zones:  # the entrances' cells are free again (rows they cover only)
        _, y0, _, y1 = shapely.total_bounds(np.asarray(zones, dtype=object)).tolist()
        r0 = max(0, int((y0 - frame.y0) / frame.resolution) - 1)
        r1 = min(height, int((y1 - frame.y0) / frame.resolution) + 2)
        rows = grid[r0:r1]
        np.copyto(rows, FREE, where=rows == _ENTRY, casting="unsafe")
    return sealed
