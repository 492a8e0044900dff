"""Storey assignment: explicit tags when the file has them, else clusters of floor heights.

Files tag storeys as ``level`` (1.1/2.0), an extension element, or ``storey="F1"`` / ``level=4;`` in
gml:description. Without tags we cluster the cells' z_min: a new storey starts where sorted floor
heights jump by more than max(1.2 m, 25 % of the median cell height) - lower steps are windows,
sills and landings of the same storey (FZK-Haus: windows at 0.8/0.95 m sit on the ground floor).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

MIN_STOREY_GAP = 1.2  # metres


@dataclass
class CellZ:
    id: str
    z_min: float | None
    z_max: float | None
    hint: str | None
    hint_source: str


@dataclass
class StoreyPlan:
    names: list[str]  # bottom to top
    elevation: dict[str, float | None]
    of_cell: dict[str, str]
    source: dict[str, str]
    notes: list[str]


_RANGE = re.compile(r"^\s*([^~\-]+?)\s*[~\-]\s*(\S+)\s*$")


def _first_of_range(tag: str) -> str:
    """``2-3`` / ``F01~F02`` (stairs spanning storeys) belong to the lower storey."""
    if tag.lstrip("-").replace(".", "").isdigit():
        return tag  # a plain (possibly negative) number is not a range
    m = _RANGE.match(tag)
    return m.group(1) if m else tag


def _gap(cells: list[CellZ]) -> float:
    heights = sorted(c.z_max - c.z_min for c in cells if c.z_min is not None and c.z_max is not None)
    median = heights[len(heights) // 2] if heights else 0.0
    return max(MIN_STOREY_GAP, 0.25 * median)


def plan_storeys(cells: list[CellZ]) -> StoreyPlan:
    """Decide storeys for ``cells`` (z in metres)."""
    notes: list[str] = []
    tagged = [c for c in cells if c.hint]
    if tagged and len(tagged) * 2 >= len(cells):
        of_cell = {c.id: _first_of_range(c.hint) for c in tagged if c.hint}
        floor: dict[str, float | None] = {}
        for c in tagged:
            s = of_cell[c.id]
            if c.z_min is not None:
                cur = floor.get(s)
                floor[s] = c.z_min if cur is None else min(cur, c.z_min)
            else:
                floor.setdefault(s, None)
        untagged = [c for c in cells if not c.hint]
        for c in untagged:
            known = [(abs((z or 0.0) - (c.z_min or 0.0)), s) for s, z in floor.items()]
            of_cell[c.id] = min(known)[1]
        if untagged:
            notes.append(f"{len(untagged)} cells without a storey tag were put on the nearest storey by z")
        sources = {s: next(c.hint_source for c in tagged if of_cell[c.id] == s) for s in floor}
        names = sorted(floor, key=lambda s: (floor[s] if floor[s] is not None else 0.0, _natural(s)))
        return StoreyPlan(names, floor, of_cell, sources, notes)
    with_z = sorted((c for c in cells if c.z_min is not None), key=lambda c: c.z_min or 0.0)
    if not with_z:
        return StoreyPlan(["0"], {"0": None}, {c.id: "0" for c in cells}, {"0": "single"}, notes)
    gap = _gap(cells)
    groups: list[list[CellZ]] = [[with_z[0]]]
    for c in with_z[1:]:
        if (c.z_min or 0.0) - (groups[-1][-1].z_min or 0.0) > gap:
            groups.append([])
        groups[-1].append(c)
    single = len(groups) == 1
    names = [str(i) for i in range(len(groups))]
    of_cell = {c.id: names[i] for i, g in enumerate(groups) for c in g}
    for c in cells:
        of_cell.setdefault(c.id, names[0])
    elevation: dict[str, float | None] = {names[i]: g[0].z_min for i, g in enumerate(groups)}
    source = {n: ("single" if single else "z") for n in names}
    if not single:
        notes.append(
            f"storeys found by clustering floor heights (gap > {gap:.2f} m): "
            + ", ".join(f"{n} at z={elevation[n]:.2f} m" for n in names)
        )
    return StoreyPlan(names, elevation, of_cell, source, notes)


def _natural(s: str) -> tuple[object, ...]:
    return tuple(int(p) if p.isdigit() else p for p in re.split(r"(\d+)", s))
