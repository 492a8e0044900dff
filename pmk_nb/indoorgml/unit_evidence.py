"""The sizes a plan carries, in file units, gathered for the unit guess (:mod:`pmk_nb.indoorgml.units`).

Everything here is measured before the unit is known, so every rule is scale-free: "the larger half
of the cells", "levels closer than a sixth of the largest gap", "rises under a tenth of the stair's
height".
"""

from __future__ import annotations

import itertools
import math
import re
from collections.abc import Sequence

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pmk_nb.indoorgml.footprint import FLAT_SLOPE, STEP_RISE, Footprint
from pmk_nb.indoorgml.gml import PolygonZ
from pmk_nb.indoorgml.layers import KeptCell
from pmk_nb.indoorgml.model import CellKind
from pmk_nb.indoorgml.records import RawDocument
from pmk_nb.indoorgml.units import UnitEvidence

DOOR_EVIDENCE = ("type", "name", "partial")  # boundary evidence that marks a door, not a whole wall
HEAD_BYTES = 8192  # writers name themselves in a comment at the top of the file
# A writer named in the file whose unit is known. CityGML coordinates are in their CRS, metres in every
# CityGML converter seen; a metric projected CRS in srsName says metres outright.
EXPORTERS: tuple[tuple[re.Pattern[str], str, str], ...] = (
    (re.compile(r"CityGML\s+to\s+IndoorGML", re.IGNORECASE), "m", "written by a CityGML-to-IndoorGML converter"),
)
METRIC_CRS = re.compile(
    r"EPSG(?::|::|/0/|/)(?:326\d\d|327\d\d|258\d\d|3857|900913|2056|28992|3146[789]|5179|518[5-8]|5174)\b"
    r"|\butm\b",
    re.IGNORECASE,
)


def gather(
    doc: RawDocument, cells: list[KeptCell], kinds: dict[str, CellKind], bfps: dict[str, tuple[Footprint, str]]
) -> UnitEvidence:
    """Every size in ``cells`` and the boundaries ``bfps`` that says which unit the file uses."""
    minx, miny, maxx, maxy = shapely.total_bounds([c.geometry for c in cells]).tolist()
    big = sorted(cells, key=lambda c: c.geometry.area)[len(cells) // 2 :]  # rooms, not windows or doors
    big_ids = {c.raw.id for c in big}  # by id: comparing the records themselves made this O(cells²)
    ev = UnitEvidence(extent=max(maxx - minx, maxy - miny), exporter=exporter(doc), crs=metric_crs(doc.srs_name))
    ev.cell_heights = [h for c in big if (h := _height(c.fp)) is not None]
    for fp, why in bfps.values():
        if fp.geometry is None or fp.geometry.geom_type != "LineString" or not why:
            continue
        if why in DOOR_EVIDENCE:
            ev.door_widths.append(fp.geometry.length)
            if (h := _height(fp)) is not None:
                ev.door_heights.append(h)
        else:  # the face a transition crosses: a door in some files, the whole wall in others
            ev.passage_widths.append(fp.geometry.length)
    rooms_z: list[tuple[float, float | None]] = []
    for c in cells:
        kind, geom = kinds[c.raw.id], c.geometry
        if kind.is_door:
            ev.door_widths.append(_long_side(geom))
            if (h := _height(c.fp)) is not None:
                ev.door_heights.append(h)
        elif kind is CellKind.TRANSITION and geom.length > 0:
            ev.corridor_widths.append(2 * geom.area / geom.length)  # mean width of a long shape
        elif kind.is_free and c.raw.id in big_ids:
            ev.room_areas.append(geom.area)
            if c.fp.z_min is not None:
                rooms_z.append((c.fp.z_min, _height(c.fp)))
        if c.fp.stepped and (rise := stair_rise(c.raw.polygons)) is not None:
            ev.stair_risers.append(rise)
    ev.storey_heights = storey_heights(rooms_z)
    return ev


def _height(fp: Footprint) -> float | None:
    return None if fp.z_min is None or fp.z_max is None else fp.z_max - fp.z_min


def _long_side(geom: BaseGeometry) -> float:
    """The long side of a door cell's plan: its width (the short side is the wall's thickness)."""
    xy = shapely.get_coordinates(geom.minimum_rotated_rectangle)
    return max((math.dist(xy[i], xy[i + 1]) for i in range(min(2, len(xy) - 1))), default=0.0)


def storey_heights(rooms: Sequence[tuple[float, float | None]]) -> list[float]:
    """Floor-to-floor heights from the levels rooms (z_min, height or None) start at. Rooms less than
    half the usual room's height (windows, sills) are left out; levels closer than half the usual room's
    height (or, for flat cells, a sixth of the largest gap) are one storey (a platform, a ramp, a
    landing); a single level gives none."""
    heights = sorted(h for _, h in rooms if h)
    usual = heights[len(heights) // 2] if heights else 0.0
    levels = sorted({z for z, h in rooms if not heights or (h or 0.0) >= usual / 2})
    gaps = [b - a for a, b in itertools.pairwise(levels)]
    if not gaps or max(gaps) <= 0:
        return []
    tol = usual / 2 if usual else max(gaps) / 6
    groups: list[list[float]] = [[levels[0]]]
    for z in levels[1:]:
        if z - groups[-1][-1] <= tol:
            groups[-1].append(z)
        else:
            groups.append([z])
    lows = [g[0] for g in groups]
    return [b - a for a, b in itertools.pairwise(lows)]


def stair_rise(polys: Sequence[PolygonZ]) -> float | None:
    """The median rise between the treads of a stair drawn as a solid (the horizontal faces' heights)."""
    levels = []
    for p in polys:
        xyz = np.asarray([c for c in p.exterior if len(c) > 2], dtype=float)
        if len(xyz) < 3:
            continue
        size = float(np.ptp(xyz[:, :2], axis=0).max())
        if np.ptp(xyz[:, 2]) <= FLAT_SLOPE * size:
            levels.append(float(xyz[:, 2].min()))
    if len(levels) < 2:
        return None
    zs = sorted(set(levels))
    span = zs[-1] - zs[0]
    rises = [b - a for a, b in itertools.pairwise(zs) if 1e-3 * span < b - a <= STEP_RISE * span]
    import statistics  # here: its import (fractions, decimal) is 10 ms of a small plan's convert

    return statistics.median(rises) if rises else None


def metric_crs(srs_name: str | None) -> str:
    """What the file says when ``srs_name`` is a metric projected CRS (its coordinates are metres), else ''."""
    if srs_name and METRIC_CRS.search(srs_name):
        return f"drawn in {srs_name} (srsName), a projected CRS in metres"
    return ""


def exporter(doc: RawDocument) -> tuple[str, str] | None:
    """(unit, what the file says) when it names a writer whose unit is known."""
    try:
        with open(doc.path, "rb") as fh:
            head = fh.read(HEAD_BYTES).decode("utf-8", "replace")
    except OSError:
        return None
    comments = " ".join(re.findall(r"<!--(.*?)-->", head, re.DOTALL))
    for pattern, unit, said in EXPORTERS:
        if pattern.search(comments):
            return unit, said
    return None
