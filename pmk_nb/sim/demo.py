"""Built-in maps for a simulator started without one.

``demo_grid()`` is generated (no files, no converter), so ``SimChair()`` always starts fast: a
20 m x 12 m floor, rooms on both sides of a corridor, 0.05 m cells, 10 cm walls, 1.2 m doors and a
1 m band of unknown space around it (like a rasterised plan). ``sample_floor()`` converts the
repository's ``sample_maps/clinic_floor.gml`` (0.9 m doors) when it and the converter are there.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pmk_nb.defaults import DEFAULT_RESOLUTION
from pmk_nb.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid

SAMPLE_GML = Path(__file__).resolve().parents[2] / "sample_maps" / "clinic_floor.gml"


def demo_grid(resolution: float = DEFAULT_RESOLUTION) -> OccupancyGrid:
    def c(metres: float) -> int:
        return round(metres / resolution)

    margin, width, height, wall = 1.0, 20.0, 12.0, 0.10
    data = np.full((c(height + 2 * margin), c(width + 2 * margin)), UNKNOWN, dtype=np.int8)

    def box(x0: float, y0: float, x1: float, y1: float, value: int) -> None:
        data[c(y0 + margin) : c(y1 + margin), c(x0 + margin) : c(x1 + margin)] = value

    box(0, 0, width, height, OCCUPIED)
    box(wall, wall, width - wall, height - wall, FREE)
    corridor_lo, corridor_hi = 5.0, 7.0
    box(0, corridor_lo - wall / 2, width, corridor_lo + wall / 2, OCCUPIED)  # corridor walls
    box(0, corridor_hi - wall / 2, width, corridor_hi + wall / 2, OCCUPIED)
    for x in (5.0, 10.0, 15.0):  # room partitions
        box(x - wall / 2, 0, x + wall / 2, corridor_lo, OCCUPIED)
        box(x - wall / 2, corridor_hi, x + wall / 2, height, OCCUPIED)
    for room in range(4):  # one door per room on each side
        door = room * 5.0 + 1.5
        box(door, corridor_lo - wall, door + 1.2, corridor_lo + wall, FREE)
        box(door + 1.0, corridor_hi - wall, door + 2.2, corridor_hi + wall, FREE)
    box(2.0, 1.0, 3.0, 2.0, OCCUPIED)  # a table in the first room
    box(12.0, 9.0, 13.5, 9.6, OCCUPIED)  # a bed in a room across the corridor
    return OccupancyGrid(data=data, resolution=resolution, origin=(-margin, -margin, 0.0), meta={"source": "demo"})


def sample_floor(resolution: float = DEFAULT_RESOLUTION) -> OccupancyGrid | None:
    """The sample clinic floor rasterised, or None outside a source checkout / without the converter."""
    if not SAMPLE_GML.is_file():
        return None
    try:
        from pmk_nb.indoorgml import read_building
        from pmk_nb.raster import rasterise_storey
    except ImportError:
        return None
    building = read_building(SAMPLE_GML)
    grid = rasterise_storey(building, building.storeys[0].name, resolution)
    grid.meta.setdefault("source", str(SAMPLE_GML))
    return grid
