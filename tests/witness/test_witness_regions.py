"""The storey labelled once (:mod:`pmk_nb.witness.regions`) decides only what it can prove: with it or
without it (every pair judged in its own window), the witness finds the same things on any map.

The clinic is converted once; random faults are painted into its grid (rooms opened into each other,
doors drawn shut or narrow, walls freed, obstacles dropped); each map is judged both ways.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from pmk_nb.indoorgml import Building, read_building
from pmk_nb.indoorgml.model import Cell, CellKind
from pmk_nb.library.convert import convert_plan
from pmk_nb.rosmap import read_map
from pmk_nb.witness import storey as witness_storey_module
from pmk_nb.witness import witness_grid

SAMPLES = Path(__file__).resolve().parents[2] / "sample_maps"
CHAIR = 0.7


@pytest.fixture(scope="module")
def plans(tmp_path_factory: pytest.TempPathFactory) -> list[tuple[Building, OccupancyGrid]]:
    out = []
    for name in ("clinic_floor.gml", "clinic_two_storeys.gml"):
        folder = tmp_path_factory.mktemp(name.split(".")[0])
        result = convert_plan(SAMPLES / name, folder, "m")
        building = read_building(SAMPLES / name)
        out += [(building, read_map(m.files.yaml)) for m in result.maps]
    return [*out, _overlapped(*out[0])]


def _overlapped(building: Building, grid: OccupancyGrid) -> tuple[Building, OccupancyGrid]:
    """The clinic with two cells that claim floor of others: one across two rooms' wall, one inside a
    room (pixels claimed twice are owned by neither: the graph must still rule out only what it can)."""
    storey = building.storeys[0]
    rooms = [building.cells[c] for c in storey.cell_ids if building.cells[c].kind.is_free][:2]
    a, b = (r.footprint for r in rooms)
    across = shapely.box(*a.union(b).envelope.buffer(-0.5).bounds).intersection(a.union(b).buffer(0.3))
    inside = shapely.box(*a.centroid.buffer(0.8).bounds)
    extra = {
        "ACROSS": Cell("ACROSS", CellKind.GENERAL, across, storey.name, name="across"),
        "INSIDE": Cell("INSIDE", CellKind.GENERAL, inside, storey.name, name="inside"),
    }
    cells = {**building.cells, **extra}
    storeys = [replace(storey, cell_ids=[*storey.cell_ids, *extra]), *building.storeys[1:]]
    return replace(building, cells=cells, storeys=storeys), grid


def _findings(building: Building, grid: OccupancyGrid) -> list[tuple[str, tuple[str, ...]]]:
    report = witness_grid(building, grid, chair_width=CHAIR)
    return sorted((f.kind.value, tuple(sorted(f.cells))) for f in report.findings)


def _per_pair(monkeypatch: pytest.MonkeyPatch, building: Building, grid: OccupancyGrid) -> list:
    with monkeypatch.context() as m:
        m.setattr(witness_storey_module._Storey, "proven", lambda *a, **k: False)
        m.setattr(witness_storey_module._Storey, "may_leak", lambda *a, **k: True)
        return _findings(building, grid)


box = st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.005, 0.25), st.floats(0.005, 0.25))


@pytest.mark.slow
@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(which=st.integers(0, 3), faults=st.lists(st.tuples(box, st.sampled_from([FREE, OCCUPIED, UNKNOWN])), max_size=4))
def test_labelled_once_or_pair_by_pair_the_findings_are_the_same(
    plans: list[tuple[Building, OccupancyGrid]], monkeypatch: pytest.MonkeyPatch, which: int, faults: list
) -> None:
    building, grid = plans[which % len(plans)]
    data = grid.data.copy()
    h, w = data.shape
    for (x, y, dx, dy), value in faults:
        r0, c0 = int(y * h), int(x * w)
        data[r0 : r0 + max(1, int(dy * h)), c0 : c0 + max(1, int(dx * w))] = value
    painted = OccupancyGrid(data, grid.resolution, grid.origin, meta=dict(grid.meta))
    assert _findings(building, painted) == _per_pair(monkeypatch, building, painted)


def test_the_right_maps_are_proven_without_the_per_pair_check(
    plans: list[tuple[Building, OccupancyGrid]], monkeypatch: pytest.MonkeyPatch
) -> None:
    """On a right map the labelled storey proves every way and rules out every leak: the per-pair check
    (what cost a 100 M-cell storey 44 s) never runs."""
    calls: list[str] = []
    real = witness_storey_module._connected
    monkeypatch.setattr(witness_storey_module, "_connected", lambda *a, **k: calls.append("c") or real(*a, **k))
    for building, grid in plans[:3]:  # the converter's own maps (the fourth has cells added after)
        assert _findings(building, grid) == []
    assert calls == []
