"""The witness against maps with the converter's kinds of fault painted in (issue 37).

A right map of the clinic is converted, then one fault at a time is painted into a copy of its grid,
as a wrong converter would have drawn it; the witness must name each fault by its cells and place,
and must say nothing on the right map.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from pmk_nb.grid import FREE, OCCUPIED, OccupancyGrid
from pmk_nb.indoorgml import Building, read_building
from pmk_nb.indoorgml.model import Cell, CellKind, GraphStatus, Link, Storey
from pmk_nb.library.convert import convert_plan
from pmk_nb.rosmap import read_map
from pmk_nb.witness import FindingKind, witness_grid, witness_map

pytestmark = pytest.mark.slow  # the clinic converted once, then judged a dozen times

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
CHAIR = 0.7


@pytest.fixture(scope="module")
def clinic(tmp_path_factory: pytest.TempPathFactory) -> tuple[Building, OccupancyGrid, Path]:
    out = tmp_path_factory.mktemp("clinic")
    result = convert_plan(SAMPLE, out, "clinic")
    yaml = result.maps[0].files.yaml
    return read_building(SAMPLE), read_map(yaml), yaml


def _paint(grid: OccupancyGrid, box: tuple[float, float, float, float], value: int) -> OccupancyGrid:
    """A copy of ``grid`` with every pixel whose centre lies in ``box`` (metres) set to ``value``."""
    data = grid.data.copy()
    res, (ox, oy, _) = grid.resolution, grid.origin
    cols = (np.arange(data.shape[1]) + 0.5) * res + ox
    rows = (np.arange(data.shape[0]) + 0.5) * res + oy
    c = (cols >= box[0]) & (cols <= box[2])
    r = (rows >= box[1]) & (rows <= box[3])
    data[np.ix_(r, c)] = value
    return OccupancyGrid(data, res, grid.origin, meta=dict(grid.meta))


def _kinds(report: object) -> dict[FindingKind, list[tuple[str, ...]]]:
    out: dict[FindingKind, list[tuple[str, ...]]] = {}
    for f in report.findings:  # type: ignore[attr-defined]
        out.setdefault(f.kind, []).append(tuple(sorted(f.cells)))
    return out


def test_the_right_map_is_ok_on_the_written_files(clinic: tuple[Building, OccupancyGrid, Path]) -> None:
    _, _, yaml = clinic
    report, _ = witness_map(yaml, chair_width=CHAIR)
    assert report.ok, [f.describe() for f in report.findings]
    assert report.counts["transitions"] == 12


def test_an_opening_where_the_graph_has_none_is_a_leak_named_by_its_cells_and_place(
    clinic: tuple[Building, OccupancyGrid, Path],
) -> None:
    building, grid, _ = clinic
    wrong = _paint(grid, (9.8, 2.0, 10.2, 3.2), FREE)  # 1.2 m of the wall between waiting room and exam room 1
    report = witness_grid(building, wrong, chair_width=CHAIR)
    leaks = [f for f in report.findings if f.kind is FindingKind.LEAK]
    assert [tuple(sorted(f.cells)) for f in leaks] == [("R1", "R2")]
    x, y = leaks[0].place
    assert abs(x - 10.0) < 0.3 and 1.9 < y < 3.3
    assert not report.ok


def test_a_door_drawn_shut_blocks_its_transition(clinic: tuple[Building, OccupancyGrid, Path]) -> None:
    building, grid, _ = clinic
    wrong = _paint(grid, (4.3, 5.7, 5.6, 6.3), OCCUPIED)  # the waiting room's door, walled
    kinds = _kinds(witness_grid(building, wrong, chair_width=CHAIR))
    assert ("D1", "R1") in kinds[FindingKind.BLOCKED] or ("COR", "D1") in kinds[FindingKind.BLOCKED]
    assert set(kinds) <= {FindingKind.BLOCKED, FindingKind.NO_WAY_THROUGH, FindingKind.ROOM_NOT_FREE}
    assert ("COR", "D1", "R1") in kinds[FindingKind.NO_WAY_THROUGH]  # the door cell cannot be crossed


def test_a_door_narrower_than_the_chair_is_blocked_but_passable_for_a_point(
    clinic: tuple[Building, OccupancyGrid, Path],
) -> None:
    building, grid, _ = clinic
    wrong = _paint(grid, (4.3, 5.7, 4.8, 6.3), OCCUPIED)
    wrong = _paint(wrong, (5.2, 5.7, 5.6, 6.3), OCCUPIED)  # 0.4 m left open
    report = witness_grid(building, wrong, chair_width=CHAIR)
    blocked = [f for f in report.findings if f.kind is FindingKind.BLOCKED]  # the plan's door is 0.90 m
    assert blocked and all(
        "the plan's door is 0.90 m wide, the map lets only a point through" in f.detail for f in blocked
    )
    assert "DISAGREES" in report.summary()
    assert not report.ok and "DISAGREES" in report.summary()


def test_a_door_the_plan_itself_makes_too_narrow_is_narrow_not_a_disagreement() -> None:
    building, grid = _slab_building(offset=0.0, span=(1.1, 1.8))  # the plan's doorway: 0.7 m
    report = witness_grid(building, grid, chair_width=CHAIR)
    assert {f.kind for f in report.findings} == {FindingKind.NARROW}
    assert not report.ok and "narrower than the chair in the map" in report.summary()


def test_an_obstacle_drawn_as_floor_is_found(clinic: tuple[Building, OccupancyGrid, Path]) -> None:
    building, grid, _ = clinic
    wrong = _paint(grid, (2.9, 3.4, 7.1, 4.6), FREE)  # the reception desk drawn as floor
    kinds = _kinds(witness_grid(building, wrong, chair_width=CHAIR))
    assert kinds == {FindingKind.OBSTACLE_FREE: [("DESK",)]}


def test_a_room_drawn_occupied_is_found(clinic: tuple[Building, OccupancyGrid, Path]) -> None:
    building, grid, _ = clinic
    wrong = _paint(grid, (14.0, 11.0, 16.0, 13.0), OCCUPIED)
    report = witness_grid(building, wrong, chair_width=CHAIR)
    found = [f for f in report.findings if f.kind is FindingKind.ROOM_NOT_FREE]
    assert [f.cells for f in found] == [("R5",)]
    assert 0.05 < found[0].amount < 0.2  # 4 m² of 47 m²
    assert abs(found[0].place[0] - 15.0) < 0.2 and abs(found[0].place[1] - 12.0) < 0.2


def test_an_unknown_map_area_is_not_free_either(clinic: tuple[Building, OccupancyGrid, Path]) -> None:
    building, grid, _ = clinic
    wrong = _paint(grid, (21.0, 1.0, 29.0, 5.0), -1)
    assert FindingKind.ROOM_NOT_FREE in _kinds(witness_grid(building, wrong, chair_width=CHAIR))


def _slab_building(offset: float, span: tuple[float, float] = (0.0, 6.0)) -> tuple[Building, OccupancyGrid]:
    """Two 6 x 4 m rooms either side of a door slab 0.6 m deep along ``span`` (x), its two faces opened
    by 0.9 m openings ``offset`` metres apart, drawn straight into a grid (walls 0.1 m)."""
    south = shapely.box(0.0, 0.0, 6.0, 4.0)
    slab = shapely.box(span[0], 4.0, span[1], 4.6)
    north = shapely.box(0.0, 4.6, 6.0, 8.6)
    cells = {
        "S": Cell("S", CellKind.GENERAL, south, "0", name="south room"),
        "SLAB": Cell("SLAB", CellKind.CONNECTION, slab, "0", name="door slab"),
        "N": Cell("N", CellKind.GENERAL, north, "0", name="north room"),
    }
    building = Building(
        source="slab.gml",
        sha256="",
        version="1.0.3",
        namespaces={},
        unit="m",
        unit_reason="test",
        storeys=[Storey("0", 0.0, list(cells))],
        cells=cells,
        links=[Link("T1", "S", "SLAB", storeys=("0", "0")), Link("T2", "SLAB", "N", storeys=("0", "0"))],
        graph_status=GraphStatus(transitions=2, resolved=2, absent=False),
    )
    res = 0.05
    data = np.full((round(9.0 / res), round(6.4 / res)), OCCUPIED, dtype=np.int8)
    origin = (-0.2, -0.2, 0.0)

    def paint(box: tuple[float, float, float, float], value: int) -> None:
        c0, c1 = round((box[0] - origin[0]) / res), round((box[2] - origin[0]) / res)
        r0, r1 = round((box[1] - origin[1]) / res), round((box[3] - origin[1]) / res)
        data[r0:r1, c0:c1] = value

    for box in ((0.05, 0.05, 5.95, 3.95), (span[0] + 0.05, 4.05, span[1] - 0.05, 4.55), (0.05, 4.65, 5.95, 8.55)):
        paint(box, FREE)
    x0, x1 = max(1.0, span[0]), min(1.9, span[1])
    paint((x0, 3.9, x1, 4.1), FREE)  # the south face's opening
    paint((x0 + offset, 4.5, x1 + offset, 4.7), FREE)  # the north face's
    return building, OccupancyGrid(data, res, origin, meta={"storey": "0", "wall_thickness": 0.1})


def test_openings_through_a_door_slab_that_do_not_line_up_leave_no_way_through() -> None:
    building, grid = _slab_building(offset=2.6)
    report = witness_grid(building, grid, chair_width=CHAIR)
    assert [f.cells for f in report.findings if f.kind is FindingKind.NO_WAY_THROUGH] == [("N", "SLAB", "S")]


def test_openings_through_a_door_slab_in_line_are_a_way_through() -> None:
    building, grid = _slab_building(offset=0.0)
    report = witness_grid(building, grid, chair_width=CHAIR)
    assert report.ok, [f.describe() for f in report.findings]


def test_a_plan_without_a_graph_is_never_ok(clinic: tuple[Building, OccupancyGrid, Path]) -> None:
    building, grid, _ = clinic
    bare = Building(
        source=building.source,
        sha256=building.sha256,
        version=building.version,
        namespaces=building.namespaces,
        unit=building.unit,
        unit_reason=building.unit_reason,
        storeys=building.storeys,
        cells=building.cells,
    )
    report = witness_grid(bare, grid, chair_width=CHAIR)
    assert (report.graph, report.ok, report.findings) == (False, False, [])
