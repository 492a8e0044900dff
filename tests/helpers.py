"""Plain helpers shared by several test files (fixtures live in fixtures_sim.py / fixtures_ssh.py).

- ``wait_until(cond, ...)``: poll until true or fail the test, naming what it waited for (UI flows).
- ``wait_ticking(cond, timeout, tick)``: poll, calling ``tick()`` first each time (a screen's timer
  driven by hand); True or False, for the test to assert.
- ``app_context(tmp_path)``: the dashboard's AppContext on a fresh maps folder and profile store.
- ``building`` / ``room``: hand-made IndoorGML models; ``centres`` / ``cells_in``: grid cells whose
  centre lies in a shape; ``flood`` / ``reachable``: what a robot can reach through free cells.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from pmk_nb.indoorgml import Boundary, Building, Cell, CellKind, Georeference, Storey

if TYPE_CHECKING:
    from shapely.geometry import Polygon

    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.ui import AppContext


def wait_ticking(cond: Callable[[], bool], timeout: float, tick: Callable[[], None] | None = None) -> bool:
    """Poll ``cond`` every 50 ms for ``timeout`` s, calling ``tick()`` before each look."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if tick is not None:
            tick()
        if cond():
            return True
        time.sleep(0.05)
    return cond()


def wait_until(cond: Callable[[], Any], timeout: float = 60.0, what: str = "condition") -> Any:
    """Poll ``cond`` every 50 ms; returns its first truthy value, or fails after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = cond()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


@contextlib.contextmanager
def app_context(tmp_path: Path) -> Iterator[AppContext]:
    """An AppContext on ``tmp_path/maps`` with profiles in ``tmp_path/cfg`` (no keyring), closed at exit."""
    from pmk_nb.chair import ProfileStore
    from pmk_nb.library import MapsFolder
    from pmk_nb.ui import AppContext

    store = ProfileStore(tmp_path / "cfg" / "profiles.json", secrets=False)
    context = AppContext(MapsFolder(tmp_path / "maps"), store, config_dir=tmp_path / "cfg")
    try:
        yield context
    finally:
        context.close()


# --- hand-made buildings and grid geometry ---------------------------------------------------------


def building(cells: list[Cell], boundaries: list[Boundary] = (), storeys: list[str] | None = None) -> Building:
    names = storeys or sorted({c.storey for c in cells})
    return Building(
        source="hand-made.gml",
        sha256="ab" * 32,
        version="test",
        namespaces={},
        unit="m",
        unit_reason="built by the test",
        storeys=[Storey(n, None, [c.id for c in cells if c.storey == n]) for n in names],
        cells={c.id: c for c in cells},
        boundaries={b.id: b for b in boundaries},
        georef=Georeference(translation=(10.0, 20.0), rotation=15.0, lla=(45.8, 9.09, -151.3)),
    )


def room(cid: str, geom: Polygon, kind: CellKind = CellKind.GENERAL, storey: str = "F1") -> Cell:
    return Cell(cid, kind, geom, storey)


def centres(grid: OccupancyGrid) -> tuple[np.ndarray, np.ndarray]:
    cols = grid.origin[0] + (np.arange(grid.width) + 0.5) * grid.resolution
    rows = grid.origin[1] + (np.arange(grid.height) + 0.5) * grid.resolution
    return np.meshgrid(cols, rows)


def cells_in(grid: OccupancyGrid, geom: shapely.Geometry) -> np.ndarray:
    """Mask of the cells (grid rows, row 0 at the bottom) whose centre lies inside ``geom``."""
    x, y = centres(grid)
    return shapely.contains_xy(geom, x, y)


def flood(free: np.ndarray, seed: np.ndarray, *, diagonal: bool = True) -> np.ndarray:
    """Cells reachable from ``seed`` through ``free`` (iterative dilation, bounded by the cell count).

    8-connected moves by default; ``diagonal=False`` allows only the 4 axis moves.
    """
    reached = seed & free
    for _ in range(free.size):
        grown = reached.copy()
        grown[1:] |= reached[:-1]
        grown[:-1] |= reached[1:]
        grown[:, 1:] |= reached[:, :-1]
        grown[:, :-1] |= reached[:, 1:]
        if diagonal:
            grown[1:, 1:] |= reached[:-1, :-1]
            grown[1:, :-1] |= reached[:-1, 1:]
            grown[:-1, 1:] |= reached[1:, :-1]
            grown[:-1, :-1] |= reached[1:, 1:]
        grown &= free
        if np.array_equal(grown, reached):
            return reached
        reached = grown
    return reached


def reachable(free: np.ndarray, seed: tuple[int, int]) -> np.ndarray:
    """4-connected flood fill over ``free`` from the cell (row, col)."""
    start = np.zeros_like(free)
    start[seed] = True
    return flood(free, start, diagonal=False)
