"""Issue 31 rule 5: every GML 3.2 geometry spelling exporters use reads to the right footprint.

Each case draws room A (x 0-5, y 0-4, 3 m high where 3D) in one spelling, beside a plain 2D room B
(x 5-10) that a transition joins to it, and is read in the three document spellings of a cell's
geometry: IndoorGML 1.0 (``Geometry2D``/``Geometry3D`` right under the cell), 1.0.3 (wrapped in
``cellSpaceGeometry``) and 2.0 (``cellSpaceGeom/CellSpaceGeometry/geometry2D|geometry3D``, Node/Edge).
The footprint's area and bounds are checked, and the converted grid is FREE inside A.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from shapely.geometry import Point

from pmk_nb.grid import FREE
from pmk_nb.indoorgml import read_building
from pmk_nb.indoorgml.footprint import cell_footprint
from pmk_nb.indoorgml.scan import scan
from pmk_nb.raster import rasterise_storey
from tests.access.test_access_rules import RES, _graph, _ring
from tests.shared_data import INDOORGML_DATA

BOX = (0.0, 0.0, 5.0, 4.0)
NS1 = (
    'xmlns="http://www.opengis.net/indoorgml/1.0/core" xmlns:gml="http://www.opengis.net/gml/3.2" '
    'xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:navi="http://www.opengis.net/indoorgml/1.0/navigation"'
)
NS2 = NS1.replace("indoorgml/1.0/", "indoorgml/2.0/")
WRAPPERS = ["1.0-bare", "1.0.3-cellSpaceGeometry", "2.0-cellSpaceGeom"]


def _wrap(geom: str, dim: str, spelling: str) -> str:
    """``geom`` as a cell's geometry property in ``spelling`` (``dim``: "2D" or "3D")."""
    if spelling == "2.0-cellSpaceGeom":
        inner = f"<geometry{dim}>{geom}</geometry{dim}>"
        return f"<cellSpaceGeom><CellSpaceGeometry>{inner}</CellSpaceGeometry></cellSpaceGeom>"
    inner = f"<Geometry{dim}>{geom}</Geometry{dim}>"
    return inner if spelling == "1.0-bare" else f"<cellSpaceGeometry>{inner}</cellSpaceGeometry>"


def _plan(tmp_path: Path, geom: str, dim: str, spelling: str, boundaries: str = "") -> Path:
    v2 = spelling.startswith("2.0")
    b = _wrap(
        f"<gml:Polygon><gml:exterior><gml:LinearRing><gml:posList>{_ring(5, 0, 10, 4)}</gml:posList>"
        "</gml:LinearRing></gml:exterior></gml:Polygon>",
        "2D",
        spelling,
    )
    cells = (
        f'<cellSpaceMember><CellSpace gml:id="A">{_wrap(geom, dim, spelling)}</CellSpace></cellSpaceMember>'
        f'<cellSpaceMember><CellSpace gml:id="B">{b}</CellSpace></cellSpaceMember>'
    )
    layer = "PrimalSpaceLayer" if v2 else "PrimalSpaceFeatures"
    text = (
        f'<?xml version="1.0"?><IndoorFeatures {NS2 if v2 else NS1} gml:id="F"><primalSpaceFeatures>'
        f'<{layer} gml:id="P">{cells}{boundaries}</{layer}></primalSpaceFeatures>'
        f"{_graph([('A', 'B')], {0: '2.5 2 7.5 2'}, v2=v2)}</IndoorFeatures>"
    )
    path = tmp_path / f"{spelling}.gml"
    path.write_text(text)
    return path


def _poly(ring: str, tag: str = "Polygon", interiors: str = "") -> str:
    return (
        f"<gml:{tag}><gml:exterior><gml:LinearRing><gml:posList>{ring}</gml:posList></gml:LinearRing>"
        f"</gml:exterior>{interiors}</gml:{tag}>"
    )


def _box_faces(box: tuple[float, float, float, float], z0: float, z1: float, tag: str = "Polygon") -> list[str]:
    """The six faces of a box: floor, ceiling and four walls, each a ring of 3D points."""
    x0, y0, x1, y1 = box
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    walls = []
    for (ax, ay), (bx, by) in zip(corners, corners[1:] + corners[:1], strict=True):
        pts = [(ax, ay, z0), (bx, by, z0), (bx, by, z1), (ax, ay, z1), (ax, ay, z0)]
        walls.append(" ".join(f"{x:g} {y:g} {z:g}" for x, y, z in pts))
    return [_poly(r, tag) for r in (_ring(*box, z=z0), _ring(*box, z=z1), *walls)]


def _members(faces: list[str], member: str = "surfaceMember") -> str:
    return "".join(f"<gml:{member}>{f}</gml:{member}>" for f in faces)


HALVES = ((0.0, 0.0, 2.5, 4.0), (2.5, 0.0, 5.0, 4.0))
TRIANGLES = "".join(_poly(r, "Triangle") for r in ("0 0 5 0 5 4 0 0", "0 0 5 4 0 4 0 0"))
POS = "".join(f"<gml:pos>{x} {y}</gml:pos>" for x, y in ((0, 0), (5, 0), (5, 4), (0, 4), (0, 0)))


def _el(tag: str, inner: str, attrs: str = "") -> str:
    return f"<gml:{tag}{attrs}>{inner}</gml:{tag}>"


SEGMENTS = "".join(  # no srsDimension: read in the dimension in which the two runs chain into a ring
    _el("LineStringSegment", _el("posList", r)) for r in ("0 0 5 0 5 4", "5 4 0 4 0 0")
)


def _ring_of(inner: str, ring: str = "LinearRing") -> str:
    """A Polygon whose exterior ``ring`` holds ``inner`` (coordinates, or curve members)."""
    return _el("Polygon", _el("exterior", _el(ring, inner)))


def _orientable(face: str) -> str:
    return _el("OrientableSurface", _el("baseSurface", face), ' orientation="-"')


def _solid(faces: list[str], shell: str = "Shell") -> str:
    return _el("Solid", _el("exterior", _el(shell, _members(faces))))


SPELLINGS_2D = {
    "Polygon-posList": _poly(_ring(*BOX)),
    "Polygon-pos": _ring_of(POS),
    "Surface-patches-PolygonPatch": _el("Surface", _el("patches", _poly(_ring(*BOX), "PolygonPatch"))),
    "Surface-patches-Rectangle": _el("Surface", _el("patches", _poly(_ring(*BOX), "Rectangle"))),
    "PolyhedralSurface-2-patches": _el(
        "PolyhedralSurface", _el("polygonPatches", "".join(_poly(_ring(*h), "PolygonPatch") for h in HALVES))
    ),
    "TriangulatedSurface": _el("TriangulatedSurface", _el("trianglePatches", TRIANGLES)),
    "Tin": _el("Tin", _el("trianglePatches", TRIANGLES)),
    "MultiSurface-surfaceMember": _el("MultiSurface", _members([_poly(_ring(*h)) for h in HALVES])),
    "MultiSurface-surfaceMembers": _el(
        "MultiSurface", _el("surfaceMembers", "".join(_poly(_ring(*h)) for h in HALVES))
    ),
    "CompositeSurface": _el("CompositeSurface", _members([_poly(_ring(*h)) for h in HALVES])),
    "OrientableSurface-minus": _orientable(_poly("0 0 0 4 5 4 5 0 0 0")),  # drawn clockwise: "-" flips it back
    "Ring-curveMember-segments": _ring_of(_el("curveMember", _el("Curve", _el("segments", SEGMENTS))), "Ring"),
    "coordinates-default": _ring_of("<gml:coordinates>0,0 5,0 5,4 0,4 0,0</gml:coordinates>"),
    "coordinates-cs-ts-decimal": _ring_of(
        '<gml:coordinates cs=";" ts="|" decimal=",">0,0;0,0|5,0;0,0|5,0;4,0|0,0;4,0|0,0;0,0</gml:coordinates>'
    ),
    "coordinates-space-after-comma": _ring_of("<gml:coordinates>0, 0 5, 0 5, 4 0, 4 0, 0</gml:coordinates>"),
}
PATCHES = _el("PolyhedralSurface", _el("polygonPatches", "".join(_box_faces(BOX, 0, 3, "PolygonPatch"))))
SPELLINGS_3D = {
    "Solid-Shell": _solid(_box_faces(BOX, 0, 3)),
    "Solid-CompositeSurface": _solid(_box_faces(BOX, 0, 3), "CompositeSurface"),
    "Solid-Shell-OrientableSurface": _solid([_orientable(f) for f in _box_faces(BOX, 0, 3)]),
    "PolyhedralSurface-srsDimension-inherited": _el(
        "PolyhedralSurface", _el("polygonPatches", "".join(_box_faces(BOX, 0, 3, "PolygonPatch"))), ' srsDimension="3"'
    ),
    "MultiSolid": _el("MultiSolid", _members([_solid(_box_faces(h, 0, 3)) for h in HALVES], "solidMember")),
    "CompositeSolid": _el("CompositeSolid", _members([_solid(_box_faces(h, 0, 3)) for h in HALVES], "solidMember")),
    # issue 37 item 7: a Solid's shell in every surface spelling GML allows, and a Solid written with
    # interior shells only (no exterior to be a void in: the interior shells are the solid)
    "Solid-exterior-PolyhedralSurface": _el("Solid", _el("exterior", PATCHES)),
    "Solid-exterior-Surface-patches": _el(
        "Solid", _el("exterior", _el("Surface", _el("patches", "".join(_box_faces(BOX, 0, 3, "PolygonPatch")))))
    ),
    "Solid-interior-only-PolyhedralSurface": _el("Solid", _el("interior", PATCHES)),
    "Solid-interior-only-Shell": _el("Solid", _el("interior", _el("Shell", _members(_box_faces(BOX, 0, 3))))),
    "Solid-interior-only-CompositeSurface": _el(
        "Solid", _el("interior", _el("CompositeSurface", _members(_box_faces(BOX, 0, 3))))
    ),
    # walls only, no floor or ceiling face: the room is what the walls enclose
    "PolyhedralSurface-walls-only": _el(
        "PolyhedralSurface", _el("polygonPatches", "".join(_box_faces(BOX, 0, 3, "PolygonPatch")[2:]))
    ),
}
CASES = [(k, v, "2D") for k, v in SPELLINGS_2D.items()] + [(k, v, "3D") for k, v in SPELLINGS_3D.items()]


@pytest.mark.parametrize("spelling", WRAPPERS)
@pytest.mark.parametrize(("name", "geom", "dim"), CASES, ids=[c[0] for c in CASES])
def test_spelling_reads_to_the_room(tmp_path: Path, name: str, geom: str, dim: str, spelling: str) -> None:
    b = read_building(_plan(tmp_path, geom, dim, spelling), unit="m")
    room = b.cells["A"].footprint
    assert room.area == pytest.approx(20.0, abs=1e-6), name
    assert room.bounds == pytest.approx(BOX, abs=1e-9)
    if dim == "3D":
        assert (b.cells["A"].z_min, b.cells["A"].z_max) == (0.0, 3.0)
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    for x, y in ((0.5, 0.5), (2.5, 2.0), (4.5, 3.5), (1.0, 3.0)):
        assert grid.value_at(x, y) == FREE, (x, y)


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_polygon_interior_is_a_hole(tmp_path: Path, spelling: str) -> None:
    hole = _el("interior", _el("LinearRing", _el("posList", "1 1 2 1 2 2 1 2 1 1")))
    geom = _el("PolyhedralSurface", _el("polygonPatches", _poly(_ring(*BOX), "PolygonPatch", hole)))
    b = read_building(_plan(tmp_path, geom, "2D", spelling), unit="m")
    assert b.cells["A"].footprint.area == pytest.approx(19.0)
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(1.5, 1.5) != FREE and grid.value_at(3.5, 2.0) == FREE


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_solid_of_interior_shells_only_is_read_and_said(tmp_path: Path, spelling: str) -> None:
    """The interior shells of a solid with no exterior are its geometry, and the reader says it read them so."""
    b = read_building(_plan(tmp_path, SPELLINGS_3D["Solid-interior-only-PolyhedralSurface"], "3D", spelling))
    assert b.cells["A"].footprint.area == pytest.approx(20.0)
    assert any("interior shells but no exterior" in w for w in b.warnings)
    plain = read_building(_plan(tmp_path, SPELLINGS_3D["Solid-Shell"], "3D", spelling))
    assert not any("interior shells" in w for w in plain.warnings)


def _solid_with_voids(voids: list[tuple[tuple[float, float, float, float], float, float]]) -> str:
    inner = "".join(_el("interior", _el("Shell", _members(_box_faces(box, z0, z1)))) for box, z0, z1 in voids)
    return _solid(_box_faces(BOX, 0, 3)).replace("</gml:Solid>", f"{inner}</gml:Solid>")


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_solid_interior_shell_at_floor_level_is_cut_out(tmp_path: Path, spelling: str) -> None:
    """pnu201 draws each corridor as one solid round the blocks of rooms it rings, the blocks as interior
    shells from 0.1 to 19.9 of a 20 high storey: the void is not floor, and it is no part of the room."""
    geom = _solid_with_voids([((1, 1, 2, 2), 0.1, 2.9)])
    b = read_building(_plan(tmp_path, geom, "3D", spelling), unit="m")
    cell = b.cells["A"]
    assert cell.footprint.area == pytest.approx(19.0) and cell.footprint.bounds == pytest.approx(BOX)
    assert (cell.z_min, cell.z_max) == (0.0, 3.0)
    grid = rasterise_storey(b, b.storeys[0].name, RES)
    assert grid.value_at(1.5, 1.5) != FREE
    assert grid.value_at(3.5, 2.0) == FREE and grid.value_at(0.5, 1.5) == FREE


@pytest.mark.parametrize("spelling", WRAPPERS)
def test_solid_interior_shells_high_up_are_neither_floor_nor_steps(tmp_path: Path, spelling: str) -> None:
    """Voids in the upper half (ducts under the ceiling) leave the floor whole, and their faces are not
    treads: three stacked 0.2 m voids would read as a stair if they counted as horizontal faces."""
    geom = _solid_with_voids([((1, 1, 2, 2), 1.6, 1.8), ((1, 1, 2, 2), 2.0, 2.2), ((1, 1, 2, 2), 2.4, 2.6)])
    path = _plan(tmp_path, geom, "3D", spelling)
    fp = cell_footprint(next(c for c in scan(path).cells if c.id == "A").polygons)
    assert fp.geometry.area == pytest.approx(20.0) and (fp.z_min, fp.z_max) == (0.0, 3.0)
    assert not fp.stepped
    b = read_building(path, unit="m")
    assert rasterise_storey(b, b.storeys[0].name, RES).value_at(1.5, 1.5) == FREE


@pytest.mark.parametrize("spelling", ["1.0.3-cellSpaceGeometry", "2.0-cellSpaceGeom"])
def test_door_boundary_as_vertical_surface_spellings(tmp_path: Path, spelling: str) -> None:
    """A door (navi ConnectionBoundary) drawn as a vertical 3D face in the wall x = 5, y 1-1.9, written as
    an OrientableSurface over a Surface patch: its plan is the 0.9 m door line."""
    face = "5 1 0 5 1.9 0 5 1.9 2.1 5 1 2.1 5 1 0"
    geom = _orientable(_el("Surface", _el("patches", _poly(face, "PolygonPatch"))))
    boundary = (
        '<cellSpaceBoundaryMember><navi:ConnectionBoundary gml:id="D"><cellSpaceBoundaryGeometry><geometry3D>'
        f"{geom}</geometry3D></cellSpaceBoundaryGeometry></navi:ConnectionBoundary></cellSpaceBoundaryMember>"
    )
    b = read_building(_plan(tmp_path, _poly(_ring(*BOX)), "2D", spelling, boundary), unit="m")
    door = b.boundaries["D"]
    assert door.is_door and door.geometry.length == pytest.approx(0.9)
    assert door.geometry.bounds == pytest.approx((5.0, 1.0, 5.0, 1.9))


def test_pnu201_corridors_are_rings_round_their_voids() -> None:
    """pnu201's corridors CC1-CC3 are solids whose interior shells (0.1-19.9 of a 20 high storey) are the
    blocks of rooms they ring: CC1's outline holds 15637 units², its voids 4138 and 3611."""
    b = read_building(INDOORGML_DATA / "pnu201_3floors_navi_corrected.gml")
    assert b.cells["C82"].footprint.area == pytest.approx(15637.5 - 4138.2 - 3610.9, abs=1)
    for cid in ("C82", "C34", "C35"):
        assert len(b.cells[cid].footprint.interiors) == 1  # the voids' plan, a hole in the corridor
    # the middle of storey 2's block: inside CC2's outline, in no cell now
    assert not any(c.footprint.contains(Point(199.66, 184.96)) for c in b.cells_of("2"))
