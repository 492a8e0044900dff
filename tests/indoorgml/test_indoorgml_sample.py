"""The ALMA-style samples in sample_maps/: what the rasteriser tests rely on."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest
from shapely.geometry import Point

from pmk_nb.indoorgml import CellKind, read_building, summarize

SAMPLES = Path(__file__).resolve().parents[2] / "sample_maps"

# room centres in metres (README.md table); all free, all on the single storey "0"
ROOMS = {
    "COR": (15.0, 7.5),
    "R1": (5.0, 2.95),
    "R2": (15.0, 2.95),
    "R3": (25.0, 2.95),
    "R4": (6.0, 12.05),
    "R5": (16.0, 12.05),
    "R6": (25.0, 12.05),
}


@pytest.fixture(scope="module")
def clinic():
    return read_building(SAMPLES / "clinic_floor.gml")


def test_alma_style_detected_in_centimetres(clinic) -> None:
    assert clinic.version == "alma"
    assert clinic.unit == "cm" and "ALMA" in clinic.unit_reason
    assert clinic.layers == ["L1", "L2"] and {c.layer for c in clinic.cells.values()} == {"L1"}


def test_storey_cells_doors(clinic) -> None:
    assert [s.name for s in clinic.storeys] == ["0"]
    kinds = [c.kind for c in clinic.cells.values()]
    assert len(kinds) == 15
    assert kinds.count(CellKind.CONNECTION) == 6
    assert kinds.count(CellKind.NON_NAVIGABLE) == 2
    assert summarize(clinic)["doors"]["total"] == 6


def test_room_centres_and_obstacles(clinic) -> None:
    for cid, (x, y) in ROOMS.items():
        assert clinic.cells[cid].footprint.contains(Point(x, y)), cid
        assert clinic.cells[cid].kind.is_free
    assert clinic.cells["DESK"].footprint.contains(Point(5.0, 4.0))
    assert clinic.cells["DESK"].kind is CellKind.NON_NAVIGABLE
    wall = Point(12.0, 6.0)  # between exam room 1 and the corridor, away from its door
    assert not any(c.footprint.contains(wall) for c in clinic.cells.values())


def test_rooms_share_walls_and_doors_span_the_gap(clinic) -> None:
    shared = clinic.cells["R1"].footprint.intersection(clinic.cells["R2"].footprint)
    assert shared.geom_type == "LineString" and shared.length == pytest.approx(5.9)
    for i in range(1, 7):
        door = clinic.cells[f"D{i}"].footprint
        room = clinic.cells[f"R{i}"].footprint
        assert door.touches(room) and door.touches(clinic.cells["COR"].footprint)
        minx, miny, maxx, maxy = door.bounds
        assert maxx - minx == pytest.approx(0.9) and maxy - miny == pytest.approx(0.2)


def test_georeference(clinic) -> None:
    assert clinic.georef.translation == pytest.approx((2500.0, 1200.0))
    assert clinic.georef.rotation == pytest.approx(30.0)


def test_two_storeys() -> None:
    b = read_building(SAMPLES / "clinic_two_storeys.gml")
    assert [(s.name, len(s.cell_ids)) for s in b.storeys] == [("F1", 15), ("F2", 15)]
    assert b.cells["DESK_F1"].storey == "F1" and b.cells["BED_F2"].storey == "F2"
    assert b.cells["R2_F2"].kind.is_free and b.cells["R2_F2"].footprint.contains(Point(15.0, 2.95))


def test_generator_is_reproducible(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    spec = importlib.util.spec_from_file_location("make_clinic", SAMPLES / "make_clinic.py")
    assert spec and spec.loader
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, "make_clinic", module)  # dataclasses look their module up
    spec.loader.exec_module(module)
    for path in module.main(tmp_path):
        assert path.read_bytes() == (SAMPLES / path.name).read_bytes()
