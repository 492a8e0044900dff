"""The IndoorGML reader on every real file in the shared data folder (see its README table)."""

from __future__ import annotations

import pytest
from shapely.geometry import Point

from pmk_nb.indoorgml import CellKind, read_building, summarize
from pmk_nb.progress import Progress
from tests.shared_data import INDOORGML_DATA

DATA = INDOORGML_DATA

# file -> unit, {storey: cell count}, (storey -> point inside a free cell, point outside all cells), doors
EXPECTED: dict[str, dict] = {
    "pnu313_4F_2D_doors_subset.gml": {
        "unit": "dm",
        "storeys": {"F1": 7},
        "doors": 6,
        "inside": {"F1": (19.94, 17.33)},
        "outside": {"F1": (-1.5, -1.3)},
    },
    "pnu313_4F_2D_indoordistance.gml": {
        "unit": "dm",
        "storeys": {"F1": 30},
        "doors": 26,
        "inside": {"F1": (3.23, 14.88)},
        "outside": {"F1": (-1.6, -1.4)},
    },
    "fjk_haus_v1_0_nowrapper.gml": {
        "unit": "m",
        "storeys": {"0": 6, "1": 4, "2": 4},
        "doors": 0,
        # UTM 32N, read from the local origin (445534, 5444897): the points are 445539.85 E 5444906.80 N, ...
        "inside": {"0": (5.85, 9.80), "1": (3.99, 9.62), "2": (3.94, 10.22)},
        "outside": {s: (-1.6, -1.6) for s in "012"},
    },
    "fjk_haus_v1_0_3.gml": {
        "unit": "m",
        "storeys": {"0": 6, "1": 4, "2": 4},
        "doors": 0,
        # UTM 32N, read from the local origin (445534, 5444897): the points are 445539.85 E 5444906.80 N, ...
        "inside": {"0": (5.85, 9.80), "1": (3.99, 9.62), "2": (3.94, 10.22)},
        "outside": {s: (-1.6, -1.6) for s in "012"},
    },
    # FZK-Haus: z_min clusters {0, 0.8, 0.95} (ground floor, doors and windows) and
    # {2.5, 2.7, 3.51} (attic and its gable windows): a two-storey house.
    "fzk_haus_poslist.gml": {
        "unit": "m",
        "storeys": {"0": 20, "1": 4},
        "doors": 0,
        "inside": {"0": (8.35, 2.15), "1": (6.0, 4.98)},
        "outside": {"0": (-2.0, -2.0), "1": (-2.0, -2.0)},
    },
    "pnu201_3floors_navi_corrected.gml": {
        "unit": "m",
        "storeys": {"1": 28, "2": 31, "3": 21},
        "doors": 92,
        "inside": {"1": (199.97, 149.64), "2": (159.47, 220.77), "3": (159.55, 220.35)},
        "outside": {s: (105.0, 25.0) for s in "123"},
    },
    "pnu_abc_3floors_4layers.gml": {
        "unit": "m",
        "storeys": {"F2": 4, "F3": 17, "F4": 15},
        "doors": 39,
        "inside": {"F2": (84.84, 44.54), "F3": (84.85, 46.26), "F4": (84.91, 44.18)},
        "outside": {s: (24.0, 15.0) for s in ("F2", "F3", "F4")},
    },
    "ineditor_example2_5floors.gml": {
        "unit": "m",
        "storeys": {"1": 2, "2": 3, "3": 3, "4": 3, "5": 3},
        "doors": 17,
        "inside": {
            "1": (36.81, 24.88),
            "2": (37.83, 24.90),
            "3": (58.59, 25.89),
            "4": (50.49, 32.46),
            "5": (58.36, 25.92),
        },
        "outside": {s: (3.0, 4.0) for s in "12345"},
    },
}


def test_every_shared_file_is_covered() -> None:
    files = sorted(p.name for p in DATA.glob("*.gml"))
    assert files, f"no IndoorGML files in {DATA} (set PMK_INDOORGML_DATA)"
    assert set(files) == set(EXPECTED)


@pytest.fixture(scope="module", params=sorted(EXPECTED))
def parsed(request: pytest.FixtureRequest):
    return request.param, read_building(DATA / request.param)


def test_storeys_and_cell_counts(parsed) -> None:
    name, b = parsed
    exp = EXPECTED[name]
    assert {s.name: len(s.cell_ids) for s in b.storeys} == exp["storeys"]
    assert len(b.cells) == sum(exp["storeys"].values())
    assert all(c.storey in exp["storeys"] for c in b.cells.values())


def test_unit_and_reason(parsed) -> None:
    name, b = parsed
    assert b.unit == EXPECTED[name]["unit"]
    assert b.unit_reason.startswith("auto:")


def test_known_points_inside_and_outside(parsed) -> None:
    name, b = parsed
    exp = EXPECTED[name]
    for storey, (x, y) in exp["inside"].items():
        cells = b.cells_of(storey)
        hit = [c for c in cells if c.footprint.contains(Point(x, y))]
        assert hit and any(c.kind.is_free for c in hit), (storey, x, y)
        minx = min(c.footprint.bounds[0] for c in cells)
        maxx = max(c.footprint.bounds[2] for c in cells)
        assert minx <= x <= maxx
    for storey, (x, y) in exp["outside"].items():
        assert not any(c.footprint.contains(Point(x, y)) for c in b.cells_of(storey))


def test_footprints_valid_and_metric(parsed) -> None:
    _, b = parsed
    for c in b.cells.values():
        assert c.footprint.is_valid and not c.footprint.is_empty and c.footprint.area > 0, c.id
        assert c.footprint.geom_type in ("Polygon", "MultiPolygon")
    sizes = [s["extent"]["size"] for s in summarize(b)["storeys"]]
    assert all(3.0 < max(sz) < 300.0 for sz in sizes), sizes  # a building, in metres


def test_doors(parsed) -> None:
    name, b = parsed
    s = summarize(b)
    assert s["doors"]["total"] == EXPECTED[name]["doors"]
    for d in b.boundaries.values():
        if d.is_door:
            assert d.storey in EXPECTED[name]["storeys"], d.id
            assert d.geometry is not None and d.geometry.geom_type in ("LineString", "MultiLineString", "Polygon")


def test_pnu313_doors_are_short_segments_on_room_outlines() -> None:
    """cellspaceboundary_door.gml encodes doors only as bare 2-point LineStrings (+ '-REVERSE' copies)."""
    b = read_building(DATA / "pnu313_4F_2D_doors_subset.gml")
    doors = [d for d in b.boundaries.values() if d.is_door]
    assert sorted(d.id for d in doors) == [f"B{i}" for i in range(1, 7)]
    assert all(0.5 < d.geometry.length < 2.5 for d in doors)  # metres
    assert any("REVERSE" in w for w in b.warnings)


def test_layers_avoid_double_counting() -> None:
    abc = read_building(DATA / "pnu_abc_3floors_4layers.gml")
    assert abc.layers == ["base", "network", "landmark", "safety"]
    assert {c.layer for c in abc.cells.values()} == {"base"}
    ined = read_building(DATA / "ineditor_example2_5floors.gml")
    assert {c.layer for c in ined.cells.values()} == {"base"}
    assert any("layer 'sub'" in w for w in ined.warnings)


def test_kinds_and_graph() -> None:
    b = read_building(DATA / "pnu201_3floors_navi_corrected.gml")
    kinds = {c.kind for c in b.cells.values()}
    assert kinds == {CellKind.GENERAL, CellKind.TRANSITION}
    assert len(b.graph.states) == 80 and len(b.graph.transitions) == 184
    assert sum(1 for s in b.graph.states.values() if s.cell_id in b.cells) == 80
    fzk = read_building(DATA / "fzk_haus_poslist.gml")
    windows = [c for c in fzk.cells.values() if c.kind is CellKind.NON_NAVIGABLE]
    assert windows and all((c.z_min or 0) - (fzk.storey(c.storey).elevation or 0) > 0.5 for c in windows)


def test_versions() -> None:
    assert read_building(DATA / "fjk_haus_v1_0_nowrapper.gml").version == "1.0"
    assert read_building(DATA / "fjk_haus_v1_0_3.gml").version == "1.0.3"


def test_progress_reports_bytes() -> None:
    path = DATA / "pnu201_3floors_navi_corrected.gml"
    calls: list[Progress] = []
    read_building(path, progress=calls.append)
    size = path.stat().st_size
    assert calls[-1] == Progress("read", 1.0, f"{size} bytes")
    assert {p.step for p in calls} == {"read"}
    fractions = [p.fraction for p in calls]
    assert fractions == sorted(fractions) and 0 < fractions[0] < 1  # type: ignore[type-var]
    assert len(calls) > 2


def test_explicit_unit_overrides_auto() -> None:
    b = read_building(DATA / "pnu313_4F_2D_doors_subset.gml", unit="m")
    assert b.unit == "m" and b.unit_reason == "given: m"
    assert max(summarize(b)["storeys"][0]["extent"]["size"]) > 300
