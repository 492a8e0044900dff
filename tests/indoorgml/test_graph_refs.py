"""Issue 31, rule 2: graph references in every spelling exporters use; what stays dangling is said loudly.

``xlink:href`` comes as ``#id``, ``id``, ``file.gml#id`` or an XPointer; ``connects`` may name the cell
instead of its state; the duality may be written on the cell's side only, or name a cell that is not
in the file. A graph that is absent, or whose transitions (nearly) all name states that are not in the
file, is lost: ``pmk check`` exits 3 ("nothing could be checked") and never says "ok".
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from pmk_nb.access import check_grid
from pmk_nb.cli import main
from pmk_nb.indoorgml import read_building
from pmk_nb.raster import rasterise_storey
from tests.access.test_access_rules import RES, ROOMS, _cell, _graph, _plan

V = pytest.mark.parametrize("v2", [False, True], ids=["1.x-state-transition", "2.0-node-edge"])


def _respell(text: str, spelling: str) -> str:
    """The plan's hrefs to states (``#SA``) and the states' dualities, as another exporter writes them."""
    if spelling == "no-hash":
        return text.replace('xlink:href="#', 'xlink:href="')
    if spelling == "file-and-id":
        return text.replace('xlink:href="#', 'xlink:href="building.gml#')
    if spelling == "xpointer":
        return re.sub(r'xlink:href="#(\w+)"', r"""xlink:href="#xpointer(id('\1'))" """, text)
    if spelling == "connects-the-cell":
        return text.replace('connects xlink:href="#S', 'connects xlink:href="#')
    if spelling in ("duality-on-the-cell", "state-names-a-missing-cell"):  # the cell names its state
        text = re.sub(r'(<CellSpace gml:id="(\w+)">)', r'\1<duality xlink:href="#S\2"/>', text)
        missing = '<duality xlink:href="#GONE"/>' if spelling == "state-names-a-missing-cell" else ""
        return re.sub(r'<duality xlink:href="#\w+"/>(</(?:State|Node)>)', missing + r"\1", text)
    raise AssertionError(spelling)


SPELLINGS = [
    "hash",
    "no-hash",
    "file-and-id",
    "xpointer",
    "connects-the-cell",
    "duality-on-the-cell",
    "state-names-a-missing-cell",
]


@V
@pytest.mark.parametrize("spelling", SPELLINGS)
def test_every_href_spelling_resolves(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], v2: bool, spelling: str
) -> None:
    path = _plan(tmp_path, ROOMS, _graph([("A", "B")], v2=v2), v2=v2)
    if spelling != "hash":
        path.write_text(_respell(path.read_text(), spelling))
    b = read_building(path, unit="m")
    assert [(k.a, k.b) for k in b.links] == [("A", "B")]
    status = b.graph_status
    assert (status.transitions, status.resolved, status.dangling, status.lost) == (1, 1, 0, False)
    assert main(["check", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is True and doc["graph"]["resolved"] == 1 and doc["graph"]["lost"] is False


@V
def test_a_graph_of_dangling_transitions_is_lost_and_check_exits_3(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], v2: bool
) -> None:
    path = _plan(tmp_path, ROOMS, _graph([("A", "B"), ("B", "A")], v2=v2), v2=v2)
    path.write_text(path.read_text().replace('connects xlink:href="#S', 'connects xlink:href="#OTHER-'))
    b = read_building(path, unit="m")
    status = b.graph_status
    assert (status.transitions, status.resolved, status.dangling, status.lost) == (2, 0, 2, True)
    said = "2 of 2 transitions name states that are not in the file: the navigation graph was not used"
    assert status.reason == said
    storey = b.storeys[0].name
    report = check_grid(b, storey, rasterise_storey(b, storey, RES))
    assert not report.ok and said in report.summary()
    assert main(["check", str(path)]) == 3
    out = capsys.readouterr().out
    assert said in out and "ok:" not in out
    assert main(["check", str(path), "--json"]) == 3
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is False and doc["exit_code"] == 3 and doc["graph"]["reason"] == said
    assert doc["storeys"][0]["ok"] is False


@V
def test_no_graph_at_all_exits_3_and_says_why(tmp_path: Path, capsys: pytest.CaptureFixture[str], v2: bool) -> None:
    path = _plan(tmp_path, ROOMS, v2=v2)
    b = read_building(path, unit="m")
    assert b.graph_status.absent and b.graph_status.lost
    storey = b.storeys[0].name
    assert not check_grid(b, storey, rasterise_storey(b, storey, RES)).ok
    assert main(["check", str(path)]) == 3
    out = capsys.readouterr().out
    assert "no navigation graph" in out and "ok:" not in out


@V
def test_a_few_dangling_transitions_are_counted_and_the_rest_checked(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], v2: bool
) -> None:
    cells = ROOMS + _cell("C", (10, 0, 15, 4))
    path = _plan(tmp_path, cells, _graph([("A", "B"), ("B", "C"), ("C", "D")], v2=v2), v2=v2)
    path.write_text(path.read_text().replace('<duality xlink:href="#D"/>', ""))  # no cell D: state SD is gone too
    path.write_text(re.sub(r'<\w+Member><(State|Node) gml:id="SD">.*?</\1></\w+Member>', "", path.read_text()))
    b = read_building(path, unit="m")
    status = b.graph_status
    assert (status.transitions, status.resolved, status.dangling, status.lost) == (3, 2, 1, False)
    assert any("1 of 3 transitions name states that are not in the file" in w for w in b.warnings)
    assert main(["check", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is True and doc["storeys"][0]["counts"]["links"] == 2 and doc["graph"]["dangling"] == 1


def test_a_map_written_from_a_lost_graph_is_not_ok_when_checked_later(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    cells = ROOMS + _cell("C", (10, 0, 15, 4))
    pairs = [("A", "B")] + [("B", "C")] * 9  # 9 of 10 transitions will name states that are not in the file
    path = _plan(tmp_path, cells, _graph(pairs), v2=False)
    text = path.read_text()
    path.write_text(re.sub(r'(<Transition gml:id="T[1-9]"><connects xlink:href=")#S', r"\1#GONE-", text))
    assert read_building(path, unit="m").graph_status.lost
    out = tmp_path / "maps"
    assert main(["convert", str(path), "-r", "0.05", "--out", str(out), "--no-progress", "--unit", "m"]) == 0
    assert "NAVIGATION GRAPH NOT USED: 9 of 10 transitions name states" in capsys.readouterr().out
    [yaml] = out.glob("*.yaml")
    assert main(["check", str(yaml)]) == 3
    assert "9 of 10 transitions name states that are not in the file" in capsys.readouterr().out


def test_check_help_documents_the_exit_codes(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["check", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for code in ("0 = every transition checked", "1 = problems found", "2 = bad input", "3 = nothing could be checked"):
        assert code in text


def test_pmk_maps_says_nothing_was_checked_for_a_plan_without_graph(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from pmk_nb.cli.maps import accessibility_line
    from pmk_nb.library import MapsFolder

    maps = MapsFolder(tmp_path / "maps")
    entry = maps.import_file(_plan(tmp_path, ROOMS), "nograph")
    [gm] = maps.convert(entry.name, 0.1, unit="m")
    assert accessibility_line(gm.yaml).startswith("NOTHING CHECKED: the file has no navigation graph")
