"""Walls modelled as gaps between cells: the gap is drawn occupied, doors still open it, wide gaps
(courtyards) and the outside of concave buildings stay unknown."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st
from shapely import affinity
from shapely.geometry import LineString, Polygon, box

from pmk_nb.defaults import DEFAULT_MAX_WALL_GAP
from pmk_nb.errors import OccupancyError
from pmk_nb.indoorgml import Boundary, CellKind, read_building
from pmk_nb.raster import RasterOptions, rasterise_storey
from pmk_nb.raster.walls import door_gaps, gap_walls
from tests.helpers import building, cells_in, flood, room

CLINIC = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
L_SHAPE = Polygon([(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)])


@pytest.fixture(scope="module")
def clinic():
    return read_building(CLINIC)


# --- the vector step ---------------------------------------------------------------------------------


def test_gap_between_two_rooms_is_filled_exactly() -> None:
    a, b = box(0, 0, 3, 3), box(3.3, 1, 6, 5)  # 0.3 m apart, overlapping along y from 1 to 3
    fill = gap_walls([a, b], [], np.zeros(0), 0.5, 0.01)
    assert fill.area == pytest.approx(0.3 * 2.0)
    assert fill.equals(box(3, 1, 3.3, 3)) or fill.symmetric_difference(box(3, 1, 3.3, 3)).area < 1e-9


def test_nothing_filled_when_off_wider_gap_or_concave_building() -> None:
    a, b = box(0, 0, 3, 3), box(3.3, 0, 6, 3)
    assert gap_walls([a, b], [], np.zeros(0), 0.0, 0.01).is_empty  # max_gap 0 turns it off
    assert gap_walls([a, box(5, 0, 8, 3)], [], np.zeros(0), 0.5, 0.01).is_empty  # 2 m apart
    assert gap_walls([L_SHAPE], [], np.zeros(0), 0.5, 0.01).is_empty  # the L's inner corner is outside
    two_part_l = [box(0, 0, 10, 4), box(0, 4.2, 4, 10)]  # the same L with a wall gap between its parts
    assert gap_walls(two_part_l, [], np.zeros(0), 0.5, 0.01).area == pytest.approx(4 * 0.2)


def test_small_hole_filled_large_hole_kept() -> None:
    small = Polygon(box(0, 0, 6, 6).exterior.coords, [box(2, 2, 2.4, 2.4).exterior.coords])
    large = Polygon(box(0, 0, 6, 6).exterior.coords, [box(2, 2, 4, 4).exterior.coords])
    assert gap_walls([small], [], np.zeros(0), 0.5, 0.01).area == pytest.approx(0.16)
    assert gap_walls([large], [], np.zeros(0), 0.5, 0.01).is_empty


def test_door_line_cuts_the_gap_fill_across_to_both_rooms() -> None:
    a, b = box(0, 0, 3, 3), box(3.2, 0, 6, 3)
    door = LineString([(3.1, 1.0), (3.1, 1.9)])
    gaps = door_gaps([door], [a, b], 1.0)
    assert gaps[0] == pytest.approx(0.1)
    fill = gap_walls([a, b], [door], gaps, 0.5, 0.01)
    assert fill.area == pytest.approx(0.2 * (3 - 0.9))
    assert not fill.intersects(box(3.0, 1.01, 3.2, 1.89))


def test_door_gaps_counts_the_nearest_room_on_each_side() -> None:
    a, b = box(0, 0, 3, 3), box(3.45, 0, 6, 3)  # door on A's edge, B 0.45 m away (pnu313 style)
    door = LineString([(3.0, 1.0), (3.0, 1.9)])
    assert door_gaps([door], [a, b], 1.0)[0] == pytest.approx(0.45)
    # a room further off on the same side does not widen the opening; nor does one behind A
    assert door_gaps([door], [a, b, box(3.9, 0, 5, 3), box(-0.9, 0, -0.5, 3)], 1.0)[0] == pytest.approx(0.45)
    # rooms sharing the door's edge: no gap; an outside door: no gap; a door drawn there and back
    assert door_gaps([door], [a, box(3, 0, 6, 3)], 1.0)[0] == 0
    assert door_gaps([door], [a], 1.0)[0] == 0
    there_and_back = LineString([(3.0, 1.0), (3.0, 1.9), (3.0, 1.0)])
    assert door_gaps([there_and_back], [a, b], 1.0)[0] == pytest.approx(0.45)


@settings(max_examples=60, deadline=None)
@example(width=0.625, shift=2.0, angle=216.0457, max_gap=0.5)  # GEOS mitre buffers once filled this
@example(width=0.5, shift=0.00390625, angle=0.0, max_gap=0.8)  # a tiny step: its notch may fill
@given(
    width=st.floats(0.02, 1.2),
    shift=st.floats(-2.5, 2.5),
    angle=st.floats(0, 360),
    max_gap=st.sampled_from([0.3, 0.5, 0.8]),
)
def test_gap_fill_is_the_overlap_strip_at_any_rotation(
    width: float, shift: float, angle: float, max_gap: float
) -> None:
    # two rooms ``width`` apart, the second shifted along the gap: the fill is the strip they both
    # face (width x overlap) when the gap is at most max_gap, and nothing otherwise
    a, b = box(0, 0, 3, 3), box(3 + width, shift, 6, 3 + shift)
    rot = [affinity.rotate(g, angle, origin=(0, 0)) for g in (a, b)]
    fill = gap_walls(rot, [], np.zeros(0), max_gap, 0.01)
    if width > max_gap:
        assert fill.area == pytest.approx(0.0, abs=1e-6)
    else:
        # the strip both rooms face; where one room ends above the other the step is a notch at most
        # ``width`` wide and ``|shift|`` deep at each end, which the closing may fill too
        strip = width * (3 - abs(shift))
        assert strip - 1e-6 <= fill.area <= strip + 2 * width * abs(shift) + 1e-6
    if not fill.is_empty:
        assert fill.difference(shapely.convex_hull(shapely.union_all(rot))).area < 1e-6


# --- on the grid ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("res", [0.05, 0.1])
def test_clinic_gap_is_wall_except_at_the_doors(clinic, res: float) -> None:
    grid = rasterise_storey(clinic, "0", res)
    assert grid.value_at(12.0, 6.0) == 100  # mid-gap between exam room 1 and the corridor
    strip = cells_in(grid, box(10.2, 5.91, 14.3, 6.09))  # the whole gap beside door D2
    assert strip.any() and (grid.data[strip] == 100).all()
    assert grid.value_at(14.95, 6.0) == 0  # door D2
    free = grid.data == 0
    corridor, exam = cells_in(grid, box(1, 7, 29, 8)), cells_in(grid, box(11, 1, 19, 5))
    assert (flood(free, exam) & corridor).any()
    # every room reaches the corridor, and only through its door
    reached = flood(free, corridor)
    for x, y in [(5.0, 2.95), (15.0, 2.95), (25.0, 2.95), (6.0, 12.05), (16.0, 12.05), (25.0, 12.05)]:
        assert reached[cells_in(grid, box(x - 0.2, y - 0.2, x + 0.2, y + 0.2))].all()
    no_door = free & ~cells_in(grid, box(14.2, 5.5, 15.7, 6.5))
    assert not (flood(no_door, exam) & corridor).any()
    assert grid.meta["max_wall_gap"] == DEFAULT_MAX_WALL_GAP


def test_clinic_gap_stays_unknown_when_turned_off(clinic) -> None:
    grid = rasterise_storey(clinic, "0", 0.05, RasterOptions(max_wall_gap=0))
    assert grid.value_at(12.0, 6.0) == -1


def test_rooms_a_little_apart_get_a_solid_wall_far_apart_keep_unknown() -> None:
    near = rasterise_storey(building([room("A", box(0, 0, 3, 3)), room("B", box(3.3, 0, 6, 3))]), "F1", 0.05)
    between = cells_in(near, box(3.0, 0.05, 3.3, 2.95))
    assert between.any() and (near.data[between] == 100).all()
    seed_a, seed_b = cells_in(near, box(0.5, 0.5, 2.5, 2.5)), cells_in(near, box(3.8, 0.5, 5.5, 2.5))
    assert not (flood(near.data == 0, seed_a) & seed_b).any()
    # 2 m apart: a courtyard / light well, not a wall: unknown apart from the two walls' bands
    far = rasterise_storey(building([room("A", box(0, 0, 3, 3)), room("B", box(5, 0, 8, 3))]), "F1", 0.05)
    assert (far.data[cells_in(far, box(3.2, 0.2, 4.8, 2.8))] == -1).all()


def test_l_shaped_building_outer_corner_stays_unknown() -> None:
    for cells in ([room("L", L_SHAPE)], [room("A", box(0, 0, 10, 4)), room("B", box(0, 4.2, 4, 10))]):
        grid = rasterise_storey(building(cells), "F1", 0.1)
        assert (grid.data[cells_in(grid, box(4.2, 4.5, 9.8, 9.8))] == -1).all()
        assert (grid.data[cells_in(grid, box(4.2, 4.05, 9.8, 4.25))] != 0).all()
    assert grid.value_at(2.0, 4.1) == 100  # the two-part L: its wall gap is wall


def test_door_on_one_rooms_edge_reaches_across_the_gap() -> None:
    # pnu313 style: the door line lies on the room's edge, the corridor 0.45 m away
    a, b = box(0, 0, 3, 3), box(3.45, 0, 6, 3)
    door = Boundary("d", True, LineString([(3.0, 1.0), (3.0, 1.9)]), "F1")
    grid = rasterise_storey(building([room("A", a), room("B", b)], [door]), "F1", 0.05)
    free = grid.data == 0
    seed_a, seed_b = cells_in(grid, box(0.5, 0.5, 2.5, 2.5)), cells_in(grid, box(4, 0.5, 5.5, 2.5))
    assert (flood(free, seed_a) & seed_b).any()
    beside = cells_in(grid, box(3.0, 2.2, 3.45, 2.8))
    assert (grid.data[beside] == 100).all()
    blocked = free & ~cells_in(grid, box(2.7, 0.8, 3.8, 2.1))
    assert not (flood(blocked, seed_a) & seed_b).any()


def test_door_cell_spanning_the_gap_stays_open_and_obstacles_stay() -> None:
    cells = [
        room("A", box(0, 0, 3, 3)),
        room("B", box(3.2, 0, 6, 3)),
        room("D", box(3.0, 1.0, 3.2, 1.9), CellKind.CONNECTION),
        room("P", box(3.2, 2.5, 3.5, 2.8), CellKind.NON_NAVIGABLE),
    ]
    grid = rasterise_storey(building(cells), "F1", 0.05)
    assert (grid.data[cells_in(grid, box(3.0, 1.05, 3.2, 1.85))] == 0).all()
    assert (grid.data[cells_in(grid, box(3.0, 2.0, 3.2, 2.95))] == 100).all()
    assert (grid.data[cells_in(grid, box(3.25, 2.55, 3.45, 2.75))] == 100).all()


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf"), "wide"])
def test_bad_max_wall_gap_rejected(bad: object) -> None:
    with pytest.raises(OccupancyError, match="max wall gap"):
        rasterise_storey(building([room("A", box(0, 0, 3, 3))]), "F1", 0.1, RasterOptions(max_wall_gap=bad))  # type: ignore[arg-type]
