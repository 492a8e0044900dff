"""Issue 31, rule 1: only the navigable layer makes floor and walls.

A thematic layer (Wi-Fi coverage, light zones) has cells that overlap the rooms and reach outside the
building. Drawn, its outlines would be walls across rooms and its cells floor outside. The navigable
layer is the one whose cells the navigation graph connects; the layers' words (1.x SpaceLayer class /
usage, 2.0 ThematicLayer theme) decide when each layer has a graph of its own. Each layer not drawn
is recorded with its reason; ``--layer`` draws another on request.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.errors import UnknownLayer
from pmk_nb.grid import FREE, OCCUPIED
from pmk_nb.indoorgml import read_building
from pmk_nb.raster import rasterise_storey
from tests.access.test_access_rules import NS, RES, _cell, _solid

ROOMS = _cell("A", (0, 0, 5, 4)) + _cell("B", (5, 0, 10, 4))
# Wi-Fi zones: cross room A at x = 4 and reach 8 m outside the building (43 % inside it: the old
# overlap rule kept them)
ZONES = _cell("W1", (4, 1, 18, 3)) + _cell("W2", (4, 3, 18, 3.5))
CROSSED = (4.0, 2.0)  # in room A, on the zones' outline
OUTSIDE = (15.0, 2.0)  # in a zone, outside the building


def _nodes(pairs: list[tuple[str, str]], cells: list[str], v2: bool) -> tuple[str, str]:
    state, trans = ("Node", "Edge") if v2 else ("State", "Transition")
    nodes = "".join(
        f'<{state.lower()}Member><{state} gml:id="S{c}"><duality xlink:href="#{c}"/></{state}></{state.lower()}Member>'
        for c in cells
    )
    edges = "".join(
        f'<{trans.lower()}Member><{trans} gml:id="T{a}{b}"><connects xlink:href="#S{a}"/>'
        f'<connects xlink:href="#S{b}"/></{trans}></{trans.lower()}Member>'
        for a, b in pairs
    )
    return nodes, edges


def _layered_plan(
    tmp_path: Path,
    *,
    v2: bool,
    zone_graph: bool,
    zone_words: str,
    zones: tuple[str, list[str]] = (ZONES, ["W1", "W2"]),
    draft: bool = False,
) -> Path:
    """Rooms A, B (joined by a transition) and two zone cells in a second layer: with its own graph
    (``zone_graph``) and words (1.x ``class``, 2.0 ``theme``; '' for none); ``zones``: other cells instead.
    2.0 as the final schema writes it (``layers/ThematicLayer/primalSpace``), or as the drafts did
    (``primalSpaceLayer``: the same name as the feature once lower-cased)."""
    primal, dual = ("primalSpaceLayer", "dualSpaceLayer") if draft else ("primalSpace", "dualSpace")
    room_nodes, room_edges = _nodes([("A", "B")], ["A", "B"], v2)
    zone_nodes, zone_edges = _nodes([tuple(zones[1][:2])] if zone_graph else [], zones[1], v2)
    if v2:

        def thematic(tid: str, theme: str, cells: str, nodes: str, edges: str) -> str:
            return (
                f'<layers><ThematicLayer gml:id="{tid}"><semanticExtension>false</semanticExtension>'
                f"{f'<theme>{theme}</theme>' if theme else ''}"
                f'<{primal}><PrimalSpaceLayer gml:id="P{tid}">{cells}</PrimalSpaceLayer></{primal}>'
                f'<{dual}><DualSpaceLayer gml:id="D{tid}">{nodes}{edges}</DualSpaceLayer></{dual}>'
                f"</ThematicLayer></layers>"
            )

        body = thematic("TOPO", "Physical", ROOMS, room_nodes, room_edges) + thematic(
            "L2", zone_words, zones[0], zone_nodes, zone_edges
        )
        ns = NS.replace("1.0/core", "2.0/core")
        text = f'<?xml version="1.0"?><IndoorFeatures {ns} gml:id="F">{body}</IndoorFeatures>'
    else:

        def layer(lid: str, words: str, nodes: str, edges: str) -> str:
            return (
                f'<spaceLayerMember><SpaceLayer gml:id="{lid}">{f"<class>{words}</class>" if words else ""}'
                f'<nodes gml:id="N{lid}">{nodes}</nodes><edges gml:id="E{lid}">{edges}</edges></SpaceLayer>'
                f"</spaceLayerMember>"
            )

        graph = layer("TOPO", "", room_nodes, room_edges) + layer("L2", zone_words, zone_nodes, zone_edges)
        text = (
            f'<?xml version="1.0"?><IndoorFeatures {NS} gml:id="F"><primalSpaceFeatures>'
            f'<PrimalSpaceFeatures gml:id="P">{ROOMS}{zones[0]}</PrimalSpaceFeatures></primalSpaceFeatures>'
            f'<multiLayeredGraph><MultiLayeredGraph gml:id="G"><spaceLayers gml:id="L">{graph}</spaceLayers>'
            f"</MultiLayeredGraph></multiLayeredGraph></IndoorFeatures>"
        )
    path = tmp_path / ("v2.gml" if v2 else "v1.gml")
    path.write_text(text)
    return path


# (v2, zone layer has its own graph, its words): the graph decides, or (both have graphs) the words do
CASES = [
    pytest.param(False, False, "", id="1.x-graph-connects-rooms-only"),
    pytest.param(False, True, "SENSOR", id="1.x-class-SENSOR"),
    pytest.param(True, False, "", id="2.0-graph-connects-rooms-only"),
    pytest.param(True, True, "Virtual", id="2.0-theme-Virtual"),
    pytest.param(True, True, "other: WiFiCoverage", id="2.0-theme-other"),
    # a graph of its own and no words: its cells straddle the rooms' walls, as no room or wing does
    pytest.param(False, True, "", id="1.x-own-graph-no-words"),
    pytest.param(True, True, "", id="2.0-own-graph-no-words"),
]


def _zone_layer(v2: bool) -> str:
    return "PL2" if v2 else "L2"


@pytest.mark.parametrize(("v2", "zone_graph", "words"), CASES)
def test_a_thematic_layer_makes_no_floor_and_no_walls(tmp_path: Path, v2: bool, zone_graph: bool, words: str) -> None:
    b = read_building(_layered_plan(tmp_path, v2=v2, zone_graph=zone_graph, zone_words=words), unit="m")
    assert sorted(b.cells) == ["A", "B"]
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(*CROSSED) == FREE  # no wall where the zones' outline crosses room A
    assert grid.value_at(*OUTSIDE) != FREE  # no floor where the zones reach outside
    [note] = b.skipped_layers
    assert (note.id, note.cells) == (_zone_layer(v2), 2)
    # said, and by the evidence that decided
    assert ("graph connects none" in note.reason) if not zone_graph else ((words or "partly outside") in note.reason)


@pytest.mark.parametrize(("v2", "zone_graph", "words"), CASES)
def test_pmk_info_lists_the_layer_not_drawn_and_why(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], v2: bool, zone_graph: bool, words: str
) -> None:
    path = _layered_plan(tmp_path, v2=v2, zone_graph=zone_graph, zone_words=words)
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "layers not drawn (1" in out and f"- {_zone_layer(v2)}, 2 cells: " in out
    assert main(["info", str(path), "--json"]) == 0
    [note] = json.loads(capsys.readouterr().out)["skipped_layers"]
    assert note["id"] == _zone_layer(v2) and note["cells"] == 2 and note["reason"]


SPELLINGS = [(False, False), (True, False), (True, True)]


@pytest.mark.parametrize(("v2", "draft"), SPELLINGS, ids=["1.x", "2.0", "2.0-draft"])
def test_layer_option_draws_the_named_layer(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], v2: bool, draft: bool
) -> None:
    path = _layered_plan(tmp_path, v2=v2, zone_graph=False, zone_words="", draft=draft)
    asked = "L2"  # the 1.x SpaceLayer, or the 2.0 ThematicLayer holding the zones' primal layer
    b = read_building(path, unit="m", layers=[asked])
    assert sorted(b.cells) == ["W1", "W2"]
    assert [n.id for n in b.skipped_layers] == ["PTOPO" if v2 else "TOPO"]
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(*OUTSIDE) == FREE
    assert main(["info", str(path), "--layer", asked, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["cells"] == 2


def test_an_unknown_layer_is_a_typed_error_listing_the_layers(tmp_path: Path) -> None:
    path = _layered_plan(tmp_path, v2=False, zone_graph=False, zone_words="")
    with pytest.raises(UnknownLayer) as err:
        read_building(path, unit="m", layers=["lights"])
    assert err.value.layer == "lights" and err.value.known == ["TOPO", "L2"]
    assert main(["check", str(path), "--layer", "lights"]) == 2


@pytest.mark.parametrize("v2", [False, True], ids=["1.x", "2.0"])
def test_a_layer_of_non_navigable_spaces_is_drawn_as_obstacles(tmp_path: Path, v2: bool) -> None:
    """Columns and installations in a layer of their own (KU Central Plaza: layer Nonnavi, 24 cells) are
    obstacles wherever they stand, though no transition joins them."""
    columns = _cell("C1", (2, 1, 3, 2), "NonNavigableSpace") + _cell("C2", (7, 1, 8, 2), "NonNavigableSpace")
    path = _layered_plan(tmp_path, v2=v2, zone_graph=False, zone_words="", zones=(columns, ["C1", "C2"]))
    b = read_building(path, unit="m")
    assert sorted(b.cells) == ["A", "B", "C1", "C2"] and b.skipped_layers == []
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(2.5, 1.5) == OCCUPIED and grid.value_at(7.5, 1.5) == OCCUPIED
    assert grid.value_at(1.0, 3.0) == FREE


def test_the_layer_choice_is_kept_in_the_rooms_files_and_the_maps_screen_lists_layers_not_drawn(
    tmp_path: Path,
) -> None:
    from pmk_nb.access import sidecar_doc
    from pmk_nb.library import MapsFolder
    from pmk_nb.library.choices import ConvertChoices, read_choices
    from pmk_nb.ui.maps.access import AccessPanel

    maps = MapsFolder(tmp_path / "maps")
    entry = maps.import_file(_layered_plan(tmp_path, v2=False, zone_graph=False, zone_words=""), "zones")
    [gm] = maps.convert(entry.name, 0.1, unit="m")
    doc = sidecar_doc(gm.yaml)
    assert [n["id"] for n in doc["skipped_layers"]] == ["L2"] and read_choices(doc) == ConvertChoices("m")
    panel = AccessPanel()
    panel.show(maps.entry("zones"), [doc])
    assert "Layers not drawn" in panel.text.value and "L2 (2 cells): the navigation graph connects none" in (
        panel.text.value
    )
    [gm] = maps.convert(entry.name, 0.1, unit="m", layers=["L2"])
    doc = sidecar_doc(gm.yaml)
    assert read_choices(doc) == ConvertChoices("m", (), ("L2",)) and {r["id"] for r in doc["rooms"]} == {"W1", "W2"}


@pytest.mark.parametrize("v2", [False, True], ids=["1.x", "2.0"])
def test_storeys_drawn_as_layers_of_their_own_are_all_drawn(tmp_path: Path, v2: bool) -> None:
    """Two layers over the same ground at different heights are two storeys, not a repeat of one."""
    lower = _solid("A", (0, 0, 5, 4), 0, 3) + _solid("B", (5, 0, 10, 4), 0, 3)
    upper = _solid("W1", (0, 0, 4, 4), 3, 6) + _solid("W2", (4, 0, 10, 4), 3, 6)
    path = _layered_plan(tmp_path, v2=v2, zone_graph=True, zone_words="", zones=(upper, ["W1", "W2"]))
    path.write_text(path.read_text().replace(ROOMS, lower))
    b = read_building(path, unit="m")
    assert sorted(b.cells) == ["A", "B", "W1", "W2"] and b.skipped_layers == []
    assert len(b.storeys) == 2 and sorted(len(s.cell_ids) for s in b.storeys) == [2, 2]


def test_pmk_convert_says_which_layers_it_did_not_draw(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _layered_plan(tmp_path, v2=True, zone_graph=True, zone_words="Virtual")
    out = tmp_path / "maps"
    assert main(["convert", str(path), "-r", "0.1", "--out", str(out), "--no-progress", "--unit", "m"]) == 0
    text = capsys.readouterr().out
    assert "layers not drawn (1; pmk convert --layer NAME draws one)" in text and "- PL2, 2 cells: " in text
    assert "theme Virtual" in text
