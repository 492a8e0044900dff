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

from typing import TYPE_CHECKING, cast

import numpy as np
import shapely

if TYPE_CHECKING:
    from shapely.geometry.base import BaseGeometry

    from pmk_nb.indoorgml import Boundary

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
        geom = cast("BaseGeometry", door.geometry)  # not None: ``guessed`` keeps doors with a geometry
        if all(_faces_a_cell(geom, side * reach, tree, cells) for side in (1.0, -1.0)):
            continue  # a cell on each side: between rooms, the graph and the seams decide
        if lines is not None and len(lines.query(geom, predicate="dwithin", distance=CROSS)):
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


def facing_outside(lines: list[BaseGeometry], cells: list[BaseGeometry], reach: float) -> list[bool]:
    """Per line, whether one of its sides has no cell within ``reach``: a door there opens onto the
    outside (the seal leaves its opening open, :mod:`pmk_nb.raster.seal`). Most door lines have a cell
    1 mm off each side of their middle (two point-in-cell probes, vectorised); only the others get the
    strip test of :func:`outer_guesses`, so a storey of thousands of doors costs no GEOS buffer each."""
    if not lines:
        return []
    if not cells:
        return [True] * len(lines)
    arr, n = np.asarray(lines, dtype=object), len(lines)
    tree = shapely.STRtree(cells)
    coords, index = shapely.get_coordinates(arr, return_index=True)
    counts = np.bincount(index, minlength=n)
    last = np.cumsum(counts) - 1
    p0, p1 = coords[np.maximum(last - counts + 1, 0)], coords[np.maximum(last, 0)]
    mid = (p0 + p1) / 2
    bent = counts > 2
    if bent.any():
        mid[bent] = shapely.get_coordinates(shapely.line_interpolate_point(arr[bent], 0.5, normalized=True))
    d = p1 - p0
    length = np.hypot(d[:, 0], d[:, 1])
    normal = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.where(length > 0, length, 1.0)[:, None] * 1e-3
    hit = np.zeros(2 * n, dtype=bool)
    hit[tree.query(shapely.points(np.vstack([mid + normal, mid - normal])), predicate="within")[0]] = True
    # a door line drawn in the middle of a wall gap has no cell 1 mm off it: probe a straight line again
    # half the strip deep (a point inside a cell there is a cell covering some of the strip)
    deep = np.flatnonzero(~(hit[:n] & hit[n:]) & (counts == 2) & (length > 0) & (reach > 0))
    if len(deep):
        off = normal[deep] * (reach / 2 / 1e-3)
        far = np.zeros(2 * len(deep), dtype=bool)
        far[tree.query(shapely.points(np.vstack([mid[deep] + off, mid[deep] - off])), predicate="within")[0]] = True
        hit[deep] |= far[: len(deep)]
        hit[n + deep] |= far[len(deep) :]
    both = hit[:n] & hit[n:] & (length > 0)
    out = [False] * len(lines)
    for i in np.flatnonzero(~both).tolist():
        out[i] = not all(_faces_a_cell(lines[i], side * reach, tree, cells) for side in (1.0, -1.0))
    return out
