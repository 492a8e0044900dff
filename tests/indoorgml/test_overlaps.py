"""Issue 37 item 6: cells of one storey that overlap are named, with how much they share.

Two rooms A and B, in IndoorGML 1.0, 1.0.3 and 2.0 spellings (:mod:`tests.indoorgml.test_gml_spellings`),
drawn so that they overlap, meet in a sliver, or stack in height.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.cli import main
from pmk_nb.indoorgml import CellOverlap, read_building
from tests.access.test_access_rules import _graph, _ring
from tests.indoorgml.test_gml_spellings import NS1, NS2, WRAPPERS, _box_faces, _poly, _solid, _wrap

Box = tuple[float, float, float, float]


def _room(box: Box, z: tuple[float, float] | None) -> tuple[str, str]:
    """A cell's geometry: a 2D polygon, or a 3D solid between heights ``z``."""
    return (_poly(_ring(*box)), "2D") if z is None else (_solid(_box_faces(box, *z)), "3D")


def _two_rooms(
    tmp_path: Path,
    spelling: str,
    a: Box,
    b: Box,
    za: tuple[float, float] | None = None,
    zb: tuple[float, float] | None = None,
) -> Path:
    v2 = spelling.startswith("2.0")
    cells = "".join(
        f'<cellSpaceMember><CellSpace gml:id="{cid}">{_wrap(*_room(box, z), spelling)}</CellSpace></cellSpaceMember>'
        for cid, box, z in (("A", a, za), ("B", b, zb))
    )
    layer = "PrimalSpaceLayer" if v2 else "PrimalSpaceFeatures"
    path = tmp_path / f"{spelling}.gml"
    path.write_text(
        f'<?xml version="1.0"?><IndoorFeatures {NS2 if v2 else NS1} gml:id="F"><primalSpaceFeatures>'
        f'<{layer} gml:id="P">{cells}</{layer}></primalSpaceFeatures>{_graph([("A", "B")], v2=v2)}</IndoorFeatures>'
    )
    return path


@pytest.mark.parametrize("spelling", WRAPPERS)
@pytest.mark.parametrize("z", [None, (0.0, 3.0)], ids=["2D", "3D"])
def test_overlapping_rooms_are_named_with_their_share(
    tmp_path: Path, spelling: str, z: tuple[float, float] | None
) -> None:
    """A (0-6 x 0-4) reaches 1 m into B (5-10 x 0-4): 4 m² shared, a fifth of B (the smaller)."""
    b = read_building(_two_rooms(tmp_path, spelling, (0, 0, 6, 4), (5, 0, 10, 4), z, z), unit="m")
    assert b.overlaps == [CellOverlap(b.storeys[0].name, "A", "B", pytest.approx(4.0), pytest.approx(0.2))]


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_a_room_inside_another_is_all_of_the_smaller(tmp_path: Path, spelling: str) -> None:
    b = read_building(_two_rooms(tmp_path, spelling, (0, 0, 10, 8), (2, 2, 4, 4)), unit="m")
    [o] = b.overlaps
    assert (o.a, o.b, o.area, o.share) == ("A", "B", pytest.approx(4.0), pytest.approx(1.0))


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_slivers_and_touching_rooms_are_no_overlap(tmp_path: Path, spelling: str) -> None:
    """Rooms drawn 5 mm into their shared wall overlap by a 4 m long strip 5 mm wide: drawing noise."""
    assert read_building(_two_rooms(tmp_path, spelling, (0, 0, 5.005, 4), (5, 0, 10, 4)), unit="m").overlaps == []
    assert read_building(_two_rooms(tmp_path, spelling, (0, 0, 5, 4), (5, 0, 10, 4)), unit="m").overlaps == []


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_cells_stacked_in_height_do_not_overlap(tmp_path: Path, spelling: str) -> None:
    """A landing slab (2.5-2.7) under a room (2.7-6) on one storey, as in FZK-Haus: no shared volume."""
    path = _two_rooms(tmp_path, spelling, (0, 0, 5, 4), (0, 0, 5, 4), (2.7, 6.0), (2.5, 2.7))
    assert read_building(path, unit="m").overlaps == []


def test_pmk_info_lists_the_overlaps(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _two_rooms(tmp_path, "2.0-cellSpaceGeom", (0, 0, 6, 4), (5, 0, 10, 4))
    assert main(["info", str(path), "--unit", "m", "--json"]) == 0
    [o] = json.loads(capsys.readouterr().out)["overlaps"]
    assert (o["a"], o["b"], o["area"], o["share"]) == ("A", "B", pytest.approx(4.0), pytest.approx(0.2))
    assert main(["info", str(path), "--unit", "m"]) == 0
    out = capsys.readouterr().out
    assert "OVERLAPPING CELLS (1 pair;" in out and "A and B" in out and "20.0% of the smaller cell" in out


def test_pmk_convert_reports_the_overlaps(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _two_rooms(tmp_path, "1.0-bare", (0, 0, 6, 4), (5, 0, 10, 4))
    out = tmp_path / "maps"
    assert main(["convert", str(path), "--unit", "m", "--out", str(out), "-r", "0.1", "--no-preview", "--json"]) == 0
    [o] = json.loads(capsys.readouterr().out)["overlaps"]
    assert (o["a"], o["b"], o["area"]) == ("A", "B", pytest.approx(4.0))
    assert main(["convert", str(path), "--unit", "m", "--out", str(out), "-r", "0.1", "--no-preview"]) == 0
    assert "OVERLAPPING CELLS (1 pair;" in capsys.readouterr().out
