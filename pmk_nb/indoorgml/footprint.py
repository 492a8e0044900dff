"""2D footprints of cells and boundaries (file units; scaling happens later).

A 3D solid's footprint is the union of its roughly horizontal faces projected to the plane (floor
and ceiling coincide for prisms; stairs give the union of their steps); a cell drawn with walls only
(no face with area in plan) is the area its walls enclose; vertical surfaces become LineStrings. A
solid's interior shells are voids, never floor: one that reaches into the lower half of the cell is
cut out of the footprint (a block of rooms a corridor rings round, a column), one higher up is not.
Every polygon is validated; self-intersections are repaired with ``make_valid`` and
reported, because one bad ring in an editor export should not sink a whole building.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon
from shapely.geometry.base import BaseGeometry

from pmk_nb.indoorgml.gml import Coord, PolygonZ

FLAT_SLOPE = 0.02  # a face whose z spread is < 2 % of its plan size counts as horizontal
WALL_TILT = 0.2  # a face whose normal has a smaller vertical part (over ~78° steep) is a wall


@dataclass
class Footprint:
    geometry: BaseGeometry | None  # Polygon/MultiPolygon, None when nothing with area remains
    z_min: float | None
    z_max: float | None
    repaired: bool = False
    stepped: bool = False  # horizontal faces rise in a run of small steps: a stair, by its geometry


STEP_RISE = 0.1  # a tread rises at most this share of the cell's height above the one before
STEP_RUN = 3  # rises in a row that make a stair (a platform and a dropped ceiling make at most two)


def stepped(levels: list[float], span: float) -> bool:
    """Whether the heights of a cell's horizontal faces climb in a run of :data:`STEP_RUN` small rises.

    A room has a floor and a ceiling, perhaps a platform or a dropped ceiling; a stair drawn as a solid
    has a tread every 15-20 cm. Heights are relative to the cell's height, so the file's unit does not
    matter."""
    if span <= 0:
        return False
    zs = sorted(levels)
    distinct = [z for i, z in enumerate(zs) if i == 0 or z - zs[i - 1] > 1e-3 * span]
    run = best = 0
    for lower, upper in itertools.pairwise(distinct):
        run = run + 1 if upper - lower <= STEP_RISE * span else 0
        best = max(best, run)
    return best >= STEP_RUN


def polygonal(geom: BaseGeometry) -> BaseGeometry:
    """Keep only the polygonal parts (make_valid may return collections with lines/points)."""
    if geom.is_empty:
        return Polygon()
    if isinstance(geom, Polygon | MultiPolygon):
        return geom
    parts = [g for g in shapely.get_parts(geom) if isinstance(g, Polygon | MultiPolygon) and not g.is_empty]
    if not parts:
        return Polygon()
    return shapely.union_all(parts)


def _to_polygon(poly: PolygonZ) -> tuple[BaseGeometry, bool]:
    if len(poly.exterior) < 4:
        return Polygon(), False
    ext = [c[:2] for c in poly.exterior]
    holes = [[c[:2] for c in ring] for ring in poly.interiors]
    # no holes (the common case): what Polygon() makes, without its checks of the input
    geom = Polygon(ext, holes) if holes else shapely.polygons(ext)
    if geom.is_valid:
        return geom, False
    return polygonal(shapely.make_valid(geom)), True


def _z_spread(poly: PolygonZ) -> tuple[float, float] | None:
    zs = [c[2] for c in poly.exterior if len(c) > 2]
    return (min(zs), max(zs)) if zs else None


def _plan_size(poly: PolygonZ) -> float:
    xy = np.asarray([c[:2] for c in poly.exterior], dtype=float)
    return float(np.ptp(xy, axis=0).max()) if len(xy) else 0.0


def cell_footprint(polys: list[PolygonZ]) -> Footprint:
    """Footprint of a cell from its polygons (2D polygon, flat 3D polygon, or solid faces)."""
    voids = [p for p in polys if p.void]
    if voids:
        polys = [p for p in polys if not p.void]
    fp = _solid_footprint(polys)
    if voids and fp.geometry is not None:
        fp.geometry = _cut_voids(fp, voids)
    return fp


def _cut_voids(fp: Footprint, voids: list[PolygonZ]) -> BaseGeometry | None:
    """``fp``'s geometry less the plan of each void (interior shell) that reaches into the lower half of the
    cell, where a chair moves; None if nothing is left."""
    geom = fp.geometry
    shells: dict[int, list[PolygonZ]] = {}
    for p in voids:
        shells.setdefault(p.void, []).append(PolygonZ(p.exterior, p.interiors))
    for shell in shells.values():
        void = _solid_footprint(shell)
        if void.geometry is None or geom is None:
            continue
        # a 2D void (no heights) is a hole; a 3D one only when it reaches into the lower half
        if (
            fp.z_min is None
            or fp.z_max is None
            or void.z_min is None
            or void.z_min - fp.z_min < 0.5 * (fp.z_max - fp.z_min)
        ):
            geom = polygonal(geom.difference(void.geometry))
    return None if geom is None or geom.is_empty or geom.area <= 0 else geom


def _walls_plan(polys: list[PolygonZ]) -> BaseGeometry:
    """The area enclosed by the plan of faces that have none of their own (a cell drawn as walls)."""
    lines = [shapely.linestrings([c[:2] for c in p.exterior]) for p in polys if len(p.exterior) >= 2]
    lines = [g for g in lines if g.length > 0]
    if not lines:
        return Polygon()
    noded = shapely.get_parts(shapely.union_all(lines))
    return polygonal(shapely.union_all(shapely.get_parts(shapely.polygonize(noded))))


def _solid_footprint(polys: list[PolygonZ]) -> Footprint:
    """:func:`cell_footprint` of faces that are not voids."""
    spreads = [_z_spread(p) for p in polys]
    zr = [z for z in spreads if z is not None]
    z_min = min(z[0] for z in zr) if zr else None
    z_max = max(z[1] for z in zr) if zr else None
    flat: list[PolygonZ] = []
    flat_z: list[float] = []
    for p, z in zip(polys, spreads, strict=True):
        if z is None or z[1] - z[0] <= FLAT_SLOPE * _plan_size(p):
            flat.append(p)
            if z is not None:
                flat_z.append(z[0])
    chosen = flat or polys
    is_stair = z_min is not None and z_max is not None and stepped(flat_z, z_max - z_min)
    repaired = False
    geoms: list[BaseGeometry] = []
    for p in chosen:
        g, fixed = _to_polygon(p)
        repaired |= fixed
        if not g.is_empty and g.area > 0:
            geoms.append(g)
    if not geoms and (walls := _walls_plan(polys)).area > 0:
        geoms.append(walls)
    if not geoms:
        return Footprint(None, z_min, z_max, repaired, is_stair)
    union = geoms[0] if len(geoms) == 1 else shapely.union_all(geoms)  # one valid polygon is its own union
    if not union.is_valid:
        union = shapely.make_valid(union)
        repaired = True
    union = polygonal(union)
    if union.is_empty or union.area <= 0:
        return Footprint(None, z_min, z_max, repaired, is_stair)
    return Footprint(union, z_min, z_max, repaired, is_stair)


def floor_height(polys: list[PolygonZ], x: float, y: float, tol: float) -> float | None:
    """The floor's height under (x, y): the lowest plane of the faces that are not walls and lie within
    ``tol`` of the point, or None (no z, or no such face).

    A sloping floor is one tilted face: its lowest vertex says nothing about the height at a door
    halfway up, so the plane through the face is evaluated at the point."""
    point = shapely.Point(x, y)
    best: float | None = None
    for poly in polys:
        xyz = np.asarray([c[:3] for c in poly.exterior if len(c) > 2], dtype=float)
        if len(xyz) < 3 or poly.void:
            continue  # no height, or the floor of a void (not of the cell)
        centre = xyz.mean(axis=0)
        normal = np.linalg.svd(xyz - centre, full_matrices=False)[2][-1]
        if abs(normal[2]) < WALL_TILT:
            continue  # a wall (or nearly): it has no height to stand on
        ring: BaseGeometry = shapely.Polygon(xyz[:, :2])
        if not ring.is_valid:  # a floor drawn around a stairwell through a slit is still a floor
            ring = shapely.make_valid(ring)
        if ring.distance(point) > tol:
            continue
        z = centre[2] - (normal[0] * (x - centre[0]) + normal[1] * (y - centre[1])) / normal[2]
        best = z if best is None else min(best, z)
    return best


def boundary_footprint(polys: list[PolygonZ], lines: list[list[Coord]]) -> Footprint:
    """2D footprint of a boundary: a LineString for walls/doors, a polygon for flat surfaces."""
    pts = [c for line in lines for c in line] + [c for p in polys for c in p.exterior]
    if not pts:
        return Footprint(None, None, None)
    zs = [c[2] for c in pts if len(c) > 2]
    z_min, z_max = (min(zs), max(zs)) if zs else (None, None)
    if lines and not polys:
        parts = [shapely.linestrings([c[:2] for c in line]) for line in lines if len(line) >= 2]
        parts = [g for g in parts if g.length > 0]
        if not parts:
            return Footprint(None, z_min, z_max)
        geom = parts[0] if len(parts) == 1 else shapely.line_merge(shapely.union_all(parts))
        return Footprint(geom, z_min, z_max)
    xy = np.asarray([c[:2] for c in pts], dtype=float)
    centre = xy.mean(axis=0)
    spread = xy - centre
    if not np.any(spread):
        return Footprint(None, z_min, z_max)
    _, _, vt = np.linalg.svd(spread, full_matrices=False)
    along = spread @ vt[0]
    across = spread @ vt[1] if vt.shape[0] > 1 else np.zeros(len(xy))
    length = float(along.max() - along.min())
    width = float(across.max() - across.min())
    if width <= 0.05 * length:  # a vertical surface: its plan is a segment
        a = centre + vt[0] * along.min()
        b = centre + vt[0] * along.max()
        return Footprint(LineString([tuple(a), tuple(b)]), z_min, z_max)
    flat = cell_footprint(polys)
    return Footprint(flat.geometry, z_min, z_max, flat.repaired)


def _ragged(runs: list[list[Coord]]) -> tuple[list[Coord], np.ndarray]:
    """The coordinates of several lines or rings, and which one each belongs to: shapely's vectorised form."""
    return [c for run in runs for c in run], np.repeat(np.arange(len(runs)), [len(run) for run in runs])


def boundary_footprints(boundaries: Sequence[tuple[list[PolygonZ], list[list[Coord]]]]) -> list[Footprint]:
    """:func:`boundary_footprint` of each (polygons, lines) pair. Most boundaries are one 2D line (a wall or
    door in a 2D plan): those are made in one vectorised call, which on a large plan is most of the time."""
    simple = [
        i
        for i, (polys, lines) in enumerate(boundaries)
        if not polys and len(lines) == 1 and len(lines[0]) >= 2 and all(len(c) == 2 for c in lines[0])
    ]
    out: list[Footprint | None] = [None] * len(boundaries)
    if simple:
        coords, which = _ragged([boundaries[i][1][0] for i in simple])
        geoms = np.asarray(shapely.linestrings(coords, indices=which))
        for i, g, length in zip(simple, geoms, np.asarray(shapely.length(geoms)), strict=True):
            out[i] = Footprint(g if length > 0 else None, None, None)
    return [fp if fp is not None else boundary_footprint(*boundaries[i]) for i, fp in enumerate(out)]


def cell_footprints(cells: Sequence[list[PolygonZ]]) -> list[Footprint]:
    """:func:`cell_footprint` of each cell's polygons. A cell that is one valid 2D polygon without holes (a 2D
    plan's room) is made in one vectorised call with the others; any other cell goes through the full rules."""
    simple = [
        i
        for i, polys in enumerate(cells)
        if len(polys) == 1
        and not polys[0].interiors
        and not polys[0].void
        and len(polys[0].exterior) >= 4
        and all(len(c) == 2 for c in polys[0].exterior)
    ]
    out: list[Footprint | None] = [None] * len(cells)
    if simple:
        coords, which = _ragged([cells[i][0].exterior for i in simple])
        geoms = np.asarray(shapely.polygons(shapely.linearrings(coords, indices=which)))
        valid_area = zip(np.asarray(shapely.is_valid(geoms)), np.asarray(shapely.area(geoms)), strict=True)
        for i, g, (valid, area) in zip(simple, geoms, valid_area, strict=True):
            if valid and area > 0:
                out[i] = Footprint(g, None, None)
    return [fp if fp is not None else cell_footprint(cells[i]) for i, fp in enumerate(out)]
