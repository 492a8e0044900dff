"""Rasterise a building's storeys into occupancy grids, straight from the vector geometry.

Not drawn on a 100 px/m bitmap and shrunk (the original app: 10 000 pixels per m² at any resolution,
and thin walls lost): each storey is rasterised once, at the target resolution, with the cell-centre
rule (:mod:`pmk_nb.raster.scanline`), in this order:

1. free cells (navigable, general, transition, anchor and connection spaces) -> 0;
2. non-navigable cells -> 100;
3. wall gaps: regions between cells narrower than the thickest wall (at least 1 m, :mod:`thickness`)
   are wall (ALMA leaves walls out as gaps), except across doors and openings (:func:`walls.gap_walls`);
4. walls: every free cell's rings, minus the stretches where a door sits, drawn as a band of
   ``wall_thickness`` centred on the line *and* as a 4-connected supercover line, so rooms that share
   an edge never merge even when the wall is thinner than a cell;
5. doors opened after the walls: door cells and door boundaries clear the wall across their width, plus
   a passage line across it (only towards cells the graph links a door cell to) for coarse resolutions;
6. everything outside all cells stays unknown (or occupied with ``outside="occupied"``), and free cells
   never touch unknown: one cell of wall seals them, except at entrances (:mod:`seal`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pmk_nb.defaults import NAV2_MAX_CELLS_PER_SIDE
from pmk_nb.errors import GridTooLarge, OccupancyError
from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid, new_cells, nice_ceil
from pmk_nb.openings import OpeningPlan, plan_openings, thickest_wall
from pmk_nb.progress import ProgressCallback, emit, sub_range
from pmk_nb.raster.options import OUTSIDE_VALUES, RasterOptions
from pmk_nb.raster.scanline import (
    Frame,
    axis_line_rects,
    fill_segment_bands,
    segments_with_owner,
    supercover_cells,
    write_rects,
)
from pmk_nb.raster.seal import seal_storey
from pmk_nb.raster.spans import fill_polygons
from pmk_nb.raster.wallcut import wall_segments
from pmk_nb.raster.walls import door_gaps, door_geometry, door_neighbours, gap_walls, passages, shrink_segments

if TYPE_CHECKING:
    from pmk_nb.indoorgml import Building, Cell

_WALL = 101  # transient markers while drawing: a wall cell that a door may still open,
_OUTSIDE = 102  # and a cell outside every cell (unknown or occupied once finished)
_MAX_DOOR_GAP = 1.0  # metres between a door line and the rooms it joins, at most (walls modelled as gaps)


def _check_number(name: str, value: float, *, positive: bool) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError) as err:
        raise OccupancyError(f"{name} must be a number of metres, got {value!r}") from err
    if not math.isfinite(v) or v < 0 or (positive and v == 0):
        need = "a positive" if positive else "a non-negative"
        raise OccupancyError(f"{name} must be {need} finite number of metres, got {value!r}")
    return v


def _storey_cells(building: Building, storey: str) -> list[Cell]:
    names = [s.name for s in building.storeys]
    if storey not in names:
        raise OccupancyError(f"{building.source}: no storey named {storey!r}; storeys are: {', '.join(names)}")
    cells = [c for c in building.cells_of(storey) if c.footprint is not None and not c.footprint.is_empty]
    if not cells:
        raise OccupancyError(f"{building.source}: storey {storey!r} has no cell with a 2D footprint to rasterise")
    coords, index = shapely.get_coordinates(np.asarray([c.footprint for c in cells], dtype=object), return_index=True)
    bad = ~np.isfinite(coords).all(axis=1)
    if bad.any():
        cell = cells[int(index[bad][0])]
        raise OccupancyError(f"{building.source}: cell {cell.id!r} has non-finite coordinates (NaN or infinity)")
    return cells


def plan_storey(
    building: Building,
    storey: str,
    resolution: float,
    options: RasterOptions | None = None,
    *,
    cells: list[Cell] | None = None,
) -> Frame:
    """The grid frame a storey needs, checked against the memory budget and the Nav2 size limit
    (``options``: the wall thickness, margin, budget and size limit; the defaults when None).

    ``cells``: the storey's cells when the caller has them from :func:`_storey_cells` already.

    Raises:
        GridTooLarge: the grid would exceed ``max_cells`` or 32767 cells per side (unless
            ``allow_large``); ``suggested_resolution`` is the finest resolution that fits.
        OccupancyError: bad numbers or an empty storey.
    """
    opts = RasterOptions() if options is None else options
    max_cells, allow_large = opts.max_cells, opts.allow_large
    res = _check_number("resolution", resolution, positive=True)
    thick = _check_number("wall thickness", opts.wall_thickness, positive=False)
    pad = thick + res if opts.margin is None else _check_number("margin", opts.margin, positive=False)
    if cells is None:
        cells = _storey_cells(building, storey)
    b = shapely.bounds(np.asarray([c.footprint for c in cells], dtype=object))
    minx, miny = float(b[:, 0].min()), float(b[:, 1].min())
    maxx, maxy = float(b[:, 2].max()), float(b[:, 3].max())

    def frame_at(r: float, pad_r: float) -> Frame:
        i0, i1 = math.floor((minx - pad_r) / r), math.ceil((maxx + pad_r) / r)
        j0, j1 = math.floor((miny - pad_r) / r), math.ceil((maxy + pad_r) / r)
        return Frame(i0 * r, j0 * r, r, max(1, i1 - i0), max(1, j1 - j0))

    frame = frame_at(res, pad)
    total = frame.width * frame.height
    too_many = total > max_cells
    too_wide = max(frame.width, frame.height) > NAV2_MAX_CELLS_PER_SIDE and not allow_large
    if not (too_many or too_wide):
        return frame
    # the finest resolution that fits (margin grows with the resolution when it is the default)
    extent_w, extent_h = maxx - minx + 2 * thick, maxy - miny + 2 * thick
    guess = max(
        math.sqrt(extent_w * extent_h / max_cells) if too_many else 0.0,
        max(extent_w, extent_h) / (NAV2_MAX_CELLS_PER_SIDE - 4) if too_wide else 0.0,
        res,
    )
    fit = nice_ceil(guess)
    for _ in range(100):
        f = frame_at(fit, thick + fit if opts.margin is None else pad)
        if f.width * f.height <= max_cells and (allow_large or max(f.width, f.height) <= NAV2_MAX_CELLS_PER_SIDE):
            break
        fit = nice_ceil(fit * 1.01)
    what = (
        f"{total:.2g} cells, more than the budget of {max_cells:.2g}"
        if too_many
        else f"wider or taller than the {NAV2_MAX_CELLS_PER_SIDE} cells Nav2 (Jazzy and later) accepts"
    )
    raise GridTooLarge(
        f"storey {storey!r}: grid would be {frame.width} x {frame.height} cells ({what}) at {res:g} m.",
        cells=total if too_many else max(frame.width, frame.height),
        limit=max_cells if too_many else NAV2_MAX_CELLS_PER_SIDE,
        suggested_resolution=fit,
        hint=f"Use a resolution of {fit:g} m or coarser.",
    )


def _draw_lines(
    grid: np.ndarray, frame: Frame, segments: np.ndarray, value: int, keep: tuple[int, ...], *, axis: bool = True
) -> None:
    """Write ``value`` on the supercover cells of ``segments`` (sparing ``keep`` cells), in batches of
    segments that cross half a million cells at most, so memory stays bounded for any input.
    ``axis=False`` leaves the axis-aligned segments out (a wider band drawn over them holds their cells)."""
    if len(segments) == 0:
        return
    _, segments, rects = axis_line_rects(segments, frame)
    if axis:
        write_rects(grid, *rects, value, keep)
    if len(segments) == 0:
        return
    span = (np.abs(segments[:, 2] - segments[:, 0]) + np.abs(segments[:, 3] - segments[:, 1])) / frame.resolution
    batch = (np.cumsum(span + 2) // 500_000).astype(np.int64)
    cuts = [0, *(np.flatnonzero(np.diff(batch)) + 1).tolist(), len(segments)]
    for lo, hi in itertools.pairwise(cuts):
        rows, cols = supercover_cells(segments[lo:hi], frame)
        current = grid[rows, cols]
        ok = np.ones(len(rows), dtype=bool)
        for k in keep:
            ok &= current != k
        grid[rows[ok], cols[ok]] = value


@dataclass
class _Plan:
    """What one storey's rasterisation works on: the frame, the cells by role and the door geometry."""

    frame: Frame
    half: float  # half the wall thickness, metres
    max_gap: float
    cells: list[Cell]
    rooms: list[BaseGeometry]
    blocked: list[BaseGeometry]
    door_polys: list[BaseGeometry]
    door_lines: list[BaseGeometry]
    openings: OpeningPlan
    outside_mark: int = _OUTSIDE  # what cells outside every cell hold while drawing

    @property
    def spare(self) -> tuple[int, ...]:
        """Values a wall or door must not overwrite: obstacles, when the storey has any (with none,
        nothing is occupied while drawing, and writes need not read the grid first)."""
        return (OCCUPIED,) if self.blocked else ()

    @property
    def steps(self) -> int:
        return len(self.cells) + len(self.door_polys) + len(self.door_lines) + 2


class _Ticker:
    """Counts finished pieces of work and reports them as ``rasterise`` progress."""

    def __init__(self, progress: ProgressCallback | None, total: int, storey: str) -> None:
        self.progress, self.total, self.done, self.storey = progress, total, 0, storey

    def __call__(self, n: int = 1) -> None:
        self.done += n
        emit(self.progress, "rasterise", self.done / max(self.total, 1), f"storey {self.storey}")


def _plan(
    building: Building,
    storey: str,
    resolution: float,
    opts: RasterOptions,
    openings: OpeningPlan | None = None,
) -> _Plan:
    """Step 1: the frame (budget-checked), the storey's cells sorted into rooms, blocked and doors, and
    the openings the navigation graph asks for (door lines between cells it does not join stay shut)."""
    max_gap = _check_number("max wall gap", opts.max_wall_gap, positive=False)
    width = _check_number("door width", opts.door_width, positive=True)
    cells = _storey_cells(building, storey)
    frame = plan_storey(building, storey, resolution, opts, cells=cells)
    if openings is None:
        openings = plan_openings(building, storey, door_width=width, max_gap=max_gap)
    door_polys, door_lines = door_geometry(building, storey, cells, skip=openings.shut_doors)
    return _Plan(
        frame=frame,
        half=float(opts.wall_thickness) / 2,
        max_gap=max_gap,
        cells=cells,
        rooms=[c.footprint for c in cells if c.kind.is_free and not c.kind.is_door],
        blocked=[c.footprint for c in cells if not c.kind.is_free],
        door_polys=door_polys,
        door_lines=door_lines,
        openings=openings,
    )


def _fill_cells(plan: _Plan, storey: str, tick: _Ticker) -> np.ndarray:
    """Step 2: a grid of "outside" with free spaces (and door cells) free and non-navigable cells occupied."""
    frame = plan.frame
    try:
        grid = new_cells(frame.height, frame.width, plan.outside_mark)
    except MemoryError as err:
        raise OccupancyError(
            f"storey {storey!r}: not enough memory for {frame.width} x {frame.height} cells; use a coarser resolution"
        ) from err
    fill_polygons(grid, frame, plan.rooms + plan.door_polys, FREE)
    fill_polygons(grid, frame, plan.blocked, OCCUPIED)
    tick(len(plan.cells))
    return grid


def _draw_walls(grid: np.ndarray, plan: _Plan, tick: _Ticker) -> np.ndarray:
    """Step 3: wall gaps the file left out, then every room's outline as a wall band; returns the door gaps."""
    frame, res = plan.frame, plan.frame.resolution
    tol = max(0.01, 0.25 * res)
    gaps = door_gaps(plan.door_lines, plan.rooms, max_gap=max(_MAX_DOOR_GAP, plan.max_gap))
    walls = thickest_wall(plan.openings, gaps, plan.max_gap)  # a gap no transition crosses is wall up to this
    gap_fill = gap_walls([c.footprint for c in plan.cells] + plan.door_polys, plan.door_lines, gaps, walls, tol)
    fill_polygons(grid, frame, [gap_fill], _WALL, keep=(FREE, OCCUPIED))
    segments = wall_segments(plan.rooms, plan.door_polys, plan.door_lines, gaps, tol)
    fill_segment_bands(grid, frame, segments, plan.half, _WALL, plan.spare)
    # an axis-aligned band more than a cell wide already holds its line's supercover cells
    _draw_lines(grid, frame, segments, _WALL, plan.spare, axis=plan.half <= res / 2 + 1e-9)
    tick()
    return gaps


def _open_doors(grid: np.ndarray, plan: _Plan, gaps: np.ndarray, tick: _Ticker) -> None:
    """Step 4: doors clear the wall across their width (plus a passage); last, the seams the graph keeps shut."""
    frame, res = plan.frame, plan.frame.resolution
    reach = plan.half + res
    fill_polygons(grid, frame, plan.door_polys, FREE, keep=plan.spare)
    tick(len(plan.door_polys))
    door_segs, owner = segments_with_owner(plan.door_lines)
    door_reach = reach + gaps[owner]
    fill_segment_bands(grid, frame, door_segs, door_reach, FREE, plan.spare, caps=False)
    _draw_lines(grid, frame, shrink_segments(door_segs, 0.5 * res), FREE, plan.spare)
    tick(len(plan.door_lines))
    doors = [c for c in plan.cells if c.kind.is_door]  # in door_polys' order: door_geometry lists them first
    rooms = [c for c in plan.cells if c.kind.is_free and not c.kind.is_door]
    sides = door_neighbours(doors, rooms, plan.openings.links, reach)
    _draw_lines(grid, frame, passages(plan.door_polys, door_segs, door_reach, reach, sides), FREE, plan.spare)
    # the graph's openings: wall cells only (never obstacles or outside), after every wall is drawn
    polys = plan.openings.wall_polygons(reach)
    fill_polygons(grid, frame, polys, FREE, keep=(OCCUPIED, plan.outside_mark, FREE))
    _lay_bridges(grid, plan, reach)
    seams, _ = segments_with_owner(list(plan.openings.seams))
    _draw_lines(grid, frame, seams, _WALL, (OCCUPIED, plan.outside_mark, _WALL))


def _lay_bridges(grid: np.ndarray, plan: _Plan, reach: float) -> None:
    """Passages across gaps between linked cells (rule "bridge"): walls along both sides where the gap
    is outside every cell, then the lane free (never over an obstacle)."""
    bridges = [o for o in plan.openings.openings if o.path is not None]
    if not bridges:
        return
    frame = plan.frame
    side = [o.width / 2 + 0.75 * frame.resolution for o in bridges]
    paths = [cast("BaseGeometry", o.path) for o in bridges]  # not None: bridges have a path
    edges = [shapely.offset_curve(p, s * k) for p, s in zip(paths, side, strict=True) for k in (-1, 1)]
    segs, _ = segments_with_owner([e for e in edges if not e.is_empty])
    _draw_lines(grid, frame, segs, _WALL, (FREE, OCCUPIED, _WALL))
    fill_polygons(grid, frame, [p for o in bridges for p in o.polygons(reach)], FREE, keep=(OCCUPIED,))


def _finish(grid: np.ndarray, outside_mark: int, tick: _Ticker) -> None:
    """Step 5: walls become occupied, outside cells unknown (or occupied), in strips of 64 Ki cells
    (no full-size temporary; a strip's mask stays in cache)."""
    step = max(1, 65536 // max(1, grid.shape[1]))
    for start in range(0, grid.shape[0], step):
        block = grid[start : start + step]
        np.copyto(block, OCCUPIED, where=block == _WALL, casting="unsafe")
        if outside_mark == _OUTSIDE:
            np.copyto(block, OCCUPIED, where=block == _OUTSIDE, casting="unsafe")
    tick()


def rasterise_storey(
    building: Building,
    storey: str,
    resolution: float,
    options: RasterOptions | None = None,
    *,
    openings: OpeningPlan | None = None,
    progress: ProgressCallback | None = None,
) -> OccupancyGrid:
    """One storey as an OccupancyGrid (-1 unknown, 0 free, 100 occupied; row 0 = bottom).

    Steps: plan -> cells -> walls -> doors -> grid (see the module docstring for the rules).
    ``options``: how to draw it (:class:`~pmk_nb.raster.options.RasterOptions`, passed whole; the
    defaults when None); ``openings``: the openings plan when the caller has made it already.
    ``progress`` gets ``rasterise`` reports, 0..1 for this storey.

    Raises:
        OccupancyError: bad parameters or an empty storey; GridTooLarge over budget (see plan_storey).
    """
    opts = RasterOptions() if options is None else options
    outside = opts.outside
    if outside not in OUTSIDE_VALUES:
        raise OccupancyError(f"outside must be 'unknown' or 'occupied', got {outside!r}")
    plan = _plan(building, storey, resolution, opts, openings)
    plan.outside_mark = UNKNOWN if outside == "unknown" else _OUTSIDE  # unknown from the start: no pass
    tick = _Ticker(progress, plan.steps, storey)
    grid = _fill_cells(plan, storey, tick)
    gaps = _draw_walls(grid, plan, tick)
    _open_doors(grid, plan, gaps, tick)
    seal_storey(grid, building, storey, plan, max(_MAX_DOOR_GAP, plan.max_gap), _WALL)  # outer edge: wall
    _finish(grid, plan.outside_mark, tick)
    return OccupancyGrid(
        data=grid,
        resolution=plan.frame.resolution,
        origin=(plan.frame.x0, plan.frame.y0, 0.0),
        frame_id="map",
        meta={
            **_meta(building, storey, float(opts.wall_thickness), outside, plan.max_gap),
            "door_width": float(opts.door_width),
            "openings": plan.openings.rule_counts(),
        },
    )


def _meta(building: Building, storey: str, wall_thickness: float, outside: str, max_gap: float) -> dict[str, Any]:
    geo = building.georef
    return {
        "storey": storey,
        "source": building.source,
        "source_sha256": building.sha256,
        "unit": building.unit,
        "unit_reason": building.unit_reason,
        "translation": [float(geo.translation[0]), float(geo.translation[1])],
        "rotation": float(geo.rotation),
        "lla_origin": None if geo.lla is None else [float(v) for v in geo.lla],
        "wall_thickness": wall_thickness,
        "outside": outside,
        "max_wall_gap": max_gap,
        # large projected coordinates are read from a local origin: where the map's (0, 0) lies in the CRS
        **({"crs_origin": [float(geo.origin[0]), float(geo.origin[1])]} if any(geo.origin) else {}),
        **({"srs_name": geo.srs_name} if geo.srs_name else {}),
    }


def rasterise(
    building: Building,
    resolution: float,
    options: RasterOptions | None = None,
    *,
    storeys: Iterable[str] | None = None,
    progress: ProgressCallback | None = None,
) -> dict[str, OccupancyGrid]:
    """One grid per storey (all storeys, or those named), in building order.

    Every storey is planned (budget-checked) before any is rasterised, so an oversize storey fails
    fast. ``progress`` gets ``rasterise`` reports, 0..1 over all storeys.

    Raises:
        OccupancyError: see rasterise_storey.
    """
    names = [s.name for s in building.storeys] if storeys is None else list(dict.fromkeys(storeys))
    if not names:
        raise OccupancyError(f"{building.source}: no storeys to rasterise")
    for name in names:
        plan_storey(building, name, resolution, options)
    grids: dict[str, OccupancyGrid] = {}
    for i, name in enumerate(names):
        sub = sub_range(progress, i / len(names), (i + 1) / len(names))
        grids[name] = rasterise_storey(building, name, resolution, options, progress=sub)
    emit(progress, "rasterise", 1.0, f"{len(names)} storeys")
    return grids
