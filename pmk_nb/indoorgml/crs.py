"""Which frame a plan's coordinates are in, and a local origin for large projected ones (issue 37 item 4).

GML 3.2 puts coordinates in the CRS the geometry's ``srsName`` names, else in a frame the file leaves
unsaid (most IndoorGML files: an editor's local frame). A projected CRS (UTM, Web Mercator, a national
grid) gives eastings and northings of millions of metres; such a plan is read relative to a local
origin, a whole number of file units at its lower-left corner, and the origin is kept in the
georeference (``Georeference.origin``: where the map's (0, 0) lies in the CRS), so nothing about where
the building stands is lost and no map carries seven-digit coordinates (ROS tools hold poses in single
precision: 0.5 m steps at 5e6).

Refused, with a typed error that names the way out (``--crs``):

* geographic coordinates: an ``srsName`` that is a geographic CRS (EPSG:4326, CRS84, ...: degrees, not
  lengths), or, with no ``srsName``, a plan under a hundredth of a unit across at values that could be
  longitude and latitude (a building spans about a thousandth of a degree);
* inconsistent values: a plan more than 100 km across once its unit is known (a stray coordinate, or
  numbers that are no building).

``crs``: ``auto`` (the file's ``srsName``, else the evidence), ``local`` (a local frame whatever the file
says: no CRS, nothing refused as degrees), or a CRS name (``EPSG:3857``, an OGC URN or URL) that replaces
the file's ``srsName``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from pmk_nb.errors import IndoorGMLError
from pmk_nb.indoorgml.records import RawDocument

CRS_AUTO = "auto"
CRS_LOCAL = "local"
LOCAL_FROM = 1e5  # file units: a plan whose corner lies farther from (0, 0) is read from a local origin
DEGREE_EXTENT = 0.01  # file units: a plan narrower than this at lon/lat-like values is in degrees
MAX_EXTENT_M = 100_000.0  # m: no building plan spans more
CRS_NAME = re.compile(
    r"(?:urn:ogc:def:crs:)?(?:EPSG:{1,2}(?:[\d.]*:)?\d+|OGC:(?:1\.3:)?CRS84|CRS:?84)"
    r"|https?://www\.opengis\.net/def/crs/(?:EPSG/0/\d+|OGC/1\.3/CRS84)",
    re.IGNORECASE,
)
GEOGRAPHIC = re.compile(
    r"EPSG(?::|::|/0/|/)(?:[\d.]*:)?(?:4326|4258|4269|4979|4937|4283|4167|4490|4612|4674|4019)\b|CRS:?84",
    re.IGNORECASE,
)


class CrsError(IndoorGMLError):
    """The plan's coordinates are not lengths in one frame; ``srs`` is the CRS they were read in (None: none)."""

    def __init__(self, message: str, *, path: str, srs: str | None, element: str | None = None, hint: str = "") -> None:
        super().__init__(message, path=path, element=element, hint=hint)
        self.srs = srs


class UnknownCrs(CrsError):
    """``--crs`` names no CRS this reader knows how to name."""


class GeographicCoordinates(CrsError):
    """Longitude and latitude (degrees), not a plan in metres; ``declared``: the srsName says so (else the
    values look like it)."""

    def __init__(self, message: str, *, path: str, srs: str | None, declared: bool, hint: str) -> None:
        super().__init__(message, path=path, srs=srs, hint=hint)
        self.declared = declared


class InconsistentCoordinates(CrsError):
    """The plan spans more than any building (``extent_m`` metres): a stray coordinate or no building."""

    def __init__(self, message: str, *, path: str, srs: str | None, element: str, extent_m: float, hint: str) -> None:
        super().__init__(message, path=path, srs=srs, element=element, hint=hint)
        self.extent_m = extent_m


@dataclass(frozen=True)
class Frame:
    """How the plan's coordinates are read: in which CRS, from which origin (file units)."""

    srs: str | None  # the CRS (the file's srsName or --crs); None: a local frame
    origin: tuple[float, float] = (0.0, 0.0)  # subtracted from every coordinate (file units)


def check_crs_option(crs: str, path: str = "") -> str:
    """``crs`` as given, when it is ``auto``, ``local`` or a CRS name; else :class:`UnknownCrs`."""
    if crs in (CRS_AUTO, CRS_LOCAL) or CRS_NAME.fullmatch(crs.strip()):
        return crs.strip()
    raise UnknownCrs(
        f"{path + ': ' if path else ''}unknown CRS {crs!r}",
        path=path,
        srs=None,
        hint="Use --crs auto, --crs local, or a CRS name such as EPSG:3857 or urn:ogc:def:crs:EPSG::25832.",
    )


def _bounds(doc: RawDocument) -> tuple[float, float, float, float] | None:
    """The plan's bounds in file units (every cell's exterior rings): what the frame is judged by."""
    xs = [c[0] for cell in doc.cells for poly in cell.polygons for c in poly.exterior]
    if not xs:
        return None
    ys = [c[1] for cell in doc.cells for poly in cell.polygons for c in poly.exterior]
    return min(xs), min(ys), max(xs), max(ys)


def _degree_like(b: tuple[float, float, float, float]) -> bool:
    minx, miny, maxx, maxy = b
    if max(maxx - minx, maxy - miny) >= DEGREE_EXTENT:
        return False
    lon_lat = all(abs(v) <= 180 for v in (minx, maxx)) and all(abs(v) <= 90 for v in (miny, maxy))
    lat_lon = all(abs(v) <= 90 for v in (minx, maxx)) and all(abs(v) <= 180 for v in (miny, maxy))
    return lon_lat or lat_lon


def choose_frame(doc: RawDocument, crs: str = CRS_AUTO) -> Frame:
    """The frame of ``doc``'s coordinates (see the module docstring); refuses geographic coordinates."""
    srs = None if crs == CRS_LOCAL else (doc.srs_name if crs == CRS_AUTO else crs)
    path = str(doc.path)
    hint = (
        "Export the plan in a projected CRS (metres), or, if its numbers are a local frame after all, "
        "read it with --crs local."
    )
    if srs and GEOGRAPHIC.search(srs):
        raise GeographicCoordinates(
            f"{path}: the plan is drawn in {srs}, a geographic CRS: its coordinates are degrees of longitude "
            "and latitude, not lengths a map can be drawn in",
            path=path,
            srs=srs,
            declared=True,
            hint=hint,
        )
    bounds = _bounds(doc)
    if bounds is None:
        return Frame(srs)
    if crs == CRS_AUTO and srs is None and _degree_like(bounds):
        minx, miny, maxx, maxy = bounds
        raise GeographicCoordinates(
            f"{path}: the plan is {max(maxx - minx, maxy - miny):.2g} units across at ({minx:.6g}, {miny:.6g}): "
            "longitude and latitude in degrees, not lengths (no srsName says otherwise)",
            path=path,
            srs=None,
            declared=False,
            hint=hint.replace("projected CRS (metres)", "projected CRS (metres) and name it in srsName")
            + " A projected CRS can be named with --crs EPSG:NNNN.",
        )
    minx, miny = bounds[0], bounds[1]
    if max(abs(minx), abs(miny)) <= LOCAL_FROM:
        return Frame(srs)
    return Frame(srs, (float(math.floor(minx)), float(math.floor(miny))))


def shift(doc: RawDocument, origin: tuple[float, float]) -> None:
    """Move every coordinate of ``doc`` by ``-origin`` (file units), in place: cells, boundaries, states and
    transitions, so that everything read from it is in the local frame."""
    ox, oy = origin
    if not (ox or oy):
        return

    def move(points: list[tuple[float, ...]]) -> list[tuple[float, ...]]:
        return [(p[0] - ox, p[1] - oy, *p[2:]) for p in points]

    for polys in [c.polygons for c in doc.cells] + [b.polygons for b in doc.boundaries]:
        for poly in polys:
            poly.exterior = move(poly.exterior)
            poly.interiors = [move(ring) for ring in poly.interiors]
    for b in doc.boundaries:
        b.lines = [move(line) for line in b.lines]
    for s in doc.states:
        if s.point is not None:
            s.point = move([s.point])[0]
    for t in doc.transitions:
        if t.line is not None:
            t.line = move(t.line)


def refuse_extent(path: str, srs: str | None, extent_m: float, worst: str, line: int | None) -> None:
    """Refuse a plan that spans more than any building (over :data:`MAX_EXTENT_M`), naming the likely stray cell."""
    raise InconsistentCoordinates(
        f"{path}: the plan spans {extent_m / 1000:.3g} km (cell {worst!r}, line {line}, lies farthest out): "
        "no building is that large; a coordinate is wrong, or the numbers are not a building plan",
        path=path,
        srs=srs,
        element=worst,
        extent_m=extent_m,
        hint="Check that cell's coordinates; if the plan is in another unit, give it with --unit, "
        "and if it is in a CRS the file does not name, give that with --crs.",
    )
