"""Run the accessibility check on a building plan (rasterised in memory) or on a written map."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.access.report import DEFAULT_CHAIR_WIDTH, StoreyReport, check_storey
from pmk_nb.access.sidecar import StoreyPlanFile, read_sidecar
from pmk_nb.errors import OccupancyError
from pmk_nb.openings import OpeningPlan, plan_openings
from pmk_nb.raster import RasterOptions, rasterise_storey

if TYPE_CHECKING:
    from collections.abc import Callable

    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.indoorgml import Building


def check_chair_width(value: float) -> float:
    """A chair width in metres (0.3-2 m), or OccupancyError saying what is expected."""
    try:
        w = float(value)
    except (TypeError, ValueError) as err:
        raise OccupancyError(f"chair width must be a number of metres, got {value!r}") from err
    if not 0.3 <= w <= 2.0:
        raise OccupancyError(f"chair width must be between 0.3 and 2 m, got {value!r}")
    return w


def profile_chair_width(given: float | None, profile: object | None) -> float:
    """The chair width to check for: ``given`` (--chair-width) when set, else the chair profile's
    ``chair_width`` (Settings), else :data:`~pmk_nb.defaults.DEFAULT_CHAIR_WIDTH`."""
    if given is not None:
        return check_chair_width(given)
    width = getattr(profile, "chair_width", None)
    return DEFAULT_CHAIR_WIDTH if width is None else check_chair_width(width)


def check_grid(
    building: Building,
    storey: str,
    grid: OccupancyGrid,
    *,
    chair_width: float = DEFAULT_CHAIR_WIDTH,
    options: RasterOptions | None = None,
    plan: OpeningPlan | None = None,
) -> StoreyReport:
    """The report of one storey's grid against the building's graph (``options``: how the grid was
    drawn, the defaults when None; ``plan``: the openings the grid was rasterised with, when the caller
    has them)."""
    opts = RasterOptions() if options is None else options
    if plan is None:
        plan = plan_openings(building, storey, door_width=opts.door_width, max_gap=opts.max_wall_gap)
    cells = [c for c in building.cells_of(storey) if c.footprint is not None and not c.footprint.is_empty]
    report = check_storey(
        storey,
        grid,
        cells,
        plan.openings,
        chair_width=chair_width,
        wall_thickness=opts.wall_thickness,
        max_gap=opts.max_wall_gap,
        skipped=plan.skipped,
    )
    status = building.graph_status
    report.graph_lost = status.reason if status.lost else ""  # a lost graph checks nothing, whatever resolved
    return report


def check_building(
    building: Building,
    resolution: float,
    *,
    chair_width: float = DEFAULT_CHAIR_WIDTH,
    options: RasterOptions | None = None,
    storeys: list[str] | None = None,
    on_grid: Callable[[str, OccupancyGrid], None] | None = None,
) -> list[StoreyReport]:
    """Rasterise each storey in memory (nothing written) with ``options`` and check it; ``on_grid``
    sees each storey's grid before it is dropped (the command line's witness judges it there)."""
    width = check_chair_width(chair_width)
    opts = RasterOptions() if options is None else options
    out = []
    for name in storeys or [s.name for s in building.storeys]:
        plan = plan_openings(building, name, door_width=opts.door_width, max_gap=opts.max_wall_gap)
        grid = rasterise_storey(building, name, resolution, opts, openings=plan)
        out.append(check_grid(building, name, grid, chair_width=width, options=opts, plan=plan))
        if on_grid is not None:
            on_grid(name, grid)
        del grid
    return out


def check_map(yaml_path: str | os.PathLike[str], *, chair_width: float = DEFAULT_CHAIR_WIDTH) -> StoreyReport:
    """Check a written map against the rooms file written beside it.

    Raises:
        MapFormatError: the map or its rooms file cannot be read.
    """
    from pmk_nb.rosmap import read_map

    width = check_chair_width(chair_width)
    grid = read_map(Path(yaml_path))
    return check_plan_file(read_sidecar(Path(yaml_path)), grid, chair_width=width)


def check_plan_file(plan: StoreyPlanFile, grid: OccupancyGrid, *, chair_width: float) -> StoreyReport:
    """A written map against its rooms file, with the wall thickness and gap the map was written with
    (its YAML), and the links left unchecked: ``pmk check MAP.yaml`` and the route planner agree."""
    report = check_storey(
        plan.storey,
        grid,
        plan.cells,
        plan.openings,
        chair_width=check_chair_width(chair_width),
        wall_thickness=float(grid.meta.get("wall_thickness", RasterOptions.wall_thickness)),
        max_gap=float(grid.meta.get("max_wall_gap", RasterOptions.max_wall_gap)),
        skipped=plan.skipped,
    )
    graph = plan.raw.get("graph")  # the plan's graph status, in rooms files written since issue 31
    if isinstance(graph, dict) and graph.get("lost"):
        report.graph_lost = str(graph.get("reason") or "the plan's navigation graph was lost")
    return report
