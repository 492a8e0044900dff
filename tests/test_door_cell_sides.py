"""A door cell opens only towards the cells the navigation graph links it to.

A door cell's passage line reaches across the wall on both faces so that the opening survives coarse
resolutions. When a file leaves its walls out as gaps, that passage also crossed a 0.13 m gap to a room
the graph never links the door to, and the two rooms leaked into each other (a real plan from
pgrouting-for-indoorgml, door_new_64). The graph decides: the passage stays inside the door on a side
with only unlinked cells. Plans are written in both IndoorGML spellings (1.0 State/Transition, 2.0
Node/Edge).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE, OCCUPIED
from tests.test_access_rules import _cell, _graph, _grid_and_report, _plan

SPELLINGS = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
# room A, a 0.3 m deep door cell D 0.15 m from A, room B 0.13 m beyond D (walls modelled as gaps);
# C above both, linked to B, so that B is in the graph too
CELLS = (
    _cell("A", (0, 0, 5, 4)) + _cell("D", (5.15, 1, 5.45, 2.1), "navi:ConnectionSpace")
    + _cell("B", (5.58, 0, 10, 4)) + _cell("C", (0, 4.2, 10, 8))
)  # fmt: skip
GAP_TO_B = (5.515, 1.55)  # the middle of the gap between D and B, on the passage's line


@SPELLINGS
def test_a_door_cell_linked_on_one_side_does_not_open_to_the_other(tmp_path: Path, v2: bool) -> None:
    _, grid, report = _grid_and_report(_plan(tmp_path, CELLS, _graph([("A", "D"), ("B", "C")], v2=v2), v2=v2))
    assert grid.value_at(*GAP_TO_B) == OCCUPIED
    assert grid.value_at(5.075, 1.55) == FREE  # the side the graph links still opens
    assert report.leaks == [], report.summary()
    assert {k.cells: k.chair for k in report.links}[("A", "D")]


@SPELLINGS
def test_a_door_cell_linked_on_both_sides_opens_both(tmp_path: Path, v2: bool) -> None:
    graph = _graph([("A", "D"), ("D", "B"), ("B", "C")], v2=v2)
    _, grid, report = _grid_and_report(_plan(tmp_path, CELLS, graph, v2=v2))
    assert grid.value_at(*GAP_TO_B) == FREE and grid.value_at(5.075, 1.55) == FREE
    assert report.ok, report.summary()


def test_without_a_graph_a_door_cell_opens_both_faces(tmp_path: Path) -> None:
    """No transitions at all: the old door rules apply, and a door cell joins what it sits between."""
    _, grid, _ = _grid_and_report(_plan(tmp_path, CELLS))
    assert grid.value_at(*GAP_TO_B) == FREE and grid.value_at(5.075, 1.55) == FREE
