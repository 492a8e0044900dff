"""Map server with hot reload, speaking all three reload dialects the dashboard must support.

- ``/change_map`` (ROS 1 Noetic map_server, ``nav_msgs/LoadMap``): ``{map_url}`` -> ``{map, result}``,
  result 0 = success, 255 = failure.
- ``/map_server/load_map`` (Nav2, ``nav2_msgs/srv/LoadMap``): same fields, result 0 success,
  1 map does not exist (empty url), 2 invalid map data (image), 3 invalid map metadata (YAML),
  255 undefined failure.
- ``/map_update`` (the thesis' modified map server, ``map_server_pmk/MapUpdate``):
  ``{path}`` -> ``{done}``.

Which of them exist is configurable so clients' service detection can be tested. ``/static_map``
(``nav_msgs/GetMap``) is always there. Files are read with :func:`pmk_nb.rosmap.files.read_map` off the
loop; a successful load republishes the latched ``/map`` and ``/map_metadata``.

A reload never stalls the loop (odometry keeps flowing): reading the file, building the world and
encoding the grid's JSON (once per load, see :mod:`pmk_nb.sim.jsonfast`) run in worker threads,
the last two side by side.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable, Iterable
from typing import TYPE_CHECKING, Any

from pmk_nb.rosmap import read_map
from pmk_nb.wire import LOAD_SUCCESS, LoadAnswer, empty_request, load_failure, ros1_result

if TYPE_CHECKING:
    from pathlib import Path

    from pmk_nb.grid import OccupancyGrid
    from pmk_nb.rosmap import ImageReader
    from pmk_nb.sim.messages import Names, RosVersion
    from pmk_nb.sim.paths import ChairFS
    from pmk_nb.sim.protocol import Bridge

RELOAD_SERVICES: tuple[str, ...] = ("change_map", "load_map", "map_update")
DEFAULT_RELOAD: dict[str, tuple[str, ...]] = {
    "ros1": ("change_map", "map_update"),
    "ros2": ("load_map", "map_update"),
}
SERVICE_NAMES = {"change_map": "/change_map", "load_map": "/map_server/load_map", "map_update": "/map_update"}


def image_reader(ros: RosVersion) -> ImageReader:
    """How this chair's map server turns map images into cells: Noetic's for ROS 1, Nav2 Humble's for ROS 2."""
    return "ros1" if ros == "ros1" else "nav2_humble"


class MapServer:
    """Owns the current grid and its latched messages; ``install`` swaps the simulator's world."""

    def __init__(
        self,
        bridge: Bridge,
        names: Names,
        fs: ChairFS,
        install: Callable[[OccupancyGrid], Awaitable[None]],
        reload_services: Iterable[str] | None = None,
    ) -> None:
        self.bridge = bridge
        self.names = names
        self.fs = fs
        self._install = install
        chosen = tuple(reload_services) if reload_services is not None else DEFAULT_RELOAD[names.ros]
        unknown = [s for s in chosen if s not in RELOAD_SERVICES]
        if unknown:
            raise ValueError(f"unknown reload service(s) {unknown}; choose from {', '.join(RELOAD_SERVICES)}")
        self.reload_services = chosen
        self.grid: OccupancyGrid | None = None
        self.source: Path | None = None
        self.load_time = 0.0
        self.loads = 0
        self._grid_msg: dict[str, Any] = names.empty_grid(0.0)
        self._lock = asyncio.Lock()

    @property
    def image_reader(self) -> ImageReader:
        return image_reader(self.names.ros)

    def register(self) -> None:
        n, b = self.names, self.bridge
        b.advertise_internal("/map", n.msg("nav_msgs", "OccupancyGrid"), latched=True)
        b.advertise_internal("/map_metadata", n.msg("nav_msgs", "MapMetaData"), latched=True)
        b.add_service("/static_map", n.srv("nav_msgs", "GetMap"), self._static_map)
        if n.ros == "ros2":
            b.add_service("/map_server/map", n.srv("nav_msgs", "GetMap"), self._static_map)
        handlers = {
            "change_map": (n.srv("nav_msgs", "LoadMap"), self._change_map),
            "load_map": (n.srv("nav2_msgs", "LoadMap"), self._load_map),
            "map_update": (n.srv("map_server_pmk", "MapUpdate"), self._map_update),
        }
        for key in self.reload_services:
            type_name, handler = handlers[key]
            b.add_service(SERVICE_NAMES[key], type_name, handler)

    async def set_grid(self, grid: OccupancyGrid, source: Path | None = None) -> None:
        """Install ``grid`` in the simulator and publish it (latched)."""
        now = time.time()
        encoding = asyncio.ensure_future(asyncio.to_thread(self.names.occupancy_grid, grid, now, now))
        try:
            await self._install(grid)
        except BaseException:
            encoding.cancel()
            raise
        msg = await encoding
        self.grid, self.source, self.load_time = grid, source, now
        self.loads += 1
        self._grid_msg = msg
        self.bridge.publish("/map", msg)
        self.bridge.publish("/map_metadata", self.names.map_metadata(grid, now))

    async def load(self, path: str) -> LoadAnswer:
        """Load a YAML path as a chair would see it; returns (Nav2 result code, message)."""
        empty = empty_request(path)
        if empty is not None:
            return empty
        host_path = self.fs.map_server_path(path)
        async with self._lock:
            try:
                grid = await asyncio.to_thread(read_map, host_path, reader=self.image_reader, within=self.fs.maps_dir)
                await self.set_grid(grid, host_path)
            except Exception as err:  # a MapLoadError carries its code; anything else is Nav2's "undefined"
                return load_failure(err)
        return LOAD_SUCCESS, f"loaded {host_path}"

    # -- service handlers -------------------------------------------------------------------------

    async def _static_map(self, _: dict[str, Any]) -> tuple[dict[str, Any], bool]:
        return {"map": self._grid_msg}, True

    async def _change_map(self, args: dict[str, Any]) -> tuple[dict[str, Any], bool]:
        code, _ = await self.load(str(args.get("map_url", "")))
        result = ros1_result(code)  # ROS 1 only knows success / undefined failure
        return {"map": self._reply_map(code), "result": result}, True

    async def _load_map(self, args: dict[str, Any]) -> tuple[dict[str, Any], bool]:
        code, _ = await self.load(str(args.get("map_url", "")))
        return {"map": self._reply_map(code), "result": code}, True

    async def _map_update(self, args: dict[str, Any]) -> tuple[dict[str, Any], bool]:
        code, _ = await self.load(str(args.get("path", "")))
        return {"done": code == 0}, True

    def _reply_map(self, code: int) -> dict[str, Any]:
        return self._grid_msg if code == 0 else self.names.empty_grid(time.time())
