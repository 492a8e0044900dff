"""Which free cells are windows or sills rather than floor: judged against the cells they touch.

A window cell sits in a room's wall, starting well above that room's floor and ending below its
ceiling. Comparing with the storey's lowest point instead (as before) turned every higher cell of a
sloping floor (an underground plaza from -3.9 m to -0.9 m, a ramp, a split level) into a window.
So a cell is raised only when a cell it touches on the same storey starts more than ``RAISED`` below
it where the two meet (a sloping corridor's floor at a door, not the corridor's lowest point) *and*
reaches at least as high (within ``TOP_SLACK``), unless the navigation graph links the two and the
cell is wider than a wall (``WINDOW_DEPTH``): a door beside a sloping floor, a step up to a higher
floor whose ceiling rises with it, a gallery the graph reaches from the ramp below it, or a cell
touching nothing lower, stays navigable.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

import numpy as np
import shapely

from pmk_nb.errors import IndoorGMLError

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

RAISED = 0.5  # metres above a touching cell's floor: a window/sill, not floor space
WINDOW_DEPTH = 1.0  # metres: a raised cell this thin is a window in a wall, linked in the graph or not
TOP_SLACK = 0.3  # metres: a window ends below (or at) the ceiling of the room it is in

CellLevel = tuple[str, "BaseGeometry", float | None, float | None, str]  # id, footprint, z_min, z_max, storey
FloorAt = Callable[[str, float, float], "float | None"]  # cell id, x, y (footprint units) -> floor height, m


def raised_cells(
    cells: list[CellLevel],
    touch: float,
    linked: frozenset[frozenset[str]] = frozenset(),
    thin: float = 0.0,
    floor_at: FloorAt | None = None,
) -> set[str]:
    """Ids of cells that are windows/sills; ``touch`` is the adjacency tolerance in footprint units.

    A cell the navigation graph links to a touching cell, and wider than ``thin`` (footprint units), is
    reached from it on wheels: a gallery at the top of a ramp, not a window of the ramp. Windows sit in
    walls, and some files link them too (FZK-Haus: 0.3 m deep window cells with states and transitions).
    ``floor_at`` gives a cell's floor height at a point: both floors are then compared where the cells
    meet (KU Central Plaza: doors along a corridor sloping from -3.9 m to -0.9 m)."""
    with_z = [c for c in cells if c[2] is not None and c[3] is not None and c[1] is not None]
    if not with_z:
        return set()
    tree = shapely.STRtree([c[1] for c in with_z])
    left, right = tree.query([c[1] for c in with_z], predicate="dwithin", distance=touch)
    out: set[str] = set()
    for i, j in zip(left.tolist(), right.tolist(), strict=True):
        if i == j:
            continue
        cid, _, z0, z1, storey = with_z[i]
        nid, _, n0, n1, n_storey = with_z[j]
        if storey != n_storey or z0 is None or z1 is None or n0 is None or n1 is None:
            continue
        if not (z0 - n0 > RAISED and z1 <= n1 + TOP_SLACK and z1 > z0):
            continue
        if floor_at is not None and _step_where_they_meet(with_z[i], with_z[j], z0, n0, floor_at) <= RAISED:
            continue  # level with the sloping floor beside it: a door or an alcove, not a sill
        if frozenset((cid, nid)) in linked and _narrow_side(with_z[i][1]) > thin:
            continue  # reached from the lower cell: a gallery, not a window
        out.add(cid)
    return out


def _step_where_they_meet(cell: CellLevel, other: CellLevel, low: float, other_low: float, floor_at: FloorAt) -> float:
    """How far ``cell``'s floor sits above ``other``'s where they meet: at the point of ``other`` nearest
    ``cell``'s centre, and the point of ``cell`` nearest that. A floor with no height there counts by its
    lowest point (``low``, ``other_low``), as before."""
    fp, ofp = cell[1], other[1]
    there = shapely.shortest_line(ofp, fp.centroid).coords[0]
    here = shapely.shortest_line(fp, shapely.Point(there)).coords[0]
    mine, theirs = floor_at(cell[0], *here), floor_at(other[0], *there)
    return (low if mine is None else mine) - (other_low if theirs is None else theirs)


def _narrow_side(footprint: BaseGeometry) -> float:
    """The shorter side of the footprint's minimum rotated rectangle (a wall's depth for a window)."""
    box = shapely.get_coordinates(shapely.minimum_rotated_rectangle(footprint))
    if len(box) < 3:
        return 0.0
    sides = np.hypot(*(box[1] - box[0])), np.hypot(*(box[2] - box[1]))
    return float(min(sides))


def not_window_ids(cells: Iterable[tuple[str, str]], wanted: Iterable[str], source: str) -> frozenset[str]:
    """Ids of the cells ``wanted`` names (by id or name): the window rule leaves them free. The user's
    answer when the report names a door as a cell taken for a window or sill.

    Raises:
        IndoorGMLError: a word matches no cell's id or name (names the file and the word).
    """
    want = {w.strip() for w in wanted if w and w.strip()}
    pairs = list(cells)
    known = {i for i, _ in pairs} | {n for _, n in pairs if n}
    missing = sorted(want - known)
    if missing:
        raise IndoorGMLError(
            f"{source}: --not-window {missing[0]!r}: no cell of the plan has that id or name",
            path=source,
            element=missing[0],
            hint="`pmk check` names the cells taken for windows or sills; give one of those names (or its id).",
        )
    return frozenset(i for i, name in pairs if i in want or name in want)
