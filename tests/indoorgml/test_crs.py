"""Issue 37 item 4: projected coordinates are read from a local origin; only degrees and nonsense are refused.

A 44 x 91 m plan (4 x 10 rooms of 11 x 9.1 m) drawn in Web Mercator metres (x about 1.4e7), in UTM
(northing 5.4e6), in degrees, or spanning more than any building, in the IndoorGML 1.0, 1.0.3 and 2.0
spellings (:mod:`tests.indoorgml.test_gml_spellings`).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from pmk_nb.cli import main
from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.crs import GeographicCoordinates, InconsistentCoordinates, UnknownCrs
from tests.access.test_access_rules import _graph, _ring
from tests.indoorgml.test_gml_spellings import NS1, NS2, WRAPPERS, _poly, _wrap

MERCATOR = (14_000_123.37, 6_000_456.81)  # a plan in EPSG:3857 metres
UTM = (445_534.2, 5_444_897.6)  # FJK-Haus's corner, UTM 32N


def _plan(
    tmp_path: Path, spelling: str, at: tuple[float, float], srs: str = "", size: tuple[float, float] = (11.0, 9.1)
) -> Path:
    """4 x 10 rooms of ``size`` (file units) from ``at``, each joined to its neighbour on the right."""
    v2 = spelling.startswith("2.0")
    x0, y0 = at
    w, h = size
    srs_attr = f' srsName="{srs}"' if srs else ""
    cells, pairs = "", []
    for i in range(4):
        for j in range(10):
            ring = _ring(x0 + i * w, y0 + j * h, x0 + (i + 1) * w, y0 + (j + 1) * h)
            geom = _poly(ring).replace("<gml:Polygon>", f"<gml:Polygon{srs_attr}>")
            cells += f'<cellSpaceMember><CellSpace gml:id="R{i}_{j}">{_wrap(geom, "2D", spelling)}</CellSpace>'
            cells += "</cellSpaceMember>"
            if i:
                pairs.append((f"R{i - 1}_{j}", f"R{i}_{j}"))
    layer = "PrimalSpaceLayer" if v2 else "PrimalSpaceFeatures"
    path = tmp_path / f"{spelling}.gml"
    path.write_text(
        f'<?xml version="1.0"?><IndoorFeatures {NS2 if v2 else NS1} gml:id="F"><primalSpaceFeatures>'
        f'<{layer} gml:id="P">{cells}</{layer}></primalSpaceFeatures>{_graph(pairs, v2=v2)}</IndoorFeatures>'
    )
    return path


def _extent(b) -> tuple[float, float, float, float]:  # type: ignore[no-untyped-def]
    xs = [c.footprint.bounds for c in b.cells.values()]
    return (min(x[0] for x in xs), min(x[1] for x in xs), max(x[2] for x in xs), max(x[3] for x in xs))


@pytest.mark.parametrize("spelling", WRAPPERS)
@pytest.mark.parametrize("srs", ["EPSG:3857", "urn:ogc:def:crs:EPSG::3857", ""], ids=["epsg", "urn", "unsaid"])
def test_web_mercator_plan_is_read_from_a_local_origin(tmp_path: Path, spelling: str, srs: str) -> None:
    """Was refused as 'beyond 1e7 m'. Now the map's (0, 0) is a whole metre at the plan's corner, kept
    in the georeference with the CRS the file names."""
    b = read_building(_plan(tmp_path, spelling, MERCATOR, srs))
    assert b.unit == "m", b.unit_reason
    assert b.georef.origin == (14_000_123.0, 6_000_456.0) and b.georef.srs_name == (srs or None)
    assert _extent(b) == pytest.approx((0.37, 0.81, 44.37, 91.81), abs=1e-6)
    room = b.cells["R1_2"].footprint.bounds  # 11-22 x 18.2-27.3 m from the plan's corner
    assert room == pytest.approx((11.37, 19.01, 22.37, 28.11), abs=1e-6)
    if srs:
        assert "drawn in" in b.unit_reason and "a projected CRS in metres" in b.unit_reason


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_utm_plan_keeps_its_place_in_the_crs(tmp_path: Path, spelling: str) -> None:
    b = read_building(_plan(tmp_path, spelling, UTM, "EPSG:25832"))
    assert b.georef.origin == (445_534.0, 5_444_897.0)
    x0, y0, _, _ = _extent(b)
    assert (x0 + b.georef.origin[0], y0 + b.georef.origin[1]) == pytest.approx(UTM, abs=1e-6)


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_a_plan_near_its_own_origin_is_not_moved(tmp_path: Path, spelling: str) -> None:
    b = read_building(_plan(tmp_path, spelling, (3.0, 4.0)))
    assert b.georef.origin == (0.0, 0.0) and _extent(b) == pytest.approx((3.0, 4.0, 47.0, 95.0))


@pytest.mark.parametrize("spelling", WRAPPERS)
@pytest.mark.parametrize(
    "srs", ["EPSG:4326", "urn:ogc:def:crs:OGC:1.3:CRS84", "http://www.opengis.net/def/crs/EPSG/0/4326"]
)
def test_a_geographic_crs_is_refused_and_local_reads_it(tmp_path: Path, spelling: str, srs: str) -> None:
    path = _plan(tmp_path, spelling, (8.4, 49.0), srs, size=(0.0001, 0.0001))
    with pytest.raises(GeographicCoordinates) as info:
        read_building(path)
    assert info.value.declared and info.value.srs == srs and "--crs local" in info.value.hint
    b = read_building(path, crs="local", unit="m")  # the user says the numbers are a local frame
    assert b.georef.srs_name is None and len(b.cells) == 40


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_degree_like_values_without_srs_name_are_refused(tmp_path: Path, spelling: str) -> None:
    """A plan 0.0004 units across at 8.4, 49.0: Karlsruhe in longitude and latitude, not a building."""
    path = _plan(tmp_path, spelling, (8.4, 49.0), size=(0.0001, 0.0001))
    with pytest.raises(GeographicCoordinates) as info:
        read_building(path)
    assert not info.value.declared and info.value.srs is None and "--crs" in info.value.hint


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_crs_option_names_the_crs_the_file_leaves_out(tmp_path: Path, spelling: str) -> None:
    """--crs EPSG:3857 on a file with no srsName: metres (the CRS's unit), the CRS kept in the georeference."""
    path = _plan(tmp_path, spelling, MERCATOR, size=(110.0, 91.0))  # 1e4 m² "rooms": the sizes alone say dm
    assert read_building(path).unit == "dm"
    b = read_building(path, crs="EPSG:3857")
    assert b.unit == "m" and b.georef.srs_name == "EPSG:3857" and b.georef.origin == (14_000_123.0, 6_000_456.0)


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_a_plan_larger_than_any_building_is_refused(tmp_path: Path, spelling: str) -> None:
    path = _plan(tmp_path, spelling, MERCATOR, "EPSG:3857", size=(50_000.0, 9.1))  # 200 km wide
    with pytest.raises(InconsistentCoordinates) as info:
        read_building(path)
    assert info.value.extent_m == pytest.approx(200_000.0) and info.value.srs == "EPSG:3857"


def test_an_unknown_crs_is_refused(tmp_path: Path) -> None:
    with pytest.raises(UnknownCrs):
        read_building(_plan(tmp_path, "2.0-cellSpaceGeom", MERCATOR), crs="Mercator")


def test_pmk_info_and_convert_take_crs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _plan(tmp_path, "2.0-cellSpaceGeom", MERCATOR)
    assert main(["info", str(path), "--crs", "EPSG:3857", "--json"]) == 0
    geo = json.loads(capsys.readouterr().out)["georeference"]
    assert geo["srs_name"] == "EPSG:3857" and geo["origin"] == [14_000_123.0, 6_000_456.0]
    assert main(["info", str(path), "--crs", "EPSG:3857"]) == 0
    text = capsys.readouterr().out
    assert "srs EPSG:3857, map origin at [14000123.0, 6000456.0] m in the CRS" in text
    out = tmp_path / "maps"
    assert main(["convert", str(path), "--crs", "EPSG:3857", "--out", str(out), "-r", "0.1", "--no-preview"]) == 0
    doc = yaml.safe_load((out / f"{path.stem}.yaml").read_text())
    assert doc["crs_origin"] == [14_000_123.0, 6_000_456.0] and doc["srs_name"] == "EPSG:3857"
    assert abs(doc["origin"][0]) < 10 and abs(doc["origin"][1]) < 10  # the map in the local frame
    assert main(["info", str(path), "--crs", "nonsense"]) == 2
