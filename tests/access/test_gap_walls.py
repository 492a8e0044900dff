"""Issue 31, rule 7: gaps between rooms are walls.

A gap between cells that no transition crosses is occupied up to the thickest wall the building has
(at least 1 m), not unknown: Nav2's planners take unknown for passable (``allow_unknown: true``), so
an unknown gap between two rooms is a way between them that no door allows. Rooms A (x 0-5) and B
(x 5.8-10.8), y 0-4, are 0.8 m apart; room C (x 0-5, y 4-10) stands on A, so the L's inner corner
is outside the building, 3 m and more from every cell.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN
from tests.access.test_access_rules import _cell, _graph, _grid_and_report, _plan

V = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
CELLS = _cell("A", (0, 0, 5, 4)) + _cell("B", (5.8, 0, 10.8, 4)) + _cell("C", (0, 4, 5, 10))


@V
@pytest.mark.parametrize("linked", [True, False], ids=["graph-A-C", "no-graph"])
def test_a_gap_no_transition_crosses_is_wall_and_the_outside_stays_unknown(
    tmp_path: Path, v2: bool, linked: bool
) -> None:
    graph = _graph([("A", "C")], v2=v2) if linked else ""
    _, grid, report = _grid_and_report(_plan(tmp_path, CELLS, graph, v2=v2))
    for y in (0.2, 2.0, 3.8):
        assert [grid.value_at(x, y) for x in (5.2, 5.4, 5.6)] == [OCCUPIED] * 3, y
    assert grid.value_at(8.0, 7.5) == UNKNOWN and grid.value_at(8.3, 8.0) == UNKNOWN  # 3 m from every cell
    assert grid.value_at(2.5, 2.0) == FREE and grid.value_at(8.3, 2.0) == FREE
    assert all(k.chair for k in report.links)


@V
def test_a_transition_across_the_gap_keeps_its_walled_passage(tmp_path: Path, v2: bool) -> None:
    """The same 0.8 m gap, crossed by an A-B transition: a 0.9 m passage, walled along both sides."""
    graph = _graph([("A", "B"), ("A", "C")], {0: "2.5 2.0 8.3 2.0"}, v2=v2)
    _, grid, report = _grid_and_report(_plan(tmp_path, CELLS, graph, v2=v2))
    assert [grid.value_at(x, 2.0) for x in (5.2, 5.4, 5.6)] == [FREE] * 3
    assert grid.value_at(5.4, 0.5) == OCCUPIED and grid.value_at(5.4, 3.5) == OCCUPIED
    assert all(k.chair for k in report.links) and report.ok, report.summary()
