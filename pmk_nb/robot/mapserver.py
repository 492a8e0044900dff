"""The PMK map server as a ROS 2 node (rclpy): what a lab runs on its chair instead of Nav2's map_server.

Topics: ``/map`` and ``/map_metadata``, both reliable + transient local (late subscribers get the map,
as from Nav2's map_server). Services:

- ``/map_server/load_map`` (``nav2_msgs/srv/LoadMap``): Nav2's fields and result codes;
- ``/map_update`` (``map_server_pmk/srv/MapUpdate``): ``string path`` -> ``bool done``, as the original;
- ``/change_map`` (``nav_msgs/srv/LoadMap``) when asked for: success 0, anything else 255, as ROS 1;
- ``/map_server/map_info`` (``map_server_pmk/srv/MapInfo``): header, metadata, SHA-256 of the grid
  and the YAML path, so a deploy confirms a big map without moving the grid;
- ``/map_server/map`` (``nav_msgs/srv/GetMap``).

Nav2 puts the whole grid in the LoadMap reply; a rosbridge server cannot carry a 4000x4000 one as
JSON and closes the client instead. Above ``reply_map_cells`` cells the reply holds an empty map
(result still exact); clients confirm with ``map_info``. ``without`` leaves ``/map_metadata`` and/or
``map_info`` out, to act like Nav2's map_server (the tests of the dashboard's fallbacks). rclpy is
imported here only.
"""

from __future__ import annotations

import array
import logging
import math
from pathlib import Path
from typing import Any

from pmk_nb.robot.mapstore import LoadedMap, MapStore
from pmk_nb.wire import ros1_result

READY_LINE = "pmk robot map-server: ready"
RELOAD_SERVICES = ("load_map", "map_update", "change_map")
DEFAULT_SERVICES = ("load_map", "map_update")
OPTIONAL = ("map_metadata", "map_info")  # what --without may leave out (Nav2's map_server has neither)
REPLY_MAP_CELLS = 4_000_000  # 2000x2000: what rosbridge still carries as JSON
log = logging.getLogger(__name__)


def fill_grid_msg(msg: Any, loaded: LoadedMap, stamp: Any) -> None:
    """Fill a nav_msgs/OccupancyGrid from a loaded map (the data copied once, as int8 bytes)."""
    fill_header(msg.header, loaded, stamp)
    fill_info(msg.info, loaded, stamp)
    data = array.array("b")
    data.frombytes(loaded.grid.data.astype("int8", copy=False).tobytes())
    msg.data = data


def fill_header(header: Any, loaded: LoadedMap, stamp: Any) -> None:
    header.frame_id = loaded.grid.frame_id or "map"
    header.stamp = stamp


def fill_info(info: Any, loaded: LoadedMap, stamp: Any) -> None:
    """nav_msgs/MapMetaData: load time, size, resolution, origin (yaw as a quaternion)."""
    grid = loaded.grid
    info.map_load_time = stamp
    info.resolution = float(grid.resolution)
    info.width, info.height = grid.width, grid.height
    ox, oy, oth = grid.origin
    info.origin.position.x, info.origin.position.y = float(ox), float(oy)
    info.origin.orientation.z, info.origin.orientation.w = math.sin(oth / 2.0), math.cos(oth / 2.0)


def run(
    maps_dir: Path,
    first_map: str | None,
    services: tuple[str, ...],
    reply_map_cells: int,
    without: tuple[str, ...] = (),
) -> int:
    """Start the node and spin until shut down; prints READY_LINE once everything is offered."""
    import rclpy
    from rclpy.executors import ExternalShutdownException

    rclpy.init()
    try:
        node = _build(MapStore(maps_dir), first_map, services, reply_map_cells, without)
        print(READY_LINE, flush=True)
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        rclpy.try_shutdown()
    return 0


def _build(
    store: MapStore, first_map: str | None, services: tuple[str, ...], reply_map_cells: int, without: tuple[str, ...]
) -> Any:
    from nav_msgs.msg import MapMetaData, OccupancyGrid
    from rclpy.node import Node
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

    latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node = Node("map_server")
    map_pub = node.create_publisher(OccupancyGrid, "/map", latched)
    meta_pub = None if "map_metadata" in without else node.create_publisher(MapMetaData, "/map_metadata", latched)
    cache: dict[str, Any] = {}

    def publish() -> None:
        loaded = store.current
        if loaded is None:
            return
        stamp = node.get_clock().now().to_msg()
        msg = OccupancyGrid()
        fill_grid_msg(msg, loaded, stamp)
        meta = MapMetaData()
        fill_info(meta, loaded, stamp)
        cache.update(msg=msg, stamp=stamp, loaded=loaded)
        map_pub.publish(msg)
        if meta_pub is not None:
            meta_pub.publish(meta)

    def load(request: str) -> int:
        code, text = store.load(request)
        if code == 0:  # one severity per call site: rclpy refuses to change it between calls
            node.get_logger().info(text)
            publish()
        else:
            node.get_logger().warning(text)
        return code

    def reply_map(response: Any, code: int) -> None:
        loaded = cache.get("loaded")
        if code == 0 and loaded is not None and loaded.grid.data.size <= reply_map_cells:
            response.map = cache["msg"]

    def nav2_load(request: Any, response: Any) -> Any:
        response.result = load(request.map_url)
        reply_map(response, response.result)
        return response

    def ros1_load(request: Any, response: Any) -> Any:
        code = load(request.map_url)
        response.result = ros1_result(code)
        reply_map(response, code)
        return response

    def map_update(request: Any, response: Any) -> Any:
        response.done = load(request.path) == 0
        return response

    def map_info(_: Any, response: Any) -> Any:
        loaded = cache.get("loaded")
        response.loaded = loaded is not None
        if loaded is not None:
            fill_header(response.header, loaded, cache["stamp"])
            fill_info(response.info, loaded, cache["stamp"])
            response.sha256, response.path = loaded.sha256, str(loaded.path)
        return response

    def get_map(_: Any, response: Any) -> Any:
        if "msg" in cache:
            response.map = cache["msg"]
        return response

    reloads = {"load_map": nav2_load, "map_update": map_update, "change_map": ros1_load}
    _offer(node, services, reloads, None if "map_info" in without else map_info, get_map)
    if first_map:
        code = load(first_map)
        if code != 0:
            node.get_logger().error(f"could not load the first map {first_map!r} (code {code})")
    return node


def _offer(node: Any, services: tuple[str, ...], reload: dict[str, Any], map_info: Any, get_map: Any) -> None:
    """Create the chosen reload services and the always-on MapInfo and GetMap."""
    from map_server_pmk.srv import MapInfo, MapUpdate
    from nav2_msgs.srv import LoadMap as Nav2LoadMap
    from nav_msgs.srv import GetMap
    from nav_msgs.srv import LoadMap as Ros1LoadMap

    offered = {
        "load_map": (Nav2LoadMap, "/map_server/load_map"),
        "map_update": (MapUpdate, "/map_update"),
        "change_map": (Ros1LoadMap, "/change_map"),
    }
    for key in services:
        srv_type, name = offered[key]
        node.create_service(srv_type, name, reload[key])
    if map_info is not None:
        node.create_service(MapInfo, "/map_server/map_info", map_info)
    node.create_service(GetMap, "/map_server/map", get_map)
