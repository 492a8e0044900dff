"""Issue 8's per-file figures on the shared real IndoorGML files, and `pmk check` as a linter.

Expected counts were checked by hand on rendered crops (see the closing note of issue 8). pnu_abc links
three stair cells to corridors 1.5-1.8 m away (nothing drawn between them): a "bridge" passage is laid
across the gap. Its two north restrooms are reached through a door cell 1.1-1.4 m wide, which the
check lets a way cross (it is part of the wall).

FZK-Haus (issue 31, rule 9): its two entrance niches (0.3 m deep: the outer wall's depth, at floor level)
lead only to the unknown outside, and no chair fits in them on the written 0.05 m grid, as an independent
distance transform of the grid agrees (tests/access/test_access_property.py). They were called passable from
the 0.88 m free along the opening; they are now named "not checked: a doorway out of the map", not
counted as links (a narrow door they are not). Its attic door, cut into a corner, was blocked until rule 8
slid it along the wall to its full 0.9 m.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.access.check import check_building
from pmk_nb.cli import main
from pmk_nb.indoorgml import read_building
from tests.shared_data import INDOORGML_DATA as INDOORGML_DIR

# file -> (links, passable r = 0, passable 0.60 m chair, leaks)
EXPECTED = {
    "fjk_haus_v1_0_3.gml": (12, 12, 12, 0),
    "fjk_haus_v1_0_nowrapper.gml": (12, 12, 12, 0),
    "fzk_haus_poslist.gml": (10, 10, 10, 0),  # and two entrance niches not checked: see the note
    "ineditor_example2_5floors.gml": (8, 8, 8, 0),
    "pnu201_3floors_navi_corrected.gml": (81, 81, 81, 0),
    "pnu_abc_3floors_4layers.gml": (33, 33, 33, 0),
    "pnu313_4F_2D_doors_subset.gml": (0, 0, 0, 0),
    "pnu313_4F_2D_indoordistance.gml": (0, 0, 0, 0),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_transitions_passable_per_file(name: str) -> None:
    building = read_building(INDOORGML_DIR / name)
    reports = check_building(building, 0.05, chair_width=0.6)
    got = (
        sum(len(r.links) for r in reports),
        sum(k.point for r in reports for k in r.links),
        sum(k.chair for r in reports for k in r.links),
        sum(len(r.leaks) for r in reports),
    )
    assert got == EXPECTED[name]
    for r in reports:  # every failure is named by its cells
        assert all(k.names[0] and k.names[1] for k in r.blocked)


@pytest.mark.slow
def test_pmk_check_exit_codes_and_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(INDOORGML_DIR / "fzk_haus_poslist.gml"), "--chair-width", "1.0"]) == 1
    out = capsys.readouterr().out  # the attic door (0.9 m) and the others for a 1.0 m chair
    assert "transitions passable for a 1.00 m chair" in out and "problems found" in out
    assert main(["check", str(INDOORGML_DIR / "fzk_haus_poslist.gml")]) == 0  # the entrance niches: not checked
    assert "storey 0: 9/9 transitions passable for a 0.70 m chair" in capsys.readouterr().out
    assert main(["check", str(INDOORGML_DIR / "pnu_abc_3floors_4layers.gml")]) == 0
    out = capsys.readouterr().out
    assert "storey F3: 17/17 transitions passable for a 0.70 m chair" in out and "ok:" in out
    wide = ["--chair-width", "1.0"]  # wider than a restroom door of pnu_abc
    assert main(["check", str(INDOORGML_DIR / "pnu_abc_3floors_4layers.gml"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ok"] is True
    assert main(["check", str(INDOORGML_DIR / "pnu_abc_3floors_4layers.gml"), "--json", *wide]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is False and any(s["counts"]["narrow"] for s in doc["storeys"])
    assert main(["check", str(tmp_path)]) == 2
    assert main(["check", str(tmp_path / "missing.gml")]) == 2
    assert main(["check", str(INDOORGML_DIR / "fzk_haus_poslist.gml"), "--chair-width", "5"]) == 2
    assert "chair width" in capsys.readouterr().err


@pytest.mark.slow
def test_pmk_check_a_written_map_uses_its_rooms_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = INDOORGML_DIR / "pnu_abc_3floors_4layers.gml"
    assert main(["convert", str(src), "-r", "0.05", "--out", str(tmp_path), "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "accessibility:" in out and "unit warning" in out
    f3 = next(tmp_path.glob("*_F3.yaml"))
    assert main(["check", str(f3), "--json", "--chair-width", "1.0"]) == 1
    [storey] = json.loads(capsys.readouterr().out)["storeys"]
    assert storey["storey"] == "F3" and storey["counts"]["links"] == 17
    (tmp_path / f3.name.replace(".yaml", ".rooms.json")).unlink()
    assert main(["check", str(f3)]) == 2
    assert "rooms" in capsys.readouterr().err


OWNER_FILES = ["pnu_abc_3floors_4layers.gml", "fjk_haus_v1_0_3.gml", "ineditor_example2_5floors.gml"]


@pytest.mark.parametrize("name", OWNER_FILES)
def test_owners_painted_strip_by_strip_match_the_whole_grid_paint(name: str) -> None:
    """The check paints cell owners a strip at a time; every strip equals the same rows of the whole
    grid painted cell by cell, largest first, door cells grown by half a cell (the rule it replaced)."""
    import numpy as np
    import shapely

    from pmk_nb.access.report import _Owners
    from pmk_nb.pixels import strip_rows
    from pmk_nb.raster import Frame, rasterise_storey
    from pmk_nb.raster.spans import fill_polygons

    building = read_building(INDOORGML_DIR / name)
    most = 0
    for storey in building.storeys:
        cells = [c for c in building.cells_of(storey.name) if c.footprint is not None and not c.footprint.is_empty]
        grid = rasterise_storey(building, storey.name, 0.05)
        frame = Frame(grid.origin[0], grid.origin[1], grid.resolution, grid.width, grid.height)
        whole = np.zeros((grid.height, grid.width), dtype=np.int32)
        for i, cell in sorted(enumerate(cells), key=lambda ic: -ic[1].footprint.area):
            shape = shapely.buffer(cell.footprint, 0.025, join_style="mitre") if cell.kind.is_door else cell.footprint
            fill_polygons(whole, frame, [shape], i + 1)
        owners = _Owners(grid, cells)
        step = max(1, strip_rows(grid.width, grid.height) // 3)  # strips that cut through cells
        painted = np.vstack([owners.rows(a, min(a + step, grid.height)) for a in range(0, grid.height, step)])
        assert np.array_equal(painted.astype(np.int32), whole)
        most = max(most, len(np.unique(whole)))
    assert most > 3  # a storey with several cells, so paint order was exercised
