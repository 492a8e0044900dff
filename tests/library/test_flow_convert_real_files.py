"""Flow: every real IndoorGML file goes through the maps folder (import -> convert -> map files) and
the maps read back say what the building says.

Test points are derived from the Building model, not hard-coded: deep inside the largest room is
free, on a wall between two cells (away from doors) is occupied, the grid corner in the margin is
unknown. The sample clinic (layout in sample_maps/README.md) also checks that rooms sharing a wall
are connected only through their doors.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import shapely
from shapely.geometry import Point
from shapely.ops import polylabel

from pmk_nb.defaults import DEFAULT_WALL_THICKNESS
from pmk_nb.indoorgml import Building, Cell, read_building
from pmk_nb.library.folder import MapsFolder
from pmk_nb.openings import plan_openings
from pmk_nb.rosmap import read_map
from tests.helpers import cells_in, reachable
from tests.shared_data import INDOORGML_DATA

SHARED = INDOORGML_DATA
SAMPLES = Path(__file__).resolve().parents[2] / "sample_maps"
FILES = sorted(SHARED.glob("*.gml")) + sorted(SAMPLES.glob("*.gml"))
WALL = DEFAULT_WALL_THICKNESS
MAX_SIDE = 1000  # cells: keeps every grid small enough for a fast test


def test_the_real_files_are_there() -> None:
    assert len(sorted(SHARED.glob("*.gml"))) >= 8, f"shared IndoorGML samples missing in {SHARED}"
    assert {p.name for p in SAMPLES.glob("*.gml")} >= {"clinic_floor.gml", "clinic_two_storeys.gml"}


def sensible_resolution(building: Building) -> float:
    """0.05 m for metre-sized buildings; coarser (a round number) so no side exceeds MAX_SIDE cells."""
    x0, y0, x1, y1 = shapely.union_all([c.footprint for c in building.cells.values()]).bounds
    extent = max(x1 - x0, y1 - y0)
    res = 0.05
    while extent / res > MAX_SIDE:
        res = round(res * 2 if str(res)[-1] == "5" else res * 2.5, 6)  # 0.05 0.1 0.25 0.5 1 2.5 ...
    return res


def parts(geom: Any) -> list[Any]:
    return [g for g in shapely.get_parts(geom) if isinstance(g, shapely.Polygon) and not g.is_empty]


def rooms_of(cells: list[Cell]) -> list[Cell]:
    return sorted((c for c in cells if c.kind.is_free and not c.kind.is_door), key=lambda c: -c.footprint.area)


def door_geometry(building: Building, storey: str, cells: list[Cell]) -> Any:
    """Door cells, door boundaries and the openings the navigation graph asks for (all may be open)."""
    geoms = [c.footprint for c in cells if c.kind.is_door]
    geoms += [b.geometry for b in building.doors_of(storey) if b.geometry is not None and not b.geometry.is_empty]
    geoms += [s for o in plan_openings(building, storey).openings for s in o.segments]
    return shapely.union_all(geoms) if geoms else None


def free_point(cells: list[Cell], res: float) -> Point | None:
    """Pole of inaccessibility of the largest room whose pole is well clear of every cell edge."""
    rings = shapely.union_all([c.footprint.boundary for c in cells])
    blocked = [c.footprint for c in cells if not c.kind.is_free]
    for cell in rooms_of(cells):
        for poly in sorted(parts(cell.footprint), key=lambda p: -p.area):
            p = polylabel(poly, tolerance=res / 4)
            if p.distance(rings) > WALL / 2 + 2 * res and not any(b.covers(p) for b in blocked):
                return p
    return None


def wall_point(cells: list[Cell], doors: Any, res: float) -> tuple[Point, str] | None:
    """A point on an edge two rooms share (else on a room's outer edge), away from any door."""
    rooms = rooms_of(cells)
    shared: list[Any] = []
    tol = max(0.01, res / 4)
    for i, a in enumerate(rooms):
        for b in rooms[i + 1 :]:
            if a.footprint.distance(b.footprint) > tol:
                continue
            common = a.footprint.boundary.intersection(b.footprint.buffer(tol))
            shared += [g for g in shapely.get_parts(common) if isinstance(g, shapely.LineString)]
    edges = [(g, "shared") for g in sorted(shared, key=lambda g: -g.length) if g.length > 4 * res]
    edges += [(r.footprint.boundary, "outer") for r in rooms]
    clear = WALL / 2 + 2 * res
    for line, how in edges:
        for frac in (0.5, 0.3, 0.7, 0.15, 0.85, 0.05, 0.95):
            p = line.interpolate(frac, normalized=True)
            if doors is None or p.distance(doors) > clear:
                return p, how
    return None


def value(grid: Any, p: Point) -> int | None:
    return grid.value_at(p.x, p.y)


@pytest.mark.slow
@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_real_file_imports_and_converts(tmp_path: Path, path: Path) -> None:
    folder = MapsFolder(tmp_path / "ALMA_MAPS")
    entry = folder.import_file(path)
    building = read_building(entry.source)
    res = sensible_resolution(building)
    maps = folder.convert(entry.name, res)

    assert sorted(g.storey for g in maps) == sorted(s.name for s in building.storeys)
    assert folder.entry(entry.name).status == "converted"
    for gm in maps:
        assert gm.storey is not None
        grid = read_map(gm.yaml)  # through the files, as the chair's map server reads them
        assert grid.meta["storey"] == gm.storey and grid.meta["map"] == entry.name
        assert grid.resolution == pytest.approx(res)
        assert (grid.width, grid.height) == (gm.width, gm.height)
        assert gm.preview is not None and gm.preview.is_file()
        cells = building.cells_of(gm.storey)
        where = f"{path.name} storey {gm.storey} at {res} m"

        p = free_point(cells, res)
        assert p is not None, f"{where}: no room large enough for a free test point"
        assert value(grid, p) == 0, f"{where}: {p} deep inside a room is not free"

        found = wall_point(cells, door_geometry(building, gm.storey, cells), res)
        assert found is not None, f"{where}: no wall away from doors"
        w, how = found
        assert value(grid, w) == 100, f"{where}: {w} on a {how} wall is not occupied"

        footprint = shapely.union_all([c.footprint for c in cells])
        corners = [grid.cell_center(c, r) for c in (0, grid.width - 1) for r in (0, grid.height - 1)]
        outside = [Point(xy) for xy in corners if footprint.distance(Point(xy)) > WALL / 2 + res]
        assert outside, f"{where}: no grid corner lies in the margin"
        for q in outside:
            assert value(grid, q) == -1, f"{where}: corner {q} outside every cell is not unknown"


# ---------------------------------------------------------------- the clinic: walls and doors
@pytest.mark.parametrize("name", ["clinic_floor.gml", "clinic_two_storeys.gml"])
def test_clinic_rooms_connect_only_through_doors(tmp_path: Path, name: str) -> None:
    folder = MapsFolder(tmp_path)
    entry = folder.import_file(SAMPLES / name)
    building = read_building(entry.source)
    for gm in folder.convert(entry.name, 0.05):
        assert gm.storey is not None
        grid = read_map(gm.yaml)
        suffix = "" if len(building.storeys) == 1 else f"_{gm.storey}"
        cells = {c.id.removesuffix(suffix): c for c in building.cells_of(gm.storey)}
        obstacles = shapely.union_all([c.footprint for c in cells.values() if not c.kind.is_free])

        def at(
            cell_id: str, cells: dict[str, Cell] = cells, grid: Any = grid, obstacles: Any = obstacles
        ) -> tuple[int, int]:
            """(row, col) of the point of the cell farthest from its edges and obstacles (desk, bed)."""
            [room] = sorted(parts(cells[cell_id].footprint.difference(obstacles)), key=lambda g: -g.area)[:1]
            p = polylabel(room, tolerance=0.01)
            col, row = grid.world_to_cell(p.x, p.y)
            return row, col

        # R1 and R2 share the edge x = 10: a wall, occupied along its length
        edge = cells["R1"].footprint.boundary.intersection(cells["R2"].footprint.buffer(0.01))
        assert edge.length == pytest.approx(5.9, abs=0.05)
        for frac in (0.1, 0.5, 0.9):
            p = edge.interpolate(frac, normalized=True)
            assert grid.value_at(p.x, p.y) == 100
        # each door cell is free and every room reaches every other one
        for i in range(1, 7):
            door = polylabel(cells[f"D{i}"].footprint, tolerance=0.01)
            assert grid.value_at(door.x, door.y) == 0, f"door D{i} closed"
        free = grid.data == 0
        everywhere = reachable(free, at("R2"))
        for room in ("R1", "R3", "R4", "R5", "R6", "COR"):
            assert everywhere[at(room)], f"{room} not reachable from R2 on storey {gm.storey}"
        # close R1's door: R1 is cut off (its shared wall with R2 has no gap), the rest stays connected
        closed = free & ~cells_in(grid, cells["D1"].footprint.buffer(WALL / 2 + 2 * grid.resolution))
        from_r2 = reachable(closed, at("R2"))
        assert not from_r2[at("R1")]
        assert from_r2[at("COR")] and from_r2[at("R4")]
        from_r1 = reachable(closed, at("R1"))
        assert not from_r1[at("R2")] and not from_r1[at("COR")]
