"""The navigation graph resolved to cells: which cells a transition joins, whatever the dialect.

Transitions connect States (1.x) or Nodes (2.0), and a State names its cell by duality. Files in the
wild also connect cells directly (FZK-Haus: ``connects`` points at CellSpaces), give the duality only
on the cell's side, name a cell that is not in the file, or give a State with a point but no duality;
such a state is put in the cell whose footprint holds its point, nearest in z. Each unordered pair of
cells is one :class:`Link` (a graph with both directions, or repeated layers, says the same thing
twice). What cannot be resolved is counted in a :class:`GraphStatus`, said loudly, never guessed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import shapely

from pmk_nb.indoorgml.model import GraphStatus, Link, NavGraph, State, Transition

if TYPE_CHECKING:
    from pmk_nb.indoorgml.model import Cell
    from pmk_nb.indoorgml.records import RawDocument


def state_cells(doc: RawDocument) -> dict[str, str | None]:
    """The cell each state stands for: its duality when that cell is in the file, else the cell whose own
    duality names the state (exporters write it on one side only; ALMA writes the cell inside the state)."""
    ids = {c.id for c in doc.cells}
    back = {c.duality: c.id for c in doc.cells if c.duality}
    return {rs.id: rs.cell if rs.cell in ids else back.get(rs.id) for rs in doc.states}


def linked_pairs(doc: RawDocument) -> frozenset[frozenset[str]]:
    """Cell pairs a transition joins through its states' duality, or cells it names directly."""
    cell_of = state_cells(doc)
    ids = {c.id for c in doc.cells}
    pairs = set()
    for t in doc.transitions:
        ends = [e for ref in t.connects[:2] if (e := cell_of.get(ref) or (ref if ref in ids else None))]
        if len(ends) == 2 and ends[0] != ends[1]:
            pairs.add(frozenset(ends))
    return frozenset(pairs)


def nav_graph(doc: RawDocument, cells: dict[str, Cell], s: float) -> NavGraph:
    """The file's states and transitions in metres; a state's cell only when it is one of ``cells``."""
    graph = NavGraph()
    cell_of = state_cells(doc)
    for rs in doc.states:
        point = None
        if rs.point is not None:
            z = rs.point[2] * s if len(rs.point) > 2 else 0.0
            point = (rs.point[0] * s, rs.point[1] * s, z)
        cell = cell_of[rs.id]
        graph.states[rs.id] = State(rs.id, point, cell if cell in cells else None, rs.layer)
    for t in doc.transitions:
        if len(t.connects) >= 2:
            line = None
            if t.line is not None and len(t.line) >= 2:
                line = shapely.LineString([(p[0] * s, p[1] * s) for p in t.line])
            graph.transitions.append(Transition(t.id, t.connects[0], t.connects[1], t.weight, t.layer, line))
    return graph


def _locator(graph: NavGraph, cells: dict[str, Cell]) -> Callable[[str], str | None]:
    """ref (a state or a cell) -> the kept cell it stands for, or None."""
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

    return cell_of


def resolve_links(graph: NavGraph, cells: dict[str, Cell]) -> list[Link]:
    """One link per pair of distinct kept cells that a transition joins, in file order."""
    cell_of = _locator(graph, cells)
    seen: set[frozenset[str]] = set()
    links: list[Link] = []
    for t in graph.transitions:
        a, b = cell_of(t.source), cell_of(t.target)
        if a is None or b is None or a == b or frozenset((a, b)) in seen:
            continue
        seen.add(frozenset((a, b)))
        links.append(Link(t.id, a, b, t.line, (cells[a].storey, cells[b].storey)))
    return links


def graph_status(doc: RawDocument, graph: NavGraph, cells: dict[str, Cell], warnings: list[str]) -> GraphStatus:
    """How much of the file's graph resolved to drawn cells; a partial loss is added to ``warnings``."""
    n = len(doc.transitions)
    if n == 0:
        why = f"{len(doc.states)} states but no transitions" if doc.states else "no states, no transitions"
        return GraphStatus(reason=f"the file has no navigation graph ({why}): nothing to check the map against")
    known = set(graph.states) | {c.id for c in doc.cells}
    dangling = sum(1 for t in doc.transitions if len(t.connects) < 2 or any(r not in known for r in t.connects[:2]))
    cell_of = _locator(graph, cells)
    resolved = sum(1 for t in graph.transitions if cell_of(t.source) and cell_of(t.target))
    missing = sorted({rs.cell for rs in doc.states if rs.cell and rs.id in graph.states} - known)
    if missing:
        warnings.append(f"{len(missing)} states name cells that are not in the file (e.g. {missing[0]!r})")
    faces = {b.id for b in doc.boundaries}
    if unfaced := [t.duality for t in doc.transitions if t.duality and t.duality not in faces]:
        warnings.append(
            f"{len(unfaced)} transitions name a dual boundary that is not in the file "
            f"(e.g. {unfaced[0]!r}): their doors come from the cells' shapes"
        )
    said = f"{dangling} of {n} transitions name states that are not in the file"
    status = GraphStatus(n, resolved, dangling, absent=False)
    if status.lost:
        if dangling:
            end = "the navigation graph was not used" if not resolved else f"only {resolved} joined drawn cells"
            return GraphStatus(n, resolved, dangling, False, f"{said}: {end}")
        return GraphStatus(
            n,
            resolved,
            dangling,
            False,
            f"none of the {n} transitions joins two drawn cells "
            "(their states name no drawn cell and hold no point inside one): the navigation "
            "graph was not used",
        )
    if dangling:
        warnings.append(f"{said}: ignored; {resolved} transitions join drawn cells and are checked")
    return status
