"""Issue 31 rule 3: the unit of a plan that does not say, from every size it carries.

Small synthetic plans, in the 1.0.x (State/Transition) and 2.0 (Node/Edge) spellings, drawn in metres
and scaled by the unit's factor; and :func:`choose_unit` as a pure function. The plans the old guess
got wrong: an office and a house whose transitions are dual to the whole wall between two cells (the
old guess took those faces for doors: a 10 m "door" fits decimetres, so a 50 m office became 5 m).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pmk_nb.cli import main
from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.units import UNIT_SCALE, UnitEvidence, UnitVote, choose_unit, unit_suspect
from tests.access.test_access_rules import _boundary, _cell, _graph, _plan, _ring, _solid

SPELLINGS = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
UNITS = pytest.mark.parametrize("unit", ["m", "dm", "cm", "mm"])
Box = tuple[float, float, float, float]


def _k(unit: str) -> float:
    """File units per metre."""
    return 1 / UNIT_SCALE[unit]


def _box(box: Box, k: float) -> Box:
    return (box[0] * k, box[1] * k, box[2] * k, box[3] * k)


def _face(bid: str, a: tuple[float, float], b: tuple[float, float], transition: str) -> str:
    """A bare boundary dual to a transition: the face it crosses, here the whole wall between two cells."""
    dual = f'<duality xlink:href="#{transition}"/></CellSpaceBoundary>'
    return _boundary(bid, (a, b)).replace("</CellSpaceBoundary>", dual)


def _door(bid: str, a: tuple[float, float], b: tuple[float, float]) -> str:
    return _boundary(bid, (a, b), "navi:ConnectionBoundary")


def _office(tmp_path: Path, unit: str, *, v2: bool) -> Path:
    """50 x 20 m: ten 10 x 8 m rooms on a 4 m corridor, each room's transition dual to its whole 10 m wall."""
    k = _k(unit)
    cells, faces, pairs = _cell("C", _box((0, 8, 50, 12), k)), "", []
    for i in range(10):
        x, below = 10 * (i % 5), i < 5
        cells += _cell(f"R{i}", _box((x, 0, x + 10, 8) if below else (x, 12, x + 10, 20), k))
        y = (8 if below else 12) * k
        faces += _face(f"F{i}", (x * k, y), ((x + 10) * k, y), f"T{i}")
        pairs.append((f"R{i}", "C"))
    return _plan(tmp_path, cells, _graph(pairs, v2=v2), faces, v2=v2)


HOUSE = {"A": (0, 0, 5, 3.5), "B": (5, 0, 10, 3.5), "C": (0, 4.5, 5, 8), "D": (5, 4.5, 10, 8), "H": (0, 3.5, 10, 4.5)}


def _house(tmp_path: Path, unit: str, *, v2: bool, solid: bool = False, faces: bool = True, extra: str = "") -> Path:
    """10 x 8 m: four rooms on a 1 m hall, each room's transition dual to its whole wall with the hall."""
    k = _k(unit)
    cells = "".join(_solid(c, _box(b, k), 0, 2.5 * k) if solid else _cell(c, _box(b, k)) for c, b in HOUSE.items())
    walls = ""
    for i, c in enumerate("ABCD"):
        x0, y0, x1, y1 = HOUSE[c]
        y = (y1 if y0 == 0 else y0) * k
        walls += _face(f"F{i}", (x0 * k, y), (x1 * k, y), f"T{i}") if faces else ""
    return _plan(tmp_path, cells + extra, _graph([(c, "H") for c in "ABCD"], v2=v2), walls, v2=v2)


@SPELLINGS
@UNITS
def test_office_with_whole_wall_transitions_keeps_its_unit(tmp_path: Path, unit: str, v2: bool) -> None:
    b = read_building(_office(tmp_path, unit, v2=v2))
    assert b.unit == unit, b.unit_reason  # was: m -> dm (a 5 m office), dm -> cm, cm -> mm
    assert "of 6 room areas (median 80 m²)" in b.unit_reason and "plan extent 50 m" in b.unit_reason
    assert b.unit_conflict == ""  # whole-wall faces count little and are no conflict


@SPELLINGS
@pytest.mark.parametrize("unit", ["m", "dm", "cm"])
def test_small_house_with_whole_wall_transitions_keeps_its_unit(tmp_path: Path, unit: str, v2: bool) -> None:
    b = read_building(_house(tmp_path, unit, v2=v2))
    assert b.unit == unit, b.unit_reason  # was: m -> dm (5 m walls read as 0.5 m doors), dm -> cm, cm -> mm
    xs = [c.footprint.bounds for c in b.cells.values()]
    assert max(x[2] for x in xs) == pytest.approx(10.0) and max(x[3] for x in xs) == pytest.approx(8.0)


@SPELLINGS
@UNITS
def test_small_house_of_solids_is_read_in_its_unit(tmp_path: Path, unit: str, v2: bool) -> None:
    b = read_building(_house(tmp_path, unit, v2=v2, solid=True))
    assert b.unit == unit and "3 of 3 cell heights (median 2.5 m)" in b.unit_reason
    assert "votes" in b.unit_reason and b.unit_suspect is None


def _stair(cid: str, x0: float, k: float, steps: int = 16, rise: float = 0.175, run: float = 0.28) -> str:
    """A straight stair drawn as a solid: one horizontal face per tread (rise and run in metres)."""
    faces = "".join(
        f"<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>"
        f"{_ring(*_box((x0 + i * run, 0, x0 + (i + 1) * run, 1.0), k), z=i * rise * k)}</gml:posList>"
        "</gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        for i in range(steps)
    )
    return (
        f'<cellSpaceMember><CellSpace gml:id="{cid}"><cellSpaceGeometry><Geometry3D><gml:Solid><gml:exterior>'
        f"<gml:Shell>{faces}</gml:Shell></gml:exterior></gml:Solid></Geometry3D></cellSpaceGeometry>"
        "</CellSpace></cellSpaceMember>"
    )


def _door_cell(cid: str, box: Box, height: float, k: float) -> str:
    return (
        _solid(cid, _box(box, k), 0, height * k)
        .replace("<CellSpace ", "<navi:ConnectionSpace ")
        .replace("</CellSpace>", "</navi:ConnectionSpace>")
    )


@SPELLINGS
@pytest.mark.parametrize("unit", ["m", "cm", "mm"])
def test_stair_risers_and_door_heights_are_evidence(tmp_path: Path, unit: str, v2: bool) -> None:
    k = _k(unit)
    extra = _stair("S", 12, k) + _door_cell("DC", (2.0, 3.4, 2.9, 3.6), 2.1, k)
    b = read_building(_house(tmp_path, unit, v2=v2, solid=True, extra=extra))
    assert b.unit == unit
    assert "stair risers 0.175 m" in b.unit_reason and "door heights 2.1 m" in b.unit_reason
    assert "door widths 0.9 m" in b.unit_reason


@SPELLINGS
def test_storey_heights_from_floor_to_floor(tmp_path: Path, v2: bool) -> None:
    """Two storeys of flat 2D rooms at z 0 and 300 (no heights of their own): 3 m storeys say centimetres."""

    def flat(cid: str, box: Box, z: float) -> str:
        flat_z = f"<gml:posList srsDimension='3'>{_ring(*box, z=z)}"
        return _cell(cid, box).replace(f"<gml:posList>{_ring(*box)}", flat_z)

    cells = "".join(flat(f"{c}{z}", _box(b, 100), z) for c, b in HOUSE.items() for z in (0, 300))
    b = read_building(_plan(tmp_path, cells, v2=v2))
    assert b.unit == "cm" and "storey heights 3 m" in b.unit_reason


@SPELLINGS
def test_heights_say_metres_doors_say_centimetres_is_a_conflict(tmp_path: Path, v2: bool) -> None:
    doors = "".join(_door(f"D{i}", (x, 3.5), (x + 90, 3.5)) for i, x in enumerate((1, 6)))
    doors += "".join(_door(f"E{i}", (x, 4.5), (x + 90, 4.5)) for i, x in enumerate((1, 6)))
    path = _house(tmp_path, "m", v2=v2, solid=True, faces=False)
    path.write_text(
        path.read_text()
        .replace("</PrimalSpaceFeatures>", f"{doors}</PrimalSpaceFeatures>")
        .replace("</PrimalSpaceLayer>", f"{doors}</PrimalSpaceLayer>")
    )
    b = read_building(path)
    assert b.unit == "m"
    assert "the door widths are 90 m in metres (0 of 4 fit): they say centimetres" in b.unit_conflict
    assert "because of the cell heights, room areas, plan extent" in b.unit_conflict
    assert b.unit_suspect is not None and not b.unit_suspect.probable and b.unit_suspect.better == "cm"
    assert b.unit_suspect.message.startswith("all doors are 90 m wide in metres: in centimetres they would be 0.9 m")


def test_a_named_writer_with_a_known_unit_is_evidence(tmp_path: Path) -> None:
    path = _house(tmp_path, "m", v2=False, faces=False)
    path.write_text(path.read_text().replace("?>", "?><!--CityGML to IndoorGML by IndoorGML Editor-->", 1))
    b = read_building(path)
    assert b.unit == "m" and "written by a CityGML-to-IndoorGML converter" in b.unit_reason


@SPELLINGS
def test_a_metric_projected_crs_says_metres(tmp_path: Path, v2: bool) -> None:
    """Two 30 x 30 m halls: 900 m² rooms fit decimetres (9 m²) better, until srsName names UTM 32N."""
    halls = _cell("A", (445000, 5444000, 445030, 5444030)) + _cell("B", (445030, 5444000, 445060, 5444030))
    plain = read_building(_plan(tmp_path, halls, _graph([("A", "B")], v2=v2), v2=v2))
    assert plain.unit == "dm"
    utm = halls.replace("<gml:Polygon>", '<gml:Polygon srsName="urn:ogc:def:crs:EPSG::25832">', 1)
    b = read_building(_plan(tmp_path, utm, _graph([("A", "B")], v2=v2), v2=v2))
    assert b.unit == "m" and "drawn in urn:ogc:def:crs:EPSG::25832 (srsName), a projected CRS" in b.unit_reason
    assert "the room areas are 900 m² in metres (0 of 1 fit): they say decimetres (room areas 9 m²)" in b.unit_conflict


# choose_unit alone: a pure function of the evidence


def test_items_are_counted_not_only_the_median() -> None:
    ev = UnitEvidence(door_widths=[0.9] * 9 + [9.0], room_areas=[20.0] * 4, extent=12.0)
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert choice.unit == "m" and "9 of 10 door widths (median 0.9 m)" in choice.reason
    assert "4 of 4 room areas (median 20 m²)" in choice.reason and choice.conflict == ""


def test_whole_wall_faces_do_not_outvote_rooms() -> None:
    """The old guess: ten 10 m faces as doors (weight 3) beat the rooms and gave decimetres."""
    ev = UnitEvidence(room_areas=[80.0] * 6, extent=50.0, passage_widths=[10.0] * 10)
    assert choose_unit(alma=False, alma_why="", evidence=ev).unit == "m"


def test_writer_outweighs_weak_evidence_and_a_disagreement_is_said() -> None:
    ev = UnitEvidence(room_areas=[2000.0] * 3, extent=60.0, exporter=("m", "written by a CityGML converter"))
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert choice.unit == "m" and "room areas are 2e+03 m² in metres" in choice.conflict


def test_strong_sizes_outweigh_a_named_writer_and_say_so() -> None:
    ev = UnitEvidence(
        door_widths=[90.0] * 5,
        cell_heights=[250.0] * 4,
        room_areas=[2e5] * 4,
        extent=1000.0,
        exporter=("m", "written by a CityGML converter"),
    )
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert choice.unit == "cm" and "3 of 5 votes, next metres 1)" in choice.reason
    assert "the file is written by a CityGML converter, which means metres" in choice.conflict


def _hall_with_a_centimetre_door(tmp_path: Path, v2: bool) -> Path:
    """Issue 37 item 5: two 90 x 140 m halls 3 m high, drawn in metres, and the door between them drawn 90
    units wide (centimetres) and 2.1 high (metres); its transition crosses the whole 140-unit wall."""
    cells = _solid("A", (0, 0, 90, 140), 0, 3) + _solid("B", (90, 0, 180, 140), 0, 3)
    face = "90 20 0 90 110 0 90 110 2.1 90 20 2.1 90 20 0"
    door = (
        '<cellSpaceBoundaryMember><navi:ConnectionBoundary gml:id="D"><cellSpaceBoundaryGeometry><geometry3D>'
        f"<gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension='3'>{face}</gml:posList>"
        "</gml:LinearRing></gml:exterior></gml:Polygon></geometry3D></cellSpaceBoundaryGeometry>"
        "</navi:ConnectionBoundary></cellSpaceBoundaryMember>"
    )
    return _plan(tmp_path, cells, _graph([("A", "B")], v2=v2), door + _face("F", (90, 0), (90, 140), "T0"), v2=v2)


@SPELLINGS
def test_one_door_cannot_outvote_three_kinds_that_agree(tmp_path: Path, v2: bool) -> None:
    """The door width (and the face that repeats it) say centimetres, the door height, the cell heights and
    the extent metres: the majority reads metres (the old weights read centimetres: 1.8 x 1.4 m halls),
    and the conflict lists every vote."""
    b = read_building(_hall_with_a_centimetre_door(tmp_path, v2))
    assert b.unit == "m", b.unit_reason
    assert b.cells["B"].footprint.bounds == pytest.approx((90, 0, 180, 140))
    votes = {v.source: v.units for v in b.unit_votes}
    assert votes == {
        "door widths": ("cm",),
        "door heights": ("m",),
        "cell heights": ("m",),
        "room areas": ("dm",),
        "transition faces": ("cm",),
        "plan extent": ("m",),
    }
    assert "3 of 5.5 votes, next centimetres 1.5" in b.unit_reason
    assert "The votes: metres 3 (door heights, cell heights, plan extent); decimetres 1 (room areas); " in (
        b.unit_conflict
    )
    assert "centimetres 1.5 (door widths, transition faces)" in b.unit_conflict


def test_votes_are_counted_by_kind_not_by_weight() -> None:
    ev = UnitEvidence(door_widths=[90.0], door_heights=[2.1], cell_heights=[3.0], extent=180.0, passage_widths=[90.0])
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert ev.score("cm") > ev.score("m")  # the weights alone (doors count four times) say centimetres
    assert choice.unit == "m" and [v.units for v in choice.votes] == [("cm",), ("m",), ("m",), ("cm",), ("m",)]
    assert choice.votes[0] == UnitVote("door widths", ("cm",), 1.0, "door widths 0.9 m in centimetres")


def test_a_tie_is_decided_by_the_weightier_evidence_and_said() -> None:
    """PNU 201's doors and extent say metres, its rooms and corridors decimetres: the doors weigh more."""
    ev = UnitEvidence(door_widths=[2.4] * 5, room_areas=[1500.0] * 4, corridor_widths=[11.0], extent=240.0)
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert choice.unit == "m"
    assert "2 of 4 votes, next decimetres 2; a tie, the weightier evidence decides: 5.0 to 3.0)" in choice.reason


def test_a_metric_crs_in_srs_name_is_the_unit_not_a_vote() -> None:
    """GML: coordinates are in the unit of the CRS srsName names; every kind voting decimetres does not change it."""
    ev = UnitEvidence(door_widths=[9.0] * 3, room_areas=[2000.0] * 3, extent=300.0, crs="drawn in EPSG:25832")
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert choice.unit == "m" and choice.reason.startswith("auto: metres (drawn in EPSG:25832;")
    assert "The votes: decimetres 3 (door widths, room areas, plan extent)" in choice.conflict


def test_a_unit_given_by_hand_that_makes_doors_absurd_is_the_suspect() -> None:
    ev = UnitEvidence(door_widths=[0.9, 1.0, 0.8], cell_heights=[2.6] * 3, room_areas=[20.0] * 3, extent=10.0)
    s = unit_suspect(ev, "cm")
    assert s is not None and s.better == "m" and s.probable and (s.doors_wrong, s.doors) == (3, 3)
    assert s.message.startswith("all doors are 0.009 m wide in centimetres: the plan is probably in metres")
    assert s.message.endswith("try --unit m")
    assert unit_suspect(ev, "m") is None


def test_doors_that_fit_another_unit_are_a_doubt_and_doors_that_fit_none_are_not() -> None:
    ev = UnitEvidence(door_widths=[9.0, 9.5, 10.0], cell_heights=[2.6] * 3, room_areas=[20.0] * 3, stair_risers=[0.18])
    s = unit_suspect(ev, "m")  # the doors say decimetres, everything else metres: the unit is still named first
    assert s is not None and s.better == "dm" and not s.probable
    assert s.message == (
        "all doors are 9.5 m wide in metres: in decimetres they would be 0.95 m, but the cell heights, stair "
        "risers, room areas say metres; try --unit dm"
    )
    assert unit_suspect(UnitEvidence(door_widths=[40.0, 50.0]), "dm") is None  # 4-5 m, or 0.4-0.5 m: no unit fits


@pytest.mark.slow
@settings(max_examples=200, deadline=None)
@given(
    unit=st.sampled_from(list(UNIT_SCALE)),
    doors=st.lists(st.floats(0.7, 2.4), max_size=12),
    heights=st.lists(st.floats(2.3, 5.5), max_size=8),
    areas=st.lists(st.floats(5.0, 180.0), max_size=20),
    risers=st.lists(st.floats(0.13, 0.21), max_size=2),
    extent=st.floats(6.0, 450.0),
)
def test_a_plausible_building_is_read_back_in_its_unit(
    unit: str, doors: list[float], heights: list[float], areas: list[float], risers: list[float], extent: float
) -> None:
    """Property: sizes a real building has, written in any unit, are read back in that unit (the extent
    alone cannot tell metres from decimetres, so at least one other kind is given)."""
    if not (doors or heights or areas or risers):
        doors = [0.9]
    k, k2 = _k(unit), _k(unit) ** 2
    ev = UnitEvidence(
        door_widths=[d * k for d in doors],
        cell_heights=[h * k for h in heights],
        room_areas=[a * k2 for a in areas],
        stair_risers=[r * k for r in risers],
        extent=extent * k,
    )
    choice = choose_unit(alma=False, alma_why="", evidence=ev)
    assert choice.unit == unit and choice.conflict == "" and choice.suspect is None


@settings(max_examples=12, deadline=None)
@given(
    unit=st.sampled_from(list(UNIT_SCALE)),
    widths=st.lists(st.floats(2.5, 12.0), min_size=2, max_size=6),
    depth=st.floats(3.0, 9.0),
    door=st.floats(0.8, 1.6),
    v2=st.booleans(),
)
def test_a_random_plan_is_read_back_in_its_unit(
    tmp_path_factory: pytest.TempPathFactory, unit: str, widths: list[float], depth: float, door: float, v2: bool
) -> None:
    """Property on whole files: a row of rooms on a 2 m corridor, a door each, written in ``unit``."""
    k, x, cells, doors = _k(unit), 0.0, "", ""
    for i, w in enumerate(widths):
        cells += _cell(f"R{i}", _box((x, 0, x + w, depth), k))
        mid = x + w / 2
        doors += _door(f"D{i}", ((mid - door / 2) * k, depth * k), ((mid + door / 2) * k, depth * k))
        x += w
    cells += _cell("C", _box((0, depth, x, depth + 2), k))
    graph = _graph([(f"R{i}", "C") for i in range(len(widths))], v2=v2)
    b = read_building(_plan(tmp_path_factory.mktemp("p"), cells, graph, doors, v2=v2))
    assert b.unit == unit, b.unit_reason


# what a person sees: pmk check and pmk info


@SPELLINGS
def test_check_names_the_unit_before_any_door(tmp_path: Path, v2: bool, capsys: pytest.CaptureFixture[str]) -> None:
    path = _house(tmp_path, "m", v2=v2, solid=True, faces=False)
    doors = "".join(
        _door(f"D{i}", (HOUSE[c][0] + 2, 3.5 if c in "AB" else 4.5), (HOUSE[c][0] + 2.9, 3.5 if c in "AB" else 4.5))
        for i, c in enumerate("ABCD")
    )
    layer = "PrimalSpaceLayer" if v2 else "PrimalSpaceFeatures"
    path.write_text(path.read_text().replace(f"</{layer}>", f"{doors}</{layer}>"))
    assert main(["check", str(path), "--unit", "cm", "-r", "0.01"]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("suspect the unit first: all doors are 0.009 m wide in centimetres: ")
    assert "the plan is probably in metres" in lines[0] and lines[0].endswith("try --unit m")
    assert main(["check", str(path), "--unit", "cm", "-r", "0.01", "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    suspect = doc["unit_suspect"]
    assert suspect["unit"] == "cm" and suspect["better"] == "m" and suspect["probable"] is True
    assert suspect["doors"] == 4 and suspect["doors_wrong"] == 4 and suspect["door_width"] == pytest.approx(0.009)
    assert main(["check", str(path), "--json"]) == 0  # read in metres (auto): nothing to suspect
    assert json.loads(capsys.readouterr().out)["unit_suspect"] is None
    assert main(["info", str(path), "--unit", "cm"]) == 0
    out = capsys.readouterr().out
    assert "units: cm (given: cm)" in out and "UNIT SUSPECT: all doors are 0.009 m wide" in out


def test_pmk_info_and_convert_list_every_vote(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _hall_with_a_centimetre_door(tmp_path, v2=True)
    assert main(["info", str(path), "--json"]) == 0
    votes = json.loads(capsys.readouterr().out)["unit_votes"]
    assert {v["source"]: v["units"] for v in votes}["door widths"] == ["cm"]
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "unit votes: metres 3 (door heights, cell heights, plan extent); decimetres 1 (room areas); " in out
    assert "    - door widths: cm (door widths 0.9 m in centimetres)" in out
    assert main(["convert", str(path), "--out", str(tmp_path / "maps"), "-r", "1", "--no-preview", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["unit"] == "m" and len(result["unit_votes"]) == 6 and "The votes: metres 3" in result["unit_conflict"]
