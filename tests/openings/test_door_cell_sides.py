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
from pmk_nb.openings import plan_openings
from tests.access.test_access_rules import _cell, _graph, _grid_and_report, _plan

SPELLINGS = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
# room A, a 0.3 m deep door cell D 0.15 m from A, room B 0.13 m beyond D (walls modelled as gaps);
# C above both, linked to B, so that B is in the graph too
CELLS = (
    _cell("A", (0, 0, 5, 4))
    + _cell("D", (5.15, 1, 5.45, 2.1), "navi:ConnectionSpace")
    + _cell("B", (5.58, 0, 10, 4))
    + _cell("C", (0, 4.2, 10, 8))
)
GAP_TO_B = (5.515, 1.55)  # the middle of the gap between D and B, on the passage's line


@SPELLINGS
def test_a_door_cell_linked_on_one_side_does_not_open_to_the_other(tmp_path: Path, v2: bool) -> None:
    _, grid, report = _grid_and_report(_plan(tmp_path, CELLS, _graph([("A", "D"), ("B", "C")], v2=v2), v2=v2))
    assert grid.value_at(*GAP_TO_B) == OCCUPIED
    assert grid.value_at(5.075, 1.55) == FREE  # the side the graph links still opens
    assert report.leaks == [], report.summary()
    [ad] = [k for k in report.links if k.cells == ("A", "D")]
    # open for a point; not for the chair since issue 31: D leads nowhere (its far side is wall) and its
    # 0.3 m depth holds no 0.70 m chair, so the chair's centre never reaches it on the written grid
    assert ad.point and not ad.chair and ad.free_width > 0.7, ad


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


def _poly_cell(cid: str, pts: list[tuple[float, float]], tag: str = "CellSpace") -> str:
    ring = " ".join(f"{x} {y}" for x, y in [*pts, pts[0]])
    return (
        f'<cellSpaceMember><{tag} gml:id="{cid}"><cellSpaceGeometry><Geometry2D><gml:Polygon><gml:exterior>'
        f"<gml:LinearRing><gml:posList>{ring}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon>"
        f"</Geometry2D></cellSpaceGeometry></{tag}></cellSpaceMember>"
    )


# a 1 m wide, 0.25 m deep door cell drawn 3.4 degrees askew in a wall left as a gap: 0.04-0.10 m from
# room A, 0.10-0.16 m from room B (pgrouting PUN-IT draws its door cells like this)
ASKEW = (
    _cell("A", (0, 0, 5, 4))
    + _poly_cell("D", [(5.10, 1.0), (5.35, 1.0), (5.29, 2.0), (5.04, 2.0)], "navi:ConnectionSpace")
    + _cell("B", (5.45, 0, 10, 4))
)


@SPELLINGS
def test_a_door_cell_drawn_askew_keeps_its_width(tmp_path: Path, v2: bool) -> None:
    """Only a corner of the askew door lies within the gap's width of each room: the opening used to be
    that corner (0.2 m, too narrow for the chair); the door's face towards each room is 1 m."""
    b, grid, report = _grid_and_report(_plan(tmp_path, ASKEW, _graph([("A", "D"), ("D", "B")], v2=v2), v2=v2))
    openings = plan_openings(b, b.storeys[0].name).openings
    assert [o.rule for o in openings] == ["door", "door"]
    assert all(o.width == pytest.approx(1.0, abs=0.01) for o in openings), [o.width for o in openings]
    assert report.ok and report.counts()["passable_chair"] == 2, report.summary()
    assert all(k.free_width >= 0.9 for k in report.links), [k.free_width for k in report.links]
    for y in (1.1, 1.5, 1.9):  # across the gaps on both sides, the whole width
        assert grid.value_at(5.02, y) == FREE and grid.value_at(5.4, y) == FREE
    assert grid.value_at(5.02, 0.5) == OCCUPIED and grid.value_at(5.4, 2.5) == OCCUPIED  # the wall beside it
