"""How a storey is drawn, as one value: ``RasterOptions`` passes whole from the convert pipeline
(``library.convert.ConvertOptions.raster``), the accessibility check and the simulator's demo maps to
:func:`~pmk_nb.raster.storey.rasterise_storey` and :func:`~pmk_nb.raster.storey.plan_storey`, instead of
a dozen keyword arguments each caller repeats with its own copy of the defaults. Every default is
:mod:`pmk_nb.defaults`'s (issue 25)."""

from __future__ import annotations

from dataclasses import dataclass

from pmk_nb.defaults import DEFAULT_DOOR_WIDTH, DEFAULT_MAX_CELLS, DEFAULT_MAX_WALL_GAP, DEFAULT_WALL_THICKNESS

OUTSIDE_VALUES = ("unknown", "occupied")


@dataclass(frozen=True)
class RasterOptions:
    """The drawing settings of one storey's grid (the resolution, the building and the storey are the
    call's own arguments; an openings plan and a progress callback are inputs, not settings)."""

    wall_thickness: float = DEFAULT_WALL_THICKNESS  # metres: the wall band along every cell's outline
    max_wall_gap: float = DEFAULT_MAX_WALL_GAP  # metres: gaps up to this wide are walls a door may open
    door_width: float = DEFAULT_DOOR_WIDTH  # metres: openings made where the file gives no door geometry
    outside: str = "unknown"  # one of OUTSIDE_VALUES: the value outside every cell
    max_cells: int = DEFAULT_MAX_CELLS  # the memory budget: refuse bigger grids
    allow_large: bool = False  # allow more than Nav2's 32767 cells per side
    margin: float | None = None  # metres around the storey; None: a wall band and a cell
