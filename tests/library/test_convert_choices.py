"""The Maps screen's conversion choices: the plan's unit and the cells that are not windows.

A kiosk user has no command line, so what ``pmk convert --unit`` and ``--not-window`` do is offered on the
screen, next to Convert; what was chosen is kept in the rooms files, so converting again keeps it. The plan
is the balcony plan of test_not_window: its "office window" (1 m up a wall) is really a door to a balcony.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import shapely
import traitlets

from pmk_nb.access import sidecar_doc, sidecar_path
from pmk_nb.cli import main
from pmk_nb.library.choices import (
    ConvertChoices,
    last_choices,
    offered,
    read_choices,
    window_cells,
)
from pmk_nb.library.folder import MapsFolder
from pmk_nb.ui import AppContext
from pmk_nb.ui.maps.screen import MapsScreen
from tests.access.test_not_window import _balcony

WINDOW = "office window"


def _report(not_checked: list[dict[str, str]]) -> dict[str, object]:
    return {"accessibility": {"not_checked": not_checked}}


def test_choices_read_from_rooms_files_and_damaged_ones_ignored() -> None:
    good = {"choices": {"unit": "cm", "not_windows": ["W1", "hall door"]}}
    assert read_choices(good) == ConvertChoices("cm", ("W1", "hall door"))
    damaged = [
        {"unit": "furlong", "not_windows": []},
        {"unit": "m", "not_windows": "W1"},
        {"unit": "m", "not_windows": [3]},
    ]
    for bad in [None, {}, {"choices": []}, *({"choices": c} for c in damaged)]:
        assert read_choices(bad) is None, bad
    assert last_choices([None, {"choices": {"unit": "x"}}, good]) == ConvertChoices("cm", ("W1", "hall door"))
    assert last_choices([None, {}]) == ConvertChoices()  # converted before choices were kept: the defaults


def test_window_cells_are_the_reports_window_items_once_each_in_order() -> None:
    docs = [
        _report([{"cell": "W2", "reason": "window"}, {"cell": "stair", "reason": "non-navigable"}]),
        None,
        _report([{"cell": "W1", "reason": "window"}, {"cell": "W2", "reason": "window"}, {"reason": "window"}]),
    ]
    assert window_cells(docs) == ["W2", "W1"]
    # kept cells are no longer windows, so no report names them: they are offered ticked, first
    assert offered(ConvertChoices("m", ("W9", "W1")), ["W2", "W1"]) == [("W9", True), ("W1", True), ("W2", False)]


@pytest.mark.parametrize("v2", [False, True], ids=["1.0-state-transition", "2.0-node-edge"])
def test_convert_records_the_choices_in_every_rooms_file_also_from_the_cli(tmp_path: Path, v2: bool) -> None:
    src = _balcony(tmp_path, v2)
    maps = MapsFolder(tmp_path / "maps")
    entry = maps.import_file(src, "balcony")
    [gm] = maps.convert(entry.name, 0.05, unit="m", not_windows=[WINDOW])
    assert json.loads(sidecar_path(gm.yaml).read_text(encoding="utf-8"))["choices"] == {
        "unit": "m",
        "not_windows": [WINDOW],
    }
    out = tmp_path / "cli"
    assert main(["convert", str(src), "-r", "0.05", "--out", str(out), "--no-progress", "--unit", "dm"]) == 0
    [yaml] = out.glob("*.yaml")
    assert read_choices(sidecar_doc(yaml)) == ConvertChoices("dm", ())


def _extent(yaml: Path) -> float:
    """Width of the rooms in the written map, in metres."""
    rooms = [shapely.from_geojson(json.dumps(r["polygon"])) for r in (sidecar_doc(yaml) or {})["rooms"]]
    minx, _, maxx, _ = shapely.total_bounds(rooms)
    return float(maxx - minx)


def _converted(screen: MapsScreen, timeout: float = 60) -> None:
    thread = screen.convert()
    assert thread is not None, screen.status.value
    thread.join(timeout)
    assert not thread.is_alive()
    assert screen.status.value.startswith("Converted"), screen.status.value


def _balcony_converted(screen: MapsScreen, tmp_path: Path, v2: bool) -> None:
    """The balcony plan imported on the screen, selected and converted with what the screen first offers."""
    screen.import_bytes("balcony.gml", _balcony(tmp_path, v2).read_bytes())
    screen.select("balcony")
    assert screen.choices.unit.value == "auto" and screen.choices.windows_box.layout.display == "none"
    _converted(screen)


def test_a_user_keeps_a_misjudged_window_navigable_from_the_screen(
    screen: MapsScreen, ctx: AppContext, tmp_path: Path
) -> None:
    _balcony_converted(screen, tmp_path, False)
    access = screen.access_panel.text.value
    assert "Not checked: 2 passages into cells taken for windows or sills (office window)" in access
    assert "tick it under <i>Not windows</i>" in access
    assert screen.choices.windows_box.layout.display == "flex"
    [box] = screen.choices.windows.children
    assert box.description == WINDOW and box.value is False
    screen.choices.tick([WINDOW])
    _converted(screen)
    access = screen.access_panel.text.value
    assert "3 of 3 passages fit a 0.70 m wheelchair" in access and "Not checked" not in access
    [box] = screen.choices.windows.children  # no report names it now, and it is still offered, ticked
    assert box.description == WINDOW and box.value is True
    [gm] = screen.entries["balcony"].generated
    assert read_choices(sidecar_doc(gm.yaml)) == ConvertChoices("auto", (WINDOW,))
    screen.select("balcony")  # chosen again later: the choices come back from the rooms file
    assert [b.value for b in screen.choices.windows.children] == [True]
    screen.choices.tick([])  # and undone
    _converted(screen)
    assert "Not checked: 2 passages" in screen.access_panel.text.value
    assert [(b.description, b.value) for b in screen.choices.windows.children] == [(WINDOW, False)]
    with pytest.raises(Exception, match="No cell nowhere"):
        screen.choices.tick(["nowhere"])


def test_the_unit_chosen_on_the_screen_sizes_the_map_and_is_kept(
    screen: MapsScreen, ctx: AppContext, tmp_path: Path
) -> None:
    _balcony_converted(screen, tmp_path, True)
    [metres] = screen.entries["balcony"].generated
    extent = _extent(metres.yaml)  # the same files are written again below
    assert extent == pytest.approx(13.0)
    assert "13.0 × 4.0 m" in screen.storeys_panel.table.value
    screen.choices.unit.value = "dm"  # the plan read as decimetres: a tenth of the size, shown before Convert
    table = screen.storeys_panel.table.value
    assert "<th>Size (plan in dm)</th>" in table and "1.3 × 0.4 m" in table and "13.0" not in table
    screen.refresh()  # a refresh before Convert does not undo what the user chose
    assert screen.choices.unit.value == "dm" and "1.3 × 0.4 m" in screen.storeys_panel.table.value
    _converted(screen)
    [tenth] = screen.entries["balcony"].generated
    assert _extent(tenth.yaml) == pytest.approx(extent / 10)
    assert tenth.width < metres.width / 5  # the grid too (plus its margin)
    screen.select("balcony")
    assert screen.choices.unit.value == "dm"
    assert read_choices(sidecar_doc(tenth.yaml)) == ConvertChoices("dm", ())
    screen.choices.unit.value = "mm"  # a unit far too small says so at once
    assert "0.013 × 0.004 m" in screen.storeys_panel.table.value
    screen.choices.unit.value = "auto"  # as the plan's sizes say: metres
    assert "<th>Size</th>" in screen.storeys_panel.table.value and "13.0 × 4.0 m" in screen.storeys_panel.table.value
    screen.choices.unit.value = "m"
    with pytest.raises(traitlets.TraitError):
        screen.choices.unit.value = "furlong"  # what a page could send: refused, the choice stays
    assert screen.choices.choices() == ConvertChoices("m", ())


def test_a_storeys_size_as_another_unit_would_read_it() -> None:
    from pmk_nb.library.info import StoreyInfo

    read_as_m = StoreyInfo("0", 4, 0, (0.0, 0.0, 13.0, 4.0), unit="m")
    assert read_as_m.size_as("auto") == read_as_m.size_as("m") == (13.0, 4.0)
    assert read_as_m.size_as("cm") == pytest.approx((0.13, 0.04))
    read_as_mm = StoreyInfo("0", 4, 0, (0.0, 0.0, 13.0, 4.0), unit="mm")  # 13 000 mm in the file
    assert read_as_mm.size_as("m") == pytest.approx((13000.0, 4000.0))
    assert StoreyInfo("0", 0, 0, None).size_as("dm") is None
