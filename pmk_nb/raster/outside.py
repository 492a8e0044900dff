"""Which guessed doors face the outside: those stay wall (issue 31, rule 4).

A bare boundary shorter than its wall is taken for a door (``partial`` evidence: PNU 313 draws its
doors so), but on an outer wall the same short line is as often a window: FZK-like exports write
floor-to-ceiling windows as short boundaries, and opening them joins a room to the outside, which a
planner that takes unknown for passable drives into. Only the graph or a door decides there: a
guessed door with a cell on one side only (nothing within ``reach``, the thickest wall, on the other) stays wall
unless a transition's line crosses it; a door by type (Connection/AnchorBoundary: an entrance) or by
name, or a transition dual to the boundary, still opens.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import shapely

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml.model import Boundary

GUESSED = frozenset({"partial"})  # door evidence that is only a guess from the geometry
CROSS = 0.05  # metres: a transition's line this close to a door line goes through it (not one passing by)


def outer_guesses(
    doors: list[Boundary], cells: list[BaseGeometry], crossings: list[BaseGeometry], reach: float
) -> list[Boundary]:
    """The ``doors`` whose door evidence is a guess and that face one cell only (the outside) and no
    transition line in ``crossings``: each stays wall. ``cells``: every cell of the storey, of any kind
    (a non-navigable cell on the other side is a cell, not the outside)."""
    guessed = [d for d in doors if d.evidence in GUESSED and d.geometry is not None]
    if not guessed or not cells:
        return []
    tree = shapely.STRtree(cells)
    lines = shapely.STRtree(crossings) if crossings else None
    out = []
    for door in guessed:
        if all(_faces_a_cell(door.geometry, side * reach, tree, cells) for side in (1.0, -1.0)):
            continue  # a cell on each side: between rooms, the graph and the seams decide
        if lines is not None and len(lines.query(door.geometry, predicate="dwithin", distance=CROSS)):
            continue  # a transition goes through it (or ends on it, at a door's state)
        out.append(door)
    return out


def _faces_a_cell(line: BaseGeometry, reach: float, tree: shapely.STRtree, cells: list[BaseGeometry]) -> bool:
    """A cell covers some of the strip ``reach`` wide on one side of ``line`` (left for positive
    ``reach``); a cell merely touching the strip, as the next room at a corner does, does not count."""
    try:
        strip = shapely.buffer(line, reach, single_sided=True, cap_style="flat")
    except shapely.errors.GEOSException:
        return True  # degenerate line: keep the old rule
    return any(shapely.intersection(cells[i], strip).area > 1e-9 for i in tree.query(strip, predicate="intersects"))
