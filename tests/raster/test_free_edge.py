"""The free space's outer edge is a wall: no free cell beside an unknown one, except in front of an entrance.

Nav2 plans through unknown cells by default, so a free cell touching the unknown outside is a way out of
the building nobody drew. Seen on real files: door cells standing out of the outer wall as free bars
into the unknown (TopologyEditor test4), door bands and graph lanes across gaps between rooms (PNU 313,
PNU abc), openings at a wall's end reaching past the corner (PNU abc). Ways out stay open: an
AnchorSpace, or a door the file gives on the outer wall (by type or name; rule 4 shuts the guessed ones).
Plans in the 1.0.x (State/Transition) and 2.0 (Node/Edge) spellings, builders from test_access_rules.
"""

from __future__ import annotations

import glob
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from pmk_nb.indoorgml import Building, CellKind, read_building
from pmk_nb.openings import plan_openings
from pmk_nb.raster.scanline import Frame
from pmk_nb.raster.seal import seal_outside
from pmk_nb.raster.storey import rasterise_storey
from tests.access.test_access_rules import RES, _boundary, _cell, _graph, _plan
from tests.shared_data import INDOORGML_DATA

SPELLINGS = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
ROOM = _cell("A", (0, 0, 5, 4))
REPO = Path(__file__).resolve().parents[2]


def _free_on_unknown(grid: OccupancyGrid) -> np.ndarray:
    """(row, col) of FREE cells with an UNKNOWN cell among their 8 neighbours."""
    d = grid.data
    pad = np.pad(d == UNKNOWN, 1)
    near = np.zeros(d.shape, dtype=bool)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            near |= pad[1 + dr : 1 + dr + d.shape[0], 1 + dc : 1 + dc + d.shape[1]]
    return np.argwhere((d == FREE) & near)


def _entrances(b: Building, storey: str) -> list[shapely.Geometry]:
    """The file's ways out on ``storey``: AnchorSpace cells, and door boundaries with no cell 0.3 m off
    one side of their middle (found here by plain point probes, not the rasteriser's rule)."""
    cells = [c.footprint for c in b.cells_of(storey)]
    ways = [c.footprint for c in b.cells_of(storey) if c.kind is CellKind.ANCHOR]
    for door in b.doors_of(storey):
        line = door.geometry
        if line is None or line.geom_type != "LineString" or line.length == 0:
            continue
        (x0, y0), (x1, y1) = line.coords[0], line.coords[-1]
        mid, n = line.interpolate(0.5, normalized=True), np.array([y0 - y1, x1 - x0]) / line.length * 0.3
        probes = [shapely.Point(mid.x + k * n[0], mid.y + k * n[1]) for k in (1, -1)]
        if not all(any(c.contains(p) for c in cells) for p in probes):
            ways.append(line)
    return ways


def _leaks(b: Building, storey: str, grid: OccupancyGrid, near: float = 1.5) -> int:
    """Free cells on unknown farther than ``near`` metres from every entrance (the gap a door line may
    bridge, 1 m, plus the wall and a few cells)."""
    cells = _free_on_unknown(grid)
    if len(cells) == 0:
        return 0
    x0, y0, _ = grid.origin
    pts = shapely.points(x0 + (cells[:, 1] + 0.5) * grid.resolution, y0 + (cells[:, 0] + 0.5) * grid.resolution)
    ways_out = _entrances(b, storey)
    if not ways_out:
        return len(cells)
    return int(np.count_nonzero(shapely.distance(pts, shapely.union_all(ways_out)) > near))


def _convert(path: Path) -> tuple[Building, OccupancyGrid]:
    b = read_building(path, unit="m")
    return b, rasterise_storey(b, b.storeys[0].name, RES)


@SPELLINGS
@pytest.mark.parametrize("tag", ["navi:ConnectionSpace", "CellSpace"], ids=["connection", "named-door"])
def test_door_cell_standing_out_is_walled_at_its_outer_end(tmp_path: Path, v2: bool, tag: str) -> None:
    door = _cell("D", (2, 4, 3, 4.3), tag, name="Door 1")  # in the outer wall, nothing beyond it
    _, grid = _convert(_plan(tmp_path, ROOM + door, _graph([("A", "D")], v2=v2), v2=v2))
    assert len(_free_on_unknown(grid)) == 0
    assert grid.value_at(2.5, 4.15) == FREE and grid.value_at(2.5, 3.9) == FREE  # the door is still there
    assert grid.value_at(2.5, 4.35) == OCCUPIED  # its outer end is wall, no free bar into the unknown


@SPELLINGS
def test_door_cell_without_graph_is_walled_at_its_outer_end(tmp_path: Path, v2: bool) -> None:
    door = _cell("D", (2, 4, 3, 4.3), "navi:ConnectionSpace")
    _, grid = _convert(_plan(tmp_path, ROOM + door + _cell("C", (6, 0, 9, 4)), v2=v2))
    assert len(_free_on_unknown(grid)) == 0 and grid.value_at(2.5, 4.35) == OCCUPIED


@SPELLINGS
def test_entrance_cell_stays_open_to_the_outside(tmp_path: Path, v2: bool) -> None:
    door = _cell("D", (2, 4, 3, 4.3), "navi:AnchorSpace")
    b, grid = _convert(_plan(tmp_path, ROOM + door, _graph([("A", "D")], v2=v2), v2=v2))
    assert grid.value_at(2.5, 4.35) == FREE  # the way out is not walled
    assert len(_free_on_unknown(grid)) > 0 and _leaks(b, b.storeys[0].name, grid, near=0.3) == 0


@SPELLINGS
@pytest.mark.parametrize("tag", ["navi:AnchorBoundary", "navi:ConnectionBoundary"], ids=["anchor", "connection"])
def test_door_in_the_facade_stays_open_but_only_there(tmp_path: Path, v2: bool, tag: str) -> None:
    """A door the file gives on the outer wall opens onto the outside (rule 4); the seal keeps that
    opening, and nothing else, next to unknown."""
    door = _boundary("D1", ((0, 1), (0, 2)), tag)
    b, grid = _convert(_plan(tmp_path, ROOM + _cell("C", (6, 0, 9, 4)), _graph([("A", "C")], v2=v2), door, v2=v2))
    assert grid.value_at(-0.03, 1.5) == FREE and grid.value_at(-0.03, 0.5) != FREE
    assert len(_free_on_unknown(grid)) > 0 and _leaks(b, b.storeys[0].name, grid, near=0.3) == 0


@SPELLINGS
def test_door_across_a_wide_gap_is_walled_along_its_sides(tmp_path: Path, v2: bool) -> None:
    rooms = ROOM + _cell("B", (5.8, 0, 10.8, 4))  # 0.8 m between the rooms: wider than a wall left out
    door = _boundary("D1", ((5.4, 1.5), (5.4, 2.5)), "navi:ConnectionBoundary")
    _, grid = _convert(_plan(tmp_path, rooms, _graph([("A", "B")], v2=v2), door, v2=v2))
    assert grid.value_at(5.4, 2.0) == FREE  # the door still joins the rooms
    assert len(_free_on_unknown(grid)) == 0


@SPELLINGS
def test_lane_across_a_gap_is_walled_along_its_sides(tmp_path: Path, v2: bool) -> None:
    """PNU abc F2: a stair landing 1.5 m from the corridor, linked by the graph with nothing drawn between:
    the lane laid across the gap was filled wider than the walls along it (29 free cells on unknown)."""
    rooms = ROOM + _cell("B", (6.5, 0, 11.5, 4))
    b, grid = _convert(_plan(tmp_path, rooms, _graph([("A", "B")], v2=v2), v2=v2))
    [lane] = plan_openings(b, b.storeys[0].name).openings
    assert lane.rule == "bridge" and lane.path is not None
    mid = lane.path.interpolate(0.5, normalized=True)
    assert grid.value_at(mid.x, mid.y) == FREE  # the lane joins the rooms
    assert len(_free_on_unknown(grid)) == 0


SHARED = sorted(glob.glob(str(INDOORGML_DATA / "*.gml"))) + sorted(glob.glob(str(REPO / "sample_maps" / "*.gml")))


@pytest.mark.slow
@pytest.mark.parametrize("path", SHARED, ids=[Path(p).stem for p in SHARED])
def test_shared_files_never_put_free_beside_unknown(path: str) -> None:
    """Before this rule: InEditor example 2 storey 1 had 265 such cells (a 13 m façade boundary), PNU 201
    storey 2 438, PNU 313 doors subset 88 (door bands across gaps), PNU abc F2 32 and F4 5."""
    b = read_building(path)
    for s in b.storeys:
        grid = rasterise_storey(b, s.name, 0.05)
        assert _leaks(b, s.name, grid) == 0, f"{s.name}: free cells beside unknown"


_ROOM_BOX = st.tuples(st.integers(0, 3), st.integers(0, 2), st.integers(2, 4), st.integers(2, 3))


@pytest.mark.slow
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    gaps=st.lists(st.sampled_from([0.0, 0.2, 0.8, 1.5]), min_size=2, max_size=2),
    doors=st.lists(
        st.tuples(st.integers(0, 2), st.sampled_from(["cell", "line", "anchor"]), st.booleans()), max_size=4
    ),
    gap_doors=st.lists(st.booleans(), min_size=2, max_size=2),
    res=st.sampled_from([0.05, 0.1]),
    v2=st.booleans(),
)
def test_random_plans_never_put_free_beside_unknown(
    tmp_path: Path, gaps: list[float], doors: list, gap_doors: list[bool], res: float, v2: bool
) -> None:
    """Three rooms in a row with random gaps (door lines across some), and door cells, door lines and
    entrances on their outer walls: the only free cells beside unknown are in front of entrances."""
    xs, x, cells, bnds = [], 0.0, "", ""
    for i in range(3):
        xs.append(x)
        cells += _cell(f"R{i}", (x, 0, x + 4, 3))
        if i < 2 and gap_doors[i]:  # a door line in the middle of the gap to the next room
            mid = x + 4 + gaps[i] / 2
            bnds += _boundary(f"G{i}", ((mid, 1.0), (mid, 2.0)), "navi:ConnectionBoundary")
        x += 4 + (gaps[i] if i < 2 else 0)
    for k, (room, kind, top) in enumerate(doors):
        x0 = xs[room] + 0.5 + k * 0.8
        y = 3.0 if top else 0.0
        if kind == "line":
            bnds += _boundary(f"B{k}", ((x0, y), (x0 + 0.6, y)), "navi:ConnectionBoundary")
        else:
            tag = "navi:AnchorSpace" if kind == "anchor" else "navi:ConnectionSpace"
            cells += _cell(f"D{k}", (x0, y, x0 + 0.6, y + 0.25) if top else (x0, y - 0.25, x0 + 0.6, y), tag)
    pairs = [("R0", "R1"), ("R1", "R2")] + [
        (f"R{r}", f"D{k}") for k, (r, kind, _) in enumerate(doors) if kind != "line"
    ]
    b = read_building(_plan(tmp_path, cells, _graph(pairs, v2=v2), bnds, v2=v2), unit="m")
    grid = rasterise_storey(b, b.storeys[0].name, res)
    assert _leaks(b, b.storeys[0].name, grid, near=0.3 + res) == 0


@pytest.mark.slow
def test_seal_is_the_plain_8_neighbour_rule_across_strips() -> None:
    """The strip-wise seal equals a whole-grid dilation, also where strips are one to three rows tall
    (rows wider than the 64 Ki-cell strip) and across the halo rows."""
    rng = np.random.default_rng(7)
    for trial in range(300):
        h, w = (int(rng.integers(1, 9)), int(rng.integers(20_000, 70_000))) if trial % 2 else rng.integers(1, 40, 2)
        grid = rng.choice(np.array([UNKNOWN, FREE, OCCUPIED, 101], dtype=np.int8), size=(h, w), p=[0.5, 0.2, 0.2, 0.1])
        pad = np.pad(grid == FREE, 1)
        near = np.zeros(grid.shape, dtype=bool)
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                near |= pad[1 + dr : 1 + dr + h, 1 + dc : 1 + dc + w]
        want = np.where(near & (grid == UNKNOWN), OCCUPIED, grid)
        seal_outside(grid, Frame(0.0, 0.0, 1.0, w, h), [], UNKNOWN, (101,))
        assert (grid == want).all(), (trial, h, w)
