"""The PMK map server's state, shared by the ROS 2 (rclpy) and ROS 1 (rospy) nodes: no ROS here.

A request names a YAML path; the store reads it with the project's reader (:func:`pmk_nb.rosmap.read_map`,
so the chair publishes exactly what the dashboard previewed), refuses a YAML or an image outside its
maps folder (symlinks followed) and an image too large to decode (:mod:`pmk_nb.rosmap.guard`), and
answers with Nav2's result codes. ``info`` is the cheap answer a deploy
confirms with: header facts, metadata and the SHA-256 of the grid as published.
"""

from __future__ import annotations

import os
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.grid import OccupancyGrid
from pmk_nb.rosmap import ImageReader, read_map
from pmk_nb.wire import MAP_DOES_NOT_EXIST, LoadAnswer, empty_request, grid_sha256, load_failure

DEFAULT_MAPS = Path.home() / "ALMA_MAPS"


@dataclass(frozen=True)
class LoadedMap:
    """One loaded map and the facts a client checks without pulling the grid."""

    grid: OccupancyGrid
    path: Path
    load_time: float
    sha256: str


class MapStore:
    """The current map of one map server; ``load`` is thread-safe."""

    def __init__(self, maps_dir: Path = DEFAULT_MAPS, reader: ImageReader = "nav2_jazzy") -> None:
        self.maps_dir = Path(maps_dir).expanduser().resolve()
        self.reader: ImageReader = reader
        self.current: LoadedMap | None = None
        self._lock = threading.Lock()

    def resolve(self, request: str) -> Path | None:
        """The YAML a request names (plain path, ``file://`` URL, or relative to the maps folder),
        or None when it lies outside the maps folder."""
        raw = request.strip()
        if raw.startswith("file://"):
            raw = raw[len("file://") :]
        path = Path(raw) if raw.startswith("/") else self.maps_dir / raw
        real = Path(os.path.realpath(path))  # symlinks followed: a link out of the folder is outside
        return path if real.is_relative_to(self.maps_dir) else None

    def load(self, request: str) -> LoadAnswer:
        """Load the map a request names; returns (Nav2 LoadMap result code, message for the log)."""
        empty = empty_request(request)
        if empty is not None:
            return empty
        path = self.resolve(request)
        if path is None:
            return MAP_DOES_NOT_EXIST, f"refused {request!r}: outside the maps folder {self.maps_dir}"
        try:
            grid = read_map(path, reader=self.reader, within=self.maps_dir)  # the image confined too
        except Exception as err:  # a MapLoadError carries its code; anything else is Nav2's "undefined"
            return load_failure(err)
        loaded = LoadedMap(grid, path, time.time(), grid_sha256(grid))
        with self._lock:
            self.current = loaded
        return 0, f"loaded {path} ({grid.width}x{grid.height})"
