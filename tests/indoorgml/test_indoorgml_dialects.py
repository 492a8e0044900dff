"""Dialects and quirks: 1.1 level, 2.0 PrimalSpaceLayer, storey tags, prefixes, rings, posList dims."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from lxml import etree
from shapely.geometry import Point

from pmk_nb.indoorgml import CellKind, read_building

SAMPLE = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"
NS = (
    'xmlns="http://www.opengis.net/indoorgml/1.0/core" xmlns:gml="http://www.opengis.net/gml/3.2" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:navi="http://www.opengis.net/indoorgml/1.0/navigation"'
)


def _square(x: float, y: float, size: float, z: float | None = None) -> str:
    pts = [(x, y), (x + size, y), (x + size, y + size), (x, y + size), (x, y)]
    if z is None:
        return " ".join(f"{a} {b}" for a, b in pts)
    return " ".join(f"{a} {b} {z}" for a, b in pts)


def _cell(
    cid: str, x: float, y: float, extra: str = "", tag: str = "CellSpace", z: float | None = None, size: float = 5.0
) -> str:
    dim = "" if z is None else ' srsDimension="3"'
    return (
        f'<cellSpaceMember><{tag} gml:id="{cid}">{extra}<cellSpaceGeometry><Geometry2D><gml:Polygon>'
        f"<gml:exterior><gml:LinearRing><gml:posList{dim}>{_square(x, y, size, z)}</gml:posList>"
        f"</gml:LinearRing></gml:exterior></gml:Polygon></Geometry2D></cellSpaceGeometry></{tag}></cellSpaceMember>"
    )


def _doc(tmp_path: Path, cells: str, name: str = "t.gml", layer: str = "PrimalSpaceFeatures") -> Path:
    text = (
        f'<?xml version="1.0"?><IndoorFeatures {NS} gml:id="F"><primalSpaceFeatures>'
        f'<{layer} gml:id="P1">{cells}</{layer}></primalSpaceFeatures></IndoorFeatures>'
    )
    path = tmp_path / name
    path.write_text(text)
    return path


def test_level_element_gives_storeys(tmp_path: Path) -> None:
    cells = (
        _cell("A", 0, 0, "<level>EG</level>")
        + _cell("B", 6, 0, "<level>EG</level>")
        + _cell("C", 0, 0, "<level>OG</level>", z=3.0)
    )
    b = read_building(_doc(tmp_path, cells), unit="m")
    assert b.version == "1.1"
    assert {s.name: len(s.cell_ids) for s in b.storeys} == {"EG": 2, "OG": 1}
    assert [s.source for s in b.storeys] == ["level", "level"]


def test_indoorgml2_primal_space_layer(tmp_path: Path) -> None:
    cells = _cell("A", 0, 0, "<level>1</level>") + _cell("B", 0, 6, "<level>2</level>")
    b = read_building(_doc(tmp_path, cells, layer="PrimalSpaceLayer"), unit="m")
    assert b.version == "2.0"
    assert [s.name for s in b.storeys] == ["1", "2"]
    assert {c.layer for c in b.cells.values()} == {"P1"}


def test_description_and_extension_storeys(tmp_path: Path) -> None:
    cells = (
        _cell("A", 0, 0, "<gml:description>level=4; use=office</gml:description>")
        + _cell("B", 6, 0, '<gml:description>storey="F1":</gml:description>')
        + _cell("C", 0, 6, '<storey:CellSpaceStorey xmlns:storey="urn:x-pnu:storey">F2</storey:CellSpaceStorey>')
    )
    b = read_building(_doc(tmp_path, cells), unit="m")
    assert {s.name: s.source for s in b.storeys} == {"4": "description", "F1": "description", "F2": "extension"}


def test_plain_cells_are_navigable_and_door_named_cells_are_connections(tmp_path: Path) -> None:
    cells = _cell("R", 0, 0) + _cell("Door1", 5, 2, size=1.0) + _cell("X", 10, 0, tag="navi:NonNavigableSpace")
    b = read_building(_doc(tmp_path, cells), unit="m")
    assert b.cells["R"].kind is CellKind.NAVIGABLE
    assert b.cells["Door1"].kind is CellKind.CONNECTION
    assert b.cells["X"].kind is CellKind.NON_NAVIGABLE


def test_unclosed_rings_and_repeated_points(tmp_path: Path) -> None:
    ring = "0 0 4 0 4 0 4 4 0 4"  # unclosed, (4 0) repeated
    cell = (
        '<cellSpaceMember><CellSpace gml:id="U"><Geometry2D><gml:Polygon><gml:exterior><gml:LinearRing>'
        f'<gml:posList srsDimension="2">{ring}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon>'
        "</Geometry2D></CellSpace></cellSpaceMember>"
    )
    b = read_building(_doc(tmp_path, cell), unit="m")
    assert b.cells["U"].footprint.area == pytest.approx(16.0)
    assert any("not closed" in w for w in b.warnings)
    assert any("repeated" in w for w in b.warnings)


@pytest.mark.parametrize("dim", [2, 3])
def test_poslist_without_srsdimension(tmp_path: Path, dim: int) -> None:
    z = 0.0 if dim == 3 else None
    text = _cell("A", 0, 0, z=z, size=6.0).replace(' srsDimension="3"', "")
    b = read_building(_doc(tmp_path, text), unit="m")
    assert b.cells["A"].footprint.area == pytest.approx(36.0)
    assert b.cells["A"].footprint.bounds == pytest.approx((0, 0, 6, 6))


def test_polygon_with_hole(tmp_path: Path) -> None:
    cell = (
        '<cellSpaceMember><CellSpace gml:id="H"><Geometry2D><gml:Polygon><gml:exterior><gml:LinearRing>'
        f"<gml:posList>{_square(0, 0, 10)}</gml:posList></gml:LinearRing></gml:exterior>"
        f"<gml:interior><gml:LinearRing><gml:posList>{_square(4, 4, 2)}</gml:posList></gml:LinearRing>"
        "</gml:interior></gml:Polygon></Geometry2D></CellSpace></cellSpaceMember>"
    )
    b = read_building(_doc(tmp_path, cell), unit="m")
    fp = b.cells["H"].footprint
    assert fp.area == pytest.approx(96.0)
    assert not fp.contains(Point(5, 5)) and fp.contains(Point(1, 1))


def test_solid_footprint_and_vertical_door_boundary(tmp_path: Path) -> None:
    def face(pts: list[tuple[float, float, float]]) -> str:
        ring = " ".join(f"{x} {y} {z}" for x, y, z in [*pts, pts[0]])
        return (
            f'<gml:surfaceMember><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList srsDimension="3">'
            f"{ring}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></gml:surfaceMember>"
        )

    box = [face([(0, 0, 0), (0, 4, 0), (4, 4, 0), (4, 0, 0)]), face([(0, 0, 3), (4, 0, 3), (4, 4, 3), (0, 4, 3)])]
    box += [face([(0, 0, 0), (4, 0, 0), (4, 0, 3), (0, 0, 3)]), face([(4, 0, 0), (4, 4, 0), (4, 4, 3), (4, 0, 3)])]
    cell = (
        '<cellSpaceMember><CellSpace gml:id="S"><cellSpaceGeometry><Geometry3D><gml:Solid><gml:exterior>'
        f"<gml:Shell>{''.join(box)}</gml:Shell></gml:exterior></gml:Solid></Geometry3D></cellSpaceGeometry>"
        '<partialboundedBy xlink:href="#B1"/></CellSpace></cellSpaceMember>'
        '<cellSpaceBoundaryMember><CellSpaceBoundary gml:id="B1"><gml:name>front door</gml:name>'
        "<cellSpaceBoundaryGeometry><geometry3D><gml:Polygon><gml:exterior><gml:LinearRing>"
        '<gml:posList srsDimension="3">1 0 0 2 0 0 2 0 2 1 0 2 1 0 0</gml:posList></gml:LinearRing></gml:exterior>'
        "</gml:Polygon></geometry3D></cellSpaceBoundaryGeometry></CellSpaceBoundary></cellSpaceBoundaryMember>"
    )
    b = read_building(_doc(tmp_path, cell), unit="m")
    assert b.cells["S"].footprint.area == pytest.approx(16.0)
    assert (b.cells["S"].z_min, b.cells["S"].z_max) == (0.0, 3.0)
    door = b.boundaries["B1"]
    assert door.is_door and door.geometry.geom_type == "LineString"
    assert door.geometry.length == pytest.approx(1.0)
    assert door.storey == b.storeys[0].name


def test_self_intersecting_polygon_is_repaired_with_warning(tmp_path: Path) -> None:
    bowtie = "0 0 4 4 4 0 0 4 0 0"
    cell = (
        '<cellSpaceMember><CellSpace gml:id="BOW"><Geometry2D><gml:Polygon><gml:exterior><gml:LinearRing>'
        f"<gml:posList>{bowtie}</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></Geometry2D>"
        "</CellSpace></cellSpaceMember>"
    ) + _cell("OK", 10, 0)
    b = read_building(_doc(tmp_path, cell), unit="m")
    fp = b.cells["BOW"].footprint
    assert fp.is_valid and fp.area == pytest.approx(8.0)
    assert any("'BOW'" in w and "repaired" in w for w in b.warnings)


def test_zero_area_cell_is_skipped_with_warning(tmp_path: Path) -> None:
    flat = (
        '<cellSpaceMember><CellSpace gml:id="ZERO"><Geometry2D><gml:Polygon><gml:exterior><gml:LinearRing>'
        "<gml:posList>0 0 4 0 8 0 0 0</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></Geometry2D>"
        "</CellSpace></cellSpaceMember>"
    )
    b = read_building(_doc(tmp_path, flat + _cell("OK", 10, 0)), unit="m")
    assert "ZERO" not in b.cells and "OK" in b.cells
    assert any("'ZERO'" in w and "zero-area" in w for w in b.warnings)


def test_z_clustering_names_storeys_bottom_up(tmp_path: Path) -> None:
    cells = _cell("A", 0, 0, z=0.0) + _cell("B", 6, 0, z=0.9) + _cell("C", 0, 0, z=3.0) + _cell("D", 0, 0, z=6.1)
    b = read_building(_doc(tmp_path, cells), unit="m")
    assert [(s.name, len(s.cell_ids), s.source) for s in b.storeys] == [("0", 2, "z"), ("1", 1, "z"), ("2", 1, "z")]
    assert b.storeys[2].elevation == pytest.approx(6.1)


def test_xlink_member_and_state_duality(tmp_path: Path) -> None:
    cells = _cell("A", 0, 0) + '<cellSpaceMember xlink:href="#A"/>'
    text = (
        _doc(tmp_path, cells)
        .read_text()
        .replace(
            "</primalSpaceFeatures>",
            "</primalSpaceFeatures><multiLayeredGraph><MultiLayeredGraph gml:id='M'><spaceLayers>"
            "<spaceLayerMember><SpaceLayer gml:id='L'><nodes><stateMember><State gml:id='SA'>"
            "<duality xlink:href='#A'/><geometry><gml:Point><gml:pos>2.5 2.5</gml:pos></gml:Point></geometry>"
            "</State></stateMember></nodes></SpaceLayer></spaceLayerMember></spaceLayers></MultiLayeredGraph>"
            "</multiLayeredGraph>",
        )
    )
    path = tmp_path / "x.gml"
    path.write_text(text)
    b = read_building(path, unit="m")
    assert list(b.cells) == ["A"] and b.cells["A"].layer == "L"
    assert b.graph.states["SA"].cell_id == "A" and b.graph.states["SA"].point == (2.5, 2.5, 0.0)


def _canonical(path: Path) -> tuple:
    b = read_building(path)
    cells = sorted(
        (c.id, c.kind.value, c.storey, tuple(round(v, 6) for v in c.footprint.bounds)) for c in b.cells.values()
    )
    return (b.unit, b.version, cells, b.georef.translation, b.georef.rotation, len(b.graph.transitions))


def test_unusual_prefixes_and_default_namespace_give_same_model(tmp_path: Path) -> None:
    text = SAMPLE.read_text()
    renamed = text.replace("indoorCore:", "c:").replace("xmlns:indoorCore=", "xmlns:c=")
    renamed = renamed.replace("indoorNavi:", "nv:").replace("xmlns:indoorNavi=", "xmlns:nv=")
    renamed = renamed.replace("gml:", "g:").replace("xmlns:gml=", "xmlns:g=")
    default = re.sub(r"indoorCore:", "", text).replace("xmlns:indoorCore=", "xmlns=")
    for i, variant in enumerate((renamed, default)):
        path = tmp_path / f"v{i}.gml"
        path.write_text(variant)
        etree.parse(str(path))  # still well-formed XML
        assert _canonical(path) == _canonical(SAMPLE)


def test_lower_case_class_names_are_tolerated(tmp_path: Path) -> None:
    text = SAMPLE.read_text().replace("indoorCore:SpaceLayer", "indoorCore:spaceLayer")
    text = text.replace("indoorCore:State ", "indoorCore:state ").replace("</indoorCore:State>", "</indoorCore:state>")
    path = tmp_path / "lc.gml"
    path.write_text(text)
    assert _canonical(path) == _canonical(SAMPLE)


def test_alma_crs_metadata_and_lla(tmp_path: Path) -> None:
    text = SAMPLE.read_text()
    meta = (
        '<gml:GenericMetaData><alma:crs xmlns:alma="http://www.idsia.ch/alma">'
        "<alma:translation><gml:pos>1000 -500</gml:pos></alma:translation><alma:rotation>-90</alma:rotation>"
        "<alma:lla>46.0 8.95 273.0</alma:lla></alma:crs></gml:GenericMetaData>"
    )
    text = re.sub(r"<gml:GenericMetaData>.*?</gml:GenericMetaData>", meta, text, flags=re.DOTALL)
    path = tmp_path / "crs.gml"
    path.write_text(text)
    b = read_building(path)
    assert b.unit == "cm"
    assert b.georef.translation == pytest.approx((10.0, -5.0))
    assert b.georef.rotation == -90.0 and b.georef.lla == (46.0, 8.95, 273.0)


def test_alma_plain_cellspace_is_an_obstacle(tmp_path: Path) -> None:
    """ALMA convention: the original app painted every polygon that is not navi space black."""
    text = SAMPLE.read_text().replace("indoorNavi:NonNavigableSpace", "indoorCore:CellSpace")
    path = tmp_path / "plain.gml"
    path.write_text(text)
    assert read_building(path).cells["DESK"].kind is CellKind.NON_NAVIGABLE


def test_indoorgml2_node_and_edge_graph(tmp_path: Path) -> None:
    graph = (
        "<dualSpaceLayer><DualSpaceLayer gml:id='D'><nodeMember><Node gml:id='N1'><duality xlink:href='#A'/>"
        "</Node></nodeMember><nodeMember><Node gml:id='N2'><duality xlink:href='#B'/></Node></nodeMember>"
        "<edgeMember><Edge gml:id='E1'><connects xlink:href='#N1'/><connects xlink:href='#N2'/></Edge>"
        "</edgeMember></DualSpaceLayer></dualSpaceLayer>"
    )
    path = _doc(tmp_path, _cell("A", 0, 0) + _cell("B", 5, 0), layer="PrimalSpaceLayer")
    path.write_text(path.read_text().replace("</IndoorFeatures>", graph + "</IndoorFeatures>"))
    b = read_building(path, unit="m")
    assert set(b.graph.states) == {"N1", "N2"} and b.graph.states["N1"].cell_id == "A"
    assert [(t.source, t.target) for t in b.graph.transitions] == [("N1", "N2")]
