"""Issue 31, linear cost: the converter's indexed searches give exactly what the all-pairs ones gave."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import LineString, box

from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.model import Boundary, Cell, CellKind
from pmk_nb.raster import openings
from pmk_nb.raster.nearby import Nearby
from pmk_nb.raster.walls import door_jambs
from tests.access.test_access_rules import _boundary, _cell, _graph, _plan

TOL = 0.01


def _jambs_all_pairs(rooms: np.ndarray, doors: list, tol: float) -> list:
    """door_jambs as it was: every door measured against every other door."""
    tree = shapely.STRtree(rooms) if len(rooms) else None
    out = []
    for i, door in enumerate(doors):
        near = [d for j, d in enumerate(doors) if j != i and d.distance(door) <= tol]
        if tree is not None:
            near += list(rooms[tree.query(shapely.buffer(door, tol), predicate="intersects")])
        ring = shapely.boundary(door)
        if near:
            ring = shapely.difference(ring, shapely.buffer(shapely.union_all(near), tol))
        if not ring.is_empty:
            out.append(ring)
    return out


# door cells in a row, each a gap from the last: touching (0), exactly tol, just over, well apart
_gaps = st.lists(st.sampled_from([0.0, TOL / 2, TOL, TOL * 1.0001, 0.05, 1.0]), min_size=1, max_size=12)


@settings(max_examples=60, deadline=None)
@given(gaps=_gaps, turn=st.floats(0, 90), rooms_too=st.booleans())
def test_door_jambs_match_the_all_pairs_search(gaps: list[float], turn: float, rooms_too: bool) -> None:
    doors, x = [], 0.0
    for g in gaps:
        x += g
        doors.append(affinity.rotate(box(x, 0, x + 0.9, 0.2), turn, origin=(0, 0)))
        x += 0.9
    rooms = np.asarray(
        [affinity.rotate(box(-1, 0.2, x + 1, 4), turn, origin=(0, 0))] if rooms_too else [], dtype=object
    )
    got, want = door_jambs(rooms, doors, TOL), _jambs_all_pairs(rooms, doors, TOL)
    assert len(got) == len(want)
    assert all(shapely.equals_exact(a, b, 0.0) for a, b in zip(got, want, strict=True))


def test_door_jambs_cut_only_where_doors_meet() -> None:
    a, b, c = box(0, 0, 1, 0.2), box(1 + TOL / 2, 0, 2, 0.2), box(2.5, 0, 3.5, 0.2)  # a-b within tol, c apart
    jambs = door_jambs(np.asarray([], dtype=object), [a, b, c], TOL)
    assert jambs[2].length == c.boundary.length  # nothing near c: its whole outline stays
    assert jambs[0].length < a.boundary.length and jambs[1].length < b.boundary.length


_seg = st.tuples(*[st.floats(0, 20, allow_nan=False)] * 4).map(lambda c: LineString([c[:2], c[2:]]))


@settings(max_examples=60, deadline=None)
@given(lines=st.lists(_seg, min_size=1, max_size=15), probe=_seg, reach=st.sampled_from([0.0, 0.01, 0.5, 3.0]))
def test_nearby_finds_what_a_look_at_everything_finds(lines: list, probe: LineString, reach: float) -> None:
    doors = [Boundary(f"B{i}", True, g) for i, g in enumerate(lines)]
    cells = [Cell(f"C{i}", CellKind.NAVIGABLE, shapely.buffer(g, 0.2), "F0") for i, g in enumerate(lines)]
    near = Nearby(cells, doors, lines)
    assert near.virtual_within(probe, reach) == [v for v in lines if v.distance(probe) <= reach]
    found = near.doors_near(probe, reach)  # a superset, in file order
    close = [d for d in doors if d.geometry.distance(probe) <= reach]
    assert close == [d for d in found if d.geometry.distance(probe) <= reach]
    assert found == [d for d in doors if d in found]
    lane = shapely.buffer(probe, 0.45)
    others = near.others(cells[0], cells[-1], lane)
    every = [c.footprint for c in cells if c.id not in (cells[0].id, cells[-1].id)]
    assert [g for g in every if g.intersects(lane)] == [g for g in others if g.intersects(lane)]


def _rooms_plan(tmp_path: Path, n: int) -> Path:
    """n x n rooms 3.8 m square, 0.2 m gaps; door cells in the vertical gaps, door lines in the
    horizontal ones, all joined by transitions (the bench's generated storey, small)."""
    cells, lines, pairs = [], [], []
    for i in range(n):
        for j in range(n):
            x, y, room = i * 4.0, j * 4.0, f"R{i}_{j}"
            cells.append(_cell(room, (x, y, x + 3.8, y + 3.8)))
            if i + 1 < n:
                cells.append(_cell(f"D{i}_{j}", (x + 3.8, y + 1.45, x + 4.0, y + 2.35), "navi:ConnectionSpace"))
                pairs += [(room, f"D{i}_{j}"), (f"D{i}_{j}", f"R{i + 1}_{j}")]
            if j + 1 < n:
                lines.append(
                    _boundary(f"B{i}_{j}", ((x + 1.45, y + 3.9), (x + 2.35, y + 3.9)), "navi:ConnectionBoundary")
                )
                pairs.append((room, f"R{i}_{j + 1}"))
    folder = tmp_path / f"n{n}"
    folder.mkdir()
    return _plan(folder, "".join(cells), _graph(pairs), "".join(lines))


def test_each_link_looks_at_the_doors_near_it_not_all(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """plan_openings was quadratic: every link tested every door line of the storey. Each link now
    sees a bounded number of them, whatever the size of the plan, and the openings are the same."""
    seen: list[int] = []
    real = openings._door_lines

    def counting(link: object, shared: object, doors: list, *rest: object) -> list:
        seen.append(len(doors))
        return real(link, shared, doors, *rest)

    monkeypatch.setattr(openings, "_door_lines", counting)
    most = {}
    for n in (3, 6):
        b = read_building(_rooms_plan(tmp_path, n), unit="m")
        seen.clear()
        plan = openings.plan_openings(b, b.storeys[0].name)
        assert plan.rule_counts() == {"door": len(plan.openings)}  # every link opened at its door
        most[n] = max(seen)
    assert 0 < most[6] == most[3] <= 4  # 6 door lines on the 3 x 3 plan, 30 on the 6 x 6
