"""Issue 37 item 2: non-navigable cells in a layer that is not drawn are obstacles all the same.

Rooms A and B (layer P, joined by a transition) and a second layer that the graph does not link:
a column O (NonNavigableSpace, 1 x 1 m inside room A) and a zone Z inside room B. The second layer is
not drawn (the graph connects none of its cells), but O lies inside the drawn floor: it is drawn
occupied, the witness judges it, and ``pmk info`` names it. A column of that layer outside the
building (P) stays out.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.grid import FREE, OCCUPIED
from pmk_nb.indoorgml import CellKind, read_building
from pmk_nb.raster import rasterise_storey
from pmk_nb.witness import FindingKind, witness_grid
from tests.access.test_access_rules import NS, _cell

ROOMS = _cell("A", (0, 0, 5, 4)) + _cell("B", (5, 0, 10, 4))
OTHER = (
    _cell("O", (2, 1.5, 3, 2.5), tag="navi:NonNavigableSpace")
    + _cell("Z", (6, 1, 8, 3))
    + _cell("FAR", (20, 20, 21, 21), tag="navi:NonNavigableSpace")
)


def _states(layer: str, cells: tuple[str, ...], edges: str = "", *, v2: bool) -> str:
    state = "Node" if v2 else "State"
    nodes = "".join(
        f'<{state.lower()}Member><{state} gml:id="S{c}"><duality xlink:href="#{c}"/></{state}></{state.lower()}Member>'
        for c in cells
    )
    if v2:
        return f'<dualSpaceLayer><DualSpaceLayer gml:id="D{layer}">{nodes}{edges}</DualSpaceLayer></dualSpaceLayer>'
    return (
        f'<spaceLayerMember><SpaceLayer gml:id="{layer}"><nodes gml:id="N{layer}">{nodes}</nodes>'
        f'<edges gml:id="E{layer}">{edges}</edges></SpaceLayer></spaceLayerMember>'
    )


def _two_layers(tmp_path: Path, *, v2: bool) -> Path:
    trans = "Edge" if v2 else "Transition"
    edge = (
        f'<{trans.lower()}Member><{trans} gml:id="T0"><connects xlink:href="#SA"/><connects xlink:href="#SB"/>'
        f"</{trans}></{trans.lower()}Member>"
    )
    if v2:
        body = (
            f'<primalSpaceFeatures><PrimalSpaceLayer gml:id="P">{ROOMS}</PrimalSpaceLayer></primalSpaceFeatures>'
            f'<primalSpaceFeatures><PrimalSpaceLayer gml:id="X">{OTHER}</PrimalSpaceLayer></primalSpaceFeatures>'
            + _states("P", ("A", "B"), edge, v2=True)
            + _states("X", ("O", "Z", "FAR"), v2=True)
        )
    else:
        body = (
            f'<primalSpaceFeatures><PrimalSpaceFeatures gml:id="F1">{ROOMS}{OTHER}</PrimalSpaceFeatures>'
            f'</primalSpaceFeatures><multiLayeredGraph><MultiLayeredGraph gml:id="G"><spaceLayers gml:id="L">'
            + _states("P", ("A", "B"), edge, v2=False)
            + _states("X", ("O", "Z", "FAR"), v2=False)
            + "</spaceLayers></MultiLayeredGraph></multiLayeredGraph>"
        )
    path = tmp_path / ("v2.gml" if v2 else "v1.gml")
    path.write_text(f'<?xml version="1.0"?><IndoorFeatures {NS} gml:id="F">{body}</IndoorFeatures>')
    return path


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_a_column_in_a_layer_not_drawn_is_an_obstacle(tmp_path: Path, v2: bool) -> None:
    b = read_building(_two_layers(tmp_path, v2=v2), unit="m")
    [note] = [n for n in b.skipped_layers if n.id == "X"]
    assert note.cells == 3 and note.obstacles == 1
    assert b.cells["O"].kind is CellKind.NON_NAVIGABLE and "Z" not in b.cells and "FAR" not in b.cells
    storey = b.storeys[0].name
    grid = rasterise_storey(b, storey, 0.05)
    assert grid.value_at(2.5, 2.0) == OCCUPIED and grid.value_at(1.0, 1.0) == FREE
    report = witness_grid(b, grid, chair_width=0.7)
    kinds = {f.kind for f in report.findings}
    assert not kinds & {FindingKind.OBSTACLE_FREE, FindingKind.LEAK}, [f.describe() for f in report.findings]


@pytest.mark.parametrize("v2", [False, True], ids=["1.0", "2.0"])
def test_pmk_info_names_the_obstacles_drawn_from_a_layer(
    tmp_path: Path, v2: bool, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _two_layers(tmp_path, v2=v2)
    assert main(["info", str(path), "--unit", "m"]) == 0
    assert "drawn as obstacles: 1 cells from layer X" in capsys.readouterr().out
    assert main(["info", str(path), "--unit", "m", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [n["obstacles"] for n in doc["skipped_layers"] if n["id"] == "X"] == [1]
