"""Transitions to cells that are not free are named as not checked, never dropped unseen, and never a failure.

The reader takes a thin cell starting well above the floor beside it for a window or sill (non-navigable);
when that rule misjudges a door, the transitions through it would vanish from the check. So the check
names them: reason ``window`` (judged by the reader) or ``non-navigable`` (declared by the file).
Plans are written in both IndoorGML spellings (1.0 State/Transition, 2.0 Node/Edge).
"""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pytest
import shapely

from pmk_nb.access.check import check_building, check_map
from pmk_nb.access.report import NotChecked, StoreyReport
from pmk_nb.access.sidecar import read_sidecar, sidecar_path
from pmk_nb.cli import main
from pmk_nb.cli.check import MAX_NOT_CHECKED, format_report
from pmk_nb.errors import MapFormatError
from pmk_nb.guide import NoAccessibleRoute, load_rooms, plan_route
from pmk_nb.indoorgml import read_building
from pmk_nb.openings import SKIP_DECLARED, SKIP_WINDOW, plan_openings
from pmk_nb.raster import rasterise_storey
from pmk_nb.ui.maps.access import _storey_html
from tests.access.test_access_rules import _cell, _graph, _named_solid, _plan
from tests.shared_data import INDOORGML_DATA

SPELLINGS = pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
# hall and office side by side (floors at 0 m), a 0.3 m deep window in the office's outer wall, 1 m up
WINDOWED = (
    _named_solid("A", "hall", (0, 0, 5, 4), 0.0, 2.6)
    + _named_solid("B", "office", (5, 0, 10, 4), 0.0, 2.6)
    + _named_solid("W", "office window", (10, 1, 10.3, 2), 1.0, 2.0)
)


def _windowed(tmp_path: Path, v2: bool, pairs: tuple[tuple[str, str], ...] = (("A", "B"), ("B", "W"))) -> Path:
    return _plan(tmp_path, WINDOWED, _graph(list(pairs), v2=v2), v2=v2)


@SPELLINGS
def test_a_transition_to_a_window_is_named_not_checked_and_is_no_failure(tmp_path: Path, v2: bool) -> None:
    path = _windowed(tmp_path, v2)
    b = read_building(path, unit="m")
    assert b.cells["W"].window and not b.cells["W"].kind.is_free  # the reader judged it, the file did not say
    assert not b.cells["B"].window
    storey = b.storeys[0].name
    plan = plan_openings(b, storey)
    assert [(o.link.a, o.link.b) for o in plan.openings] == [("A", "B")]  # no opening into the window
    assert [(k.link.a, k.link.b, k.names, k.reason) for k in plan.skipped] == [
        ("B", "W", ("office", "office window"), SKIP_WINDOW)
    ]
    [report] = check_building(b, 0.05, chair_width=0.7)
    assert report.ok and report.counts()["links"] == 1 and report.counts()["passable_chair"] == 1
    assert report.not_checked == [NotChecked("T1", ("B", "W"), ("office", "office window"), "window", "office window")]
    assert report.counts()["to_windows"] == 1 and report.counts()["to_non_navigable"] == 0
    assert "; 1 transition leads to cells judged windows/sills (not checked)" in report.summary()
    assert report.to_json()["not_checked"][0]["reason"] == "window" and report.to_json()["ok"] is True


@SPELLINGS
def test_pmk_check_names_the_window_and_keeps_its_exit_code(
    tmp_path: Path, v2: bool, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _windowed(tmp_path, v2)
    assert main(["check", str(path), "--chair-width", "0.7", "--unit", "m"]) == 0
    out = capsys.readouterr().out
    assert "  not checked: office <-> office window (judged a window/sill)" in out
    assert "misjudged it" in out and "again with --not-window NAME" in out
    assert "ok: the chair can pass every transition checked (1 not checked, above)" in out
    # a narrow door still fails as before: the window changes nothing of the exit code
    door = (
        "<cellSpaceBoundaryMember><navi:ConnectionBoundary gml:id='D1'><cellSpaceBoundaryGeometry><geometry2D>"
        "<gml:LineString><gml:posList>5 1 5 1.6</gml:posList></gml:LineString></geometry2D>"
        "</cellSpaceBoundaryGeometry></navi:ConnectionBoundary></cellSpaceBoundaryMember>"
    )
    shut = _plan(tmp_path, WINDOWED, _graph([("A", "B"), ("B", "W")], v2=v2), door, v2=v2)
    assert main(["check", str(shut), "--chair-width", "0.7", "--unit", "m", "--json"]) == 1
    [storey] = json.loads(capsys.readouterr().out)["storeys"]
    assert storey["counts"]["narrow"] == 1 and storey["counts"]["to_windows"] == 1


@SPELLINGS
def test_a_transition_to_a_declared_non_navigable_cell_says_so(tmp_path: Path, v2: bool) -> None:
    cells = _cell("A", (0, 0, 5, 4)) + _cell("B", (5, 0, 10, 4)) + _cell("P", (0, 4, 10, 5), "navi:NonNavigableSpace")
    b = read_building(_plan(tmp_path, cells, _graph([("A", "B"), ("A", "P")], v2=v2), v2=v2), unit="m")
    assert not b.cells["P"].kind.is_free and not b.cells["P"].window
    [report] = check_building(b, 0.05, chair_width=0.7)
    assert report.ok and [(k.cells, k.reason, k.cell) for k in report.not_checked] == [(("A", "P"), SKIP_DECLARED, "P")]
    assert report.counts()["to_non_navigable"] == 1 and report.counts()["to_windows"] == 0
    assert "1 transition leads to non-navigable cells (not checked)" in report.summary()
    assert "windows" not in report.summary()
    assert "misjudged" not in "\n".join(format_report([report]))  # the file's word: no window hint


@SPELLINGS
def test_the_grid_is_the_same_whether_the_window_is_linked_or_not(tmp_path: Path, v2: bool) -> None:
    grids = []
    for pairs in ((("A", "B"), ("B", "W")), (("A", "B"),)):
        b = read_building(_windowed(tmp_path, v2, pairs), unit="m")
        grids.append(rasterise_storey(b, b.storeys[0].name, 0.05).data.tobytes())
    assert grids[0] == grids[1]


def test_a_storey_whose_only_transitions_lead_to_windows_says_so(tmp_path: Path) -> None:
    [report] = check_building(read_building(_windowed(tmp_path, False, (("B", "W"),)), unit="m"), 0.05)
    assert not report.graph and report.ok and len(report.not_checked) == 1
    assert report.summary() == (
        "storey 0: no transition between two free cells to check; "
        "1 transition leads to cells judged windows/sills (not checked)"
    )


@SPELLINGS
def test_the_rooms_file_carries_them_to_pmk_check_on_the_written_map(
    tmp_path: Path, v2: bool, capsys: pytest.CaptureFixture[str]
) -> None:
    src = _windowed(tmp_path, v2)
    out_dir = tmp_path / "maps"
    assert (
        main(
            [
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
        )
        == 0
    )
    said = capsys.readouterr().out
    assert "accessibility: 1/1 transitions passable" in said and "1 transition leads to cells judged windows" in said
    [yaml] = out_dir.glob("*.yaml")
    doc = json.loads(sidecar_path(yaml).read_text(encoding="utf-8"))
    assert doc["skipped"] == [{"link": "T1", "reason": "window"}]
    plan = read_sidecar(yaml)
    assert [(k.link.id, k.names, k.reason) for k in plan.skipped] == [("T1", ("office", "office window"), "window")]
    report = check_map(yaml, chair_width=0.7)
    [fresh] = check_building(read_building(src, unit="m"), 0.05, chair_width=0.7)
    assert report.not_checked == fresh.not_checked and report.ok
    assert main(["check", str(yaml), "--chair-width", "0.7"]) == 0
    assert "not checked: office <-> office window (judged a window/sill)" in capsys.readouterr().out
    html = _storey_html(SimpleNamespace(storey="0", yaml=yaml), doc)
    assert "Not checked: 1 passage into cells taken for windows or sills (office window)." in html
    assert "pmk convert --not-window NAME" in html and "✓" in html


def test_an_old_rooms_file_without_them_still_reads(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = _windowed(tmp_path, False)
    out_dir = tmp_path / "maps"
    assert main(["convert", str(src), "-r", "0.05", "--out", str(out_dir), "--no-progress", "--unit", "m"]) == 0
    [yaml] = out_dir.glob("*.yaml")
    rooms = sidecar_path(yaml)
    doc = json.loads(rooms.read_text(encoding="utf-8"))
    assert doc["skipped"] and doc["accessibility"]["not_checked"]
    del doc["skipped"], doc["accessibility"]["not_checked"]  # as written before this version
    for key in ("to_windows", "to_non_navigable"):
        del doc["accessibility"]["counts"][key]
    rooms.write_text(json.dumps(doc), encoding="utf-8")
    assert read_sidecar(yaml).skipped == ()
    report = check_map(yaml, chair_width=0.7)
    assert report.ok and report.not_checked == [] and report.counts()["links"] == 1
    html = _storey_html(SimpleNamespace(storey="0", yaml=yaml), doc)
    assert "✓" in html and "not checked" not in html.lower()
    # a list naming a link the file does not have is a damaged rooms file, said as such
    doc["skipped"] = [{"link": "T9", "reason": "window"}]
    rooms.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(MapFormatError, match="damaged rooms file"):
        read_sidecar(yaml)


def test_the_text_report_names_ten_and_counts_the_rest() -> None:
    skipped = [NotChecked(f"T{i}", ("R", f"W{i}"), ("hall", f"window {i}"), "window", f"window {i}") for i in range(13)]
    report = StoreyReport("0", 0.7, 0.05, graph=True, not_checked=skipped)
    lines = format_report([report])
    named = [line for line in lines if line.startswith("  not checked: hall <-> window")]
    assert len(named) == MAX_NOT_CHECKED == 10
    assert "  not checked: and 3 more (--json lists them all)" in lines
    html = _storey_html(SimpleNamespace(storey="0", yaml=Path("m.yaml")), {"accessibility": report.to_json()})
    assert "Not checked: 13 passages into cells taken for windows or sills (window 0, " in html
    assert "window 9 and 3 more)" in html and "window 10" not in html


def test_fzk_haus_window_cells_are_named_and_the_check_still_passes(capsys: pytest.CaptureFixture[str]) -> None:
    """FZK-Haus links its 11 window cells (0.3 m deep, in the outer walls, sills 0.8-0.95 m above the floor
    beside them, checked by hand): all are named not checked as windows, never as failures; its two entrance
    niches (0.3 m deep, the unknown outside beyond) are named not checked as doorways out of the map."""
    path = INDOORGML_DATA / "fzk_haus_poslist.gml"
    b = read_building(path)
    reports = check_building(b, 0.05, chair_width=0.7)
    outs = [k for r in reports for k in r.not_checked if k.reason == "outside"]  # its two entrance niches
    assert sorted(k.cell for k in outs) == ["CS_2142020163114_12", "CS_2142020163114_15"]
    skipped = [k for r in reports for k in r.not_checked if k.reason != "outside"]
    assert [len(r.not_checked) for r in reports] == [11, 2]
    assert all(k.link not in {n.link for n in r.not_checked} for r in reports for k in r.blocked)
    assert {k.reason for k in skipped} == {"window"}
    windows = {k.cells[0] if k.cell == k.names[0] else k.cells[1] for k in skipped}
    assert len(windows) == 11 and windows == {c.id for c in b.cells.values() if c.window}
    for cid in windows:
        cell = b.cells[cid]
        box = shapely.minimum_rotated_rectangle(cell.footprint).bounds
        assert min(box[2] - box[0], box[3] - box[1]) <= 0.31  # a wall's depth
        floor = min(b.cells[k.cells[0] if k.cells[1] == cid else k.cells[1]].z_min for k in skipped if cid in k.cells)
        assert 0.75 <= cell.z_min - floor <= 1.0 and cell.z_max - floor <= 2.2  # a sill and a lintel
    assert main(["check", str(path), "--chair-width", "0.7"]) == 0
    out = capsys.readouterr().out
    assert "storey 0: 9/9 transitions passable" in out and "9 transitions lead to cells judged windows/sills" in out
    assert "2 transitions lead to doorways out of the map (not checked)" in out
    assert out.count("  not checked: ") == 13 and "--not-window NAME" in out


@SPELLINGS
def test_the_route_planner_names_the_unchecked_way_in_when_there_is_no_route(tmp_path: Path, v2: bool) -> None:
    """A store room reached only through the cell judged a window: no route, and the error says where
    the file claims a way in, so a misjudged door is found. The planner's check equals `pmk check`'s."""
    cells = WINDOWED + _named_solid("C", "store", (10.3, 0, 14, 4), 0.0, 2.6)
    src = _plan(tmp_path, cells, _graph([("A", "B"), ("B", "W"), ("W", "C")], v2=v2), v2=v2)
    out_dir = tmp_path / "maps"
    assert main(["convert", str(src), "-r", "0.05", "--out", str(out_dir), "--no-progress", "--unit", "m"]) in (0, 1)
    [yaml] = out_dir.glob("*.yaml")
    rooms = load_rooms(yaml)
    assert rooms.access(0.7) == check_map(yaml, chair_width=0.7)
    assert len(rooms.access(0.7).not_checked) == 2
    with pytest.raises(NoAccessibleRoute) as err:
        plan_route(rooms, (2.0, 2.0), "store", chair_width=0.7)
    assert err.value.not_checked == ["store <-> office window (judged a window/sill)"]
    assert "not checked, the map has no way through: store <-> office window" in str(err.value)
    route = plan_route(rooms, (2.0, 2.0), "office", chair_width=0.7)  # the rest of the storey still routes
    assert route.destination.id == "B"
