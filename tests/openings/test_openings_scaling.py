"""Issue 31, linear cost: the openings plan's indexed searches give exactly what the all-pairs ones gave."""

from __future__ import annotations

from pathlib import Path

import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString

from pmk_nb.indoorgml import Boundary, Cell, CellKind, read_building
from pmk_nb.openings import plan
from pmk_nb.openings.nearby import Nearby
from tests.access.test_access_rules import _boundary, _cell, _graph, _plan

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
    real = plan._door_lines

    def counting(link: object, shared: object, doors: list, *rest: object) -> list:
        seen.append(len(doors))
        return real(link, shared, doors, *rest)

    monkeypatch.setattr(plan, "_door_lines", counting)
    most = {}
    for n in (3, 6):
        b = read_building(_rooms_plan(tmp_path, n), unit="m")
        seen.clear()
        opened = plan.plan_openings(b, b.storeys[0].name)
        assert opened.rule_counts() == {"door": len(opened.openings)}  # every link opened at its door
        most[n] = max(seen)
    assert 0 < most[6] == most[3] <= 4  # 6 door lines on the 3 x 3 plan, 30 on the 6 x 6
