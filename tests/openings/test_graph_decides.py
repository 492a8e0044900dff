"""Issue 37: where a plan has a navigation graph, the graph decides what opens (1.0 and 2.0 spellings).

A room R (x 0-15, y 0-4) and a corridor C above it, 0.2 m apart (the wall left out as a gap), share a
15 m wall that the file splits into two boundaries: 12.9 m and 2.1 m, each shorter than the wall, so the
reader takes them for doors ("partial" edges). No transition joins R and C. R is linked to a room Q
below it; C to a room E at its end, which lies round the corner of the short boundary. A transition to
E is no word about the wall between R and C: the wall stays wall along its whole length.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE, OCCUPIED
from pmk_nb.indoorgml import read_building
from pmk_nb.openings import plan_openings
from pmk_nb.raster import rasterise_storey
from pmk_nb.witness import FindingKind, witness_grid
from tests.access.test_access_rules import _boundary, _cell, _graph, _plan

RES = 0.05
CELLS = (
    _cell("R", (0, 0, 15, 4), name="room")
    + _cell("C", (0, 4.2, 15, 6.2), name="corridor")
    + _cell("Q", (0, -4, 15, 0))
    + _cell("E", (15, 4.2, 18, 6.2))
)
SPLIT = _boundary("B1", ((0, 4), (12.9, 4))) + _boundary("B2", ((12.9, 4), (15, 4)))


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_a_wall_no_transition_crosses_stays_wall_beside_a_corner_neighbour(tmp_path: Path, v2: bool) -> None:
    b = read_building(_plan(tmp_path, CELLS, _graph([("R", "Q"), ("C", "E")], v2=v2), SPLIT, v2=v2), unit="m")
    storey = b.storeys[0].name
    assert {d.id for d in b.doors_of(storey)} == {"B1", "B2"}  # both read as (guessed) doors
    plan = plan_openings(b, storey)
    assert {d.id for d in plan.shut_doors} >= {"B1", "B2"}
    grid = rasterise_storey(b, storey, RES)
    for x in (1.0, 6.0, 12.0, 13.5, 14.5):
        assert grid.value_at(x, 4.1) == OCCUPIED, x
    report = witness_grid(b, grid, chair_width=0.7)
    assert FindingKind.LEAK not in {f.kind for f in report.findings}, [f.describe() for f in report.findings]


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_a_transition_between_them_still_opens_their_door(tmp_path: Path, v2: bool) -> None:
    graph = _graph([("R", "Q"), ("C", "E"), ("R", "C")], v2=v2)
    b = read_building(_plan(tmp_path, CELLS, graph, SPLIT, v2=v2), unit="m")
    storey = b.storeys[0].name
    grid = rasterise_storey(b, storey, RES)
    assert sum(grid.value_at(x / 10, 4.1) == FREE for x in range(150)) >= 9  # a door at least
    report = witness_grid(b, grid, chair_width=0.7)
    kinds = {f.kind for f in report.findings}
    assert not kinds & {FindingKind.LEAK, FindingKind.NO_WAY_THROUGH}, [f.describe() for f in report.findings]
