"""The navigation graph resolved to cells: which cells a transition joins, whatever the dialect.

Transitions connect States (1.x) or Nodes (2.0), and a State names its cell by duality. Files in the
wild also connect cells directly (FZK-Haus: ``connects`` points at CellSpaces) or give a State with a
point but no duality; such a state is put in the cell whose footprint holds its point, nearest in z.
Each unordered pair of cells is one :class:`Link` (a graph with both directions, or repeated layers,
says the same thing twice).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import shapely

from pmk_nb.indoorgml.model import Link

if TYPE_CHECKING:
    from pmk_nb.indoorgml.model import Cell, NavGraph


def resolve_links(graph: NavGraph, cells: dict[str, Cell]) -> list[Link]:
    """One link per pair of distinct kept cells that a transition joins, in file order."""
    ids = list(cells)
    tree = shapely.STRtree([cells[i].footprint for i in ids]) if ids else None

    def cell_of(ref: str) -> str | None:
        if ref in cells:
            return ref
        state = graph.states.get(ref)
        if state is None:
            return None
        if state.cell_id in cells:
            return state.cell_id
        if state.point is None or tree is None:
            return None
        x, y, z = state.point
        hits = [ids[i] for i in tree.query(shapely.Point(x, y), predicate="intersects")]
        return min(hits, key=lambda c: abs((cells[c].z_min or 0.0) - z), default=None)

    seen: set[frozenset[str]] = set()
    links: list[Link] = []
    for t in graph.transitions:
        a, b = cell_of(t.source), cell_of(t.target)
        if a is None or b is None or a == b or frozenset((a, b)) in seen:
            continue
        seen.add(frozenset((a, b)))
        links.append(Link(t.id, a, b, t.line, (cells[a].storey, cells[b].storey)))
    return links
