"""Rasterise a building's storeys into occupancy grids, straight from the vector geometry.

The original app drew every polygon on a 100 px/m bitmap and shrank it by ``resolution / 0.01``;
that costs 10 000 pixels per square metre whatever the target resolution, and shrinking with
nearest-neighbour could drop thin walls and doors. Here each storey is rasterised once, at the
target resolution, with the cell-centre rule (:mod:`pmk_nb.raster.scanline`), in this order:

1. free cells (navigable, general, transition, anchor and connection spaces) -> 0;
2. non-navigable cells -> 100;
3. wall gaps: regions between cells narrower than ``max_wall_gap`` (files that leave walls out as
   gaps between cells, e.g. ALMA) are wall, except across door boundaries (:func:`walls.gap_walls`);
4. walls: every free cell's rings, minus the stretches where a door sits, drawn as a band of
   ``wall_thickness`` centred on the line *and* as a 4-connected supercover line, so rooms that share
   an edge never merge even when the wall is thinner than a cell;
5. doors opened after the walls: door cells (ConnectionSpace/AnchorSpace) and door boundaries clear
   the wall across their width, plus a short passage line across the wall so the opening survives
   coarse resolutions;
6. everything outside all cells stays unknown (or occupied with ``outside="occupied"``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from pmk_nb.errors import OccupancyError
from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid, nice_ceil
from pmk_nb.raster.scanline import (
    Frame,
    fill_geometry,
    fill_segment_bands,
    line_segments,
    segments_with_owner,
    supercover_cells,
)
from pmk_nb.raster.walls import door_gaps, door_geometry, gap_walls, passages, shrink_segments, wall_lines

if TYPE_CHECKING:
    from pmk_nb.indoorgml.model import Building, Cell

__all__ = [
    "DEFAULT_MAX_CELLS",
    "DEFAULT_MAX_WALL_GAP",
    "DEFAULT_WALL_THICKNESS",
    "NAV2_MAX_CELLS_PER_SIDE",
    "plan_storey",
    "rasterise",
    "rasterise_storey",
]

DEFAULT_WALL_THICKNESS = 0.10
DEFAULT_MAX_WALL_GAP = 0.5  # metres: a gap between cells up to this wide is a wall left out of the file
DEFAULT_MAX_CELLS = 400_000_000  # ~400 MB of int8
NAV2_MAX_CELLS_PER_SIDE = 32767
_WALL = 101  # transient markers while drawing: a wall cell that a door may still open,
_OUTSIDE = 102  # and a cell outside every cell (unknown or occupied once finished)
_MAX_DOOR_GAP = 1.0  # metres between a door line and the rooms it joins, at most (walls modelled as gaps)
Progress = Callable[[int, int], None]


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
    *,
    wall_thickness: float = DEFAULT_WALL_THICKNESS,
    margin: float | None = None,
    max_cells: int = DEFAULT_MAX_CELLS,
    allow_large: bool = False,
) -> Frame:
    """The grid frame a storey needs, checked against the memory budget and the Nav2 size limit.

    Raises:
        OccupancyError: the grid would exceed ``max_cells`` or 32767 cells per side (unless
            ``allow_large``); the message names the finest resolution that fits.
    """
    res = _check_number("resolution", resolution, positive=True)
    thick = _check_number("wall thickness", wall_thickness, positive=False)
    pad = thick + res if margin is None else _check_number("margin", margin, positive=False)
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
        f = frame_at(fit, thick + fit if margin is None else pad)
        if f.width * f.height <= max_cells and (allow_large or max(f.width, f.height) <= NAV2_MAX_CELLS_PER_SIDE):
            break
        fit = nice_ceil(fit * 1.01)
    what = (
        f"{total:.2g} cells, more than the budget of {max_cells:.2g}"
        if too_many
        else f"wider or taller than the {NAV2_MAX_CELLS_PER_SIDE} cells Nav2 (Jazzy and later) accepts"
    )
    raise OccupancyError(
        f"storey {storey!r}: grid would be {frame.width} x {frame.height} cells ({what}) at {res:g} m; "
        f"use --resolution {fit:g} or coarser"
    )


def _setter(value: int, keep: tuple[int, ...] = ()) -> Callable[[np.ndarray, np.ndarray], None]:
    """A cell op writing ``value`` except over cells currently holding one of ``keep``."""

    def op(block: np.ndarray, mask: np.ndarray) -> None:
        for k in keep:
            mask = mask & (block != k)
        block[mask] = value

    return op


def _draw_lines(grid: np.ndarray, frame: Frame, segments: np.ndarray, value: int, keep: tuple[int, ...]) -> None:
    """Write ``value`` on the supercover cells of ``segments`` (sparing ``keep`` cells), in batches of
    segments that cross a few million cells at most, so memory stays bounded for any input."""
    if len(segments) == 0:
        return
    span = (np.abs(segments[:, 2] - segments[:, 0]) + np.abs(segments[:, 3] - segments[:, 1])) / frame.resolution
    batch = (np.cumsum(span + 2) // 4_000_000).astype(np.int64)
    cuts = [0, *(np.flatnonzero(np.diff(batch)) + 1).tolist(), len(segments)]
    for lo, hi in itertools.pairwise(cuts):
        rows, cols = supercover_cells(segments[lo:hi], frame)
        current = grid[rows, cols]
        ok = np.ones(len(rows), dtype=bool)
        for k in keep:
            ok &= current != k
        grid[rows[ok], cols[ok]] = value


def rasterise_storey(
    building: Building,
    storey: str,
    resolution: float,
    *,
    wall_thickness: float = DEFAULT_WALL_THICKNESS,
    outside: str = "unknown",
    max_wall_gap: float = DEFAULT_MAX_WALL_GAP,
    max_cells: int = DEFAULT_MAX_CELLS,
    margin: float | None = None,
    allow_large: bool = False,
    progress: Progress | None = None,
) -> OccupancyGrid:
    """One storey as an OccupancyGrid (-1 unknown, 0 free, 100 occupied; row 0 = bottom).

    Raises:
        OccupancyError: bad parameters, an empty storey, or a grid over budget (see plan_storey).
    """
    if outside not in ("unknown", "occupied"):
        raise OccupancyError(f"outside must be 'unknown' or 'occupied', got {outside!r}")
    max_gap = _check_number("max wall gap", max_wall_gap, positive=False)
    frame = plan_storey(
        building, storey, resolution, wall_thickness=wall_thickness, margin=margin,
        max_cells=max_cells, allow_large=allow_large,
    )  # fmt: skip
    res, half = frame.resolution, float(wall_thickness) / 2
    cells = _storey_cells(building, storey)
    rooms = [c.footprint for c in cells if c.kind.is_free and not c.kind.is_door]
    blocked = [c.footprint for c in cells if not c.kind.is_free]
    door_polys, door_lines = door_geometry(building, storey, cells)
    total = len(cells) + len(door_polys) + len(door_lines) + 2
    done = 0

    def tick(n: int = 1) -> None:
        nonlocal done
        done += n
        if progress is not None:
            progress(done, total)

    try:
        grid = np.full((frame.height, frame.width), _OUTSIDE, np.int8)
    except MemoryError as err:
        raise OccupancyError(
            f"storey {storey!r}: not enough memory for {frame.width} x {frame.height} cells; use a coarser resolution"
        ) from err
    for geom in rooms + door_polys:
        fill_geometry(grid, frame, geom, _setter(FREE))
        tick()
    for geom in blocked:
        fill_geometry(grid, frame, geom, _setter(OCCUPIED))
        tick()

    tol = max(0.01, 0.25 * res)
    gaps = door_gaps(door_lines, rooms, max_gap=max(_MAX_DOOR_GAP, max_gap))
    gap_fill = gap_walls([c.footprint for c in cells] + door_polys, door_lines, gaps, max_gap, tol)
    fill_geometry(grid, frame, gap_fill, _setter(_WALL, keep=(FREE, OCCUPIED)))
    walls = wall_lines(rooms, door_polys, door_lines, gaps, tol)
    segments = line_segments(walls)
    fill_segment_bands(grid, frame, segments, half, _WALL, (OCCUPIED,))
    _draw_lines(grid, frame, segments, _WALL, (OCCUPIED,))
    tick()

    opener = _setter(FREE, keep=(OCCUPIED,))
    reach = half + res
    for geom in door_polys:
        fill_geometry(grid, frame, geom, opener)
        tick()
    door_segs, owner = segments_with_owner(door_lines)
    door_reach = reach + gaps[owner]
    fill_segment_bands(grid, frame, door_segs, door_reach, FREE, (OCCUPIED,), caps=False)
    _draw_lines(grid, frame, shrink_segments(door_segs, 0.5 * res), FREE, (OCCUPIED,))
    tick(len(door_lines))
    _draw_lines(grid, frame, passages(door_polys, door_segs, door_reach, reach), FREE, (OCCUPIED,))
    outside_value = OCCUPIED if outside == "occupied" else UNKNOWN
    for start in range(0, frame.height, 1024):  # finalise in chunks: no full-size temporary
        block = grid[start : start + 1024]
        block[block == _WALL] = OCCUPIED
        block[block == _OUTSIDE] = outside_value
    tick()
    return OccupancyGrid(
        data=grid, resolution=res, origin=(frame.x0, frame.y0, 0.0), frame_id="map",
        meta=_meta(building, storey, float(wall_thickness), outside, max_gap),
    )  # fmt: skip


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
    }


def rasterise(
    building: Building,
    resolution: float,
    *,
    storeys: Iterable[str] | None = None,
    progress: Progress | None = None,
    **kwargs: Any,
) -> dict[str, OccupancyGrid]:
    """One grid per storey (all storeys, or those named), in building order.

    Every storey is planned (budget-checked) before any is rasterised, so an oversize storey fails
    fast. ``progress(done, total)`` counts storeys.

    Raises:
        OccupancyError: see rasterise_storey.
    """
    names = [s.name for s in building.storeys] if storeys is None else list(dict.fromkeys(storeys))
    if not names:
        raise OccupancyError(f"{building.source}: no storeys to rasterise")
    plan_kwargs = {k: kwargs[k] for k in ("wall_thickness", "margin", "max_cells", "allow_large") if k in kwargs}
    for name in names:
        plan_storey(building, name, resolution, **plan_kwargs)
    grids: dict[str, OccupancyGrid] = {}
    for i, name in enumerate(names):

        def sub(done: int, total: int, i: int = i) -> None:
            if progress is not None:
                progress_frac = i + done / max(1, total)
                progress(int(progress_frac * 1000), len(names) * 1000)

        grids[name] = rasterise_storey(building, name, resolution, progress=sub, **kwargs)
    if progress is not None:
        progress(len(names) * 1000, len(names) * 1000)
    return grids
