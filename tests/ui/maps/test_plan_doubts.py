"""The Maps screen says a plan's doubts (issue 31): layers not drawn, a lost graph, a suspect unit.

A kiosk user has no ``pmk info`` or ``pmk check``: before converting, the storeys panel lists what the reader
doubts, and the layers with cells are offered to draw (what ``--layer`` does); after converting, the access
panel names the unit first when it makes every door absurd, and says "nothing checked" for a lost graph.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import traitlets

from pmk_nb.access import sidecar_doc
from pmk_nb.errors import LibraryError
from pmk_nb.indoorgml import read_building
from pmk_nb.library.choices import read_choices
from pmk_nb.library.info import LayerOption, layer_options, plan_notes
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.maps.screen import MapsScreen
from tests.access.test_access_rules import ROOMS, _graph, _plan
from tests.helpers import wait_until
from tests.indoorgml.test_layers_rule import _layered_plan
from tests.indoorgml.test_units_evidence import _door, _house
from tests.library.test_convert_choices import _converted

V = pytest.mark.parametrize("v2", [False, True], ids=["1.x", "2.0"])
THEMATIC = "a thematic layer"


def zoned_plan(tmp_path: Path, v2: bool = False) -> Path:
    """Rooms A, B in layer TOPO joined by the graph, and a sensor layer L2 whose zones cross room A."""
    return _layered_plan(tmp_path, v2=v2, zone_graph=True, zone_words="Virtual" if v2 else "SENSOR")


def lost_graph_plan(tmp_path: Path) -> Path:
    """Two rooms whose two transitions name states that are not in the file."""
    path = _plan(tmp_path, ROOMS, _graph([("A", "B"), ("B", "A")]))
    path.write_text(path.read_text().replace('connects xlink:href="#S', 'connects xlink:href="#OTHER-'))
    return path


def cm_house(tmp_path: Path) -> Path:
    """A 10 x 8 m house drawn in centimetres, with four 90 cm doors: read in metres, every door is 90 m."""
    doors = "".join(_door(f"D{i}", (x, 350), (x + 90, 350)) for i, x in enumerate((100, 600)))
    doors += "".join(_door(f"E{i}", (x, 450), (x + 90, 450)) for i, x in enumerate((100, 600)))
    path = _house(tmp_path, "cm", v2=False, faces=False)
    path.write_text(path.read_text().replace("</PrimalSpaceFeatures>", f"{doors}</PrimalSpaceFeatures>"))
    return path


def _storeys_shown(screen: MapsScreen, name: str, data: bytes) -> None:
    screen.import_bytes(f"{name}.gml", data)
    screen.select(name)
    wait_until(  # the storeys, then (in the same background callback) the layers offered from them
        lambda: (
            screen.storeys_panel.storeys is not None and screen.choices._offered == tuple(screen.storeys_panel.layers())
        ),
        what="storeys read in the background and their layers offered",
    )


@V
def test_plan_notes_name_each_layer_not_drawn_and_the_layers_offered(tmp_path: Path, v2: bool) -> None:
    b = read_building(zoned_plan(tmp_path, v2))
    topo, zones = ("PTOPO", "PL2") if v2 else ("TOPO", "L2")  # 2.0: the ThematicLayer's PrimalSpaceLayer
    [note] = plan_notes(b)
    assert note.startswith(f"Layer '{zones}' (2 cells) not drawn: ") and THEMATIC in note
    assert [(o.id, o.cells, o.drawn) for o in layer_options(b)] == [(topo, 2, True), (zones, 2, False)]


def test_plan_notes_say_a_lost_graph_and_a_suspect_unit_first(tmp_path: Path) -> None:
    (tmp_path / "g").mkdir()
    [lost] = plan_notes(read_building(lost_graph_plan(tmp_path / "g"), unit="m"))
    assert lost == "2 of 2 transitions name states that are not in the file: the navigation graph was not used"
    house = cm_house(tmp_path)
    assert plan_notes(read_building(house)) == ()  # read in its own unit: nothing to doubt
    [first, *_] = plan_notes(read_building(house, unit="m"))
    assert first.startswith("all doors are 90 m wide in metres") and "--unit cm" in first


def test_the_screen_lists_the_doubts_and_draws_a_layer_ticked_on_it(screen: MapsScreen, tmp_path: Path) -> None:
    _storeys_shown(screen, "zoned", zoned_plan(tmp_path).read_bytes())
    table = screen.storeys_panel.table.value
    assert "Before you convert" in table and "Layer &#x27;L2&#x27; (2 cells) not drawn" in table
    assert "tick it under <i>Layers to draw</i>" in table
    boxes = {b.description: b.value for b in screen.choices.layers.children}
    assert boxes == {"TOPO": True, "L2": False} and screen.choices.layers_box.layout.display == "flex"
    assert screen.choices.choices().layers == ()  # what the converter draws by itself: nothing asked
    screen.choices.tick_layers([])
    assert "Tick at least one layer" in screen.choices.layers_error.value
    with pytest.raises(LibraryError, match="Tick at least one layer"):
        screen.choices.choices()
    with pytest.raises(LibraryError, match="No layer nowhere"):
        screen.choices.tick_layers(["nowhere"])
    screen.choices.tick_layers(["TOPO", "L2"])
    _converted(screen)
    [gm] = screen.entries["zoned"].generated
    doc = sidecar_doc(gm.yaml) or {}
    assert read_choices(doc) is not None and read_choices(doc).layers == ("TOPO", "L2")  # type: ignore[union-attr]
    assert {r["id"] for r in doc["rooms"]} == {"A", "B", "W1", "W2"}  # the sensor zones drawn, as asked
    screen.select("zoned")  # chosen again: the layers asked for come back ticked
    # the boxes of before may still be up until the background read offers them afresh: wait for the end state
    offered = lambda: {b.description: b.value for b in screen.choices.layers.children}  # noqa: E731
    wait_until(lambda: offered() == {"TOPO": True, "L2": True}, what="layers offered again, as asked")
    screen.choices.tick_layers(["TOPO"])  # back to the navigable layer only: nothing asked
    assert screen.choices.choices().layers == ()


def test_a_refresh_keeps_the_layers_the_user_ticked(screen: MapsScreen, tmp_path: Path) -> None:
    _storeys_shown(screen, "zoned", zoned_plan(tmp_path).read_bytes())
    screen.choices.tick_layers(["L2"])
    screen.refresh()
    assert {b.description: b.value for b in screen.choices.layers.children} == {"TOPO": False, "L2": True}
    assert screen.choices.choices().layers == ("L2",)


def test_a_page_cannot_set_a_layer_box_to_a_non_boolean(screen: MapsScreen, ctx: AppContext, tmp_path: Path) -> None:
    _storeys_shown(screen, "zoned", zoned_plan(tmp_path).read_bytes())
    box = screen.choices.layers.children[1]
    with pytest.raises(traitlets.TraitError):  # refused by the trait's type before any callback runs
        box.value = "yes"  # type: ignore[assignment]
    assert box.value is False


def test_a_one_layer_plan_offers_no_layer_choice(screen: MapsScreen, tmp_path: Path) -> None:
    _storeys_shown(screen, "rooms", _plan(tmp_path, ROOMS, _graph([("A", "B")])).read_bytes())
    assert screen.choices.layers.children == () and screen.choices.layers_box.layout.display == "none"
    assert "Before you convert" not in screen.storeys_panel.table.value


@pytest.mark.slow
def test_the_access_panel_names_the_unit_before_any_door_and_a_lost_graph(screen: MapsScreen, tmp_path: Path) -> None:
    _storeys_shown(screen, "house", cm_house(tmp_path).read_bytes())
    screen.choices.unit.value = "m"  # the user picks the wrong unit: a 1000 x 800 m plan, drawn coarse
    screen.resolution.value = "0.5"
    _converted(screen)
    text = screen.access_panel.text.value
    assert "Suspect the unit first:" in text and "all doors are 90 m wide in metres" in text
    assert text.index("Suspect the unit first") < text.index("passages fit")
    _storeys_shown(screen, "lost", lost_graph_plan(tmp_path).read_bytes())
    assert "the navigation graph was not used" in screen.storeys_panel.table.value
    screen.resolution.value = "0.05"
    _converted(screen)
    text = screen.access_panel.text.value
    assert "nothing checked" in text and "2 of 2 transitions name states that are not in the file" in text
    assert "passages fit" not in text


def test_layers_without_cells_are_neither_offered_nor_noted() -> None:
    from tests.shared_data import INDOORGML_DATA

    b = read_building(INDOORGML_DATA / "pnu_abc_3floors_4layers.gml")
    assert layer_options(b) == (LayerOption("base", "", len(b.cells), True),)  # the others are graphs only
    assert plan_notes(b) == ()  # its three other layers are graphs without cells: nothing a map could draw
