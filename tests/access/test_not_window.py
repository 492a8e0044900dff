"""--not-window: the user's override when the window/sill rule takes a door for a window.

`pmk check` names the cells it took for windows and the transitions it therefore left unchecked; when one
is really a door or floor, the user names it (by name or id) and the cell stays navigable: its transitions
are opened and checked like any other. A word that matches no cell is bad input (exit 2, the file and the
word named), and nothing is written. Plans are written in both IndoorGML spellings.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.access.check import check_building, check_map
from pmk_nb.access.sidecar import read_sidecar
from pmk_nb.cli import main
from pmk_nb.errors import IndoorGMLError
from pmk_nb.grid import FREE
from pmk_nb.indoorgml import read_building
from pmk_nb.library import MapsFolder
from tests.access.test_access_not_checked import SPELLINGS, WINDOWED, _windowed

# the "window" W of WINDOWED is a 0.3 m deep, 1 m wide cell 1 m up the office's outer wall; here the file's
# graph also leads through it to a balcony, so the plan says it is a door
BALCONY = "balcony"


def _balcony(tmp_path: Path, v2: bool) -> Path:
    from tests.access.test_access_rules import _graph, _named_solid, _plan

    cells = WINDOWED + _named_solid("C", BALCONY, (10.3, 0, 13, 4), 1.0, 3.6)
    return _plan(tmp_path, cells, _graph([("A", "B"), ("B", "W"), ("W", "C")], v2=v2), v2=v2)


@SPELLINGS
@pytest.mark.parametrize("word", ["office window", "W"], ids=["by-name", "by-id"])
def test_a_cell_named_not_a_window_stays_navigable_and_its_transitions_are_checked(
    tmp_path: Path, v2: bool, word: str
) -> None:
    path = _balcony(tmp_path, v2)
    judged = read_building(path, unit="m")
    assert judged.cells["W"].window and not judged.cells["W"].kind.is_free
    [before] = check_building(judged, 0.05, chair_width=0.7)
    assert len(before.not_checked) == 2 and before.counts()["links"] == 1
    b = read_building(path, unit="m", not_windows=[word])
    assert b.cells["W"].kind.is_free and not b.cells["W"].window
    assert any("kept navigable as asked (--not-window): ['W']" in w for w in b.warnings)
    [report] = check_building(b, 0.05, chair_width=0.7)
    assert report.not_checked == [] and report.counts()["links"] == 3
    assert report.counts()["passable_chair"] == 3 and report.ok, report.summary()


def test_a_word_that_names_no_cell_is_refused_with_the_file_and_the_word(tmp_path: Path) -> None:
    path = _windowed(tmp_path, False)
    with pytest.raises(IndoorGMLError) as err:
        read_building(path, unit="m", not_windows=["ofice window"])
    assert str(path) in str(err.value) and "'ofice window'" in str(err.value) and err.value.element == "ofice window"
    assert "pmk check" in err.value.hint


@SPELLINGS
def test_pmk_convert_and_check_take_it(tmp_path: Path, v2: bool, capsys: pytest.CaptureFixture[str]) -> None:
    src = _balcony(tmp_path, v2)
    out_dir = tmp_path / "maps"
    args = [
        "convert",
        str(src),
        "-r",
        "0.05",
        "--out",
        str(out_dir),
        "--no-progress",
        "--unit",
        "m",
        "--chair-width",
        "0.7",
    ]
    assert main([*args, "--not-window", "nowhere"]) == 2  # bad input: nothing written
    assert "'nowhere'" in capsys.readouterr().err and not out_dir.exists()
    assert main([*args, "--not-window", "office window"]) == 0
    said = capsys.readouterr().out
    assert "accessibility: 3/3 transitions passable" in said and "window" not in said.split("accessibility:")[1]
    [yaml] = out_dir.glob("*.yaml")
    assert read_sidecar(yaml).skipped == () and check_map(yaml, chair_width=0.7).ok
    grid = check_map(yaml, chair_width=0.7)
    assert grid.counts()["passable_chair"] == 3
    assert main(["check", str(src), "--unit", "m", "--chair-width", "0.7", "--not-window", "W", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["storeys"][0]["not_checked"] == [] and doc["storeys"][0]["counts"]["links"] == 3
    assert main(["check", str(yaml), "--not-window", "W"]) == 2  # a written map's kinds are decided
    assert "applies to a plan" in capsys.readouterr().err
    assert main(["info", str(src), "--unit", "m", "--not-window", "W"]) == 0
    assert "kept navigable as asked" in capsys.readouterr().out


def test_the_maps_folder_converts_with_it(tmp_path: Path) -> None:
    folder = MapsFolder(tmp_path / "maps")
    folder.import_file(_balcony(tmp_path, False), name="house")
    [gm] = folder.convert("house", 0.05, unit="m", not_windows=["office window"])
    plan = read_sidecar(gm.yaml)
    assert next(c for c in plan.cells if c.id == "W").kind.is_free and plan.skipped == ()
    grid = check_map(gm.yaml, chair_width=0.7)
    assert grid.ok and grid.counts()["links"] == 3
    from pmk_nb.rosmap import read_map

    assert read_map(gm.yaml).value_at(10.15, 1.5) == FREE  # inside the kept cell


def test_pmk_maps_convert_takes_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from tests.cli.test_cli_maps import pmk

    maps = tmp_path / "maps"
    maps.mkdir()
    assert pmk(capsys, maps, "import", str(_balcony(tmp_path, False)), "--name", "house")[0] == 0
    code, _, err = pmk(capsys, maps, "convert", "house", "-r", "0.05", "--unit", "m", "--not-window", "nowhere")
    assert code == 2 and "'nowhere'" in err and not list(maps.glob("*.yaml"))
    code, out, _ = pmk(capsys, maps, "convert", "house", "-r", "0.05", "--unit", "m", "--not-window", "office window")
    assert code == 0 and "3/3 transitions passable" in out, out
