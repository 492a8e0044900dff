"""Issue 37 item 3: the two openings through a thin door cell lie on one straight line (1.0 and 2.0).

Room A (x 0-10) below a cell S 0.6 m deep and 16 m long, room B (x 6-16) above it; the graph joins A
to S and S to B, with no door geometry. Placed face by face (the middle of each face) the openings
sat 6 m apart and no chair turned inside the slab; aligned, they share the overlap's middle (x 8).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE
from pmk_nb.indoorgml import read_building
from pmk_nb.openings import plan_openings
from pmk_nb.raster import rasterise_storey
from pmk_nb.witness import FindingKind, witness_grid
from tests.access.test_access_rules import _cell, _graph, _plan

CELLS = _cell("A", (0, 0, 10, 4)) + _cell("S", (0, 4, 16, 4.6), name="door") + _cell("B", (6, 4.6, 16, 8.6))


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_the_openings_through_a_slab_line_up_and_a_chair_passes(tmp_path: Path, v2: bool) -> None:
    b = read_building(_plan(tmp_path, CELLS, _graph([("A", "S"), ("S", "B")], v2=v2), v2=v2), unit="m")
    storey = b.storeys[0].name
    plan = plan_openings(b, storey)
    centres = sorted(o.segments[0].centroid.x for o in plan.openings)
    assert len(centres) == 2 and centres[1] - centres[0] == pytest.approx(0.0, abs=0.05)
    assert 6.45 <= centres[0] <= 9.55  # where both faces can hold a door
    assert all(o.width == pytest.approx(0.9) for o in plan.openings)
    grid = rasterise_storey(b, storey, 0.05)
    for y in (3.9, 4.0, 4.3, 4.6, 4.7):
        assert grid.value_at(centres[0], y) == FREE, y
    report = witness_grid(b, grid, chair_width=0.7)
    kinds = {f.kind for f in report.findings}
    assert not kinds & {FindingKind.NO_WAY_THROUGH, FindingKind.LEAK}, [f.describe() for f in report.findings]


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_a_thin_cell_joining_three_rooms_keeps_each_door_on_its_face(tmp_path: Path, v2: bool) -> None:
    cells = CELLS + _cell("C", (0, 4.6, 6, 8.6))
    b = read_building(_plan(tmp_path, cells, _graph([("A", "S"), ("S", "B"), ("S", "C")], v2=v2), v2=v2), unit="m")
    plan = plan_openings(b, b.storeys[0].name)
    assert sorted(round(o.segments[0].centroid.x, 1) for o in plan.openings) == [3.0, 5.0, 11.0]


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_the_witness_finds_no_way_through_when_each_face_is_placed_alone(
    tmp_path: Path, v2: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The old placement (each face's own middle), kept here as the second judge's proof: it blocks."""
    monkeypatch.setattr("pmk_nb.openings.plan.align_slabs", lambda openings, *_: openings)
    b = read_building(_plan(tmp_path, CELLS, _graph([("A", "S"), ("S", "B")], v2=v2), v2=v2), unit="m")
    storey = b.storeys[0].name
    centres = sorted(o.segments[0].centroid.x for o in plan_openings(b, storey).openings)
    assert centres[1] - centres[0] > 5.0
    report = witness_grid(b, rasterise_storey(b, storey, 0.05), chair_width=0.7)
    assert FindingKind.NO_WAY_THROUGH in {f.kind for f in report.findings}
