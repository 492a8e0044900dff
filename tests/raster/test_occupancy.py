"""Rasteriser: cell-centre fill, walls that never leak, doors that always open, budgets."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Polygon, box

from pmk_nb.errors import GridTooLarge, OccupancyError
from pmk_nb.grid import OccupancyGrid
from pmk_nb.indoorgml import Boundary, CellKind
from pmk_nb.progress import Progress
from pmk_nb.raster import RasterOptions, plan_storey, rasterise, rasterise_storey
from pmk_nb.raster.scanline import Frame, fill_polygon, line_segments, supercover_cells
from tests.helpers import building, cells_in, flood, reachable, room

# --- helpers ----------------------------------------------------------------------------------------


def deep_inside(grid: OccupancyGrid, geom: Polygon, depth: float) -> np.ndarray:
    return cells_in(grid, geom.buffer(-depth)) if geom.buffer(-depth).area > 0 else np.zeros(grid.data.shape, bool)


# --- raster primitives --------------------------------------------------------------------------------


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # GEOS distance to degenerate slivers
@settings(max_examples=60, deadline=None)
@given(
    pts=st.lists(st.tuples(st.floats(-5, 5), st.floats(-5, 5)), min_size=3, max_size=12),
    res=st.floats(0.05, 1.0),
)
def test_scanline_fill_equals_centre_rule(pts: list[tuple[float, float]], res: float) -> None:
    try:
        valid = shapely.make_valid(Polygon(pts))
    except shapely.errors.GEOSException:  # GEOS cannot repair some degenerate rings (points 1e-133 apart)
        assume(False)
    parts = [p for p in shapely.get_parts(valid) if isinstance(p, Polygon)]
    poly = shapely.MultiPolygon(parts)
    assume(poly.area > 1e-3)
    frame = Frame(-6.0, -6.0, res, math.ceil(12 / res), math.ceil(12 / res))
    grid = np.zeros((frame.height, frame.width), np.int8)

    def op(block: np.ndarray, mask: np.ndarray) -> None:
        block[mask] = 1

    for part in shapely.get_parts(poly):
        if isinstance(part, Polygon):
            fill_polygon(grid, frame, part, op)
    xs = frame.x0 + (np.arange(frame.width) + 0.5) * res
    ys = frame.y0 + (np.arange(frame.height) + 0.5) * res
    x, y = np.meshgrid(xs, ys)
    inside = shapely.contains_xy(poly, x, y)
    near_edge = shapely.distance(poly.boundary, shapely.points(x, y)) < 1e-9
    assert np.array_equal((grid == 1)[~near_edge], inside[~near_edge])


@settings(max_examples=80, deadline=None)
@given(
    seg=st.tuples(st.floats(0.1, 9.9), st.floats(0.1, 9.9), st.floats(0.1, 9.9), st.floats(0.1, 9.9)),
    res=st.sampled_from([0.1, 0.25, 0.5, 1.0, 0.3]),
)
def test_supercover_is_a_4_connected_path_through_both_ends(seg: tuple[float, ...], res: float) -> None:
    frame = Frame(0.0, 0.0, res, math.ceil(10 / res), math.ceil(10 / res))
    rows, cols = supercover_cells(np.array([seg]), frame)
    grid = np.zeros((frame.height, frame.width), bool)
    grid[rows, cols] = True

    def touching(x: float, y: float) -> list[tuple[int, int]]:
        """Cells whose closed square holds (x, y): two or four when it lies on a cell border."""
        cols_ = {min(max(int(np.floor(x / res + d)), 0), frame.width - 1) for d in (-1e-9, 1e-9)}
        rows_ = {min(max(int(np.floor(y / res + d)), 0), frame.height - 1) for d in (-1e-9, 1e-9)}
        return [(r, c) for r in rows_ for c in cols_]

    starts = [cell for cell in touching(seg[0], seg[1]) if grid[cell]]
    ends = [cell for cell in touching(seg[2], seg[3]) if grid[cell]]
    assert starts and ends, "the drawn line must cover a cell at each end point"
    reached = reachable(grid, starts[0])  # 4-connected: no diagonal moves
    assert any(reached[cell] for cell in ends)


def test_line_segments_of_rings_and_lines() -> None:
    segs = line_segments([box(0, 0, 1, 1).exterior, LineString([(0, 0), (2, 0), (2, 2)])])
    assert segs.shape == (6, 4)


# --- rooms --------------------------------------------------------------------------------------------


@settings(max_examples=40, deadline=None)
@given(
    w=st.floats(0.6, 8.0),
    h=st.floats(0.6, 8.0),
    x0=st.floats(-50, 50),
    y0=st.floats(-50, 50),
    res=st.sampled_from([0.02, 0.05, 0.1, 0.13, 0.25]),
    thick=st.sampled_from([0.0, 0.02, 0.1, 0.3]),
)
def test_rectangle_room(w: float, h: float, x0: float, y0: float, res: float, thick: float) -> None:
    geom = box(x0, y0, x0 + w, y0 + h)
    grid = rasterise_storey(building([room("R", geom)]), "F1", res, RasterOptions(wall_thickness=thick))
    free = grid.data == 0
    # free only inside the room, and everything deeper than the wall band is free
    assert not (free & ~cells_in(grid, geom)).any()
    band = max(thick / 2, res) + res
    assert free[deep_inside(grid, geom, band)].all()
    n_cols, n_rows = (w - thick) / res, (h - thick) / res
    upper = (w / res + 1) * (h / res + 1)
    lower = max(0.0, n_cols - 3) * max(0.0, n_rows - 3)
    assert lower <= free.sum() <= upper
    # the wall ring is closed: free cells never touch unknown ones (8-neighbourhood)
    unknown = grid.data == -1
    seed = np.zeros_like(unknown)
    seed[0, 0] = True
    assert not (flood(unknown | free, seed) & free).any()
    assert set(np.unique(grid.data).tolist()) <= {-1, 0, 100}


def test_hole_is_respected() -> None:
    outer = Polygon([(0, 0), (6, 0), (6, 6), (0, 6)], [[(2, 2), (4, 2), (4, 4), (2, 4)]])
    grid = rasterise_storey(building([room("R", outer)]), "F1", 0.1)
    hole_core = cells_in(grid, box(2.3, 2.3, 3.7, 3.7))
    assert (grid.data[hole_core] == -1).all()  # the hole is not part of the building
    assert (grid.data[cells_in(grid, box(0.3, 0.3, 1.7, 5.7))] == 0).all()
    ring = cells_in(grid, box(1.9, 1.9, 4.1, 4.1)) & ~cells_in(grid, box(2.1, 2.1, 3.9, 3.9))
    assert (grid.data[ring] == 100).mean() > 0.9  # the hole's edge is walled


def test_non_navigable_and_outside_modes() -> None:
    cells = [room("R", box(0, 0, 5, 5)), room("P", box(2, 2, 3, 3), CellKind.NON_NAVIGABLE)]
    grid = rasterise_storey(building(cells), "F1", 0.1)
    assert (grid.data[cells_in(grid, box(2.05, 2.05, 2.95, 2.95))] == 100).all()
    assert grid.data[0, 0] == -1
    closed = rasterise_storey(building(cells), "F1", 0.1, RasterOptions(outside="occupied"))
    assert closed.data[0, 0] == 100
    assert (closed.data == 0).sum() == (grid.data == 0).sum()


# --- walls and doors ---------------------------------------------------------------------------------

two_rooms_params = {
    "split": st.floats(2.0, 4.0),
    "res": st.sampled_from([0.01, 0.03, 0.05, 0.1, 0.17, 0.25]),
    "thick": st.sampled_from([0.0, 0.01, 0.05, 0.1, 0.2]),
    "shift": st.floats(-3, 3),
}


def _two_rooms(split: float, shift: float) -> tuple[Polygon, Polygon]:
    return box(shift, shift, shift + split, shift + 3), box(shift + split, shift, shift + 6, shift + 3)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(**two_rooms_params)
def test_shared_edge_without_door_separates(split: float, res: float, thick: float, shift: float) -> None:
    a, b = _two_rooms(split, shift)
    grid = rasterise_storey(building([room("A", a), room("B", b)]), "F1", res, RasterOptions(wall_thickness=thick))
    free = grid.data == 0
    seed_a, seed_b = cells_in(grid, a.buffer(-0.4)), cells_in(grid, b.buffer(-0.4))
    assert seed_a.any() and seed_b.any()
    assert not (flood(free, seed_a) & seed_b).any()


def _door_region(grid: OccupancyGrid, x: float, y0: float, y1: float, reach: float) -> np.ndarray:
    return cells_in(grid, box(x - reach, y0 - reach, x + reach, y1 + reach))


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(door_at=st.floats(0.6, 2.0), **two_rooms_params)
def test_door_boundary_connects_only_through_the_door(
    split: float, res: float, thick: float, shift: float, door_at: float
) -> None:
    a, b = _two_rooms(split, shift)
    x, y0, y1 = shift + split, shift + door_at, shift + door_at + 0.9
    door = Boundary("door", True, LineString([(x, y0), (x, y1)]), "F1")
    grid = rasterise_storey(
        building([room("A", a), room("B", b)], [door]), "F1", res, RasterOptions(wall_thickness=thick)
    )
    free = grid.data == 0
    seed_a, seed_b = cells_in(grid, a.buffer(-0.4)), cells_in(grid, b.buffer(-0.4))
    assert (flood(free, seed_a) & seed_b).any()
    # the full width of the door is open (every cell between the door's ends on the wall line)
    span = cells_in(grid, box(x - res, y0 + res, x + res, y1 - res))
    assert free[span].all()
    blocked = free & ~_door_region(grid, x, y0, y1, thick / 2 + 2 * res)
    assert not (flood(blocked, seed_a) & seed_b).any()


@settings(max_examples=30, deadline=None)
@given(
    res=st.sampled_from([0.02, 0.05, 0.1, 0.2, 0.3]),
    thick=st.sampled_from([0.0, 0.05, 0.1, 0.2]),
    gap=st.sampled_from([0.0, 0.1, 0.25]),
)
def test_door_cell_connects_only_through_the_door(res: float, thick: float, gap: float) -> None:
    a = box(0, 0, 3, 3)
    b = box(3 + gap, 0, 6, 3)
    door = box(3 - 0.05, 1.0, 3 + gap + 0.05, 1.9) if gap else box(2.9, 1.0, 3.1, 1.9)
    cells = [room("A", a), room("B", b), room("D", door, CellKind.CONNECTION)]
    grid = rasterise_storey(building(cells), "F1", res, RasterOptions(wall_thickness=thick))
    free = grid.data == 0
    seed_a, seed_b = cells_in(grid, a.buffer(-0.4)), cells_in(grid, b.buffer(-0.4))
    assert (flood(free, seed_a) & seed_b).any()
    mid = 3 + gap / 2
    blocked = free & ~_door_region(grid, mid, 1.0, 1.9, gap / 2 + thick / 2 + 2 * res)
    assert not (flood(blocked, seed_a) & seed_b).any()


def test_thin_wall_at_coarse_resolution_is_one_cell() -> None:
    a, b = box(0, 0, 3.05, 3), box(3.05, 0, 6, 3)
    grid = rasterise_storey(building([room("A", a), room("B", b)]), "F1", 0.5, RasterOptions(wall_thickness=0.05))
    row = grid.data[grid.height // 2]
    inner = row[(row != -1)]
    assert (inner == 100).sum() == 3  # left wall, shared wall, right wall: one cell each


def test_door_is_free_on_the_preview_of_real_doors() -> None:
    # doors on the outside wall open onto the unknown: the wall is cut, the room stays closed elsewhere
    a = box(0, 0, 4, 3)
    door = Boundary("exit", True, LineString([(4, 1), (4, 2)]), "F1")
    grid = rasterise_storey(building([room("A", a)], [door]), "F1", 0.1)
    assert grid.value_at(4.0, 1.5) == 0
    assert grid.value_at(4.0, 2.5) == 100


# --- budgets and validation -------------------------------------------------------------------------


def test_budget_error_names_a_resolution_that_fits() -> None:
    b = building([room("R", box(0, 0, 200, 200))])
    with pytest.raises(GridTooLarge) as info:
        plan_storey(b, "F1", 0.005, RasterOptions(max_cells=4_000_000))
    msg = str(info.value)
    assert "0.005" in msg and "x" in msg
    assert info.value.limit == 4_000_000 and info.value.cells > 4_000_000
    suggested = info.value.suggested_resolution
    assert f"{suggested:g}" in info.value.hint
    frame = plan_storey(b, "F1", suggested, RasterOptions(max_cells=4_000_000))
    assert frame.width * frame.height <= 4_000_000
    assert suggested <= 0.11  # the finest that fits, not just any


def test_nav2_side_limit() -> None:
    b = building([room("R", box(0, 0, 400, 10))])
    with pytest.raises(GridTooLarge, match="32767") as info:
        plan_storey(b, "F1", 0.01)
    assert info.value.limit == 32767 and info.value.cells > 32767
    suggested = info.value.suggested_resolution
    assert plan_storey(b, "F1", suggested).width <= 32767
    assert plan_storey(b, "F1", 0.01, RasterOptions(allow_large=True)).width > 32767


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), 0.0, -0.1, "x"])
def test_bad_resolution_rejected(bad: object) -> None:
    with pytest.raises(OccupancyError, match="resolution"):
        rasterise_storey(building([room("R", box(0, 0, 1, 1))]), "F1", bad)  # type: ignore[arg-type]


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -0.1])
def test_bad_wall_thickness_rejected(bad: float) -> None:
    with pytest.raises(OccupancyError, match="wall thickness"):
        rasterise_storey(building([room("R", box(0, 0, 1, 1))]), "F1", 0.1, RasterOptions(wall_thickness=bad))


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # shapely warns while building the NaN ring
def test_non_finite_coordinates_rejected() -> None:
    bad = Polygon([(0, 0), (1, 0), (float("nan"), 1)])
    with pytest.raises(OccupancyError, match="R"):
        rasterise_storey(building([room("R", bad)]), "F1", 0.1)


def test_unknown_storey_and_empty_storey() -> None:
    b = building([room("R", box(0, 0, 1, 1))], storeys=["F1", "F2"])
    with pytest.raises(OccupancyError, match="F9"):
        rasterise_storey(b, "F9", 0.1)
    with pytest.raises(OccupancyError, match="F2"):
        rasterise_storey(b, "F2", 0.1)


# --- whole buildings ---------------------------------------------------------------------------------


def test_rasterise_all_storeys_meta_and_progress() -> None:
    cells = [room("A", box(0, 0, 5, 4), storey="F1"), room("B", box(10, 10, 12, 13), storey="F2")]
    seen: list[Progress] = []
    grids = rasterise(building(cells), 0.1, progress=seen.append)
    assert list(grids) == ["F1", "F2"]
    f1 = grids["F1"]
    assert f1.meta["storey"] == "F1" and f1.meta["source_sha256"] == "ab" * 32
    assert f1.meta["translation"] == [10.0, 20.0] and f1.meta["rotation"] == 15.0
    assert f1.meta["lla_origin"] == [45.8, 9.09, -151.3] and f1.meta["wall_thickness"] == 0.1
    assert f1.meta["unit"] == "m"
    # margin = wall + 1 cell, rounded outward; origin on the resolution lattice
    assert f1.origin[0] == pytest.approx(-0.2) and f1.origin[1] == pytest.approx(-0.2)
    assert f1.value_at(2.5, 2.0) == 0
    assert grids["F2"].value_at(11.0, 11.5) == 0
    dones = [p.fraction for p in seen]
    assert dones == sorted(dones) and seen[-1].fraction == 1.0  # type: ignore[type-var]
    assert {p.step for p in seen} == {"rasterise"} and any(p.message == "storey F2" for p in seen)
    assert any(0.4 < f < 0.6 for f in dones)  # type: ignore[operator]  # F1 ends half-way
    assert list(rasterise(building(cells), 0.1, storeys=["F2"])) == ["F2"]


def test_oversize_storey_fails_before_any_work() -> None:
    cells = [room("A", box(0, 0, 5, 4), storey="F1"), room("B", box(0, 0, 500, 500), storey="F2")]
    calls: list[Progress] = []
    with pytest.raises(GridTooLarge, match="F2"):
        rasterise(building(cells), 0.01, RasterOptions(max_cells=10_000_000), progress=calls.append)
    assert calls == []


@pytest.mark.parametrize("outside", ["unknown", "occupied"])
def test_door_line_across_a_gap_between_rooms(outside: str) -> None:
    # rooms 0.2 m apart (the wall itself is not modelled), door boundary in the middle of the gap
    a, b = box(0, 0, 3, 3), box(3.2, 0, 6, 3)
    door = Boundary("d", True, LineString([(3.1, 1.0), (3.1, 1.9)]), "F1")
    grid = rasterise_storey(building([room("A", a), room("B", b)], [door]), "F1", 0.05, RasterOptions(outside=outside))
    free = grid.data == 0
    seed_a, seed_b = cells_in(grid, a.buffer(-0.4)), cells_in(grid, b.buffer(-0.4))
    assert (flood(free, seed_a) & seed_b).any()
    gap = cells_in(grid, box(3.0, 2.2, 3.2, 2.8))  # beside the door: wall, never free
    assert gap.any() and not free[gap].any()
    far = grid.data[0, 0]
    assert far == (-1 if outside == "unknown" else 100)
