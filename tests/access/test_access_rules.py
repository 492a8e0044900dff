"""Issue 8's rules on small synthetic plans, in the 1.0.x (State/Transition) and 2.0 (Node/Edge) spellings.

Each plan is two 5 x 4 m rooms side by side (A: x 0-5, B: x 5-10, y 0-4) sharing the wall x = 5, plus
whatever the rule needs. The grid is read back at points: free in the opening, occupied on the wall
away from it; and the accessibility check must agree.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.access.check import check_grid
from pmk_nb.grid import FREE, OCCUPIED
from pmk_nb.indoorgml import read_building
from pmk_nb.openings import plan_openings
from pmk_nb.raster import rasterise_storey

NS = (
    'xmlns="http://www.opengis.net/indoorgml/1.0/core" xmlns:gml="http://www.opengis.net/gml/3.2" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:navi="http://www.opengis.net/indoorgml/1.0/navigation"'
)
RES = 0.05


def _ring(x0: float, y0: float, x1: float, y1: float, z: float | None = None) -> str:
    pts = [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)]
    return " ".join(f"{a} {b}" if z is None else f"{a} {b} {z}" for a, b in pts)


def _cell(cid: str, box: tuple[float, float, float, float], tag: str = "CellSpace", name: str = "") -> str:
    nm = f"<gml:name>{name}</gml:name>" if name else ""
    return (
        f'<cellSpaceMember><{tag} gml:id="{cid}">{nm}<cellSpaceGeometry><Geometry2D><gml:Polygon><gml:exterior>'
        f"<gml:LinearRing><gml:posList>{_ring(*box)}</gml:posList></gml:LinearRing></gml:exterior>"
        f"</gml:Polygon></Geometry2D></cellSpaceGeometry></{tag}></cellSpaceMember>"
    )


def _solid(cid: str, box: tuple[float, float, float, float], z0: float, z1: float) -> str:
    """A box cell as a 3D solid (floor and ceiling faces are enough for the footprint and z)."""
    faces = "".join(
        f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
        f"{_ring(*box, z=z)}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        for z in (z0, z1)
    )
    return (
        f'<cellSpaceMember><CellSpace gml:id="{cid}"><cellSpaceGeometry><Geometry3D><gml:Solid><gml:exterior>'
        f"<gml:Shell>{faces}</gml:Shell></gml:exterior></gml:Solid></Geometry3D></cellSpaceGeometry>"
        f"</CellSpace></cellSpaceMember>"
    )


def _boundary(bid: str, line: tuple[tuple[float, float], ...], tag: str = "CellSpaceBoundary") -> str:
    pts = " ".join(f"{x} {y}" for x, y in line)
    return (
        f'<cellSpaceBoundaryMember><{tag} gml:id="{bid}"><cellSpaceBoundaryGeometry><geometry2D><gml:LineString>'
        f"<gml:posList>{pts}</gml:posList></gml:LineString></geometry2D></cellSpaceBoundaryGeometry>"
        f"</{tag}></cellSpaceBoundaryMember>"
    )


def _graph(pairs: list[tuple[str, str]], lines: dict[int, str] | None = None, *, v2: bool = False) -> str:
    """States (Nodes) dual to the cells named in ``pairs`` and one Transition (Edge) per pair."""
    cells = sorted({c for p in pairs for c in p})
    state, trans, layer = ("Node", "Edge", "DualSpaceLayer") if v2 else ("State", "Transition", "SpaceLayer")
    nodes = "".join(
        f'<{state.lower()}Member><{state} gml:id="S{c}"><duality xlink:href="#{c}"/></{state}></{state.lower()}Member>'
        for c in cells
    )
    edges = ""
    for i, (a, b) in enumerate(pairs):
        geom = ""
        if lines and i in lines:
            geom = f"<geometry><gml:LineString><gml:posList>{lines[i]}</gml:posList></gml:LineString></geometry>"
        edges += (
            f'<{trans.lower()}Member><{trans} gml:id="T{i}"><connects xlink:href="#S{a}"/>'
            f'<connects xlink:href="#S{b}"/>{geom}</{trans}></{trans.lower()}Member>'
        )
    if v2:
        return f'<dualSpaceLayer><{layer} gml:id="D">{nodes}{edges}</{layer}></dualSpaceLayer>'
    return (
        f'<multiLayeredGraph><MultiLayeredGraph gml:id="G"><spaceLayers gml:id="L"><spaceLayerMember>'
        f'<SpaceLayer gml:id="SL"><nodes gml:id="N">{nodes}</nodes><edges gml:id="E">{edges}</edges>'
        f"</SpaceLayer></spaceLayerMember></spaceLayers></MultiLayeredGraph></multiLayeredGraph>"
    )


def _plan(tmp_path: Path, cells: str, graph: str = "", boundaries: str = "", *, v2: bool = False) -> Path:
    layer = "PrimalSpaceLayer" if v2 else "PrimalSpaceFeatures"
    text = (
        f'<?xml version="1.0"?><IndoorFeatures {NS} gml:id="F"><primalSpaceFeatures><{layer} gml:id="P">'
        f"{cells}{boundaries}</{layer}></primalSpaceFeatures>{graph}</IndoorFeatures>"
    )
    path = tmp_path / ("v2.gml" if v2 else "v1.gml")
    path.write_text(text)
    return path


ROOMS = _cell("A", (0, 0, 5, 4)) + _cell("B", (5, 0, 10, 4))


def _grid_and_report(path: Path, chair: float = 0.7):
    b = read_building(path, unit="m")
    storey = b.storeys[0].name
    grid = rasterise_storey(b, storey, RES)
    return b, grid, check_grid(b, storey, grid, chair_width=chair)


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_no_transition_keeps_adjacent_rooms_apart(tmp_path: Path, v2: bool) -> None:
    c = _cell("C", (0, 4, 10, 8))  # a third room, linked to A only, so the storey has a graph
    _, grid, report = _grid_and_report(_plan(tmp_path, ROOMS + c, _graph([("A", "C")], v2=v2), v2=v2))
    for y in (0.5, 2.0, 3.5):
        assert grid.value_at(5.0, y) == OCCUPIED
    assert report.counts()["links"] == 1 and report.ok


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_transition_line_opens_a_door_width_where_it_crosses(tmp_path: Path, v2: bool) -> None:
    line = "2.5 1.0 7.5 1.0"  # crosses the shared wall at y = 1.0
    b, grid, report = _grid_and_report(_plan(tmp_path, ROOMS, _graph([("A", "B")], {0: line}, v2=v2), v2=v2))
    [o] = plan_openings(b, b.storeys[0].name).openings
    assert o.rule == "line" and o.width == pytest.approx(0.9)
    assert grid.value_at(5.0, 1.0) == FREE and grid.value_at(5.0, 0.6) == FREE  # shifted to stay on the wall
    assert grid.value_at(5.0, 2.5) == OCCUPIED and grid.value_at(5.0, 3.5) == OCCUPIED
    [k] = report.links
    assert k.point and k.chair and k.free_width >= 0.9 - RES - 1e-9


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_no_door_evidence_opens_the_middle(tmp_path: Path, v2: bool) -> None:
    b, grid, report = _grid_and_report(_plan(tmp_path, ROOMS, _graph([("A", "B")], v2=v2), v2=v2))
    assert plan_openings(b, b.storeys[0].name).rule_counts() == {"middle": 1}
    assert grid.value_at(5.0, 2.0) == FREE and grid.value_at(5.0, 0.5) == OCCUPIED
    assert report.ok


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_corridor_pieces_are_open_along_their_whole_boundary(tmp_path: Path, v2: bool) -> None:
    rooms = _cell("A", (0, 0, 5, 2), "navi:TransitionSpace") + _cell("B", (5, 0, 10, 2), "navi:TransitionSpace")
    b, grid, report = _grid_and_report(_plan(tmp_path, rooms, _graph([("A", "B")], v2=v2), v2=v2))
    assert plan_openings(b, b.storeys[0].name).rule_counts() == {"corridor": 1}
    for y in (0.3, 1.0, 1.7):
        assert grid.value_at(5.0, y) == FREE
    assert report.ok


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
@pytest.mark.parametrize("tag", ["navi:ConnectionBoundary", "CellSpaceBoundary"], ids=["connection", "named-door"])
def test_door_geometry_wins_and_a_plain_wall_beside_it_stays(tmp_path: Path, tag: str, v2: bool) -> None:
    door = _boundary("Door1" if tag == "CellSpaceBoundary" else "D1", ((5, 2.6), (5, 3.6)), tag)
    line = "2.5 1.0 7.5 1.0"  # the transition's line crosses elsewhere: door geometry comes first
    b, grid, report = _grid_and_report(_plan(tmp_path, ROOMS, _graph([("A", "B")], {0: line}, v2=v2), door, v2=v2))
    assert plan_openings(b, b.storeys[0].name).rule_counts() == {"door": 1}
    assert grid.value_at(5.0, 3.1) == FREE and grid.value_at(5.0, 1.0) == OCCUPIED
    assert report.ok


@pytest.mark.parametrize("graph", ["none", "1.0", "2.0"])
@pytest.mark.parametrize("tag", ["navi:ConnectionBoundary", "CellSpaceBoundary"], ids=["connection", "named-door"])
def test_the_wall_pieces_beside_a_door_stay_wall(tmp_path: Path, tag: str, graph: str) -> None:
    """A file that splits its walls at the jambs (UCLM put-outer): the bare pieces either side of a
    marked door are shorter than the wall, yet wall; only the door opens."""
    door = _boundary("Door1" if tag == "CellSpaceBoundary" else "D1", ((5, 1.5), (5, 2.4)), tag)
    pieces = _boundary("CB1", ((5, 0), (5, 1.5))) + _boundary("CB2", ((5, 2.4), (5, 4)))
    links = "" if graph == "none" else _graph([("A", "B")], v2=graph == "2.0")
    b, grid, report = _grid_and_report(_plan(tmp_path, ROOMS, links, door + pieces, v2=graph == "2.0"))
    assert {bd.id for bd in b.boundaries.values() if bd.is_door} == {door.split('"')[1]}
    assert grid.value_at(5.0, 1.95) == FREE
    for y in (0.4, 1.0, 2.9, 3.6):
        assert grid.value_at(5.0, y) == OCCUPIED
    assert report.ok is (graph != "none")  # no graph: nothing checked, never "ok" (issue 31)


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_a_short_bare_line_off_the_doors_wall_is_still_an_opening(tmp_path: Path, v2: bool) -> None:
    """The rule is about the door's own wall: a bare short line on another wall keeps the partial rule."""
    door = _boundary("D1", ((5, 1.5), (5, 2.4)), "navi:ConnectionBoundary")
    other = _boundary("CB1", ((1, 4), (2, 4)))  # on A's top wall, 1 m of 5
    b, _, _ = _grid_and_report(_plan(tmp_path, ROOMS, "", door + other, v2=v2))
    assert {bd.id: bd.evidence for bd in b.boundaries.values() if bd.is_door} == {"D1": "type", "CB1": "partial"}


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_a_transitions_dual_face_spanning_the_wall_is_not_a_door(tmp_path: Path, v2: bool) -> None:
    """A plain CellSpaceBoundary that is the transition's dual over the whole wall must not erase it."""
    face = _boundary("W1", ((5, 0), (5, 4)))
    door = _boundary("D1", ((5, 2.6), (5, 3.6)), "navi:ConnectionBoundary")
    edge = f'<{"Edge" if v2 else "Transition"} gml:id="T0">'
    graph = _graph([("A", "B")], v2=v2).replace(edge, f'{edge}<duality xlink:href="#W1"/>')
    assert '"#W1"' in graph
    b, grid, _ = _grid_and_report(_plan(tmp_path, ROOMS, graph, face + door, v2=v2))
    assert b.boundaries["W1"].evidence == "duality"
    assert grid.value_at(5.0, 3.1) == FREE and grid.value_at(5.0, 1.0) == OCCUPIED


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_thin_door_cell_is_open_on_both_faces(tmp_path: Path, v2: bool) -> None:
    rooms = _cell("A", (0, 0, 5, 4)) + _cell("D", (5, 1, 5.2, 2), "navi:ConnectionSpace") + _cell("B", (5.2, 0, 10, 4))
    path = _plan(tmp_path, rooms, _graph([("A", "D"), ("D", "B")], v2=v2), v2=v2)
    b, grid, report = _grid_and_report(path, chair=0.6)
    assert {o.rule for o in plan_openings(b, b.storeys[0].name).openings} == {"door"}
    for x in (4.97, 5.1, 5.23):
        assert grid.value_at(x, 1.5) == FREE
    assert report.ok, report.summary()


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_gap_wall_with_a_door_in_it_stays_open(tmp_path: Path, v2: bool) -> None:
    rooms = _cell("A", (0, 0, 5, 4)) + _cell("B", (5.13, 0, 10, 4))  # walls drawn as a 0.13 m gap
    door = _boundary("D1", ((5.065, 1.5), (5.065, 2.5)), "navi:ConnectionBoundary")
    _, grid, report = _grid_and_report(_plan(tmp_path, rooms, _graph([("A", "B")], v2=v2), door, v2=v2))
    assert grid.value_at(5.065, 2.0) == FREE and grid.value_at(5.065, 0.5) == OCCUPIED
    assert report.ok


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_narrow_door_is_named_not_hidden(tmp_path: Path, v2: bool) -> None:
    door = _boundary("D1", ((5, 1.0), (5, 1.6)), "navi:ConnectionBoundary")  # 0.6 m < 0.7 m chair
    _, _, report = _grid_and_report(_plan(tmp_path, ROOMS, _graph([("A", "B")], v2=v2), door, v2=v2))
    [k] = report.links
    assert k.point and not k.chair and report.narrow == [k] and not report.ok
    assert "narrower than the chair" in k.describe() and "A" in k.names


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_leak_between_rooms_without_transition_is_reported(tmp_path: Path, v2: bool) -> None:
    """A door line between two rooms the graph does not join is kept shut; a real overlap still leaks."""
    rooms = ROOMS + _cell("C", (0, 4, 10, 8))
    door = _boundary("D1", ((5, 1.0), (5, 2.0)), "navi:ConnectionBoundary")
    b, grid, report = _grid_and_report(_plan(tmp_path, rooms, _graph([("A", "C"), ("B", "C")], v2=v2), door, v2=v2))
    assert [d.id for d in plan_openings(b, b.storeys[0].name).shut_doors] == ["D1"]
    assert grid.value_at(5.0, 1.5) == OCCUPIED and report.leaks == []


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_sloping_floor_stays_navigable_and_a_window_does_not(tmp_path: Path, v2: bool) -> None:
    steps = "".join(_solid(f"S{i}", (4 * i, 0, 4 * i + 4, 4), -3.9 + 0.75 * i, -0.9 + 0.75 * i) for i in range(5))
    window = _solid("W", (20, 1, 20.3, 2), 0.0, 1.5)  # touches S4 (floor -0.9 .. 2.1): a sill 0.9 m up its wall
    b = read_building(_plan(tmp_path, steps + window, v2=v2), unit="m")
    assert len(b.storeys) == 1
    assert all(b.cells[f"S{i}"].kind.is_free for i in range(5))
    assert not b.cells["W"].kind.is_free


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_unit_conflict_is_said_plainly(tmp_path: Path, v2: bool) -> None:
    # 20-unit storeys with 1.5-unit doors: doors say metres, storeys say otherwise
    cells = _solid("A", (0, 0, 30, 20), 0, 20) + _solid("B", (30, 0, 60, 20), 0, 20)
    door = _boundary("D1", ((30, 5), (30, 6.5)), "navi:ConnectionBoundary")
    b = read_building(_plan(tmp_path, cells, "", door, v2=v2))
    assert b.unit == "m" and "cell height" in b.unit_conflict and "20 m" in b.unit_conflict
    rooms = _solid("A", (0, 0, 6, 4), 0, 2.8) + _solid("B", (6, 0, 12, 4), 0, 2.8)
    ok = read_building(_plan(tmp_path, rooms, v2=v2))
    assert ok.unit == "m" and ok.unit_conflict == ""


def _named_solid(cid: str, name: str, box: tuple[float, float, float, float], z0: float, z1: float) -> str:
    return _solid(cid, box, z0, z1).replace(f'gml:id="{cid}">', f'gml:id="{cid}"><gml:name>{name}</gml:name>', 1)


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_split_level_joined_by_stairs_is_its_own_storey(tmp_path: Path, v2: bool) -> None:
    # lower hall 0 m, upper hall 1 m (closer than any storey gap z alone would see), a stair between
    cells = (
        _named_solid("L", "hall", (0, 0, 5, 4), 0.0, 2.6)
        + _named_solid("S", "Stair 1", (5, 0, 7, 4), 0.0, 3.6)
        + _named_solid("U", "gallery", (7, 0, 12, 4), 1.0, 3.6)
    )
    b = read_building(_plan(tmp_path, cells, _graph([("L", "S"), ("S", "U")], v2=v2), v2=v2), unit="m")
    assert len(b.storeys) == 2
    assert b.cells["L"].storey == b.cells["S"].storey != b.cells["U"].storey
    assert b.cells["U"].kind.is_free  # a floor of its own, not a window above the stair
    between = [k for k in b.links if not k.same_storey]
    assert [(k.a, k.b) for k in between] == [("S", "U")]  # the stair is the link between storeys
    assert [(k.a, k.b) for k in b.links_of(b.cells["L"].storey)] == [("L", "S")]


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_ramp_between_floor_heights_stays_one_storey(tmp_path: Path, v2: bool) -> None:
    cells = (
        _named_solid("L", "hall", (0, 0, 5, 4), 0.0, 2.6)
        + _named_solid("R", "ramp", (5, 0, 7, 4), 0.0, 3.0)  # floors 1 m apart: two height bands
        + _named_solid("U", "gallery", (7, 0, 12, 4), 1.0, 3.6)
    )
    b = read_building(_plan(tmp_path, cells, _graph([("L", "R"), ("R", "U")], v2=v2), v2=v2), unit="m")
    assert len(b.storeys) == 1 and all(k.same_storey for k in b.links)  # joined by an ordinary transition
    assert b.cells["U"].kind.is_free


def _stair_solid(
    cid: str, box: tuple[float, float, float, float], z0: float, rise: float, steps: int, top: float
) -> str:
    """A stair as a solid whose treads are horizontal faces (``steps`` rises of ``rise``), under a ceiling."""
    x0, y0, x1, y1 = box
    depth = (x1 - x0) / (steps + 1)
    faces = "".join(
        f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
        f"{_ring(x0 + i * depth, y0, x0 + (i + 1) * depth, y1, z=z0 + i * rise)}</gml:posList></gml:LinearRing>"
        f"</gml:exterior></gml:Polygon></gml:surfaceMember>"
        for i in range(steps + 1)
    ) + (
        f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
        f"{_ring(x0, y0, x1, y1, z=top)}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon>"
        "</gml:surfaceMember>"
    )
    return (
        f'<cellSpaceMember><CellSpace gml:id="{cid}"><gml:name>{cid}</gml:name><cellSpaceGeometry><Geometry3D>'
        f"<gml:Solid><gml:exterior><gml:Shell>{faces}</gml:Shell></gml:exterior></gml:Solid></Geometry3D>"
        f"</cellSpaceGeometry></CellSpace></cellSpaceMember>"
    )


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
@pytest.mark.parametrize("unit", [("m", 1.0), ("mm", 1000.0)], ids=["metres", "millimetres"])
def test_stair_known_by_its_steps_splits_levels_whatever_its_name(
    tmp_path: Path, v2: bool, unit: tuple[str, float]
) -> None:
    # the stair cell is called "X12": only its six 0.17 m treads say it is a stair
    name, k = unit
    cells = (
        _named_solid("L", "hall", (0, 0, 5 * k, 4 * k), 0.0, 2.6 * k)
        + _stair_solid("X12", (5 * k, 0, 7 * k, 4 * k), 0.0, 0.17 * k, 6, 3.6 * k)
        + _named_solid("U", "gallery", (7 * k, 0, 12 * k, 4 * k), 1.02 * k, 3.6 * k)
    )
    b = read_building(_plan(tmp_path, cells, _graph([("L", "X12"), ("X12", "U")], v2=v2), v2=v2), unit=name)
    assert len(b.storeys) == 2
    assert b.cells["L"].storey == b.cells["X12"].storey != b.cells["U"].storey
    assert [(k_.a, k_.b) for k_ in b.links if not k_.same_storey] == [("X12", "U")]
    assert any("stairs by their steps: X12" in w for w in b.warnings)


def test_a_room_with_a_platform_and_a_dropped_ceiling_is_not_a_stair() -> None:
    from pmk_nb.indoorgml.footprint import stepped

    assert not stepped([0.0, 0.3, 2.4, 2.7], 2.7)  # floor, platform, dropped ceiling, ceiling
    assert not stepped([0.0, 2.6], 2.6)  # a plain room
    assert stepped([0.0, 0.17, 0.34, 0.51, 3.6], 3.6)  # three rises in a row
    assert stepped([0.0, 170.0, 340.0, 510.0, 3600.0], 3600.0)  # the same in millimetres


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_a_ramp_drawn_as_a_sloping_solid_stays_one_storey(tmp_path: Path, v2: bool) -> None:
    # the ramp's floor is one sloping face (not steps): a wheelchair rolls up it, the levels stay one storey
    ramp_floor = "5 0 0 7 0 1.0 7 4 1.0 5 4 0 5 0 0"
    ramp = (
        '<cellSpaceMember><CellSpace gml:id="R"><gml:name>R</gml:name><cellSpaceGeometry><Geometry3D><gml:Solid>'
        "<gml:exterior><gml:Shell>"
        f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>{ramp_floor}"
        "</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
        f"{_ring(5, 0, 7, 4, z=3.6)}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        "</gml:Shell></gml:exterior></gml:Solid></Geometry3D></cellSpaceGeometry></CellSpace></cellSpaceMember>"
    )
    hall = _named_solid("L", "hall", (0, 0, 5, 4), 0.0, 2.6)
    cells = hall + ramp + _named_solid("U", "gallery", (7, 0, 12, 4), 1.0, 3.6)
    b = read_building(_plan(tmp_path, cells, _graph([("L", "R"), ("R", "U")], v2=v2), v2=v2), unit="m")
    assert len(b.storeys) == 1 and all(k.same_storey for k in b.links)
    assert b.cells["U"].kind.is_free


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_split_level_without_a_graph_keeps_the_z_rule(tmp_path: Path, v2: bool) -> None:
    cells = _named_solid("L", "hall", (0, 0, 5, 4), 0.0, 2.6) + _named_solid("U", "gallery", (7, 0, 12, 4), 1.0, 3.6)
    b = read_building(_plan(tmp_path, cells, v2=v2), unit="m")
    assert len(b.storeys) == 1


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_unit_conflict_shows_before_conversion(tmp_path: Path, v2: bool) -> None:
    from pmk_nb.library.info import storeys_of
    from pmk_nb.ui.maps.storeys import unit_warning

    cells = _solid("A", (0, 0, 30, 20), 0, 20) + _solid("B", (30, 0, 60, 20), 0, 20)
    door = _boundary("D1", ((30, 5), (30, 6.5)), "navi:ConnectionBoundary")
    info = storeys_of(read_building(_plan(tmp_path, cells, "", door, v2=v2)))
    assert info and "20 m" in info[0].unit_conflict
    shown = unit_warning(info)
    assert "<i>Plan's unit</i>" in shown and "--unit" in shown and "20 m" in shown  # the screen's choice, the CLI's
    ok = storeys_of(read_building(_plan(tmp_path, _solid("A", (0, 0, 6, 4), 0, 2.8), v2=v2)))
    assert "pmk-maps-unit-warning" not in unit_warning(ok)  # (it has no graph: that is said, not the unit)


def _poly_cell(cid: str, pts: list[tuple[float, float]], angle: float = 0.0) -> str:
    """A cell of any outline, turned by ``angle`` degrees about the origin (walls off the grid's axes)."""
    import math

    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    ring = " ".join(f"{x * c - y * s:.6f} {x * s + y * c:.6f}" for x, y in [*pts, pts[0]])
    return _cell(cid, (0, 0, 1, 1)).replace(_ring(0, 0, 1, 1), ring)


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
@pytest.mark.parametrize("angle", [0.0, 15.0], ids=["square", "turned-15deg"])
def test_a_door_in_a_wall_niche_keeps_its_width(tmp_path: Path, angle: float, v2: bool) -> None:
    """FJK-Haus draws a door as the two rooms reaching into a 0.2 m wall until they touch over 0.78 m:
    the jambs' wall bands must not narrow it below the door width less a cell, so a 0.65 m chair passes.
    (A 0.70 m chair needs 15 free pixels across at 0.05 m, as Nav2 inflates: more than the 14 this
    grid keeps between the jamb pixels, so the check no longer calls it passable for 0.70 m.)"""
    a = [(0, 0), (5, 0), (5, 1.5), (5.1, 1.5), (5.1, 2.28), (5, 2.28), (5, 4), (0, 4)]
    b = [(5.2, 0), (10, 0), (10, 4), (5.2, 4), (5.2, 2.28), (5.1, 2.28), (5.1, 1.5), (5.2, 1.5)]
    cells = _poly_cell("A", a, angle) + _poly_cell("B", b, angle)
    line = "2.5 1.9 7.5 1.9" if angle == 0 else None
    path = _plan(tmp_path, cells, _graph([("A", "B")], {0: line} if line else None, v2=v2), v2=v2)
    _, _, report = _grid_and_report(path, chair=0.65)
    [k] = report.links
    assert k.width == pytest.approx(0.78, abs=0.03)
    assert k.free_width >= 0.78 - RES - 1e-6, k
    assert k.chair and report.ok, report.summary()


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_linked_cells_apart_get_a_passage_across_the_gap(tmp_path: Path, v2: bool) -> None:
    """pnu_abc links stair cells 1.5 m from their corridor with nothing drawn between: the graph decides."""
    rooms = _cell("A", (0, 0, 5, 4)) + _cell("B", (6.5, 0, 11.5, 4))
    graph = _graph([("A", "B")], {0: "2.5 2.0 9.0 2.0"}, v2=v2)
    b, grid, report = _grid_and_report(_plan(tmp_path, rooms, graph, v2=v2))
    [o] = plan_openings(b, b.storeys[0].name).openings
    assert o.rule == "bridge" and o.width == pytest.approx(0.9)
    for x in (4.95, 5.75, 6.55):
        assert grid.value_at(x, 2.0) == FREE
    assert grid.value_at(5.75, 2.0 + 0.45 + RES / 2) == OCCUPIED  # walled along both sides
    assert grid.value_at(5.75, 2.0 - 0.45 - RES / 2) == OCCUPIED
    assert grid.value_at(5.75, 3.5) != FREE  # the rest of the gap is not opened
    assert report.ok and report.links[0].rule == "bridge", report.summary()


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_no_passage_through_a_cell_in_the_gap(tmp_path: Path, v2: bool) -> None:
    rooms = _cell("A", (0, 0, 5, 4)) + _cell("B", (6.5, 0, 11.5, 4)) + _cell("C", (5.2, 1.0, 6.3, 3.0))
    b, _, report = _grid_and_report(_plan(tmp_path, rooms, _graph([("A", "B")], {0: "2.5 2.0 9.0 2.0"}, v2=v2), v2=v2))
    assert [o.rule for o in plan_openings(b, b.storeys[0].name).openings] == ["apart"]
    assert not report.ok and "do not touch" in report.blocked[0].describe()


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_a_way_through_a_door_cell_between_two_linked_rooms_counts(tmp_path: Path, v2: bool) -> None:
    """A file may link two rooms directly and also through the door cell between them (pnu_abc's restrooms)."""
    door = _cell("D", (5, 1, 5.2, 2.2), "navi:ConnectionSpace")
    rooms = _cell("A", (0, 0, 5, 4)) + door + _cell("B", (5.2, 0, 10, 4))
    _, _, report = _grid_and_report(_plan(tmp_path, rooms, _graph([("A", "D"), ("D", "B"), ("A", "B")], v2=v2), v2=v2))
    assert report.counts()["passable_chair"] == 3 and report.ok and report.leaks == [], report.summary()


def _sloping_solid(
    cid: str,
    box: tuple[float, float, float, float],
    z_at_x0: float,
    z_at_x1: float,
    height: float,
    tag: str = "CellSpace",
) -> str:
    """A cell whose floor is one face tilted along x (KU Central Plaza's corridor), its ceiling ``height``
    above it: no face of it is flat, so only the tilted plane tells the floor's height at a point."""
    x0, y0, x1, y1 = box

    def face(dz: float) -> str:
        pts = [(x0, y0, z_at_x0), (x1, y0, z_at_x1), (x1, y1, z_at_x1), (x0, y1, z_at_x0), (x0, y0, z_at_x0)]
        ring = " ".join(f"{x} {y} {z + dz}" for x, y, z in pts)
        return (
            f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
            f"{ring}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        )

    return (
        f'<cellSpaceMember><{tag} gml:id="{cid}"><cellSpaceGeometry><Geometry3D><gml:Solid><gml:exterior>'
        f"<gml:Shell>{face(0.0)}{face(height)}</gml:Shell></gml:exterior></gml:Solid></Geometry3D>"
        f"</cellSpaceGeometry></{tag}></cellSpaceMember>"
    )


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_doors_along_a_sloping_corridor_are_doors_and_a_sill_there_is_not(tmp_path: Path, v2: bool) -> None:
    # a 20 m corridor whose floor rises from -3.9 m to -0.9 m; rooms beside it at the local floor height,
    # each behind a 0.3 m deep door cell that starts well above the corridor's lowest point
    cells = _sloping_solid("COR", (0, 0, 20, 3), -3.9, -0.9, 3.5)
    pairs = []
    for i, x in enumerate((4.0, 10.0, 16.0)):
        floor = -3.9 + 3.0 * (x + 0.5) / 20
        cells += _solid(f"D{i}", (x, 3, x + 1, 3.3), floor, floor + 2.1)
        cells += _solid(f"R{i}", (x - 1.5, 3.3, x + 2.5, 7), floor, floor + 3.0)
        pairs += [("COR", f"D{i}"), (f"D{i}", f"R{i}")]
    sill = -3.9 + 3.0 * 2.5 / 20 + 1.0  # a window in the corridor's wall, 1 m above the floor there
    cells += _solid("W", (2, -0.3, 3, 0), sill, sill + 1.2)
    path = _plan(tmp_path, cells, _graph(pairs, v2=v2), v2=v2)
    b = read_building(path, unit="m")
    assert len(b.storeys) == 1
    assert all(b.cells[f"D{i}"].kind.is_free for i in range(3)), b.warnings  # doors, not windows
    assert not b.cells["W"].kind.is_free  # a sill where it meets the floor beside it
    storey = b.storeys[0].name
    report = check_grid(b, storey, rasterise_storey(b, storey, RES), chair_width=0.7)
    assert report.counts()["links"] == 6 and report.ok, report.counts()


def test_floor_height_is_read_on_the_tilted_face_at_the_point() -> None:
    from pmk_nb.indoorgml.footprint import floor_height
    from pmk_nb.indoorgml.gml import PolygonZ

    floor = PolygonZ([(0, 0, -3.9), (20, 0, -0.9), (20, 3, -0.9), (0, 3, -3.9), (0, 0, -3.9)])
    ceiling = PolygonZ([(x, y, z + 3.5) for x, y, z in floor.exterior])
    wall = PolygonZ([(0, 0, -3.9), (20, 0, -0.9), (20, 0, 2.6), (0, 0, -0.4), (0, 0, -3.9)])
    polys = [ceiling, wall, floor]
    assert floor_height(polys, 10.0, 1.5, 0.05) == pytest.approx(-2.4)
    assert floor_height(polys, 10.0, 3.04, 0.05) == pytest.approx(-2.4)  # at its edge, within the tolerance
    assert floor_height(polys, 10.0, 3.5, 0.05) is None  # beside it: no floor there
    assert floor_height([PolygonZ([(0, 0), (1, 0), (1, 1), (0, 0)])], 0.5, 0.2, 0.05) is None  # 2D: no height


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_a_door_of_the_next_wall_meeting_this_one_at_a_corner_is_not_its_door(tmp_path: Path, v2: bool) -> None:
    # 313_4F_2D.gml (IndoorGML_OSM): two pieces of a corridor whose outer edges carry doors ending where the
    # pieces meet; the transition between the pieces crosses their shared edge. A door touching the shared
    # edge only at its end made a 1 cm "door" there; the transition's line must place the opening.
    rooms = _cell("A", (0, 0, 3, 3)) + _cell("B", (3, 0, 6, 3)) + _cell("C", (0, 3, 6, 6))
    doors = _boundary("D1", ((2.2, 3), (3, 3)), "navi:ConnectionBoundary")
    doors += _boundary("D2", ((3, 3), (3.8, 3)), "navi:ConnectionBoundary")
    line = "1.5 1.5 4.5 1.5"
    b, grid, report = _grid_and_report(
        _plan(tmp_path, rooms, _graph([("A", "B"), ("A", "C"), ("B", "C")], {0: line}, v2=v2), doors, v2=v2)
    )
    ab = next(o for o in plan_openings(b, b.storeys[0].name).openings if {o.link.a, o.link.b} == {"A", "B"})
    assert ab.rule == "line" and ab.width == pytest.approx(0.9)
    assert grid.value_at(3.0, 1.5) == FREE
    assert report.ok and report.counts()["passable_chair"] == 3, report.counts()


@pytest.mark.parametrize(
    "doors",
    [(((4.1, 4), (5, 4)), ((5, 4), (5.9, 4))), (((4.0, 4), (6.0, 4)),)],
    ids=["two-doors-meeting-at-the-partition", "one-door-line-across-the-partition"],
)
@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_openings_near_a_partition_do_not_join_the_rooms_it_parts(
    tmp_path: Path, v2: bool, doors: tuple[tuple[tuple[float, float], ...], ...]
) -> None:
    # 313_4F_2D.gml and put-outer's model.gml: rooms A and B share a partition (x = 5) and both open onto
    # the corridor C above; the door lines run up to (or across) the partition's end. Opening them
    # cleared the partition's last cells, and A leaked into B although the graph never joins them.
    cells = ROOMS + _cell("C", (0, 4, 10, 8))
    lines = "".join(_boundary(f"D{i}", d, "navi:ConnectionBoundary") for i, d in enumerate(doors))
    b, grid, report = _grid_and_report(_plan(tmp_path, cells, _graph([("A", "C"), ("B", "C")], v2=v2), lines, v2=v2))
    assert report.leaks == [] and report.ok, (report.leaks, report.counts())
    assert report.counts()["passable_chair"] == 2
    assert grid.value_at(5.0, 3.97) == OCCUPIED  # the partition reaches the corridor's wall
    assert b.storeys and plan_openings(b, b.storeys[0].name).seams  # the graph keeps A and B apart


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_a_door_cell_drawn_across_a_partition_stays_open(tmp_path: Path, v2: bool) -> None:
    # rooms A and B are not joined directly, only through the door cell D that straddles their wall:
    # the partition is drawn again everywhere but across D
    door = _cell("D", (4.9, 1.0, 5.1, 2.0), "navi:ConnectionSpace")
    b, grid, report = _grid_and_report(_plan(tmp_path, ROOMS + door, _graph([("A", "D"), ("D", "B")], v2=v2), v2=v2))
    assert report.ok and report.counts()["passable_chair"] == 2 and report.leaks == [], report.counts()
    assert grid.value_at(5.0, 1.5) == FREE and grid.value_at(5.0, 3.0) == OCCUPIED
    [seam] = plan_openings(b, b.storeys[0].name).seams  # the partition, less the door cell across it
    assert seam.length == pytest.approx(3.0, abs=0.05) and seam.intersection(b.cells["D"].footprint).length == 0
