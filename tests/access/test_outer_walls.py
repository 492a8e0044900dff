"""Issue 31, rule 4: openings only where the graph or a door says, outside walls included.

Rooms A (x 0-5) and B (x 5-10), y 0-4, linked; the outer wall y = 0 of A holds a 1.2 m boundary
(x 1.5-2.7). A window (by type, name or description, in any language), or a bare short boundary
facing one cell only (the outside), stays wall: today it is taken for a door ("partial" edge) and
the map opens 1.2 m to the outside, where a planner that takes unknown for passable drives out. A
door by type (AnchorBoundary: an entrance, ConnectionBoundary) on the outer wall still opens.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE, OCCUPIED
from tests.access.test_access_rules import ROOMS, _boundary, _cell, _graph, _grid_and_report, _plan

V = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
SPOT = ((1.5, 0.0), (2.7, 0.0))  # 1.2 m of A's 5 m outer wall


def _labelled(bid: str, tag: str = "CellSpaceBoundary", *, name: str = "", description: str = "") -> str:
    """A boundary on the outer wall with a gml:name and/or gml:description."""
    text = f"<gml:description>{description}</gml:description>" if description else ""
    text += f"<gml:name>{name}</gml:name>" if name else ""
    return _boundary(bid, SPOT, tag).replace(f'gml:id="{bid}">', f'gml:id="{bid}">{text}', 1)


def _outer_wall(tmp_path: Path, boundary: str, v2: bool):
    tmp_path.mkdir(exist_ok=True)
    _, grid, _ = _grid_and_report(_plan(tmp_path, ROOMS, _graph([("A", "B")], v2=v2), boundary, v2=v2))
    return [grid.value_at(x, y) for x in (1.7, 2.1, 2.5) for y in (-0.025, 0.025)]


@V
@pytest.mark.parametrize(
    ("name", "description"),
    [("Window", ""), ("Fenster 3", ""), ("창문", ""), ("", "function=window; floor-to-ceiling")],
    ids=["en-name", "de-name", "ko-name", "description"],
)
def test_a_window_on_the_outer_wall_stays_wall(tmp_path: Path, v2: bool, name: str, description: str) -> None:
    wall = _outer_wall(tmp_path, _labelled("W1", name=name, description=description), v2)
    assert wall.count(OCCUPIED) >= 3 and FREE not in wall, wall


@V
@pytest.mark.parametrize("tag", ["navi:AnchorBoundary", "navi:ConnectionBoundary"], ids=["anchor", "connection"])
def test_a_bare_short_boundary_facing_the_outside_stays_wall_a_door_by_type_opens(
    tmp_path: Path, v2: bool, tag: str
) -> None:
    """The same 1.2 m line: bare, it is no door (wall); typed a door (an entrance), it opens, whatever its
    name (a glazed door named "window" included)."""
    wall = _outer_wall(tmp_path / "bare", _boundary("X1", SPOT), v2)
    assert wall.count(OCCUPIED) >= 3 and FREE not in wall, wall
    door = _outer_wall(tmp_path / "door", _labelled("E1", tag, name="Glass window door"), v2)
    assert door.count(FREE) == len(door), door


@V
@pytest.mark.parametrize("name", ["Main entrance", "Eingang Nord", "정문 입구"], ids=["en", "de", "ko"])
def test_a_bare_line_named_entrance_on_the_outer_wall_opens(tmp_path: Path, v2: bool, name: str) -> None:
    """An entrance by name is a door's word, not a guess from the length: it stays open on the outer wall."""
    wall = _outer_wall(tmp_path, _labelled("E1", name=name), v2)
    assert wall.count(FREE) == len(wall), wall


@V
def test_a_window_between_two_linked_rooms_is_not_their_door(tmp_path: Path, v2: bool) -> None:
    """An inner window (x = 5, y 2.6-3.8) is no door evidence: the link opens by its own line instead."""
    window = _labelled("W1", name="window").replace("1.5 0.0 2.7 0.0", "5 2.6 5 3.8")
    graph = _graph([("A", "B")], {0: "2.5 1.0 7.5 1.0"}, v2=v2)
    _, grid, report = _grid_and_report(_plan(tmp_path, ROOMS, graph, window, v2=v2))
    assert grid.value_at(5.0, 1.0) == FREE and grid.value_at(5.0, 3.2) == OCCUPIED
    assert [k.rule for k in report.links] == ["line"]


@V
def test_a_short_boundary_across_a_wall_left_out_is_still_a_door(tmp_path: Path, v2: bool) -> None:
    """Guard (PNU 313): walls drawn as 0.6 m gaps, no graph; a bare short line on A's edge faces B across
    the gap, so it is an inner door, not an outer wall: it still opens."""
    rooms = _cell("A", (0, 0, 5, 4)) + _cell("B", (5.6, 0, 10.6, 4))
    door = _boundary("D1", ((5.0, 1.5), (5.0, 2.5)))
    _, grid, _ = _grid_and_report(_plan(tmp_path, rooms, "", door, v2=v2))
    assert [grid.value_at(x, 2.0) for x in (4.95, 5.3, 5.65)] == [FREE] * 3
    assert grid.value_at(5.3, 0.5) == OCCUPIED and grid.value_at(5.3, 3.5) == OCCUPIED  # the gap is wall


@V
def test_a_transition_passing_by_does_not_open_an_outer_guess(tmp_path: Path, v2: bool) -> None:
    """The A-B transition runs 0.4 m inside the outer wall, past the 1.2 m bare line: it does not cross it,
    so the line stays wall; one that goes out through it (to a state outside) opens it."""
    past = _graph([("A", "B")], {0: "1.0 0.4 9.0 0.4"}, v2=v2)
    _, grid, _ = _grid_and_report(_plan(tmp_path, ROOMS, past, _boundary("X1", SPOT), v2=v2))
    assert [grid.value_at(x, -0.025) for x in (1.7, 2.1, 2.5)] == [OCCUPIED] * 3
    out = _graph([("A", "B")], {0: "2.1 -1.0 2.1 2.0 7.5 2.0"}, v2=v2)
    (tmp_path / "out").mkdir()
    _, grid, _ = _grid_and_report(_plan(tmp_path / "out", ROOMS, out, _boundary("X1", SPOT), v2=v2))
    assert [grid.value_at(x, 0.0) for x in (1.7, 2.1, 2.5)] == [FREE] * 3
