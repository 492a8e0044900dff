"""Storey assignment: explicit tags when the file has them, else clusters of floor heights.

Files tag storeys as ``level`` (1.1/2.0), an extension element, or ``storey="F1"`` / ``level=4;`` in
gml:description. Without tags we cluster the cells' z_min: a new storey starts where sorted floor
heights jump by more than max(1.2 m, 25 % of the median cell height) - lower steps are windows,
sills and landings of the same storey (FZK-Haus: windows at 0.8/0.95 m sit on the ground floor).
"""

from __future__ import annotations

import itertools
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


SPLIT_STEP = 0.5  # metres: floors further apart than this in one z-cluster may be separate (split) levels
_VERTICAL = re.compile(r"stair|steps|lift|elevator|escalator|treppe|aufzug|계단|엘리베이터|승강기", re.IGNORECASE)


def is_vertical(name: str) -> bool:
    """A stair, lift or escalator by its name: its transitions lead to another level."""
    return bool(_VERTICAL.search(name or ""))


def _bands(members: list[tuple[str, float]]) -> list[list[str]]:
    """Cells (id, z_min) sorted by z, cut where the floor jumps by more than SPLIT_STEP."""
    members = sorted(members, key=lambda m: m[1])
    bands: list[list[str]] = [[members[0][0]]]
    for (_, z0), (cid, z1) in itertools.pairwise(members):
        if z1 - z0 > SPLIT_STEP:
            bands.append([])
        bands[-1].append(cid)
    return bands


def _level_groups(bands: list[list[str]], links: list[tuple[str, str]], vertical: set[str]) -> list[list[int]]:
    """Bands joined into levels: by a transition between two ordinary cells (a ramp, a sloping floor),
    and a band no transition reaches (windows, sills) with the band below it."""
    band_of = {cid: i for i, band in enumerate(bands) for cid in band}
    parent = list(range(len(bands)))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    linked: set[int] = set()
    for a, b in links:
        if a not in band_of or b not in band_of:
            continue
        linked |= {band_of[a], band_of[b]}
        if a not in vertical and b not in vertical:
            parent[find(band_of[a])] = find(band_of[b])
    for i in range(len(bands)):
        if i not in linked:
            parent[find(i)] = find(i - 1 if i else min(1, len(bands) - 1))
    groups: dict[int, list[int]] = {}
    for i in range(len(bands)):
        groups.setdefault(find(i), []).append(i)
    return sorted(groups.values(), key=min)


def split_levels(
    plan: StoreyPlan,
    cells: dict[str, tuple[float | None, str]],
    links: list[tuple[str, str]],
    stairs: frozenset[str] = frozenset(),
) -> StoreyPlan:
    """Storeys from the graph and z together: a storey found by clustering floor heights is split where
    its height bands (floors more than SPLIT_STEP apart) are joined only through stairs or lifts, so a
    split level is its own storey and those transitions link two storeys. Bands joined by an ordinary
    transition (a ramp, a sloping floor) stay one storey. ``cells``: id -> (z_min, name); a cell is a
    stair or lift by its name or, whatever its name, when it is in ``stairs`` (its treads drawn as
    steps, see :func:`pmk_nb.indoorgml.footprint.stepped`). Storeys tagged in the file are never changed.
    """
    if not links or any(src not in ("z", "single") for src in plan.source.values()):
        return plan
    vertical = {cid for cid, (_, name) in cells.items() if is_vertical(name) or cid in stairs}
    levels: list[tuple[float | None, list[str]]] = []
    notes = list(plan.notes)
    for name in plan.names:
        ids = [cid for cid, s in plan.of_cell.items() if s == name]
        with_z = [(cid, z) for cid in ids if (z := cells.get(cid, (None, ""))[0]) is not None]
        if not with_z:
            levels.append((plan.elevation[name], ids))
            continue
        bands = _bands(with_z)
        groups = _level_groups(bands, links, vertical)
        parts = [[cid for i in g for cid in bands[i]] for g in groups]
        parts[0] += [cid for cid in ids if cells.get(cid, (None, ""))[0] is None]
        for part in parts:
            levels.append((min((z for cid, z in with_z if cid in set(part)), default=None), part))
        if len(parts) > 1:
            unnamed = sorted(cells[c][1] or c for c in ids if c in stairs and not is_vertical(cells[c][1]))
            notes.append(
                f"storey {name}: {len(parts)} levels joined only by stairs or lifts in the navigation graph "
                f"(floors at {', '.join(f'{lv[0]:.2f}' for lv in levels[-len(parts) :] if lv[0] is not None)} m)"
                + (f"; stairs by their steps: {', '.join(unnamed)}" if unnamed else "")
            )
    if len(levels) == len(plan.names):
        return plan
    levels.sort(key=lambda lv: (lv[0] is None, lv[0] or 0.0))
    names = [str(i) for i in range(len(levels))]
    of_cell = {cid: names[i] for i, (_, part) in enumerate(levels) for cid in part}
    return StoreyPlan(
        names, {n: lv[0] for n, lv in zip(names, levels, strict=True)}, of_cell, {n: "z+graph" for n in names}, notes
    )
