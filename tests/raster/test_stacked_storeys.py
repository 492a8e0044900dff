"""Typical floors drawn in 2D: every storey has the same outlines, told apart only by their storey tags.

A door line repeated on each storey is that storey's door, not a copy to merge (a '-REVERSE' copy no
cell owns still is one)."""

from __future__ import annotations

from pathlib import Path

import pytest

from pmk_nb.grid import FREE, OCCUPIED
from pmk_nb.indoorgml import read_building
from pmk_nb.raster.storey import rasterise_storey

HEAD = (
    '<?xml version="1.0"?><IndoorFeatures xmlns="http://www.opengis.net/indoorgml/1.0/core" '
    'xmlns:navi="http://www.opengis.net/indoorgml/1.0/navigation" xmlns:gml="http://www.opengis.net/gml/3.2" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" gml:id="F"><primalSpaceFeatures><PrimalSpaceFeatures gml:id="P">'
)
TAIL = "</PrimalSpaceFeatures></primalSpaceFeatures></IndoorFeatures>"


def _room(cid: str, storey: str, x0: float, door: str) -> str:
    ring = f"{x0} 0 {x0 + 5} 0 {x0 + 5} 4 {x0} 4 {x0} 0"
    return (
        f'<cellSpaceMember><navi:GeneralSpace gml:id="{cid}"><gml:description>storey: {storey}</gml:description>'
        f"<cellSpaceGeometry><Geometry2D><gml:Polygon><gml:exterior><gml:LinearRing><gml:posList>{ring}"
        f"</gml:posList></gml:LinearRing></gml:exterior></gml:Polygon></Geometry2D></cellSpaceGeometry>"
        f'<partialboundedBy xlink:href="#{door}"/></navi:GeneralSpace></cellSpaceMember>'
    )


def _door(bid: str, line: str = "5 1.5 5 2.4") -> str:
    return (
        f'<cellSpaceBoundaryMember><navi:ConnectionBoundary gml:id="{bid}"><cellSpaceBoundaryGeometry>'
        f"<geometry2D><gml:LineString><gml:posList>{line}</gml:posList></gml:LineString></geometry2D>"
        f"</cellSpaceBoundaryGeometry></navi:ConnectionBoundary></cellSpaceBoundaryMember>"
    )


@pytest.mark.parametrize("storeys", [2, 3])
def test_each_typical_floor_keeps_its_own_door(tmp_path: Path, storeys: int) -> None:
    body = ""
    for s in range(storeys):
        body += _room(f"A{s}", f"F{s}", 0, f"D{s}") + _room(f"B{s}", f"F{s}", 5, f"D{s}") + _door(f"D{s}")
    body += _door("D0-REVERSE", "5 2.4 5 1.5")  # a reversed copy no cell names: still merged
    path = tmp_path / "typical.gml"
    path.write_text(HEAD + body + TAIL)
    b = read_building(path, unit="m")
    assert [s.name for s in b.storeys] == [f"F{s}" for s in range(storeys)]
    doors = {bd.id: bd.storey for bd in b.boundaries.values() if bd.is_door}
    assert doors == {f"D{s}": f"F{s}" for s in range(storeys)}
    assert any("1 boundaries repeat" in w for w in b.warnings)
    for s in b.storeys:
        grid = rasterise_storey(b, s.name, 0.05)
        assert grid.value_at(5.0, 1.95) == FREE, s.name
        assert grid.value_at(5.0, 0.5) == OCCUPIED and grid.value_at(5.0, 3.5) == OCCUPIED
