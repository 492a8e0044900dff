"""The pre-standard 0.8/0.9 drafts (namespace "indoorCore", as the 2016 archive of the IndoorGML site holds
FJK-Haus in its 0.9.2 folder): each cell is the State's ``duality`` element itself, with its own gml:id
and a Geometry3D/2D inside, and transitions name their states with ``start``/``end``. They were refused
as "0 cell elements ... only a navigation graph" although every cell's solid is in the file.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.access import check_grid
from pmk_nb.grid import FREE, OCCUPIED
from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.model import CellKind
from pmk_nb.raster import rasterise_storey

HEAD = (
    '<?xml version="1.0" standalone="yes"?><indoorcore:MultiLayeredGraph gml:id="MG1" '
    'xmlns:gml="http://www.opengis.net/gml/3.2" xmlns:xlink="http://www.w3.org/1999/xlink" '
    'xmlns:indoorcore="indoorCore"><spaceLayers gml:id="S1"><spaceLayerMember>'
    '<indoorcore:SpaceLayer gml:id="SL1">'
)
TAIL = "</indoorcore:SpaceLayer></spaceLayerMember></spaceLayers></indoorcore:MultiLayeredGraph>"


def _box(x0: float, x1: float, z: float) -> str:
    pts = [(x0, 0), (x1, 0), (x1, 4), (x0, 4), (x0, 0)]
    ring = "".join(f"<gml:pos>{x} {y} {z}</gml:pos>" for x, y in pts)
    poly = f"<gml:Polygon><gml:exterior><gml:LinearRing>{ring}</gml:LinearRing></gml:exterior></gml:Polygon>"
    return f"<gml:surfaceMember>{poly}</gml:surfaceMember>"


def _state(sid: str, x0: float, x1: float) -> str:
    shell = f"<gml:Shell>{_box(x0, x1, 0)}{_box(x0, x1, 2.8)}</gml:Shell>"
    solid = f"<gml:Solid><gml:exterior>{shell}</gml:exterior></gml:Solid>"
    return (
        f'<nodes gml:id="N{sid}"><stateMember><indoorcore:State gml:id="{sid}"><gml:name>{sid}</gml:name>'
        f'<duality gml:id="S{sid}"><gml:name>{sid}</gml:name><Geometry3D>{solid}</Geometry3D></duality>'
        f'<connects xlink:href="#T0"/><geometry><gml:Point><gml:pos>{(x0 + x1) / 2} 2 1</gml:pos></gml:Point>'
        f"</geometry></indoorcore:State></stateMember></nodes>"
    )


EDGE = (
    '<edges gml:id="E0"><transitionMember><indoorcore:Transition gml:id="T0"><weight>1</weight>'
    '<start xlink:href="#R1"/><end xlink:href="#R2"/><geometry><gml:LineString><gml:pos>2.5 2 1</gml:pos>'
    "<gml:pos>7.5 2 1</gml:pos></gml:LineString></geometry></indoorcore:Transition></transitionMember></edges>"
)


@pytest.fixture
def draft(tmp_path: Path) -> Path:
    path = tmp_path / "draft.gml"
    path.write_text(HEAD + _state("R1", 0, 5) + _state("R2", 5, 10) + EDGE + TAIL)
    return path


def test_draft_cells_inside_state_duality_are_read(draft: Path) -> None:
    b = read_building(draft, unit="m")
    assert b.version == "0.8/0.9 draft"
    assert {c.id: c.kind for c in b.cells.values()} == {"SR1": CellKind.NAVIGABLE, "SR2": CellKind.NAVIGABLE}
    assert b.graph.states["R1"].cell_id == "SR1"
    assert [(k.a, k.b) for k in b.links] == [("SR1", "SR2")]


def test_draft_plan_converts_with_its_opening(draft: Path) -> None:
    b = read_building(draft, unit="m")
    storey = b.storeys[0].name
    grid = rasterise_storey(b, storey, 0.05)
    assert grid.value_at(2.5, 2.0) == FREE and grid.value_at(7.5, 2.0) == FREE
    assert grid.value_at(5.0, 2.0) == FREE and grid.value_at(5.0, 0.3) == OCCUPIED  # door where the line crosses
    report = check_grid(b, storey, grid, chair_width=0.7)
    assert report.counts()["links"] == 1 and report.ok
