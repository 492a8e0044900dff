"""The current map's grid for the Home preview, read from its files and cached until they change.

The live view draws the map from the map files themselves (YAML + image, exact metres and origin).
Home re-checks them each time it is shown, so the cache key is the files' paths and modification
times: an unchanged map is not parsed again, a re-sent one is.
"""

from __future__ import annotations

import threading
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.ui.common.context import CurrentMap

_Key = tuple[str, float, float]


class MapGridCache:
    """Loads a current map's grid; the last one loaded is :attr:`grid`."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._cached: tuple[_Key, OccupancyGrid] | None = None

    @property
    def grid(self) -> OccupancyGrid | None:
        with self._lock:
            return self._cached[1] if self._cached is not None else None

    def load(self, current: CurrentMap) -> OccupancyGrid:
        """The map's grid; raises FileNotFoundError, MapFormatError, OSError or ValueError if unreadable."""
        from pmk_nb.rosmap import read_map, read_map_yaml

        yaml_path = Path(current.yaml)
        if not yaml_path.is_file():
            raise FileNotFoundError(f"map file {yaml_path} is missing")
        image = Path(read_map_yaml(yaml_path).image)
        key = (str(yaml_path), yaml_path.stat().st_mtime, image.stat().st_mtime if image.is_file() else -1.0)
        with self._lock:
            if self._cached is not None and self._cached[0] == key:
                return self._cached[1]
        grid = read_map(yaml_path)
        with self._lock:
            self._cached = (key, grid)
        return grid
