"""Issue 31 rule 6: names do not make doors. A plain CellSpace whose name or id says "door" is a door
(connection) cell only when nothing else says what it is and it is door-sized (at most 1 m deep and 4 m
wide); a room-sized one stays a room, and the reader says so. Both the 1.x and 2.0 document spellings."""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE
from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.model import CellKind
from pmk_nb.raster import rasterise_storey
from tests.access.test_access_rules import RES, _cell, _graph, _plan

SPELLINGS = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])


@SPELLINGS
def test_room_named_door_stays_a_room(tmp_path: Path, v2: bool) -> None:
    cells = _cell("A", (0, 0, 5, 4), name="Door-side lounge") + _cell("B", (5, 0, 10, 4))
    b = read_building(_plan(tmp_path, cells, _graph([("A", "B")], v2=v2), v2=v2), unit="m")
    lounge = b.cells["A"]
    assert lounge.kind is not CellKind.CONNECTION and lounge.kind in (CellKind.GENERAL, CellKind.NAVIGABLE)
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    for x in (0.5, 1.5, 2.5, 3.5, 4.5):  # across its middle
        assert grid.value_at(x, 2.0) == FREE
    [note] = [w for w in b.warnings if "kept as rooms" in w]
    assert "Door-side lounge" in note and "1 cells" in note
    assert not any("treated as connection" in w for w in b.warnings)


@SPELLINGS
def test_door_sized_cell_named_door_is_still_a_door(tmp_path: Path, v2: bool) -> None:
    cells = _cell("A", (0, 0, 5, 4)) + _cell("D1", (5, 1.5, 5.2, 2.4), name="door 1") + _cell("B", (5.2, 0, 10.2, 4))
    cells += _cell("L", (0, 4, 5, 9), name="Door-side lounge")
    b = read_building(_plan(tmp_path, cells, _graph([("A", "D1"), ("D1", "B"), ("A", "L")], v2=v2), v2=v2), unit="m")
    assert b.cells["D1"].kind is CellKind.CONNECTION
    assert b.cells["L"].kind is not CellKind.CONNECTION
    assert any(w.startswith("1 plain CellSpaces named 'door' treated as connection") for w in b.warnings)
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(5.1, 1.95) == FREE  # through the door


def test_the_unit_is_judged_without_the_names(tmp_path: Path) -> None:
    """A 0.9 x 0.2 door cell in a plan drawn in centimetres (90 x 20 units) is a door once the unit is
    known; with ``--unit m`` the same cell is 20 x 90 m: a room, however it is named."""
    cells = _cell("A", (0, 0, 500, 400)) + _cell("D1", (500, 150, 520, 240), name="door")
    cells += _cell("B", (520, 0, 1020, 400))
    path = _plan(tmp_path, cells, _graph([("A", "D1"), ("D1", "B")]))
    assert read_building(path, unit="cm").cells["D1"].kind is CellKind.CONNECTION
    assert read_building(path, unit="m").cells["D1"].kind is not CellKind.CONNECTION
    auto = read_building(path)  # judged without the name (a 90 x 20 'door'), then it counts as a 0.9 m door
    assert auto.unit == "cm" and auto.cells["D1"].kind is CellKind.CONNECTION


def _named_boundary(bid: str, name: str, line: tuple[tuple[float, float], ...]) -> str:
    pts = " ".join(f"{x} {y}" for x, y in line)
    return (
        f'<cellSpaceBoundaryMember><CellSpaceBoundary gml:id="{bid}"><gml:name>{name}</gml:name>'
        f"<cellSpaceBoundaryGeometry><geometry2D><gml:LineString><gml:posList>{pts}</gml:posList></gml:LineString>"
        f"</geometry2D></cellSpaceBoundaryGeometry></CellSpaceBoundary></cellSpaceBoundaryMember>"
    )


@SPELLINGS
def test_wall_named_door_stays_a_wall(tmp_path: Path, v2: bool) -> None:
    """The whole 6 m wall between two rooms, named "wall by the door": a wall, with the transition's opening
    in it; a 0.9 m boundary named "door" in the next wall is still a door."""
    cells = _cell("A", (0, 0, 5, 6)) + _cell("B", (5, 0, 10, 6)) + _cell("C", (10, 0, 15, 6))
    bounds = _named_boundary("W", "wall by the door", ((5, 0), (5, 6)))
    bounds += _named_boundary("D", "door", ((10, 2), (10, 2.9)))
    b = read_building(_plan(tmp_path, cells, _graph([("A", "B"), ("B", "C")], v2=v2), bounds, v2=v2), unit="m")
    assert not b.boundaries["W"].is_door and b.boundaries["D"].is_door
    assert any("1 boundaries named 'door' kept as walls" in w and "'W'" in w for w in b.warnings)
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(5.0, 0.3) != FREE and grid.value_at(5.0, 5.7) != FREE  # the wall's ends stay wall
    assert grid.value_at(10.0, 2.45) == FREE
